/*
 * GIF, Netpbm and Radiance HDR textures (src/image/pnm.c, stb.c).
 *
 * The files are written here from the format descriptions (GIF89a's
 * "Appendix F" LZW with a clear code often enough that codes stay 9 bits
 * wide; Netpbm's pbm(5), pgm(5), ppm(5); Radiance's RGBE picture format
 * with flat scanlines), each from a known picture that every decoded pixel
 * is compared with. Malformed and oversized files must be refused with a
 * message naming the file, leaving the image empty; a glTF embedding a GIF
 * gets its texture from the same decoder.
 */
#include "support.h"

#include "core/internal.h"
#include "geom/scene.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct buf {
    unsigned char b[1 << 16];
    size_t n;
} buf;

static void put8(buf *o, unsigned v)
{
    assert_true(o->n < sizeof o->b);
    o->b[o->n++] = (unsigned char)v;
}

static void puts_(buf *o, const char *s)
{
    while (*s) put8(o, (unsigned char)*s++);
}

/* The picture: 5 × 3, top row first, RGB; distinct colours. */
#define PW 5
#define PH 3
static void picture_rgb(int x, int y_top, unsigned c[3])
{
    c[0] = (unsigned)(x * 50 + 10), c[1] = (unsigned)(y_top * 100 + 20), c[2] = (unsigned)((x + y_top) % 2 ? 200 : 30);
}

/* Pixel (x, y_top) of img, whose row 0 is the bottom. */
static const uint8_t *pixel(const persp_image *img, int x, int y_top)
{
    return img->pixels + (size_t)(img->height - 1 - y_top) * img->stride + 4 * (size_t)x;
}

static void expect_pixel(const persp_image *img, int x, int y, unsigned r, unsigned g, unsigned b, int tol,
                         const char *what)
{
    const uint8_t *p = pixel(img, x, y);
    if (abs((int)p[0] - (int)r) > tol || abs((int)p[1] - (int)g) > tol || abs((int)p[2] - (int)b) > tol ||
        p[3] != 255)
        fail_msg("%s: pixel (%d, %d) is (%d, %d, %d, %d), the picture's (%u, %u, %u, 255)", what, x, y, p[0], p[1],
                 p[2], p[3], r, g, b);
}

static void load(persp_context *ctx, const buf *o, const char *name, persp_image *img)
{
    if (persp_image_load_memory(ctx, o->b, o->n, name, img) != PERSP_OK)
        fail_msg("%s: %s", name, persp_context_error(ctx));
}

static void expect_refused(persp_context *ctx, const buf *o, const char *name, persp_status want,
                           const char *text)
{
    persp_image img;
    memset(&img, 0xab, sizeof img);
    persp_status st = persp_image_load_memory(ctx, o->b, o->n, name, &img);
    if (st != want) fail_msg("%s: status %d, want %d (%s)", name, (int)st, (int)want, persp_context_error(ctx));
    const char *e = persp_context_error(ctx);
    if (strncmp(e, name, strlen(name)) != 0 || !strstr(e, text))
        fail_msg("%s: message '%s' does not name the file and say '%s'", name, e, text);
    assert_null(img.pixels);
    assert_int_equal(img.width, 0);
}

/* ------------------------------------------------------------- Netpbm */

