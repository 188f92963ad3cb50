/*
 * Windows bitmap (BMP) decoding, after Microsoft's documentation of
 * BITMAPFILEHEADER, BITMAPCOREHEADER, BITMAPINFOHEADER, BITMAPV4HEADER and
 * BITMAPV5HEADER (wingdi.h) and "Bitmap Compression" (BI_RLE8, BI_RLE4).
 *
 * Read: the core (12-byte, OS/2 1.x) header and the info headers of 40,
 * 52, 56, 108 and 124 bytes; 1, 2, 4 and 8 bits a pixel through a palette,
 * 16 and 32 bits (BI_RGB or masks from BI_BITFIELDS / BI_ALPHABITFIELDS),
 * 24 bits; BI_RLE8 and BI_RLE4. Not read: JPEG and PNG inside a BMP, the
 * CMYK compressions, 64 bits a pixel, the OS/2 2.x header (PERSP_ERR_UNSUPPORTED).
 *
 * A positive height stores the bottom row first, persp's own order; a
 * negative one the top row first. Every stored row is padded to a multiple
 * of 4 bytes.
 */
#include "image/decoders.h"

#include <stdint.h>

enum {
    FILE_HEADER_BYTES = 14,
    BI_RGB = 0,
    BI_RLE8 = 1,
    BI_RLE4 = 2,
    BI_BITFIELDS = 3,
    BI_JPEG = 4,
    BI_PNG = 5,
    BI_ALPHABITFIELDS = 6
};

/* A channel of a packed 16- or 32-bit pixel: its mask, where the mask
 * starts, and its largest value. */
typedef struct bmp_channel {
    uint32_t mask;
    unsigned shift;
    uint32_t max; /* 0: the channel is absent */
} bmp_channel;

typedef struct bmp_info {
    long long width, height; /* height as |biHeight| */
    int top_down;
    unsigned bits, compression;
    uint32_t header_bytes, offset;
    size_t palette_at;
    unsigned palette_count, entry_bytes;
    bmp_channel ch[4]; /* R, G, B, A */
} bmp_info;

