/*
 * persp's own decoders, for the image formats that have no system library
 * persp links (PNG and JPEG are read through libpng and libjpeg in
 * load.c): Truevision TGA (tga.c), Windows BMP (bmp.c) and Netpbm
 * (pnm.c); GIF and Radiance HDR through stb_image (stb.c), whose working
 * memory is reserved from the budget.
 *
 * Each reads a whole file from memory into RGBA8, row 0 the bottom row of
 * the displayed picture (persp.h), alpha 255 where the file has none. Every
 * size and offset is checked against the buffer before it is read, the
 * image size against PERSP_IMAGE_MAX_SIDE / _PIXELS before anything is
 * allocated, and the only allocation is the image itself. On failure ctx
 * holds a one-line detail beginning with name and *out is zeroed.
 */
#ifndef PERSP_IO_IMAGE_DECODERS_H
#define PERSP_IO_IMAGE_DECODERS_H

#include "core/internal.h"

#include <stddef.h>
#include <stdio.h>
#include <string.h>

/* Nonzero when the first bytes are a consistent TGA header (TGA has no
 * signature): a known image type, colour-map fields that agree with it, a
 * pixel depth the type allows, a non-empty size, and the fields TGA 2.0
 * says to leave zero left zero. For files whose name does not say .tga. */
int persp__tga_recognised(const unsigned char *data, size_t size);

persp_status persp__load_tga(persp_context *ctx, const unsigned char *data, size_t size,
                             const char *name, persp_image *out);
persp_status persp__load_bmp(persp_context *ctx, const unsigned char *data, size_t size,
                             const char *name, persp_image *out);

/* Netpbm P1 to P6 (pnm.c): "P", the digit, then white space. */
int persp__pnm_recognised(const unsigned char *data, size_t size);
persp_status persp__load_pnm(persp_context *ctx, const unsigned char *data, size_t size,
                             const char *name, persp_image *out);

/* GIF (its first frame) and Radiance HDR (tone-mapped) through stb_image
 * (stb.c), by their signatures. */
int persp__gif_recognised(const unsigned char *data, size_t size);
int persp__hdr_recognised(const unsigned char *data, size_t size);
persp_status persp__load_stb(persp_context *ctx, const unsigned char *data, size_t size,
                             const char *name, persp_image *out);

/* persp_image_alloc whose detail names the file: its own says "image: ...",
 * and keeps what it adds about the memory budget. */
static inline persp_status persp__decoder_alloc(persp_context *ctx, const char *name, int w,
                                                int h, persp_image *out)
{
    persp_status st = persp_image_alloc(ctx, w, h, out);
    if (st == PERSP_OK) return st;
    char detail[PERSP_ERRMSG_BYTES];
    const char *e = persp_context_error(ctx);
    if (strncmp(e, "image: ", 7) == 0) e += 7;
    snprintf(detail, sizeof detail, "%s", e);
    return persp__fail(ctx, st, "%s: %s", name, detail);
}

#endif
