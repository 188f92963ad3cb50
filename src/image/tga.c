/*
 * Truevision TGA decoding, after the Truevision TGA File Format
 * Specification, version 2.0 (1989; "TGA 2.0" below): image types 1, 2, 3
 * (colour-mapped, true-colour, grey) and their run-length forms 9, 10, 11.
 *
 * The 18-byte header (TGA 2.0, fields 1-5) is followed by the image ID
 * (field 6, skipped), the colour map (field 7) and the image data (field
 * 8); the developer area, extension area and footer that may follow are
 * ignored. Pixels are stored little-endian, B before G before R.
 */
#include "image/decoders.h"

#include <stdint.h>

enum { TGA_HEADER_BYTES = 18 };

typedef struct tga_info {
    unsigned id_len, cmap_type, type;
    unsigned cmap_first, cmap_len, cmap_bits;
    unsigned width, height, bits, descriptor;
    int rle, mapped, grey;
    int alpha;       /* descriptor bits 0-3 nonzero: the pixels carry alpha */
    int top;         /* descriptor bit 5: the first row stored is the top one */
    int right_left;  /* descriptor bit 4: each row is stored right to left */
    size_t pixel_bytes, entry_bytes;
    size_t cmap_at, data_at; /* byte offsets of fields 7 and 8 */
} tga_info;

static unsigned le16(const unsigned char *p)
{
    return (unsigned)p[0] | (unsigned)p[1] << 8;
}

static int entry_bits_valid(unsigned bits)
{
    return bits == 15 || bits == 16 || bits == 24 || bits == 32;
}

/* The header's fields, and NULL when they are consistent, else what is
 * wrong. strict (a file not named .tga): also the fields TGA 2.0 asks
 * writers to leave zero (the colour-map specification without a colour
 * map, descriptor bits 6-7), so that little else passes for a TGA. Sizes
 * are not checked here. *unsupported: the header is valid but asks for
 * what persp does not read. */
static const char *tga_parse(const unsigned char *b, size_t size, int strict, tga_info *t,
                             int *unsupported)
{
    *unsupported = 0;
    memset(t, 0, sizeof *t);
    if (size < TGA_HEADER_BYTES) return "the file is shorter than the 18-byte header";
    t->id_len = b[0];
    t->cmap_type = b[1];
    t->type = b[2];
    t->cmap_first = le16(b + 3);
    t->cmap_len = le16(b + 5);
    t->cmap_bits = b[7];
    t->width = le16(b + 12);
    t->height = le16(b + 14);
    t->bits = b[16];
    t->descriptor = b[17];
    /* Field 2: 0 no colour map, 1 a colour map; 2-127 are reserved by
     * Truevision, 128-255 for developers. */
    if (t->cmap_type > 1) return "the colour-map type is neither 0 nor 1";
    switch (t->type) {
    case 1: case 9: t->mapped = 1; break;
    case 2: case 10: break;
    case 3: case 11: t->grey = 1; break;
    case 0: return "the file holds no image data (image type 0)";
    default: return "the image type is not 1, 2, 3, 9, 10 or 11";
    }
    t->rle = t->type >= 9;
    if (t->mapped) {
        if (t->cmap_type != 1) return "a colour-mapped image has no colour map";
        if (t->cmap_len == 0) return "the colour map is empty";
        if (t->bits != 8 && t->bits != 16)
            return "a colour-mapped image has indices of neither 8 nor 16 bits";
    } else if (t->grey) {
        if (t->bits != 8 && t->bits != 16) return "a grey image has neither 8 nor 16 bits a pixel";
    } else if (!entry_bits_valid(t->bits)) {
        return "a true-colour image has not 15, 16, 24 or 32 bits a pixel";
    }
    /* A colour map may come with any type (TGA 2.0, field 2); with a
     * true-colour or grey image it is skipped unread. */
    if (t->cmap_type == 1) {
        if (t->cmap_len > 0 && !entry_bits_valid(t->cmap_bits))
            return "the colour-map entries have not 15, 16, 24 or 32 bits";
        if ((unsigned long)t->cmap_first + t->cmap_len > 65536ul)
            return "the colour map runs past entry 65535";
    } else if (strict && (t->cmap_first || t->cmap_len || t->cmap_bits)) {
        return "colour-map fields are set without a colour map";
    }
    if (t->width == 0 || t->height == 0) return "the image has an empty size";
    /* Field 5.6, bits 6-7: interleaving in TGA 1.0, "must be zero" in 2.0. */
    if (t->descriptor & 0xc0) {
        if (strict) return "image descriptor bits 6-7 are set";
        *unsupported = 1;
        return "interleaved rows (image descriptor bits 6-7) are not supported";
    }
    if (strict && (t->descriptor & 0x0f) > 8) return "more than 8 alpha bits";
    t->alpha = (t->descriptor & 0x0f) != 0;
    t->right_left = (t->descriptor & 0x10) != 0;
    t->top = (t->descriptor & 0x20) != 0;
    t->pixel_bytes = (t->bits + 7u) / 8u;
    t->entry_bytes = t->cmap_type == 1 ? (t->cmap_bits + 7u) / 8u : 0;
    t->cmap_at = TGA_HEADER_BYTES + (size_t)t->id_len;
    t->data_at = t->cmap_at + (t->cmap_type == 1 ? (size_t)t->cmap_len * t->entry_bytes : 0);
    return NULL;
}

