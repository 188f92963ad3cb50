/*
 * persp's own TGA and BMP decoders (src/image/tga.c, bmp.c).
 *
 * The files are made here: small encoders written from the format
 * specifications (Truevision TGA 2.0; Microsoft's BITMAPINFOHEADER,
 * BITMAPV4/V5HEADER and "Bitmap Compression" pages) build every variant
 * from a known picture, and a few files are written out byte by byte, so
 * that an encoder sharing a mistake with the decoder (which row comes
 * first) cannot hide it. Every decoded pixel is compared with the picture.
 * The malformed files must be refused with their status and a message
 * naming the file and the problem, leaving the image empty, and a header
 * claiming a huge size must be refused before anything is allocated.
 */
#include "support.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ------------------------------------------------------------ helpers */

typedef struct buf {
    unsigned char b[1 << 16];
    size_t n;
} buf;

static void put8(buf *o, unsigned v)
{
    assert_true(o->n < sizeof o->b);
    o->b[o->n++] = (unsigned char)v;
}

static void put16(buf *o, unsigned v)
{
    put8(o, v & 255u);
    put8(o, v >> 8 & 255u);
}

static void put32(buf *o, uint32_t v)
{
    put16(o, v & 0xffffu);
    put16(o, v >> 16);
}

/* The expected picture, top row first, 4 bytes a pixel. */
typedef struct picture {
    int w, h;
    uint8_t px[64 * 64 * 4];
} picture;

static uint8_t *at(picture *p, int x, int y_top)
{
    return p->px + 4 * ((size_t)y_top * (size_t)p->w + (size_t)x);
}

static void set(picture *p, int x, int y_top, unsigned r, unsigned g, unsigned b, unsigned a)
{
    uint8_t *o = at(p, x, y_top);
    o[0] = (uint8_t)r, o[1] = (uint8_t)g, o[2] = (uint8_t)b, o[3] = (uint8_t)a;
}

/* A colour for every pixel, all four channels varying. */
static void source_colour(int x, int y, uint8_t *o)
{
    o[0] = (uint8_t)(x * 53 + y * 97 + 11);
    o[1] = (uint8_t)(x * 31 + y * 17 + 190);
    o[2] = (uint8_t)(x * 71 + y * 29 + 77);
    o[3] = (uint8_t)(x * 29 + y * 71 + 200);
}

/* Large runs of one colour, so that RLE packets reach across rows. */
static void source_runs(int x, int y, uint8_t *o)
{
    if ((x * 7 + y * 3) % 5 < 3) {
        o[0] = 10, o[1] = 200, o[2] = 30, o[3] = 255;
    } else {
        source_colour(x, y, o);
    }
}

static const char *status_name(persp_status st)
{
    switch (st) {
    case PERSP_OK: return "OK";
    case PERSP_ERR_FORMAT: return "FORMAT";
    case PERSP_ERR_TOO_LARGE: return "TOO_LARGE";
    case PERSP_ERR_UNSUPPORTED: return "UNSUPPORTED";
    case PERSP_ERR_OUT_OF_MEMORY: return "OUT_OF_MEMORY";
    default: return "other";
    }
}

/* Decodes the file and compares every pixel with want. */
static void expect_picture(const char *label, const buf *f, const char *name, const picture *want)
{
    persp_context *ctx = test_context();
    persp_image img;
    persp_status st = persp_image_load_memory(ctx, f->b, f->n, name, &img);
    if (st != PERSP_OK) fail_msg("%s: %s: %s", label, status_name(st), persp_context_error(ctx));
    if (img.width != want->w || img.height != want->h)
        fail_msg("%s: decoded %dx%d, want %dx%d", label, img.width, img.height, want->w, want->h);
    for (int y = 0; y < want->h; y++)
        for (int x = 0; x < want->w; x++) {
            /* persp's row 0 is the bottom row of the displayed picture */
            const uint8_t *got = img.pixels + (size_t)(want->h - 1 - y) * img.stride + 4 * (size_t)x;
            const uint8_t *w = want->px + 4 * ((size_t)y * (size_t)want->w + (size_t)x);
            if (memcmp(got, w, 4) != 0)
                fail_msg("%s: pixel (%d, %d) from the top left is %u,%u,%u,%u, want %u,%u,%u,%u",
                         label, x, y, got[0], got[1], got[2], got[3], w[0], w[1], w[2], w[3]);
        }
    persp_image_free(ctx, &img);
    persp_context_destroy(ctx);
}

/* An allocator that records the largest block asked for. */
typedef struct alloc_log {
    size_t largest, count;
} alloc_log;

static void *logged_alloc(void *user, size_t size)
{
    alloc_log *l = user;
    l->count++;
    if (size > l->largest) l->largest = size;
    return malloc(size);
}

static void logged_free(void *user, void *ptr)
{
    (void)user;
    free(ptr);
}

/* Decodes data, which must be refused with want and a message containing
 * name and problem, an empty image, and no block of more than 64 KiB
 * asked for. */
static void expect_refused(const void *data, size_t size, const char *name, persp_status want,
                           const char *problem)
{
    alloc_log log = {0, 0};
    const persp_allocator a = {logged_alloc, logged_free, &log};
    const persp_context_desc desc = {.allocator = &a, .threads = 1};
    persp_context *ctx = NULL;
    assert_int_equal(persp_context_create(&desc, &ctx), PERSP_OK);
    log.largest = log.count = 0;
    persp_image img;
    memset(&img, 0x5a, sizeof img);
    persp_status st = persp_image_load_memory(ctx, data, size, name, &img);
    const char *msg = persp_context_error(ctx);
    print_message("%s -> %s: %s\n", name, status_name(st), msg);
    if (st != want)
        fail_msg("%s: status %s, want %s (%s)", name, status_name(st), status_name(want), msg);
    if (strncmp(msg, name, strlen(name)) != 0 || msg[strlen(name)] != ':')
        fail_msg("message '%s' does not begin with the name '%s'", msg, name);
    if (!strstr(msg, problem)) fail_msg("message '%s' lacks '%s'", msg, problem);
    if (strchr(msg, '\n')) fail_msg("message '%s' is not one line", msg);
    assert_null(img.pixels);
    assert_int_equal(img.width, 0);
    if (log.largest > 65536)
        fail_msg("%s: refused after asking for a block of %zu bytes", name, log.largest);
    persp_context_destroy(ctx);
}

/* 5-bit (or n-bit) channel value as a reader scales it to 8 bits. */
static unsigned scale(unsigned v, unsigned max)
{
    return (unsigned)lround((double)v * 255.0 / (double)max);
}

/* -------------------------------------------------------------- TGA */