/* The picture as P<kind> with maximum value maxval (scaled down from 255). */
static void write_pnm(buf *o, int kind, unsigned maxval)
{
    char head[128];
    snprintf(head, sizeof head, "P%d\n# made by the test\n%d %d\n", kind, PW, PH);
    puts_(o, head);
    if (kind != 1 && kind != 4) {
        snprintf(head, sizeof head, "%u\n", maxval);
        puts_(o, head);
    }
    for (int y = 0; y < PH; y++) {
        unsigned bits = 0;
        int nbits = 0;
        for (int x = 0; x < PW; x++) {
            unsigned c[3];
            picture_rgb(x, y, c);
            const unsigned grey = c[0];
            const unsigned black = c[2] == 200; /* the bitmap's 1s */
            const unsigned v[3] = {c[0] * maxval / 255, c[1] * maxval / 255, c[2] * maxval / 255};
            char t[64];
            switch (kind) {
            case 1: snprintf(t, sizeof t, "%u", black), puts_(o, t); break; /* no separators: allowed */
            case 2: snprintf(t, sizeof t, "%u ", grey * maxval / 255), puts_(o, t); break;
            case 3: snprintf(t, sizeof t, "%u %u %u\n", v[0], v[1], v[2]), puts_(o, t); break;
            case 4:
                bits = bits << 1 | black, nbits++;
                break;
            case 5:
            case 6:
                for (int k = 0; k < (kind == 6 ? 3 : 1); k++) {
                    if (maxval > 255) put8(o, v[k] >> 8);
                    put8(o, v[k] & 255u);
                }
                break;
            }
        }
        if (kind == 4) put8(o, bits << (8 - nbits));
        if (kind <= 3) put8(o, '\n');
    }
}

static void test_pnm_every_kind(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    static const unsigned maxvals[] = {255, 7, 1000, 65535};
    for (int kind = 1; kind <= 6; kind++)
        for (size_t m = 0; m < sizeof maxvals / sizeof maxvals[0]; m++) {
            if ((kind == 1 || kind == 4) && m > 0) continue;
            static buf o;
            o.n = 0;
            write_pnm(&o, kind, maxvals[m]);
            char name[32];
            snprintf(name, sizeof name, "p%d-%u.pnm", kind, maxvals[m]);
            persp_image img;
            load(ctx, &o, name, &img);
            assert_int_equal(img.width, PW);
            assert_int_equal(img.height, PH);
            for (int y = 0; y < PH; y++)
                for (int x = 0; x < PW; x++) {
                    unsigned c[3];
                    picture_rgb(x, y, c);
                    const unsigned mv = maxvals[m];
                    /* What the file holds, scaled back to 0..255. */
                    unsigned want[3];
                    for (int k = 0; k < 3; k++) want[k] = (c[k] * mv / 255 * 255 + mv / 2) / mv;
                    if (kind == 1 || kind == 4)
                        want[0] = want[1] = want[2] = c[2] == 200 ? 0u : 255u;
                    else if (kind == 2 || kind == 5)
                        want[1] = want[2] = want[0];
                    expect_pixel(&img, x, y, want[0], want[1], want[2], 0, name);
                }
            persp_image_free(ctx, &img);
        }
    persp_context_destroy(ctx);
}

static void test_pnm_malformed(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    static buf o;
    o.n = 0;
    write_pnm(&o, 6, 1000);
    o.n -= 4;
    expect_refused(ctx, &o, "cut.ppm", PERSP_ERR_FORMAT, "raster ends at row 2 of 3");
    o.n = 0;
    puts_(&o, "P3\n1 1\n15\n1 2 16\n");
    expect_refused(ctx, &o, "over.ppm", PERSP_ERR_FORMAT, "over the maximum value 15");
    o.n = 0;
    puts_(&o, "P2\n2 1\n255\n1 x\n");
    expect_refused(ctx, &o, "word.pgm", PERSP_ERR_FORMAT, "non-number at pixel (1, 0)");
    o.n = 0;
    puts_(&o, "P5\n8000 8000\n255\n\1\2\3");
    expect_refused(ctx, &o, "huge.pgm", PERSP_ERR_FORMAT, "more than the file holds");
    o.n = 0;
    puts_(&o, "P6\n99999 2\n255\n");
    expect_refused(ctx, &o, "wide.ppm", PERSP_ERR_TOO_LARGE, "");
    o.n = 0;
    puts_(&o, "P2\n2 2\n0\n0 0 0 0\n");
    expect_refused(ctx, &o, "zero.pgm", PERSP_ERR_FORMAT, "maximum value in 1..65535");
    o.n = 0;
    puts_(&o, "P1\n2\n");
    expect_refused(ctx, &o, "short.pbm", PERSP_ERR_FORMAT, "without its width and height");
    persp_context_destroy(ctx);
}

/* ---------------------------------------------------------------- GIF */

typedef struct bits_out {
    buf *o;
    unsigned char block[255];
    int nblock;
    uint32_t acc;
    int nacc;
} bits_out;

