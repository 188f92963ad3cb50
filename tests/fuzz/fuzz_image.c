/* libFuzzer harness: PNG and JPEG decoding from memory
 * (persp_image_load_memory), the path every texture of a scene or model
 * takes. The context's allocator refuses any block over 1 MiB: images of
 * fewer than 2^18 pixels decode, larger ones reach the header checks
 * against PERSP_IMAGE_MAX_SIDE / _PIXELS and then the out-of-memory path
 * (libpng and libjpeg allocate with malloc, not through it), so the
 * fuzzer explores the size limits with small inputs instead of spending
 * its time allocating and decoding gigabytes. Checked besides crashes:
 * a decoded image has a size within the limits and a stride of 4 bytes a
 * texel or more; a refused one leaves *out zeroed (nothing half-made) and a
 * one-line detail. */
#include "confine.h"
#include "persp.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define BLOCK_LIMIT ((size_t)1 << 20)

static void *capped_alloc(void *user, size_t size)
{
    (void)user;
    return size > BLOCK_LIMIT ? NULL : malloc(size);
}

static void capped_free(void *user, void *ptr)
{
    (void)user;
    free(ptr);
}

/* detail: the context's, or NULL. */
static void broken(const char *what, const char *detail)
{
    fprintf(stderr, "fuzz_image: invariant broken: %s%s%s%s\n", what, detail ? " ('" : "",
            detail ? detail : "", detail ? "')" : "");
    abort();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const persp_allocator capped = {capped_alloc, capped_free, NULL};
    const persp_context_desc desc = {&capped, 1};
    persp_context *ctx = NULL;
    if (persp_context_create(&desc, &ctx) != PERSP_OK) return 0;
    fuzz_confine(1);
    persp_image img;
    persp_status st = persp_image_load_memory(ctx, data, size, "fuzz", &img);
    fuzz_confine(0);
    if (st == PERSP_OK) {
        if (img.width < 1 || img.height < 1 || img.width > PERSP_IMAGE_MAX_SIDE ||
            img.height > PERSP_IMAGE_MAX_SIDE ||
            (unsigned long long)img.width * (unsigned long long)img.height >
                PERSP_IMAGE_MAX_PIXELS ||
            img.stride < (size_t)img.width * 4u || !img.pixels)
            broken("a decoded image outside the limits", NULL);
        persp_image_free(ctx, &img);
    } else {
        static const persp_image zero;
        if (memcmp(&img, &zero, sizeof img) != 0) broken("a refused image left *out filled in", NULL);
        const char *e = persp_context_error(ctx);
        if (!e[0]) broken("a refused image left no detail", NULL);
        if (strpbrk(e, "\r\n")) broken("a refused image's detail is not one line", e);
    }
    persp_context_destroy(ctx);
    return 0;
}