typedef struct tga_spec {
    unsigned type;       /* 1, 2, 3, 9, 10, 11 */
    unsigned bits;       /* pixel depth */
    unsigned alpha_bits; /* descriptor bits 0-3 */
    unsigned origin;     /* descriptor bits 4-5 */
    unsigned cmap_bits;  /* map entry size, colour-mapped types */
    unsigned cmap_first; /* first entry index */
    unsigned id_len;
    int w, h;
} tga_spec;

/* A TGA value of bits bits for colour c (grey: c[0]), and how a reader
 * following TGA 2.0 decodes it (alpha only with attribute bits). */
static void tga_put_value(buf *o, unsigned bits, int grey, const uint8_t *c)
{
    if (grey) {
        put8(o, c[0]);
        if (bits == 16) put8(o, c[3]);
    } else if (bits == 15 || bits == 16) {
        unsigned v = (unsigned)(c[0] >> 3) << 10 | (unsigned)(c[1] >> 3) << 5 | (unsigned)(c[2] >> 3);
        if (c[3] >= 128) v |= 0x8000u;
        put16(o, v);
    } else {
        put8(o, c[2]), put8(o, c[1]), put8(o, c[0]);
        if (bits == 32) put8(o, c[3]);
    }
}

static void tga_expect_value(unsigned bits, int grey, unsigned alpha_bits, const uint8_t *c,
                             uint8_t *o)
{
    if (grey) {
        o[0] = o[1] = o[2] = c[0];
        o[3] = bits == 16 && alpha_bits ? c[3] : 255;
    } else if (bits == 15 || bits == 16) {
        o[0] = (uint8_t)scale(c[0] >> 3, 31);
        o[1] = (uint8_t)scale(c[1] >> 3, 31);
        o[2] = (uint8_t)scale(c[2] >> 3, 31);
        o[3] = bits == 16 && alpha_bits ? (c[3] >= 128 ? 255 : 0) : 255;
    } else {
        o[0] = c[0], o[1] = c[1], o[2] = c[2];
        o[3] = bits == 32 && alpha_bits ? c[3] : 255;
    }
}

enum { PALETTE = 6 };

/* The colour-mapped pictures use PALETTE colours. */
static int palette_index(int x, int y)
{
    return (x + 2 * y + (x * y) % 3) % PALETTE;
}

static void palette_colour(int i, uint8_t *o)
{
    source_colour(i * 5 + 1, i * 3 + 2, o);
}

/* Encodes source (display coordinates) as s says and fills want. Returns
 * the number of RLE packets that run from one row into the next. */
static int tga_encode(const tga_spec *s, void (*source)(int, int, uint8_t *), buf *o,
                      picture *want)
{
    const int mapped = s->type == 1 || s->type == 9;
    const int grey = s->type == 3 || s->type == 11;
    const int rle = s->type >= 9;
    o->n = 0;
    want->w = s->w, want->h = s->h;
    put8(o, s->id_len);
    put8(o, mapped ? 1 : 0);
    put8(o, s->type);
    put16(o, mapped ? s->cmap_first : 0);
    put16(o, mapped ? PALETTE : 0);
    put8(o, mapped ? s->cmap_bits : 0);
    put16(o, 0), put16(o, 0); /* x, y origin */
    put16(o, (unsigned)s->w), put16(o, (unsigned)s->h);
    put8(o, s->bits);
    put8(o, s->alpha_bits | s->origin);
    for (unsigned i = 0; i < s->id_len; i++)
        put8(o, 0xa0 + i);
    if (mapped)
        for (int i = 0; i < PALETTE; i++) {
            uint8_t c[4];
            palette_colour(i, c);
            tga_put_value(o, s->cmap_bits, 0, c);
        }
    /* The stored values in file order: rows from the origin's edge,
     * columns from its side. */
    const size_t pb = (s->bits + 7u) / 8u;
    const size_t n = (size_t)s->w * (size_t)s->h;
    static unsigned char values[64 * 64 * 4];
    buf one;
    for (size_t i = 0; i < n; i++) {
        const int r = (int)(i / (size_t)s->w), c = (int)(i % (size_t)s->w);
        const int x = s->origin & 0x10 ? s->w - 1 - c : c;
        const int y = s->origin & 0x20 ? r : s->h - 1 - r; /* from the top */
        one.n = 0;
        if (mapped) {
            const int k = palette_index(x, y);
            const unsigned index = s->cmap_first + (unsigned)k;
            if (s->bits == 8) put8(&one, index);
            else put16(&one, index);
            uint8_t pc[4];
            palette_colour(k, pc);
            tga_expect_value(s->cmap_bits, 0, s->alpha_bits, pc, at(want, x, y));
        } else {
            uint8_t col[4];
            source(x, y, col);
            tga_put_value(&one, s->bits, grey, col);
            tga_expect_value(s->bits, grey, s->alpha_bits, col, at(want, x, y));
        }
        assert_int_equal(one.n, pb);
        memcpy(values + i * pb, one.b, pb);
    }
    int crossing = 0;
    if (!rle) {
        for (size_t i = 0; i < n * pb; i++)
            put8(o, values[i]);
        return 0;
    }
    /* Greedy packets over the whole stream: a run where two or more values
     * repeat, raw otherwise; 128 at most. */
    size_t i = 0;
    while (i < n) {
        size_t run = 1;
        while (i + run < n && run < 128 && memcmp(values + i * pb, values + (i + run) * pb, pb) == 0)
            run++;
        size_t count;
        if (run >= 2) {
            count = run;
            put8(o, 0x80u | (unsigned)(count - 1));
            for (size_t k = 0; k < pb; k++)
                put8(o, values[i * pb + k]);
        } else {
            count = 1;
            while (i + count < n && count < 128 &&
                   !(i + count + 1 < n && memcmp(values + (i + count) * pb,
                                                 values + (i + count + 1) * pb, pb) == 0))
                count++;
            put8(o, (unsigned)(count - 1));
            for (size_t k = 0; k < count * pb; k++)
                put8(o, values[i * pb + k]);
        }
        if (i / (size_t)s->w != (i + count - 1) / (size_t)s->w) crossing++;
        i += count;
    }
    return crossing;
}

/* Hand-written 2x2 files: the four corners differ, so a reader taking the
 * rows (or the columns) in the wrong order fails. */