static void flush_block(bits_out *b)
{
    if (!b->nblock) return;
    put8(b->o, (unsigned)b->nblock);
    for (int i = 0; i < b->nblock; i++) put8(b->o, b->block[i]);
    b->nblock = 0;
}

static void put_code(bits_out *b, unsigned code, int width)
{
    b->acc |= (uint32_t)code << b->nacc; /* least significant bit first (GIF89a Appendix F) */
    b->nacc += width;
    while (b->nacc >= 8) {
        b->block[b->nblock++] = (unsigned char)(b->acc & 255u);
        if (b->nblock == 255) flush_block(b);
        b->acc >>= 8, b->nacc -= 8;
    }
}

/* An image block of indices (w × h, top row first) with 8-bit codes sent
 * as literals: a clear code before every 254 of them keeps the table from
 * growing past 9-bit codes. */
static void gif_image(buf *o, int left, int top, int w, int h, const unsigned char *idx)
{
    put8(o, 0x2c);
    const unsigned v[4] = {(unsigned)left, (unsigned)top, (unsigned)w, (unsigned)h};
    for (int k = 0; k < 4; k++) put8(o, v[k] & 255u), put8(o, v[k] >> 8);
    put8(o, 0);    /* no local colour table, not interlaced */
    put8(o, 8);    /* LZW minimum code size */
    bits_out b = {o, {0}, 0, 0, 0};
    for (int i = 0; i < w * h; i++) {
        if (i % 254 == 0) put_code(&b, 256, 9);
        put_code(&b, idx[i], 9);
    }
    put_code(&b, 257, 9);
    if (b.nacc) put_code(&b, 0, 8 - b.nacc);
    flush_block(&b);
    put8(o, 0);
}

/* The picture through a 256-entry global palette (entry i: the colour of
 * pixel i), then, when frames > 1, a second frame of other colours. */
static void write_gif(buf *o, int frames)
{
    puts_(o, "GIF89a");
    put8(o, PW), put8(o, 0), put8(o, PH), put8(o, 0);
    put8(o, 0xf7); /* global table of 2^(7+1) entries */
    put8(o, 0), put8(o, 0);
    for (int i = 0; i < 256; i++) {
        unsigned c[3] = {i & 255u, 255u - (i & 255u), 77};
        if (i < PW * PH) picture_rgb(i % PW, i / PW, c);
        put8(o, c[0]), put8(o, c[1]), put8(o, c[2]);
    }
    unsigned char idx[PW * PH];
    for (int i = 0; i < PW * PH; i++) idx[i] = (unsigned char)i;
    gif_image(o, 0, 0, PW, PH, idx);
    if (frames > 1) {
        for (int i = 0; i < PW * PH; i++) idx[i] = (unsigned char)(100 + i);
        gif_image(o, 0, 0, PW, PH, idx);
    }
    put8(o, 0x3b);
}

static void check_picture(const persp_image *img, const char *what)
{
    assert_int_equal(img->width, PW);
    assert_int_equal(img->height, PH);
    for (int y = 0; y < PH; y++)
        for (int x = 0; x < PW; x++) {
            unsigned c[3];
            picture_rgb(x, y, c);
            expect_pixel(img, x, y, c[0], c[1], c[2], 0, what);
        }
}

static void check_view(const persp_image_view *v, const char *what)
{
    const persp_image img = {v->width, v->height, v->stride, (uint8_t *)(uintptr_t)v->pixels};
    check_picture(&img, what);
}

static void test_gif_first_frame(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    for (int frames = 1; frames <= 2; frames++) {
        static buf o;
        o.n = 0;
        write_gif(&o, frames);
        persp_image img;
        load(ctx, &o, frames == 1 ? "still.gif" : "animated.gif", &img);
        check_picture(&img, frames == 1 ? "still.gif" : "animated.gif");
        persp_image_free(ctx, &img);
    }
    static buf o;
    o.n = 0;
    write_gif(&o, 1);
    o.n = 6 + 7 + 300;
    expect_refused(ctx, &o, "cut.gif", PERSP_ERR_FORMAT, "malformed GIF");
    o.n = 0;
    /* A logical screen over the side limit. */
    puts_(&o, "GIF89a");
    put8(&o, 0xff), put8(&o, 0xff), put8(&o, 0xff), put8(&o, 0xff);
    put8(&o, 0), put8(&o, 0), put8(&o, 0), put8(&o, 0x3b);
    expect_refused(ctx, &o, "vast.gif", PERSP_ERR_TOO_LARGE, "");
    persp_context_destroy(ctx);
}

