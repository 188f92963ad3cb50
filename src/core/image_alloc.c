/*
 * RGBA8 image allocation and the size limits every image obeys. Here rather
 * than with the file formats (src/image/load.c) because built-in scenes,
 * textures and framebuffers allocate images without reading any file.
 */
#include "core/internal.h"

#include <stdint.h>
#include <string.h>

persp_status persp__image_check_size(persp_context *ctx, const char *name, long long w, long long h)
{
    if (w <= 0 || h <= 0)
        return persp__fail(ctx, PERSP_ERR_FORMAT, "%s: image has an empty size %lldx%lld", name,
                           w, h);
    if (w > PERSP_IMAGE_MAX_SIDE || h > PERSP_IMAGE_MAX_SIDE ||
        (unsigned long long)w * (unsigned long long)h > PERSP_IMAGE_MAX_PIXELS)
        return persp__fail(ctx, PERSP_ERR_TOO_LARGE,
                           "%s: image size %lldx%lld exceeds the limit (side %d, %u pixels)", name,
                           w, h, PERSP_IMAGE_MAX_SIDE, PERSP_IMAGE_MAX_PIXELS);
    return PERSP_OK;
}

#define IMAGE_ALIGN 64

/* Kept just before the pixels of every image persp allocates, and linked
 * into the context's list. persp_image_free looks an image's pixel pointer
 * up in that list before reading anything around it: the pixels of an image
 * the caller filled in (borrowed) are never in it, so persp_image_free
 * leaves them alone instead of reading memory in front of them. */
struct persp_image_block {
    struct persp_image_block *prev, *next;
    void *raw; /* the allocation, for persp__free */
};

persp_status persp_image_alloc(persp_context *ctx, int width, int height, persp_image *out)
{
    if (!ctx) return PERSP_ERR_INVALID_ARGUMENT;
    persp__clear_error(ctx);
    if (!out) return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "image: no image to fill");
    memset(out, 0, sizeof *out);
    if (width <= 0 || height <= 0)
        return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "image: invalid size %dx%d", width,
                           height);
    persp_status st = persp__image_check_size(ctx, "image", width, height);
    if (st != PERSP_OK) return st;
    size_t stride = (size_t)width * 4u;
    /* Pixels start on a 64-byte boundary (the allocator guarantees 16): an
     * image used as a framebuffer then shares no cache line between tiles
     * drawn by different threads (docs/PERFORMANCE.md). */
    const size_t head = sizeof(struct persp_image_block);
    size_t bytes = (size_t)height * stride + IMAGE_ALIGN + head;
    uint8_t *raw = persp__calloc(ctx, 1, bytes);
    if (!raw)
        return persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "image: out of memory for %dx%d", width,
                           height);
    uintptr_t at = ((uintptr_t)raw + head + IMAGE_ALIGN - 1) & ~(uintptr_t)(IMAGE_ALIGN - 1);
    uint8_t *px = raw + (at - (uintptr_t)raw);
    struct persp_image_block b = {NULL, ctx->images, raw};
    memcpy(px - head, &b, head);
    struct persp_image_block *node = (struct persp_image_block *)(void *)(px - head);
    if (ctx->images) ctx->images->prev = node;
    ctx->images = node;
    out->width = width;
    out->height = height;
    out->stride = stride;
    out->pixels = px;
    return PERSP_OK;
}

void persp_image_free(persp_context *ctx, persp_image *img)
{
    if (!img || !img->pixels) return;
    if (!ctx) return;
    struct persp_image_block *b = ctx->images;
    while (b && (const uint8_t *)(b + 1) != img->pixels) b = b->next;
    if (!b) {
        /* Borrowed pixels (or another context's): not persp's to free. */
        persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT,
                    "persp_image_free: these pixels were not allocated by this context's "
                    "persp_image_alloc or persp_image_load; left as they are");
        return;
    }
    if (b->prev) b->prev->next = b->next;
    else ctx->images = b->next;
    if (b->next) b->next->prev = b->prev;
    persp__free(ctx, b->raw);
    memset(img, 0, sizeof *img);
}

void persp__image_set_opaque(persp_image *img)
{
    if (!img || !img->pixels) return;
    for (int y = 0; y < img->height; y++) {
        uint8_t *row = img->pixels + (size_t)y * img->stride;
        for (int x = 0; x < img->width; x++)
            row[4 * x + 3] = 255;
    }
}