static void test_tga_origin_by_hand(void **state)
{
    (void)state;
    picture want = {.w = 2, .h = 2};
    set(&want, 0, 0, 255, 0, 0, 255);   /* top left: red */
    set(&want, 1, 0, 0, 255, 0, 255);   /* top right: green */
    set(&want, 0, 1, 0, 0, 255, 255);   /* bottom left: blue */
    set(&want, 1, 1, 255, 255, 255, 255); /* bottom right: white */
    static const unsigned char head[12] = {0, 0, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0};
    /* Bottom-left origin (descriptor 0x00): bottom row first, B G R. */
    buf f = {.n = 0};
    memcpy(f.b, head, 12), f.n = 12;
    put16(&f, 2), put16(&f, 2), put8(&f, 24), put8(&f, 0x00);
    const unsigned char bottom_first[] = {255, 0, 0, 255, 255, 255, 0, 0, 255, 0, 255, 0};
    memcpy(f.b + f.n, bottom_first, sizeof bottom_first), f.n += sizeof bottom_first;
    expect_picture("bottom-left origin", &f, "bl.tga", &want);
    /* Top-left origin (0x20): top row first. */
    f.b[17] = 0x20;
    const unsigned char top_first[] = {0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255};
    memcpy(f.b + 18, top_first, sizeof top_first);
    expect_picture("top-left origin", &f, "tl.tga", &want);
    /* Top-right origin (0x30): top row first, right to left. */
    f.b[17] = 0x30;
    const unsigned char top_right_first[] = {0, 255, 0, 0, 0, 255, 255, 255, 255, 255, 0, 0};
    memcpy(f.b + 18, top_right_first, sizeof top_right_first);
    expect_picture("top-right origin", &f, "tr.tga", &want);
    /* Bottom-right origin (0x10). */
    f.b[17] = 0x10;
    const unsigned char bottom_right_first[] = {255, 255, 255, 255, 0, 0, 0, 255, 0, 0, 0, 255};
    memcpy(f.b + 18, bottom_right_first, sizeof bottom_right_first);
    expect_picture("bottom-right origin", &f, "br.tga", &want);
}

/* A run packet of 4 pixels covering the whole first row of a 3x2 image and
 * the first pixel of the second, then a raw packet of the last 2. */
static void test_tga_rle_packet_crosses_rows(void **state)
{
    (void)state;
    static const unsigned char file[] = {
        0, 0, 10, 0, 0, 0, 0, 0, 0, 0, 0, 0, 3, 0, 2, 0, 24, 0x20,
        0x83, 1, 2, 3,              /* run of 4: R3 G2 B1 */
        0x01, 10, 20, 30, 40, 50, 60 /* raw: R30 G20 B10, R60 G50 B40 */
    };
    buf f = {.n = sizeof file};
    memcpy(f.b, file, sizeof file);
    picture want = {.w = 3, .h = 2};
    for (int x = 0; x < 3; x++)
        set(&want, x, 0, 3, 2, 1, 255);
    set(&want, 0, 1, 3, 2, 1, 255);
    set(&want, 1, 1, 30, 20, 10, 255);
    set(&want, 2, 1, 60, 50, 40, 255);
    expect_picture("RLE across rows", &f, "cross.tga", &want);
}

static void test_tga_every_variant(void **state)
{
    (void)state;
    static buf f;
    static picture want;
    static const struct {
        unsigned type, bits, alpha_bits;
    } kinds[] = {
        {2, 15, 0}, {2, 16, 0}, {2, 16, 1}, {2, 24, 0}, {2, 32, 0}, {2, 32, 8},
        {3, 8, 0},  {3, 16, 0}, {3, 16, 8},
    };
    static const unsigned cmap_bits[] = {15, 16, 24, 32};
    static const int sizes[][2] = {{1, 1}, {5, 3}, {2, 7}, {13, 4}};
    int crossing = 0, cases = 0;
    for (unsigned origin = 0; origin <= 0x30; origin += 0x10)
        for (size_t s = 0; s < sizeof sizes / sizeof sizes[0]; s++)
            for (unsigned rle = 0; rle <= 8; rle += 8) {
                for (size_t k = 0; k < sizeof kinds / sizeof kinds[0]; k++) {
                    tga_spec sp = {kinds[k].type + rle, kinds[k].bits, kinds[k].alpha_bits, origin,
                                   0, 0, (unsigned)(s * 3), sizes[s][0], sizes[s][1]};
                    for (int src = 0; src < 2; src++) {
                        crossing += tga_encode(&sp, src ? source_runs : source_colour, &f, &want);
                        char label[96];
                        snprintf(label, sizeof label, "type %u, %u bits, alpha bits %u, origin 0x%02x, %dx%d",
                                 sp.type, sp.bits, sp.alpha_bits, origin, sp.w, sp.h);
                        expect_picture(label, &f, "v.tga", &want);
                        cases++;
                    }
                }
                for (size_t c = 0; c < 4; c++)
                    for (unsigned ib = 8; ib <= 16; ib += 8)
                        for (unsigned alpha = 0; alpha <= 8; alpha += 8) {
                            tga_spec sp = {1 + rle, ib, alpha, origin, cmap_bits[c],
                                           (unsigned)c * 7, 0, sizes[s][0], sizes[s][1]};
                            crossing += tga_encode(&sp, source_colour, &f, &want);
                            char label[96];
                            snprintf(label, sizeof label,
                                     "type %u, %u-bit indices, %u-bit map from %u, alpha bits %u, origin 0x%02x, %dx%d",
                                     sp.type, ib, sp.cmap_bits, sp.cmap_first, alpha, origin,
                                     sp.w, sp.h);
                            expect_picture(label, &f, "m.tga", &want);
                            cases++;
                        }
            }
    print_message("%d TGA variants, %d RLE packets crossing a row\n", cases, crossing);
    assert_true(crossing > 50);
}

/* Without a .tga name a consistent header is still read as a TGA; the
 * ID field and a TGA 2.0 footer are skipped. */
static void test_tga_recognised_without_name(void **state)
{
    (void)state;
    static buf f;
    static picture want;
    tga_spec sp = {10, 32, 8, 0x20, 0, 0, 9, 6, 5};
    tga_encode(&sp, source_runs, &f, &want);
    /* an extension area offset, a developer directory offset, the signature */
    put32(&f, 0), put32(&f, 0);
    memcpy(f.b + f.n, "TRUEVISION-XFILE.", 18), f.n += 18;
    expect_picture("no name", &f, NULL, &want);
    expect_picture("other name", &f, "texture", &want);
    expect_picture("upper-case name", &f, "WALL.TGA", &want);
}

/* The same file through persp_image_load, by its path. */
static void test_tga_from_a_file(void **state)
{
    (void)state;
    static buf f;
    static picture want;
    tga_spec sp = {9, 8, 0, 0, 24, 0, 0, 7, 3};
    tga_encode(&sp, source_colour, &f, &want);
    char dir[256], path[300];
    assert_int_equal(test_tmpdir_make(dir, sizeof dir, "tga"), 0);
    snprintf(path, sizeof path, "%s/duck.tga", dir);
    FILE *fp = fopen(path, "wb");
    assert_non_null(fp);
    assert_int_equal(fwrite(f.b, 1, f.n, fp), f.n);
    fclose(fp);
    persp_context *ctx = test_context();
    persp_image img;
    persp_status st = persp_image_load(ctx, path, &img);
    if (st != PERSP_OK) fail_msg("%s", persp_context_error(ctx));
    for (int y = 0; y < want.h; y++)
        assert_memory_equal(img.pixels + (size_t)(want.h - 1 - y) * img.stride,
                            want.px + 4 * (size_t)(y * want.w), 4 * (size_t)want.w);
    persp_image_free(ctx, &img);
    persp_context_destroy(ctx);
    assert_int_equal(test_tmpdir_remove(dir), 0);
}