/* A GIF whose pixels need more than the memory budget leaves is refused
 * before stb_image allocates: its working memory is reserved first. */
static void test_gif_budget(void **state)
{
    (void)state;
    persp_context_desc d;
    memset(&d, 0, sizeof d);
    d.max_memory = 1u << 20;
    persp_context *ctx = NULL;
    assert_int_equal(persp_context_create(&d, &ctx), PERSP_OK);
    static buf o;
    o.n = 0;
    puts_(&o, "GIF89a");
    put8(&o, 0x00), put8(&o, 0x04), put8(&o, 0x00), put8(&o, 0x04); /* 1024 × 1024 */
    put8(&o, 0), put8(&o, 0), put8(&o, 0);
    unsigned char idx[4] = {0, 0, 0, 0};
    gif_image(&o, 0, 0, 2, 2, idx);
    put8(&o, 0x3b);
    expect_refused(ctx, &o, "big.gif", PERSP_ERR_FORMAT, "more than the file's");
    /* 1024 × 1024 that the file could hold: refused by the budget. */
    static buf pad;
    pad.n = 0;
    for (size_t i = 0; i < o.n - 1; i++) put8(&pad, o.b[i]);
    put8(&pad, 0x21), put8(&pad, 0xfe); /* a comment extension: 200 sub-blocks of 255 bytes */
    for (int k = 0; k < 200; k++) {
        put8(&pad, 255);
        for (int i = 0; i < 255; i++) put8(&pad, 'x');
    }
    put8(&pad, 0), put8(&pad, 0x3b);
    expect_refused(ctx, &pad, "big.gif", PERSP_ERR_OUT_OF_MEMORY, "decoding the GIF image");
    persp_context_destroy(ctx);
}

/* ---------------------------------------------------------- Radiance HDR */

static void test_hdr_tone_mapped(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    /* RGBE (Ward, "Real Pixels", Graphics Gems II): c = m · 2^(e − 136). */
    static const unsigned char rgbe[4][4] = {
        {128, 64, 0, 129}, {32, 128, 255, 128}, {200, 100, 50, 131}, {0, 0, 0, 0}};
    static buf o;
    o.n = 0;
    puts_(&o, "#?RADIANCE\n# made by the test\nFORMAT=32-bit_rle_rgbe\n\n-Y 2 +X 2\n");
    for (int i = 0; i < 4; i++)
        for (int k = 0; k < 4; k++) put8(&o, rgbe[i][k]);
    persp_image img;
    load(ctx, &o, "sky.hdr", &img);
    assert_int_equal(img.width, 2);
    assert_int_equal(img.height, 2);
    for (int i = 0; i < 4; i++) {
        unsigned want[3];
        for (int k = 0; k < 3; k++) {
            const double c = rgbe[i][3] ? rgbe[i][k] * ldexp(1.0, rgbe[i][3] - 136) : 0.0;
            const double v = 255.0 * pow(c, 1.0 / 2.2);
            want[k] = v > 255.0 ? 255u : (unsigned)(v + 0.5);
        }
        expect_pixel(&img, i % 2, i / 2, want[0], want[1], want[2], 1, "sky.hdr");
    }
    persp_image_free(ctx, &img);
    o.n = 0;
    puts_(&o, "#?RADIANCE\nFORMAT=32-bit_rle_xyze\n\n-Y 1 +X 1\n\1\2\3\4");
    expect_refused(ctx, &o, "xyz.hdr", PERSP_ERR_FORMAT, "malformed Radiance HDR");
    persp_context_destroy(ctx);
}