int persp__tga_recognised(const unsigned char *data, size_t size)
{
    tga_info t;
    int unsupported;
    return tga_parse(data, size, 1, &t, &unsupported) == NULL;
}

/* 5-bit channel to 8 bits, rounded: v·255/31. */
static uint8_t five(unsigned v)
{
    return (uint8_t)((v * 255u + 15u) / 31u);
}

/* One stored value of bits bits at p to RGBA. TGA 2.0 field 5.6: bits 0-3
 * of the image descriptor count the attribute (alpha) bits of a pixel;
 * with none, the fourth byte of a 32-bit value and the top bit of a 16-bit
 * one are not alpha, and the pixel is opaque. The same rule is applied to
 * colour-map entries. 16-bit values are A1 R5 G5 B5 from the top bit down;
 * 16-bit grey is a grey byte then an alpha byte. */
static void tga_value(const unsigned char *p, unsigned bits, int grey, int alpha, uint8_t *o)
{
    if (grey) {
        o[0] = o[1] = o[2] = p[0];
        o[3] = bits == 16 && alpha ? p[1] : 255;
        return;
    }
    switch (bits) {
    case 15:
    case 16: {
        unsigned v = le16(p);
        o[0] = five(v >> 10 & 31u);
        o[1] = five(v >> 5 & 31u);
        o[2] = five(v & 31u);
        o[3] = bits == 16 && alpha && !(v & 0x8000u) ? 0 : 255;
        break;
    }
    case 24:
        o[0] = p[2], o[1] = p[1], o[2] = p[0], o[3] = 255;
        break;
    default: /* 32 */
        o[0] = p[2], o[1] = p[1], o[2] = p[0], o[3] = alpha ? p[3] : 255;
        break;
    }
}

/* Where the pixels go: file order is row by row from the origin corner the
 * descriptor names (bits 4 and 5), persp's rows bottom-up. */
typedef struct tga_cursor {
    const tga_info *t;
    persp_image *img;
    size_t done; /* pixels written */
    unsigned col, row;
    uint8_t *dst_row;
} tga_cursor;

static uint8_t *row_of(const tga_cursor *c)
{
    size_t y = c->t->top ? (size_t)c->t->height - 1u - c->row : c->row;
    return c->img->pixels + y * c->img->stride;
}

static uint8_t *next_pixel(tga_cursor *c)
{
    unsigned x = c->t->right_left ? c->t->width - 1u - c->col : c->col;
    uint8_t *dst = c->dst_row + 4u * (size_t)x;
    c->done++;
    if (++c->col == c->t->width) {
        c->col = 0;
        if (++c->row < c->t->height) c->dst_row = row_of(c);
    }
    return dst;
}

/* The pixel at p to RGBA; for a colour-mapped image, the index at p looked
 * up in the map. The map's entries are numbered from the first entry index
 * (TGA 2.0 field 4.1): a map of 72 entries starting at 342 covers indices
 * 342-413. Returns 0, or 1 with *bad the index outside the map. */
static int tga_pixel(const tga_info *t, const unsigned char *data, const unsigned char *p,
                     uint8_t *o, unsigned *bad)
{
    if (!t->mapped) {
        tga_value(p, t->bits, t->grey, t->alpha, o);
        return 0;
    }
    unsigned index = t->bits == 8 ? p[0] : le16(p);
    if (index < t->cmap_first || index - t->cmap_first >= t->cmap_len) {
        *bad = index;
        return 1;
    }
    tga_value(data + t->cmap_at + (size_t)(index - t->cmap_first) * t->entry_bytes, t->cmap_bits,
              0, t->alpha, o);
    return 0;
}

static persp_status bad_index(persp_context *ctx, const char *name, const tga_cursor *c,
                              unsigned index)
{
    const tga_info *t = c->t;
    unsigned x = t->right_left ? t->width - 1u - c->col : c->col;
    unsigned y = t->top ? c->row : t->height - 1u - c->row; /* from the top */
    return persp__fail(ctx, PERSP_ERR_FORMAT,
                       "%s: invalid TGA: pixel (%u, %u) uses colour-map index %u, the map holds "
                       "entries %u to %u",
                       name, x, y, index, t->cmap_first, t->cmap_first + t->cmap_len - 1u);
}