static void test_tga_malformed(void **state)
{
    (void)state;
    static buf f, g;
    static picture want;
    /* Cut anywhere: refused, named, never read past the end (ASan). */
    tga_spec sp = {10, 24, 0, 0, 0, 0, 4, 9, 4};
    tga_encode(&sp, source_runs, &f, &want);
    for (size_t cut = 0; cut < f.n; cut++) {
        persp_image img;
        persp_context *ctx = test_context();
        persp_status st = persp_image_load_memory(ctx, f.b, cut, "cut.tga", &img);
        if (st != PERSP_OK && st != PERSP_ERR_FORMAT)
            fail_msg("cut at %zu: %s", cut, status_name(st));
        if (st == PERSP_OK) fail_msg("a TGA cut to %zu of %zu bytes was accepted", cut, f.n);
        const char *msg = persp_context_error(ctx);
        if (!strstr(msg, "cut.tga: ") || !(strstr(msg, "truncated TGA") || strstr(msg, "shorter")))
            fail_msg("cut at %zu: '%s'", cut, msg);
        assert_null(img.pixels);
        persp_context_destroy(ctx);
    }
    expect_refused(f.b, 18 + 4 + 3, "short.tga", PERSP_ERR_FORMAT,
                   "truncated TGA: 3 bytes of RLE data cannot hold 9x4 pixels (at least 4 bytes)");
    /* An uncompressed file cut inside its pixels. */
    tga_spec raw = {2, 24, 0, 0, 0, 0, 0, 4, 4};
    tga_encode(&raw, source_colour, &g, &want);
    expect_refused(g.b, g.n - 1, "wall.tga", PERSP_ERR_FORMAT,
                   "truncated TGA: 47 bytes of image data, 4x4 pixels need 48");
    /* An RLE packet whose values run past the end of the file. */
    static const unsigned char rle_end[] = {0, 0, 10, 0, 0, 0, 0, 0, 0, 0, 0, 0, 2, 0, 1, 0, 24, 0,
                                            0x01, 1, 2, 3, 4, 5};
    expect_refused(rle_end, sizeof rle_end, "wall.tga", PERSP_ERR_FORMAT,
                   "RLE packet at byte 18 runs past the end of the file");
    /* An RLE packet covering more pixels than the image has left. */
    static const unsigned char rle_over[] = {0, 0, 10, 0, 0, 0, 0, 0, 0, 0, 0, 0, 2, 0, 2, 0, 24, 0,
                                             0x82, 1, 2, 3, 0x81, 4, 5, 6};
    expect_refused(rle_over, sizeof rle_over, "over.tga", PERSP_ERR_FORMAT,
                   "RLE packet at byte 22 covers 2 pixels, 1 remain");
    /* A pixel naming an entry outside the colour map (entries 4-5). */
    static const unsigned char index_out[] = {0, 1, 1, 4, 0, 2, 0, 24, 0, 0, 0, 0, 2, 0, 1, 0, 8, 0x20,
                                              1, 2, 3, 4, 5, 6, 5, 6};
    expect_refused(index_out, sizeof index_out, "map.tga", PERSP_ERR_FORMAT,
                   "pixel (1, 0) uses colour-map index 6, the map holds entries 4 to 5");
    static const unsigned char index_low[] = {0, 1, 9, 4, 0, 2, 0, 24, 0, 0, 0, 0, 2, 0, 1, 0, 8, 0,
                                              1, 2, 3, 4, 5, 6, 0x81, 3};
    expect_refused(index_low, sizeof index_low, "map.tga", PERSP_ERR_FORMAT,
                   "pixel (0, 0) uses colour-map index 3, the map holds entries 4 to 5");
    /* 65535 x 65535 in a 30-byte file: too large, refused before any
     * allocation of the image. */
    unsigned char huge[30] = {0, 0, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0xff, 0xff, 0xff, 0xff, 32, 8};
    expect_refused(huge, sizeof huge, "huge.tga", PERSP_ERR_TOO_LARGE, "65535x65535 exceeds the limit");
    expect_refused(huge, sizeof huge, "huge", PERSP_ERR_TOO_LARGE, "exceeds the limit");
    /* Within the limits but far more pixels than a 30-byte file holds. */
    huge[12] = 0x00, huge[13] = 0x40, huge[14] = 0x00, huge[15] = 0x10; /* 16384 x 4096 */
    expect_refused(huge, sizeof huge, "big.tga", PERSP_ERR_FORMAT, "truncated TGA");
    huge[2] = 10;
    expect_refused(huge, sizeof huge, "big.tga", PERSP_ERR_FORMAT, "truncated TGA");
    /* Zero width. */
    unsigned char zero[24] = {0, 0, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 24, 0};
    expect_refused(zero, sizeof zero, "zero.tga", PERSP_ERR_FORMAT, "empty size");
    /* Headers that are not TGA headers, named .tga. */
    unsigned char h[24] = {0, 0, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 1, 0, 24, 0, 1, 2, 3};
    h[2] = 0;
    expect_refused(h, sizeof h, "t0.tga", PERSP_ERR_FORMAT, "no image data (image type 0)");
    h[2] = 4;
    expect_refused(h, sizeof h, "t4.tga", PERSP_ERR_FORMAT, "image type is not 1, 2, 3, 9, 10 or 11");
    h[2] = 2, h[16] = 8;
    expect_refused(h, sizeof h, "d8.tga", PERSP_ERR_FORMAT, "not 15, 16, 24 or 32 bits");
    h[2] = 1, h[16] = 8;
    expect_refused(h, sizeof h, "nomap.tga", PERSP_ERR_FORMAT, "colour-mapped image has no colour map");
    h[1] = 2;
    expect_refused(h, sizeof h, "ct2.tga", PERSP_ERR_FORMAT, "colour-map type is neither 0 nor 1");
    h[1] = 0, h[2] = 2, h[16] = 24, h[17] = 0x40;
    expect_refused(h, sizeof h, "il.tga", PERSP_ERR_UNSUPPORTED, "interleaved");
    /* ...and without the name: nothing persp reads. */
    expect_refused(h, sizeof h, "il", PERSP_ERR_FORMAT, "not an image persp reads");
    h[17] = 0, h[5] = 3; /* colour-map length without a colour map */
    expect_refused(h, sizeof h, "junk", PERSP_ERR_FORMAT, "not an image persp reads");
    h[5] = 0;
    expect_refused(h, 17, "junk", PERSP_ERR_FORMAT, "not an image persp reads");
    expect_refused("", 0, "empty.tga", PERSP_ERR_FORMAT, "shorter than the 18-byte header");
}