static uint32_t le32(const unsigned char *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static unsigned le16(const unsigned char *p)
{
    return (unsigned)p[0] | (unsigned)p[1] << 8;
}

/* 0 when the mask is not one run of set bits (the documentation of
 * BI_BITFIELDS: "the bits set in each mask must be contiguous"). */
static int channel_init(uint32_t mask, bmp_channel *c)
{
    c->mask = mask;
    c->shift = 0;
    c->max = 0;
    if (!mask) return 1;
    while (!(mask >> c->shift & 1u))
        c->shift++;
    c->max = mask >> c->shift;
    return (c->max & (c->max + 1u)) == 0;
}

/* The channel's value scaled to 8 bits, rounded; absent gives absent. */
static uint8_t channel_get(const bmp_channel *c, uint32_t px, uint8_t absent)
{
    if (!c->max) return absent;
    uint64_t v = (px & c->mask) >> c->shift;
    return (uint8_t)((v * 255u + c->max / 2u) / c->max);
}

static persp_status bad(persp_context *ctx, persp_status st, const char *name, const char *what)
{
    return persp__fail(ctx, st, "%s: %s", name, what);
}

/* A BITMAPINFOHEADER or larger (hs bytes at h, in the buffer): size,
 * compression, bits, the colour masks where it or the bytes after a 40-byte
 * header hold them (*masks_after: how many bytes those take), the palette's
 * declared size; each checked against the others. */
static persp_status info_header(persp_context *ctx, const unsigned char *h, uint32_t hs, size_t size,
                                const char *name, bmp_info *t, uint32_t masks[4], size_t *masks_after)
{
    t->width = (int32_t)le32(h + 4);
    long long height = (int32_t)le32(h + 8);
    t->bits = le16(h + 14);
    t->compression = le32(h + 16);
    t->entry_bytes = 4;
    t->top_down = height < 0;
    t->height = height < 0 ? -height : height;
    switch (t->compression) {
    case BI_RGB:
    case BI_RLE8:
    case BI_RLE4:
    case BI_BITFIELDS:
    case BI_ALPHABITFIELDS:
        break;
    case BI_JPEG:
        return bad(ctx, PERSP_ERR_UNSUPPORTED, name, "unsupported BMP: JPEG compression");
    case BI_PNG:
        return bad(ctx, PERSP_ERR_UNSUPPORTED, name, "unsupported BMP: PNG compression");
    default:
        return persp__fail(ctx, PERSP_ERR_UNSUPPORTED,
                           "%s: unsupported BMP: compression %u", name,
                           (unsigned)t->compression);
    }
    const int fields = t->compression == BI_BITFIELDS || t->compression == BI_ALPHABITFIELDS;
    if (fields) {
        /* The masks follow a 40-byte header (three, or four with
         * BI_ALPHABITFIELDS); the larger headers hold them. */
        const unsigned count = t->compression == BI_ALPHABITFIELDS ? 4 : 3;
        const unsigned char *m = h + 40;
        if (hs == 40) {
            *masks_after = 4u * count;
            if (size - FILE_HEADER_BYTES - hs < *masks_after)
                return bad(ctx, PERSP_ERR_FORMAT, name,
                           "truncated BMP: the file ends inside its colour masks");
        }
        for (unsigned i = 0; i < count && (hs == 40 || 40 + 4 * i + 4 <= hs); i++)
            masks[i] = le32(m + 4 * i);
        if (hs >= 56) masks[3] = le32(h + 52);
    } else if (t->bits == 32 && hs >= 56) {
        /* With BI_RGB the colour masks are not used, but the alpha mask
         * of the larger headers still says where alpha is ("color mask
         * that specifies the alpha component of each pixel"). */
        masks[3] = le32(h + 52);
    }
    if (t->width <= 0)
        return persp__fail(ctx, PERSP_ERR_FORMAT, "%s: invalid BMP: width %lld", name,
                           t->width);
    if (t->top_down && (t->compression == BI_RLE8 || t->compression == BI_RLE4))
        /* biHeight: "top-down DIBs cannot be compressed" */
        return bad(ctx, PERSP_ERR_FORMAT, name,
                   "invalid BMP: a top-down bitmap (negative height) is RLE-compressed");
    int ok;
    switch (t->compression) {
    case BI_RGB:
        ok = t->bits == 1 || t->bits == 2 || t->bits == 4 || t->bits == 8 || t->bits == 16 ||
             t->bits == 24 || t->bits == 32;
        if (t->bits == 0 || t->bits == 64)
            return persp__fail(ctx, PERSP_ERR_UNSUPPORTED,
                               "%s: unsupported BMP: %u bits a pixel", name, t->bits);
        break;
    case BI_RLE8: ok = t->bits == 8; break;
    case BI_RLE4: ok = t->bits == 4; break;
    default: ok = t->bits == 16 || t->bits == 32; break;
    }
    if (!ok)
        return persp__fail(ctx, PERSP_ERR_FORMAT,
                           "%s: invalid BMP: %u bits a pixel with compression %u", name,
                           t->bits, t->compression);
    if (t->bits <= 8) {
        uint32_t used = le32(h + 32); /* biClrUsed; 0: all 2^bits */
        t->palette_count = used && used < (1u << t->bits) ? used : 1u << t->bits;
    }
    return PERSP_OK;
}

/* The channels of 16- and 32-bit pixels: BI_RGB's fixed layouts, or the
 * masks, each one run of bits within the pixel. */
static persp_status pixel_masks(persp_context *ctx, const char *name, bmp_info *t, uint32_t masks[4])
{
    if (t->compression == BI_RGB) {
        /* BI_RGB: 16 bits are X1 R5 G5 B5; 32 bits are B, G, R and an
         * unused byte (biCompression), unless an alpha mask says. */
        if (t->bits == 16) masks[0] = 0x7c00u, masks[1] = 0x03e0u, masks[2] = 0x001fu;
        else masks[0] = 0xff0000u, masks[1] = 0xff00u, masks[2] = 0xffu;
        if (masks[3] & 0xffffffu) masks[3] = 0;
    }
    const uint32_t fits = t->bits == 16 ? 0xffffu : UINT32_MAX;
    for (int i = 0; i < 4; i++)
        if ((masks[i] & ~fits) || !channel_init(masks[i], &t->ch[i]))
            return persp__fail(ctx, PERSP_ERR_FORMAT,
                               "%s: invalid BMP: the %s mask 0x%08x is not one run of bits "
                               "within a %u-bit pixel",
                               name, (const char *[]){"red", "green", "blue", "alpha"}[i],
                               (unsigned)masks[i], t->bits);
    return PERSP_OK;
}

/* The headers, the masks and the palette's place; checks every field
 * against the buffer and each other. */
static persp_status bmp_parse(persp_context *ctx, const unsigned char *b, size_t size,
                              const char *name, bmp_info *t)
{
    memset(t, 0, sizeof *t);
    if (size < FILE_HEADER_BYTES + 4)
        return bad(ctx, PERSP_ERR_FORMAT, name, "truncated BMP: the file ends inside its headers");
    t->offset = le32(b + 10); /* bfOffBits */
    t->header_bytes = le32(b + 14);
    const uint32_t hs = t->header_bytes;
    if (hs != 12 && hs != 40 && hs != 52 && hs != 56 && hs != 108 && hs != 124) {
        if (hs == 16 || hs == 64)
            return bad(ctx, PERSP_ERR_UNSUPPORTED, name,
                       "unsupported BMP: OS/2 2.x bitmap header");
        return persp__fail(ctx, PERSP_ERR_FORMAT, "%s: invalid BMP: unknown header size %u",
                           name, (unsigned)hs);
    }
    if (size - FILE_HEADER_BYTES < hs)
        return bad(ctx, PERSP_ERR_FORMAT, name, "truncated BMP: the file ends inside its headers");
    const unsigned char *h = b + FILE_HEADER_BYTES;
    uint32_t masks[4] = {0, 0, 0, 0};
    size_t masks_after = 0; /* bytes of masks between a 40-byte header and the palette */
    if (hs == 12) {
        /* BITMAPCOREHEADER: unsigned 16-bit width and height, bottom-up,
         * no compression, RGBTRIPLE palette entries. */
        t->width = le16(h + 4);
        t->height = le16(h + 6);
        t->bits = le16(h + 10);
        t->compression = BI_RGB;
        t->entry_bytes = 3;
        if (t->bits != 1 && t->bits != 4 && t->bits != 8 && t->bits != 24)
            return persp__fail(ctx, PERSP_ERR_FORMAT,
                               "%s: invalid BMP: %u bits a pixel in a core header", name, t->bits);
    } else {
        persp_status st = info_header(ctx, h, hs, size, name, t, masks, &masks_after);
        if (st != PERSP_OK) return st;
    }
    if (hs == 12) t->palette_count = 1u << t->bits;
    if (t->bits > 8) t->palette_count = 0;
    persp_status st = persp__image_check_size(ctx, name, t->width, t->height);
    if (st != PERSP_OK) return st;
    t->palette_at = FILE_HEADER_BYTES + (size_t)hs + masks_after;
    if (t->offset < t->palette_at)
        return persp__fail(ctx, PERSP_ERR_FORMAT,
                           "%s: invalid BMP: the pixel data offset %u lies inside the headers",
                           name, (unsigned)t->offset);
    if (t->offset > size)
        return persp__fail(ctx, PERSP_ERR_FORMAT,
                           "%s: truncated BMP: the pixel data starts at byte %u, the file has %zu",
                           name, (unsigned)t->offset, size);
    if (t->bits <= 8) {
        /* The palette lies between the headers and the pixel data; where
         * the offset leaves room for fewer entries than declared (as OS/2
         * writers do), the entries that fit are the palette. */
        size_t room = (t->offset - t->palette_at) / t->entry_bytes;
        if (room < t->palette_count) t->palette_count = (unsigned)room;
    }
    if (t->bits == 16 || t->bits == 32) return pixel_masks(ctx, name, t, masks);
    return PERSP_OK;
}

static persp_status bad_index(persp_context *ctx, const char *name, const bmp_info *t,
                              long long x, long long y_top, unsigned index)
{
    return persp__fail(ctx, PERSP_ERR_FORMAT,
                       "%s: invalid BMP: pixel (%lld, %lld) uses palette index %u, the palette "
                       "has %u entries",
                       name, x, y_top, index, t->palette_count);
}

static void palette_rgba(const unsigned char *data, const bmp_info *t, unsigned index, uint8_t *o)
{
    /* RGBQUAD / RGBTRIPLE: blue, green, red (and a reserved byte). */
    const unsigned char *e = data + t->palette_at + (size_t)index * t->entry_bytes;
    o[0] = e[2], o[1] = e[1], o[2] = e[0], o[3] = 255;
}

static persp_status decode_rows(persp_context *ctx, const unsigned char *data, const char *name,
                                const bmp_info *t, size_t row_bytes, persp_image *img)
{
    const size_t w = (size_t)t->width, h = (size_t)t->height;
    for (size_t fr = 0; fr < h; fr++) {
        const unsigned char *src = data + t->offset + fr * row_bytes;
        const size_t y = t->top_down ? h - 1u - fr : fr;
        uint8_t *dst = img->pixels + y * img->stride;
        for (size_t x = 0; x < w; x++, dst += 4) {
            switch (t->bits) {
            case 1:
            case 2:
            case 4:
            case 8: {
                /* The leftmost pixel is in the most significant bits. */
                const size_t bit = x * t->bits;
                const unsigned shift = 8u - t->bits - (unsigned)(bit & 7u);
                const unsigned index = (unsigned)(src[bit >> 3] >> shift) & ((1u << t->bits) - 1u);
                if (index >= t->palette_count)
                    return bad_index(ctx, name, t, (long long)x, (long long)(h - 1u - y), index);
                palette_rgba(data, t, index, dst);
                break;
            }
            case 24:
                dst[0] = src[3 * x + 2], dst[1] = src[3 * x + 1], dst[2] = src[3 * x], dst[3] = 255;
                break;
            default: {
                const uint32_t v = t->bits == 16 ? le16(src + 2 * x) : le32(src + 4 * x);
                dst[0] = channel_get(&t->ch[0], v, 0);
                dst[1] = channel_get(&t->ch[1], v, 0);
                dst[2] = channel_get(&t->ch[2], v, 0);
                dst[3] = channel_get(&t->ch[3], v, 255);
                break;
            }
            }
        }
    }
    return PERSP_OK;
}

/* "Bitmap Compression": pairs of bytes. A nonzero first byte is a run of
 * that many pixels of the index in the second (BI_RLE4: its two nibbles
 * alternately, high first). A zero first byte is an escape: 0 end of row,
 * 1 end of bitmap, 2 a delta (two more bytes: right and up), 3-255 that
 * many indices stored as they are, padded to a 16-bit boundary. Rows go
 * bottom-up; pixels the data skips (by a delta, an early end of row or of
 * the bitmap) are left transparent black. A run past the end of its row,
 * or a delta out of the image, is refused rather than wrapped. */
static persp_status decode_rle(persp_context *ctx, const unsigned char *data, size_t size,
                               const char *name, const bmp_info *t, persp_image *img)
{
    const int four = t->compression == BI_RLE4;
    const size_t w = (size_t)t->width, h = (size_t)t->height;
    size_t pos = t->offset, x = 0, y = 0;
    for (;;) {
        if (size - pos < 2) {
            if (y >= h) return PERSP_OK; /* every row ended; no end-of-bitmap marker */
            return persp__fail(ctx, PERSP_ERR_FORMAT,
                               "%s: truncated BMP: the RLE data ends in row %zu of %zu without "
                               "an end-of-bitmap marker",
                               name, h - 1u - y, h);
        }
        const size_t at = pos;
        const unsigned a = data[pos], c = data[pos + 1];
        pos += 2;
        if (a == 0 && c == 0) { /* end of row */
            if (y >= h)
                return persp__fail(ctx, PERSP_ERR_FORMAT,
                                   "%s: invalid BMP: the RLE data at byte %zu goes past the top "
                                   "row",
                                   name, at);
            x = 0, y++;
            continue;
        }
        if (a == 0 && c == 1) return PERSP_OK; /* end of bitmap */
        if (a == 0 && c == 2) {                /* delta */
            if (size - pos < 2)
                return persp__fail(ctx, PERSP_ERR_FORMAT,
                                   "%s: truncated BMP: the RLE delta at byte %zu runs past the end "
                                   "of the file",
                                   name, at);
            x += data[pos], y += data[pos + 1];
            pos += 2;
            if (x > w || y > h || (y == h && x > 0))
                return persp__fail(ctx, PERSP_ERR_FORMAT,
                                   "%s: invalid BMP: the RLE delta at byte %zu moves out of the "
                                   "image",
                                   name, at);
            continue;
        }
        /* a run (a > 0) or a stored sequence (a == 0, c >= 3) */
        const size_t count = a ? a : c;
        const unsigned char *src = data + pos;
        if (!a) {
            const size_t bytes = four ? (count + 1u) / 2u : count;
            if (size - pos < bytes)
                return persp__fail(ctx, PERSP_ERR_FORMAT,
                                   "%s: truncated BMP: the RLE sequence at byte %zu runs past the "
                                   "end of the file",
                                   name, at);
            pos += bytes + (bytes & 1u);
            if (pos > size) pos = size; /* a missing pad byte at the very end */
        }
        if (y >= h || count > w - x)
            return persp__fail(ctx, PERSP_ERR_FORMAT,
                               "%s: invalid BMP: the RLE %s at byte %zu runs past the end of "
                               "its row",
                               name, a ? "run" : "sequence", at);
        uint8_t *dst = img->pixels + y * img->stride + 4u * x;
        for (size_t k = 0; k < count; k++, dst += 4) {
            unsigned index;
            if (a) index = four ? (k & 1u ? c & 15u : c >> 4) : c;
            else index = four ? (k & 1u ? src[k / 2u] & 15u : (unsigned)src[k / 2u] >> 4) : src[k];
            if (index >= t->palette_count)
                return bad_index(ctx, name, t, (long long)(x + k), (long long)(h - 1u - y), index);
            palette_rgba(data, t, index, dst);
        }
        x += count;
    }
}

persp_status persp__load_bmp(persp_context *ctx, const unsigned char *data, size_t size,
                             const char *name, persp_image *out)
{
    memset(out, 0, sizeof *out);
    bmp_info t;
    persp_status st = bmp_parse(ctx, data, size, name, &t);
    if (st != PERSP_OK) return st;
    const int rle = t.compression == BI_RLE8 || t.compression == BI_RLE4;
    /* Rows are padded to 4 bytes; the last row's padding may be missing
     * (some writers drop it) since no pixel is in it. Checked before the
     * image is allocated, so that a short file with a large size costs
     * nothing. */
    const size_t row_bytes = ((size_t)t.width * t.bits + 31u) / 32u * 4u;
    if (!rle) {
        const size_t need = row_bytes * (size_t)(t.height - 1) + ((size_t)t.width * t.bits + 7u) / 8u;
        if (size - t.offset < need)
            return persp__fail(ctx, PERSP_ERR_FORMAT,
                               "%s: truncated BMP: %lldx%lld pixels of %u bits need %zu bytes, "
                               "%zu remain",
                               name, t.width, t.height, t.bits, need, size - t.offset);
    }
    st = persp__decoder_alloc(ctx, name, (int)t.width, (int)t.height, out);
    if (st != PERSP_OK) return st;
    st = rle ? decode_rle(ctx, data, size, name, &t, out)
             : decode_rows(ctx, data, name, &t, row_bytes, out);
    if (st != PERSP_OK) persp_image_free(ctx, out);
    return st;
}
