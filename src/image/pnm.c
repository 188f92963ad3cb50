/*
 * Netpbm images (the formats of Netpbm's pbm(5), pgm(5) and ppm(5) pages):
 * P1 and P4 bitmaps (1 is black), P2 and P5 grey maps, P3 and P6 pixel
 * maps; the plain (ASCII) forms and the raw (binary) ones, whose samples
 * are one byte for a maximum value under 256 and two, most significant
 * first, up to 65535. Samples are scaled from [0, maxval] to [0, 255]. A
 * file may hold several images; the first is read.
 */
#include "image/decoders.h"

#include <ctype.h>
#include <stdint.h>

typedef struct pnm_reader {
    const unsigned char *p, *end;
} pnm_reader;

/* Skips white space and '#' comments (to the end of their line). */
static void skip_space(pnm_reader *r)
{
    while (r->p < r->end) {
        if (*r->p == '#') {
            while (r->p < r->end && *r->p != '\n' && *r->p != '\r') r->p++;
        } else if (isspace(*r->p)) {
            r->p++;
        } else {
            return;
        }
    }
}

/* A decimal number of the header or a plain raster; 0 when there is none
 * or it is over limit. */
static int read_number(pnm_reader *r, unsigned long limit, unsigned long *out)
{
    skip_space(r);
    if (r->p >= r->end || !isdigit(*r->p)) return 0;
    unsigned long v = 0;
    while (r->p < r->end && isdigit(*r->p)) {
        v = v * 10 + (unsigned long)(*r->p - '0');
        if (v > limit) return 0;
        r->p++;
    }
    *out = v;
    return 1;
}

int persp__pnm_recognised(const unsigned char *data, size_t size)
{
    return size >= 3 && data[0] == 'P' && data[1] >= '1' && data[1] <= '6' && (isspace(data[2]) || data[2] == '#');
}

static uint8_t scale(unsigned long v, unsigned long maxval)
{
    return (uint8_t)((v * 255u + maxval / 2u) / maxval);
}

/* One sample of a raw raster at r->p (width 1 or 2 bytes). */
static unsigned long raw_sample(pnm_reader *r, int two)
{
    unsigned long v = r->p[0];
    if (two) v = v << 8 | r->p[1];
    r->p += two ? 2 : 1;
    return v;
}

static persp_status read_raster(persp_context *ctx, const char *name, int kind, pnm_reader *r,
                                unsigned long maxval, persp_image *img)
{
    const int w = img->width, h = img->height;
    const int channels = kind == 3 || kind == 6 ? 3 : 1;
    const int two = maxval > 255;
    const size_t row = kind == 4 ? ((size_t)w + 7) / 8 : (size_t)w * (size_t)channels * (two ? 2u : 1u);
    for (int y = 0; y < h; y++) {
        uint8_t *out = img->pixels + (size_t)(h - 1 - y) * img->stride; /* the file's first row is the top */
        if (kind >= 4 && (size_t)(r->end - r->p) < row)
            return persp__fail(ctx, PERSP_ERR_FORMAT, "%s: the Netpbm raster ends at row %d of %d", name, y, h);
        for (int x = 0; x < w; x++) {
            unsigned long c[3] = {0, 0, 0};
            if (kind == 1) {
                /* Plain bitmap: digits, white space between them optional. */
                skip_space(r);
                if (r->p >= r->end || (*r->p != '0' && *r->p != '1'))
                    return persp__fail(ctx, PERSP_ERR_FORMAT, "%s: the Netpbm bitmap ends or holds a non-bit at "
                                       "pixel (%d, %d)", name, x, y);
                c[0] = *r->p++ == '1' ? 0u : 1u;
            } else if (kind == 4) {
                c[0] = ((unsigned)r->p[x / 8] >> (7 - x % 8) & 1u) ? 0u : 1u;
            } else {
                for (int k = 0; k < channels; k++) {
                    if (kind <= 3 && !read_number(r, 65535u, &c[k]))
                        return persp__fail(ctx, PERSP_ERR_FORMAT, "%s: the Netpbm raster ends or holds a "
                                           "non-number at pixel (%d, %d)", name, x, y);
                    if (kind > 3) c[k] = raw_sample(r, two);
                    if (c[k] > maxval)
                        return persp__fail(ctx, PERSP_ERR_FORMAT, "%s: sample %lu at pixel (%d, %d) is over the "
                                           "maximum value %lu", name, c[k], x, y, maxval);
                }
            }
            const unsigned long m = kind == 1 || kind == 4 ? 1u : maxval;
            const uint8_t g = scale(c[0], m);
            out[4 * x] = g;
            out[4 * x + 1] = channels == 3 ? scale(c[1], m) : g;
            out[4 * x + 2] = channels == 3 ? scale(c[2], m) : g;
            out[4 * x + 3] = 255;
        }
        if (kind == 4) r->p += row;
    }
    return PERSP_OK;
}

persp_status persp__load_pnm(persp_context *ctx, const unsigned char *data, size_t size, const char *name,
                             persp_image *out)
{
    memset(out, 0, sizeof *out);
    if (!persp__pnm_recognised(data, size))
        return persp__fail(ctx, PERSP_ERR_FORMAT, "%s: not a Netpbm image (P1 to P6)", name);
    const int kind = data[1] - '0';
    pnm_reader r = {data + 2, data + size};
    unsigned long w = 0, h = 0, maxval = 1;
    if (!read_number(&r, (unsigned long)PERSP_IMAGE_MAX_SIDE * 16u, &w) ||
        !read_number(&r, (unsigned long)PERSP_IMAGE_MAX_SIDE * 16u, &h))
        return persp__fail(ctx, PERSP_ERR_FORMAT, "%s: a Netpbm header without its width and height", name);
    if (kind != 1 && kind != 4 && (!read_number(&r, 65535u, &maxval) || maxval == 0))
        return persp__fail(ctx, PERSP_ERR_FORMAT, "%s: a Netpbm header without a maximum value in 1..65535",
                           name);
    persp_status st = persp__image_check_size(ctx, name, (long long)w, (long long)h);
    if (st != PERSP_OK) return st;
    if (kind >= 4) {
        /* One white-space byte ends a raw header. */
        if (r.p >= r.end || !isspace(*r.p))
            return persp__fail(ctx, PERSP_ERR_FORMAT, "%s: the Netpbm header does not end in white space", name);
        r.p++;
    }
    /* Every sample takes at least one byte of the file, or an eighth for P4:
     * a header declaring more than the file holds is refused before the
     * image is allocated. */
    const size_t samples = (size_t)w * (size_t)h * (kind == 3 || kind == 6 ? 3u : 1u);
    const size_t least = kind == 4 ? (size_t)h * (((size_t)w + 7) / 8) : samples;
    if ((size_t)(r.end - r.p) < least)
        return persp__fail(ctx, PERSP_ERR_FORMAT, "%s: the Netpbm header declares %lux%lu pixels, more than the "
                           "file holds", name, w, h);
    st = persp__decoder_alloc(ctx, name, (int)w, (int)h, out);
    if (st != PERSP_OK) return st;
    st = read_raster(ctx, name, kind, &r, maxval, out);
    if (st != PERSP_OK) persp_image_free(ctx, out);
    return st;
}