/* -------------------------------------------------------------- BMP */

typedef struct bmp_spec {
    unsigned header;      /* 12, 40, 56, 108, 124 */
    unsigned bits;
    unsigned compression; /* 0 BI_RGB, 3 BI_BITFIELDS, 6 BI_ALPHABITFIELDS */
    int w, h, top_down;
    uint32_t masks[4];    /* BI_BITFIELDS, or the alpha mask of a V4/V5 header */
    unsigned colours;     /* biClrUsed; 0: 2^bits */
} bmp_spec;

static unsigned mask_shift(uint32_t m)
{
    unsigned s = 0;
    while (m && !(m >> s & 1u))
        s++;
    return s;
}

static void bmp_palette_colour(int i, uint8_t *o)
{
    source_colour(i * 3 + 1, i * 5 + 4, o);
    o[3] = 255;
}

/* Packs one channel into its mask and says what a reader gets back. */
static uint32_t pack(uint32_t mask, uint8_t v, uint8_t *back, uint8_t absent)
{
    if (!mask) {
        *back = absent;
        return 0;
    }
    const unsigned s = mask_shift(mask);
    const uint32_t max = mask >> s;
    const uint32_t q = (uint32_t)lround((double)v * (double)max / 255.0);
    *back = (uint8_t)lround((double)q * 255.0 / (double)max);
    return q << s;
}

static void bmp_encode(const bmp_spec *s, buf *o, picture *want)
{
    const int core = s->header == 12;
    const int fields_after = s->header == 40 && (s->compression == 3 || s->compression == 6);
    const unsigned nmasks = s->compression == 6 ? 4 : 3;
    const unsigned ncolours = s->bits <= 8 ? (s->colours ? s->colours : 1u << s->bits) : 0;
    const unsigned entry = core ? 3 : 4;
    const size_t row = ((size_t)s->w * s->bits + 31) / 32 * 4;
    const uint32_t offset = 14 + s->header + (fields_after ? 4 * nmasks : 0) + ncolours * entry;
    o->n = 0;
    want->w = s->w, want->h = s->h;
    put8(o, 'B'), put8(o, 'M');
    put32(o, offset + (uint32_t)(row * (size_t)s->h));
    put32(o, 0);
    put32(o, offset);
    put32(o, s->header);
    if (core) {
        put16(o, (unsigned)s->w), put16(o, (unsigned)s->h), put16(o, 1), put16(o, s->bits);
    } else {
        put32(o, (uint32_t)s->w);
        put32(o, (uint32_t)(s->top_down ? -s->h : s->h));
        put16(o, 1), put16(o, s->bits);
        put32(o, s->compression);
        put32(o, (uint32_t)(row * (size_t)s->h));
        put32(o, 2835), put32(o, 2835);
        put32(o, s->colours), put32(o, 0);
        if (s->header >= 56) {
            for (int i = 0; i < 4; i++)
                put32(o, s->masks[i]);
            while (o->n < 14 + s->header)
                put8(o, o->n == 14 + 56 ? 's' : 0);
        }
        if (fields_after)
            for (unsigned i = 0; i < nmasks; i++)
                put32(o, s->masks[i]);
    }
    for (unsigned i = 0; i < ncolours; i++) {
        uint8_t c[4];
        bmp_palette_colour((int)i, c);
        put8(o, c[2]), put8(o, c[1]), put8(o, c[0]);
        if (!core) put8(o, 0);
    }
    assert_int_equal(o->n, offset);
    /* Which masks the pixels use: the given ones with BI_BITFIELDS, else
     * BI_RGB's 5-5-5 or 8-8-8, plus the header's alpha mask at 32 bits. */
    uint32_t m[4] = {s->masks[0], s->masks[1], s->masks[2], 0};
    if (s->compression == 0 && s->bits == 16) m[0] = 0x7c00, m[1] = 0x3e0, m[2] = 0x1f;
    if (s->compression == 0 && s->bits == 32) m[0] = 0xff0000, m[1] = 0xff00, m[2] = 0xff;
    if (s->compression == 6 || (s->header >= 56 && (s->compression == 3 || s->bits == 32)))
        m[3] = s->masks[3];
    for (int r = 0; r < s->h; r++) {
        const int y = s->top_down ? r : s->h - 1 - r; /* from the top */
        const size_t start = o->n;
        unsigned acc = 0, nbits = 0;
        for (int x = 0; x < s->w; x++) {
            uint8_t *w = at(want, x, y);
            if (s->bits <= 8) {
                const int k = palette_index(x, y) % (int)ncolours;
                bmp_palette_colour(k, w);
                acc = acc << s->bits | (unsigned)k, nbits += s->bits;
                if (nbits == 8) put8(o, acc), acc = 0, nbits = 0;
            } else if (s->bits == 24) {
                uint8_t c[4];
                source_colour(x, y, c);
                put8(o, c[2]), put8(o, c[1]), put8(o, c[0]);
                set(want, x, y, c[0], c[1], c[2], 255);
            } else {
                uint8_t c[4];
                source_colour(x, y, c);
                uint32_t v = pack(m[0], c[0], &w[0], 0) | pack(m[1], c[1], &w[1], 0) |
                             pack(m[2], c[2], &w[2], 0) | pack(m[3], c[3], &w[3], 255);
                if (s->bits == 16) {
                    put16(o, v);
                } else {
                    /* BI_RGB's fourth byte is unused: garbage there must
                     * not become alpha. */
                    if (!m[3]) v |= 0x5a000000u & ~(m[0] | m[1] | m[2]);
                    put32(o, v);
                }
            }
        }
        if (nbits) put8(o, acc << (8 - nbits));
        while (o->n - start < row)
            put8(o, 0xee); /* padding, to 4 bytes */
    }
}