/* --------------------------------------------------- embedded in a model */

static const char b64[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

static void base64(const unsigned char *in, size_t n, char *out)
{
    size_t j = 0;
    for (size_t i = 0; i < n; i += 3) {
        const uint32_t v = (uint32_t)in[i] << 16 | (i + 1 < n ? (uint32_t)in[i + 1] << 8 : 0u) |
                           (i + 2 < n ? in[i + 2] : 0u);
        out[j++] = b64[v >> 18 & 63];
        out[j++] = b64[v >> 12 & 63];
        out[j++] = i + 1 < n ? b64[v >> 6 & 63] : '=';
        out[j++] = i + 2 < n ? b64[v & 63] : '=';
    }
    out[j] = '\0';
}

/* A glTF whose image is a GIF in a data: URI (an embedded texture) draws
 * with the GIF's texels. */
static void test_gif_embedded_in_gltf(void **state)
{
    (void)state;
    static buf gif;
    gif.n = 0;
    write_gif(&gif, 1);
    static char image[8192], text[16384];
    base64(gif.b, gif.n, image);
    const float pos[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const float uv[6] = {0, 1, 1, 1, 0, 0};
    unsigned char bin[60];
    memcpy(bin, pos, 36);
    memcpy(bin + 36, uv, 24);
    char data[128];
    base64(bin, sizeof bin, data);
    snprintf(text, sizeof text,
             "{\"asset\": {\"version\": \"2.0\"}, \"scene\": 0, \"scenes\": [{\"nodes\": [0]}], "
             "\"nodes\": [{\"mesh\": 0}], \"meshes\": [{\"primitives\": [{\"attributes\": {\"POSITION\": 0, "
             "\"TEXCOORD_0\": 1}, \"material\": 0}]}], \"materials\": [{\"pbrMetallicRoughness\": "
             "{\"baseColorTexture\": {\"index\": 0}}}], \"textures\": [{\"source\": 0}], "
             "\"images\": [{\"uri\": \"data:image/gif;base64,%s\"}], "
             "\"buffers\": [{\"byteLength\": 60, \"uri\": \"data:application/octet-stream;base64,%s\"}], "
             "\"bufferViews\": [{\"buffer\": 0, \"byteOffset\": 0, \"byteLength\": 36}, "
             "{\"buffer\": 0, \"byteOffset\": 36, \"byteLength\": 24}], "
             "\"accessors\": [{\"bufferView\": 0, \"componentType\": 5126, \"count\": 3, \"type\": \"VEC3\", "
             "\"min\": [0, 0, 0], \"max\": [1, 1, 0]}, {\"bufferView\": 1, \"componentType\": 5126, "
             "\"count\": 3, \"type\": \"VEC2\"}]}",
             image, data);
    char dir[64], path[128];
    assert_int_equal(test_tmpdir_make(dir, sizeof dir, "gifmodel"), 0);
    snprintf(path, sizeof path, "%s/gif.gltf", dir);
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(text, 1, strlen(text), f), strlen(text));
    fclose(f);
    persp_context *ctx = test_context();
    persp_scene *s = NULL;
    if (persp_scene_load(ctx, path, &s) != PERSP_OK) fail_msg("gif.gltf: %s", persp_context_error(ctx));
    persp_scene_object o;
    assert_int_equal(persp_scene_get_object(s, 0, &o), PERSP_OK);
    assert_true(o.material.texture >= 0);
    const persp_texture *t = persp_scene_get_texture(s, o.material.texture);
    assert_non_null(t);
    persp_image_view level;
    assert_int_equal(persp_texture_level(t, 0, &level), PERSP_OK);
    check_view(&level, "gif.gltf's embedded GIF");
    persp_scene_destroy(s);
    persp_context_destroy(ctx);
    assert_int_equal(test_tmpdir_remove(dir), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pnm_every_kind),      cmocka_unit_test(test_pnm_malformed),
        cmocka_unit_test(test_gif_first_frame),     cmocka_unit_test(test_gif_budget),
        cmocka_unit_test(test_hdr_tone_mapped),     cmocka_unit_test(test_gif_embedded_in_gltf),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