static persp_status decode_raw(persp_context *ctx, const unsigned char *data, const char *name,
                               tga_cursor *c, size_t n)
{
    const tga_info *t = c->t;
    const unsigned char *p = data + t->data_at;
    uint8_t px[4];
    unsigned bad;
    for (size_t i = 0; i < n; i++, p += t->pixel_bytes) {
        if (tga_pixel(t, data, p, px, &bad)) return bad_index(ctx, name, c, bad);
        memcpy(next_pixel(c), px, 4);
    }
    return PERSP_OK;
}

/* TGA 2.0, "Run-length encoding": a packet is a header byte, whose top bit
 * says run (one pixel value repeated) or raw (that many values), and whose
 * low 7 bits are the count less one, followed by the value(s). TGA 2.0
 * asks writers not to let a packet cross a row; version 1 files do, so the
 * packets are read as one stream over the whole image. A packet that
 * would cover pixels past the last one is refused. */
static persp_status decode_rle(persp_context *ctx, const unsigned char *data, size_t size,
                               const char *name, tga_cursor *c, size_t n)
{
    const tga_info *t = c->t;
    const size_t pb = t->pixel_bytes;
    size_t pos = t->data_at;
    uint8_t px[4];
    unsigned bad;
    while (c->done < n) {
        if (pos >= size)
            return persp__fail(ctx, PERSP_ERR_FORMAT,
                               "%s: truncated TGA: the RLE data ends after %zu of %zu pixels",
                               name, c->done, n);
        const size_t at = pos;
        const unsigned head = data[pos++];
        const size_t count = (head & 0x7fu) + 1u;
        if (count > n - c->done)
            return persp__fail(ctx, PERSP_ERR_FORMAT,
                               "%s: invalid TGA: the RLE packet at byte %zu covers %zu pixels, "
                               "%zu remain in the image",
                               name, at, count, n - c->done);
        const size_t need = head & 0x80u ? pb : count * pb;
        if (size - pos < need)
            return persp__fail(ctx, PERSP_ERR_FORMAT,
                               "%s: truncated TGA: the RLE packet at byte %zu runs past the end "
                               "of the file",
                               name, at);
        if (head & 0x80u) {
            if (tga_pixel(t, data, data + pos, px, &bad)) return bad_index(ctx, name, c, bad);
            for (size_t k = 0; k < count; k++)
                memcpy(next_pixel(c), px, 4);
        } else {
            for (size_t k = 0; k < count; k++) {
                if (tga_pixel(t, data, data + pos + k * pb, px, &bad))
                    return bad_index(ctx, name, c, bad);
                memcpy(next_pixel(c), px, 4);
            }
        }
        pos += need;
    }
    return PERSP_OK;
}

persp_status persp__load_tga(persp_context *ctx, const unsigned char *data, size_t size,
                             const char *name, persp_image *out)
{
    memset(out, 0, sizeof *out);
    tga_info t;
    int unsupported;
    const char *why = tga_parse(data, size, 0, &t, &unsupported);
    if (why)
        return persp__fail(ctx, unsupported ? PERSP_ERR_UNSUPPORTED : PERSP_ERR_FORMAT,
                           "%s: %s TGA: %s", name, unsupported ? "unsupported" : "invalid", why);
    persp_status st = persp__image_check_size(ctx, name, t.width, t.height);
    if (st != PERSP_OK) return st;
    if (t.data_at > size)
        return persp__fail(ctx, PERSP_ERR_FORMAT,
                           "%s: truncated TGA: the image ID and colour map need %zu bytes, the "
                           "file has %zu",
                           name, t.data_at, size);
    /* Enough data for the pixels is checked before the image is allocated,
     * so a short file with a large size costs nothing: stored, they need
     * their bytes; run-length encoded, at least one packet (a byte and a
     * value) per 128 pixels. */
    const size_t n = (size_t)t.width * t.height;
    const size_t left = size - t.data_at;
    const size_t need = t.rle ? (n + 127u) / 128u * (1u + t.pixel_bytes) : n * t.pixel_bytes;
    if (left < need)
        return persp__fail(ctx, PERSP_ERR_FORMAT,
                           t.rle ? "%s: truncated TGA: %zu bytes of RLE data cannot hold %ux%u "
                                   "pixels (at least %zu bytes)"
                                 : "%s: truncated TGA: %zu bytes of image data, %ux%u pixels "
                                   "need %zu",
                           name, left, t.width, t.height, need);
    st = persp__decoder_alloc(ctx, name, (int)t.width, (int)t.height, out);
    if (st != PERSP_OK) return st;
    tga_cursor c = {&t, out, 0, 0, 0, NULL};
    c.dst_row = row_of(&c);
    st = t.rle ? decode_rle(ctx, data, size, name, &c, n) : decode_raw(ctx, data, name, &c, n);
    if (st != PERSP_OK) persp_image_free(ctx, out);
    return st;
}