/* Hand-written 2x2 24-bit files, bottom-up and top-down. */
static void test_bmp_rows_by_hand(void **state)
{
    (void)state;
    picture want = {.w = 2, .h = 2};
    set(&want, 0, 0, 255, 0, 0, 255);
    set(&want, 1, 0, 0, 255, 0, 255);
    set(&want, 0, 1, 0, 0, 255, 255);
    set(&want, 1, 1, 255, 255, 255, 255);
    static buf f;
    f.n = 0;
    put8(&f, 'B'), put8(&f, 'M'), put32(&f, 70), put32(&f, 0), put32(&f, 54);
    put32(&f, 40), put32(&f, 2), put32(&f, 2), put16(&f, 1), put16(&f, 24), put32(&f, 0);
    put32(&f, 16), put32(&f, 0), put32(&f, 0), put32(&f, 0), put32(&f, 0);
    /* bottom row first: blue, white, 2 bytes of padding; then red, green */
    const unsigned char bottom_up[] = {255, 0, 0, 255, 255, 255, 0, 0, 0, 0, 255, 0, 255, 0, 0, 0};
    memcpy(f.b + f.n, bottom_up, sizeof bottom_up), f.n += sizeof bottom_up;
    expect_picture("bottom-up BMP", &f, "up.bmp", &want);
    /* biHeight -2: top row first */
    f.b[22] = 0xfe, f.b[23] = f.b[24] = f.b[25] = 0xff;
    const unsigned char top_down[] = {0, 0, 255, 0, 255, 0, 0, 0, 255, 0, 0, 255, 255, 255, 0, 0};
    memcpy(f.b + 54, top_down, sizeof top_down);
    expect_picture("top-down BMP", &f, "down.bmp", &want);
}

static void test_bmp_every_variant(void **state)
{
    (void)state;
    static buf f;
    static picture want;
    static const int sizes[][2] = {{1, 1}, {5, 3}, {3, 6}, {13, 4}, {33, 2}};
    int cases = 0;
    for (size_t s = 0; s < sizeof sizes / sizeof sizes[0]; s++)
        for (int td = 0; td < 2; td++) {
            const int w = sizes[s][0], h = sizes[s][1];
            bmp_spec specs[] = {
                {40, 1, 0, w, h, td, {0}, 0},
                {40, 2, 0, w, h, td, {0}, 0},
                {40, 4, 0, w, h, td, {0}, 0},
                {40, 4, 0, w, h, td, {0}, 5},
                {40, 8, 0, w, h, td, {0}, 0},
                {40, 8, 0, w, h, td, {0}, 6},
                {124, 8, 0, w, h, td, {0}, 6},
                {40, 16, 0, w, h, td, {0}, 0},                                   /* 5-5-5 */
                {40, 16, 3, w, h, td, {0xf800, 0x07e0, 0x001f, 0}, 0},           /* 5-6-5 */
                {108, 16, 3, w, h, td, {0x0f00, 0x00f0, 0x000f, 0xf000}, 0},     /* 4-4-4-4 */
                {56, 16, 3, w, h, td, {0x7c00, 0x03e0, 0x001f, 0x8000}, 0},      /* 1-5-5-5 */
                {40, 16, 6, w, h, td, {0x001f, 0x07e0, 0xf800, 0}, 0},           /* B-G-R order */
                {40, 24, 0, w, h, td, {0}, 0},
                {124, 24, 0, w, h, td, {0}, 0},
                {40, 32, 0, w, h, td, {0}, 0},
                {124, 32, 0, w, h, td, {0, 0, 0, 0xff000000u}, 0},               /* BI_RGB + alpha mask */
                {124, 32, 0, w, h, td, {0, 0, 0, 0}, 0},
                {40, 32, 3, w, h, td, {0xff0000, 0xff00, 0xff, 0}, 0},
                {40, 32, 3, w, h, td, {0x3ff00000, 0xffc00, 0x3ff, 0}, 0},       /* 10-10-10 */
                {124, 32, 3, w, h, td, {0xff000000u, 0xff0000, 0xff00, 0xff}, 0},/* RGBA */
                {40, 32, 6, w, h, td, {0xff, 0xff00, 0xff0000, 0xff000000u}, 0},
                {12, 1, 0, w, h, 0, {0}, 0},
                {12, 4, 0, w, h, 0, {0}, 0},
                {12, 8, 0, w, h, 0, {0}, 0},
                {12, 24, 0, w, h, 0, {0}, 0},
            };
            for (size_t k = 0; k < sizeof specs / sizeof specs[0]; k++) {
                if (specs[k].header == 12 && td) continue;
                bmp_encode(&specs[k], &f, &want);
                char label[96];
                snprintf(label, sizeof label, "header %u, %u bits, compression %u, %s, %dx%d",
                         specs[k].header, specs[k].bits, specs[k].compression,
                         td ? "top-down" : "bottom-up", w, h);
                expect_picture(label, &f, "v.bmp", &want);
                cases++;
            }
        }
    print_message("%d BMP variants\n", cases);
}

static void bmp_rle_file(buf *f, unsigned bits, int w, int h, const unsigned char *rle, size_t n,
                         unsigned colours)
{
    f->n = 0;
    const uint32_t offset = 54 + 4 * colours;
    put8(f, 'B'), put8(f, 'M'), put32(f, offset + (uint32_t)n), put32(f, 0), put32(f, offset);
    put32(f, 40), put32(f, (uint32_t)w), put32(f, (uint32_t)h), put16(f, 1), put16(f, bits);
    put32(f, bits == 8 ? 1 : 2), put32(f, (uint32_t)n), put32(f, 0), put32(f, 0);
    put32(f, colours), put32(f, 0);
    for (unsigned i = 0; i < colours; i++) {
        uint8_t c[4];
        bmp_palette_colour((int)i, c);
        put8(f, c[2]), put8(f, c[1]), put8(f, c[0]), put8(f, 0);
    }
    memcpy(f->b + f->n, rle, n), f->n += n;
}

static void set_index(picture *p, int x, int y_top, int i)
{
    bmp_palette_colour(i, at(p, x, y_top));
}

/* BI_RLE8 and BI_RLE4, written by hand: runs, stored sequences of odd
 * length (padded to 16 bits), a delta, an early end of row, the end of the
 * bitmap before the last row. Skipped pixels are transparent black. */
static void test_bmp_rle(void **state)
{
    (void)state;
    static buf f;
    static picture want;
    want.w = 5, want.h = 4;
    memset(want.px, 0, sizeof want.px);
    /* RLE8, 5x4, rows bottom-up */
    static const unsigned char r8[] = {
        2, 1, 0, 3, 2, 3, 4, 0,  /* row 0 (bottom): 1 1 | 2 3 4 (+pad) */
        0, 0,                    /* end of row */
        0, 2, 1, 1,              /* delta: right 1, up 1 -> (1, 2) */
        4, 5,                    /* row 2: x 1-4 = 5 */
        0, 0,                    /* end of row -> row 3 */
        0, 3, 7, 6, 5, 0,        /* row 3: 7 6 5 (+pad) */
        0, 1,                    /* end of bitmap */
    };
    /* from the top: row 3 of the file is y 0 */
    set_index(&want, 0, 0, 7), set_index(&want, 1, 0, 6), set_index(&want, 2, 0, 5);
    for (int x = 1; x < 5; x++)
        set_index(&want, x, 1, 5);
    set_index(&want, 0, 3, 1), set_index(&want, 1, 3, 1);
    set_index(&want, 2, 3, 2), set_index(&want, 3, 3, 3), set_index(&want, 4, 3, 4);
    bmp_rle_file(&f, 8, 5, 4, r8, sizeof r8, 8);
    expect_picture("RLE8", &f, "rle8.bmp", &want);

    /* RLE4, 7x3 */
    want.w = 7, want.h = 3;
    memset(want.px, 0, sizeof want.px);
    static const unsigned char r4[] = {
        4, 0x12,                 /* row 0: 1 2 1 2 */
        0, 3, 0x34, 0x50,        /* stored 3: 3 4 5 (2 bytes, already 16-bit aligned) */
        0, 0,                    /* end of row */
        7, 0x66,                 /* row 1: 6 x7 */
        0, 0,
        0, 5, 0x01, 0x23, 0x40, 0, /* row 2: 0 1 2 3 4 (3 bytes + pad) */
        0, 1,
    };
    const int row0[] = {1, 2, 1, 2, 3, 4, 5}, row2[] = {0, 1, 2, 3, 4};
    for (int x = 0; x < 7; x++)
        set_index(&want, x, 2, row0[x]), set_index(&want, x, 1, 6);
    for (int x = 0; x < 5; x++)
        set_index(&want, x, 0, row2[x]);
    bmp_rle_file(&f, 4, 7, 3, r4, sizeof r4, 7);
    expect_picture("RLE4", &f, "rle4.bmp", &want);
    /* The last end-of-row may end the data without an end-of-bitmap. */
    static const unsigned char noend[] = {7, 0x66, 0, 0, 7, 0x66, 0, 0, 7, 0x66, 0, 0};
    for (int y = 0; y < 3; y++)
        for (int x = 0; x < 7; x++)
            set_index(&want, x, y, 6);
    bmp_rle_file(&f, 4, 7, 3, noend, sizeof noend, 7);
    expect_picture("RLE4 without end of bitmap", &f, "rle4.bmp", &want);

    /* Malformed RLE */
    static const unsigned char over[] = {6, 1, 0, 1};
    bmp_rle_file(&f, 8, 5, 1, over, sizeof over, 2);
    expect_refused(f.b, f.n, "over.bmp", PERSP_ERR_FORMAT, "RLE run at byte 62 runs past the end of its row");
    static const unsigned char seq_over[] = {0, 6, 1, 1, 1, 1, 1, 1, 0, 1};
    bmp_rle_file(&f, 8, 5, 1, seq_over, sizeof seq_over, 2);
    expect_refused(f.b, f.n, "over.bmp", PERSP_ERR_FORMAT, "RLE sequence at byte 62 runs past the end of its row");
    static const unsigned char seq_cut[] = {0, 4, 1, 1};
    bmp_rle_file(&f, 8, 5, 1, seq_cut, sizeof seq_cut, 2);
    expect_refused(f.b, f.n, "cut.bmp", PERSP_ERR_FORMAT, "RLE sequence at byte 62 runs past the end of the file");
    static const unsigned char delta_out[] = {0, 2, 0, 2, 0, 1};
    bmp_rle_file(&f, 8, 5, 1, delta_out, sizeof delta_out, 2);
    expect_refused(f.b, f.n, "delta.bmp", PERSP_ERR_FORMAT, "RLE delta at byte 62 moves out of the image");
    static const unsigned char delta_right[] = {0, 2, 6, 0, 0, 1};
    bmp_rle_file(&f, 8, 5, 1, delta_right, sizeof delta_right, 2);
    expect_refused(f.b, f.n, "delta.bmp", PERSP_ERR_FORMAT, "RLE delta at byte 62 moves out of the image");
    static const unsigned char unended[] = {5, 1, 0, 0, 2, 1};
    bmp_rle_file(&f, 8, 5, 2, unended, sizeof unended, 2);
    expect_refused(f.b, f.n, "end.bmp", PERSP_ERR_FORMAT, "RLE data ends in row 0 of 2");
    static const unsigned char past_top[] = {5, 1, 0, 0, 0, 0, 0, 1};
    bmp_rle_file(&f, 8, 5, 1, past_top, sizeof past_top, 2);
    expect_refused(f.b, f.n, "top.bmp", PERSP_ERR_FORMAT, "goes past the top row");
    static const unsigned char bad_index[] = {3, 1, 2, 7, 0, 1};
    bmp_rle_file(&f, 8, 5, 1, bad_index, sizeof bad_index, 2);
    expect_refused(f.b, f.n, "pal.bmp", PERSP_ERR_FORMAT, "pixel (3, 0) uses palette index 7, the palette has 2 entries");
    static const unsigned char bad_nibble[] = {3, 0x10, 0, 1};
    bmp_rle_file(&f, 4, 5, 1, bad_nibble, sizeof bad_nibble, 1);
    expect_refused(f.b, f.n, "pal.bmp", PERSP_ERR_FORMAT, "pixel (0, 0) uses palette index 1, the palette has 1 entries");
    /* top-down and compressed */
    static const unsigned char ok[] = {5, 1, 0, 1};
    bmp_rle_file(&f, 8, 5, 1, ok, sizeof ok, 2);
    f.b[22] = 0xff, f.b[23] = f.b[24] = f.b[25] = 0xff;
    expect_refused(f.b, f.n, "td.bmp", PERSP_ERR_FORMAT, "top-down bitmap (negative height) is RLE-compressed");
}

static void test_bmp_malformed(void **state)
{
    (void)state;
    static buf f;
    static picture want;
    /* Cut anywhere (here into the pixels, the last row's padding aside). */
    bmp_spec sp = {40, 24, 0, 5, 3, 0, {0}, 0};
    bmp_encode(&sp, &f, &want);
    for (size_t cut = 0; cut + 1 < f.n; cut++) {
        persp_context *ctx = test_context();
        persp_image img;
        persp_status st = persp_image_load_memory(ctx, f.b, cut, "cut.bmp", &img);
        const char *msg = persp_context_error(ctx);
        /* only the last row's padding (1 byte at width 5) may be missing */
        if (st == PERSP_OK) fail_msg("a BMP cut to %zu of %zu bytes was accepted", cut, f.n);
        if (st != PERSP_OK && !strstr(msg, "cut.bmp: ")) fail_msg("cut %zu: '%s'", cut, msg);
        if (st != PERSP_OK && cut >= 2 && !strstr(msg, "truncated BMP"))
            fail_msg("cut %zu: '%s'", cut, msg);
        assert_true(st == PERSP_OK || img.pixels == NULL);
        persp_image_free(ctx, &img);
        persp_context_destroy(ctx);
    }
    expect_refused(f.b, f.n - 2, "wall.bmp", PERSP_ERR_FORMAT,
                   "truncated BMP: 5x3 pixels of 24 bits need 47 bytes, 46 remain");
    /* The last row's padding may be missing. */
    buf g = f;
    g.n = f.n - 1;
    expect_picture("no last padding", &g, "pad.bmp", &want);

    /* 65535 x 65535 in 30 bytes (a core header): too large, refused before
     * any allocation. */
    static const unsigned char huge[30] = {'B', 'M', 30, 0, 0, 0, 0, 0, 0, 0, 26, 0, 0, 0,
                                           12, 0, 0, 0, 0xff, 0xff, 0xff, 0xff, 1, 0, 24, 0};
    expect_refused(huge, sizeof huge, "huge.bmp", PERSP_ERR_TOO_LARGE, "65535x65535 exceeds the limit");
    /* Within the limits, but the pixels are not in the file. */
    unsigned char big[30];
    memcpy(big, huge, 30);
    big[18] = 0x00, big[19] = 0x40, big[20] = 0x00, big[21] = 0x10;
    expect_refused(big, sizeof big, "big.bmp", PERSP_ERR_FORMAT, "truncated BMP");
    /* A negative height of -2^31, and 2^31 - 1 */
    bmp_spec one = {40, 24, 0, 1, 1, 0, {0}, 0};
    bmp_encode(&one, &f, &want);
    f.b[22] = 0, f.b[23] = 0, f.b[24] = 0, f.b[25] = 0x80;
    expect_refused(f.b, f.n, "min.bmp", PERSP_ERR_TOO_LARGE, "exceeds the limit");
    f.b[22] = 0xff, f.b[23] = 0xff, f.b[24] = 0xff, f.b[25] = 0x7f;
    expect_refused(f.b, f.n, "max.bmp", PERSP_ERR_TOO_LARGE, "exceeds the limit");
    /* Zero width, negative width, zero height. */
    bmp_encode(&one, &f, &want);
    f.b[18] = 0;
    expect_refused(f.b, f.n, "zero.bmp", PERSP_ERR_FORMAT, "width 0");
    f.b[18] = 0xff, f.b[19] = 0xff, f.b[20] = 0xff, f.b[21] = 0xff;
    expect_refused(f.b, f.n, "neg.bmp", PERSP_ERR_FORMAT, "width -1");
    bmp_encode(&one, &f, &want);
    f.b[22] = 0;
    expect_refused(f.b, f.n, "zero.bmp", PERSP_ERR_FORMAT, "empty size 1x0");
    /* A palette index past the palette (biClrUsed 2, indices up to 5). */
    bmp_spec pal = {40, 8, 0, 4, 2, 0, {0}, 6};
    bmp_encode(&pal, &f, &want);
    f.b[46] = 2; /* biClrUsed */
    expect_refused(f.b, f.n, "pal.bmp", PERSP_ERR_FORMAT, "uses palette index 2, the palette has 2 entries");
    /* Valid, but not read by persp. */
    bmp_encode(&one, &f, &want);
    f.b[30] = 4;
    expect_refused(f.b, f.n, "jpeg.bmp", PERSP_ERR_UNSUPPORTED, "unsupported BMP: JPEG compression");
    f.b[30] = 5;
    expect_refused(f.b, f.n, "png.bmp", PERSP_ERR_UNSUPPORTED, "unsupported BMP: PNG compression");
    f.b[30] = 11;
    expect_refused(f.b, f.n, "cmyk.bmp", PERSP_ERR_UNSUPPORTED, "unsupported BMP: compression 11");
    f.b[30] = 0, f.b[28] = 64;
    expect_refused(f.b, f.n, "deep.bmp", PERSP_ERR_UNSUPPORTED, "64 bits a pixel");
    f.b[28] = 24, f.b[14] = 64;
    expect_refused(f.b, f.n, "os2.bmp", PERSP_ERR_UNSUPPORTED, "OS/2 2.x");
    /* Invalid headers. */
    f.b[14] = 41;
    expect_refused(f.b, f.n, "hs.bmp", PERSP_ERR_FORMAT, "unknown header size 41");
    f.b[14] = 40, f.b[30] = 1;
    expect_refused(f.b, f.n, "rle.bmp", PERSP_ERR_FORMAT, "24 bits a pixel with compression 1");
    f.b[30] = 0, f.b[10] = 20;
    expect_refused(f.b, f.n, "off.bmp", PERSP_ERR_FORMAT, "pixel data offset 20 lies inside the headers");
    f.b[10] = 200;
    expect_refused(f.b, f.n, "off.bmp", PERSP_ERR_FORMAT, "pixel data starts at byte 200");
    bmp_spec bf = {40, 16, 3, 2, 2, 0, {0xf00f, 0x0ff0, 0, 0}, 0};
    bmp_encode(&bf, &f, &want);
    expect_refused(f.b, f.n, "mask.bmp", PERSP_ERR_FORMAT, "the red mask 0x0000f00f is not one run of bits");
    bmp_spec wide = {40, 16, 3, 2, 2, 0, {0x1f0000, 0x07e0, 0x1f, 0}, 0};
    bmp_encode(&wide, &f, &want);
    expect_refused(f.b, f.n, "mask.bmp", PERSP_ERR_FORMAT, "within a 16-bit pixel");
    /* The masks after a 40-byte header are not pixels. */
    bmp_spec fields = {40, 32, 3, 1, 1, 0, {0xff0000, 0xff00, 0xff, 0}, 0};
    bmp_encode(&fields, &f, &want);
    f.b[10] = 54;
    expect_refused(f.b, f.n, "fields.bmp", PERSP_ERR_FORMAT, "pixel data offset 54 lies inside the headers");
    expect_refused("BM", 2, "bm.bmp", PERSP_ERR_FORMAT, "truncated BMP: the file ends inside its headers");
}

/* The files persp does not read keep their message, now naming all four. */
static void test_not_an_image(void **state)
{
    (void)state;
    static const char text[] = "This is a text file.\n";
    expect_refused(text, sizeof text - 1, "notes.bmp", PERSP_ERR_FORMAT,
                   "not an image persp reads");
    expect_refused(text, 1, "notes.png", PERSP_ERR_FORMAT, "not an image persp reads");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_tga_origin_by_hand),
        cmocka_unit_test(test_tga_rle_packet_crosses_rows),
        cmocka_unit_test(test_tga_every_variant),
        cmocka_unit_test(test_tga_recognised_without_name),
        cmocka_unit_test(test_tga_from_a_file),
        cmocka_unit_test(test_tga_malformed),
        cmocka_unit_test(test_bmp_rows_by_hand),
        cmocka_unit_test(test_bmp_every_variant),
        cmocka_unit_test(test_bmp_rle),
        cmocka_unit_test(test_bmp_malformed),
        cmocka_unit_test(test_not_an_image),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
