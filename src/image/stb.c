/*
 * GIF and Radiance HDR through stb_image (Debian's libstb-dev), built here
 * with only those two readers and no file access.
 *
 * stb_image allocates with malloc, which the context's allocator cannot
 * see, so its working memory is reserved from the memory budget before it
 * runs, by the size the header declares (checked against the image limits
 * first): a GIF frame is decoded into the image, its background and a
 * history of one byte a pixel (stbi__gif_load_next), an HDR into floats
 * and then into bytes (stbi__hdr_load, stbi__hdr_to_ldr).
 *
 * A GIF gives its first frame (a texture is one picture; an animation's
 * later frames are not drawn). An HDR is tone-mapped to 8 bits as stb
 * maps it, each channel c to 255·c^(1/2.2) clamped to [0, 255]: the
 * radiance taken as linear light of which 1 is the brightest displayed,
 * the sRGB-like gamma of the other textures; brighter values clip. An HDR
 * texture in a model is a light map or a sky, to be seen, not refused.
 */
#include "image/decoders.h"

#include <limits.h>
#include <stdint.h>
#include <stdlib.h>

#define STBI_ONLY_GIF
#define STBI_ONLY_HDR
#define STBI_NO_STDIO
#define STBI_NO_LINEAR
#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
/* Third-party code, as Debian ships it, under persp's warning flags. */
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wconversion"
#pragma GCC diagnostic ignored "-Wsign-conversion"
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#pragma GCC diagnostic ignored "-Wpedantic"
#pragma GCC diagnostic ignored "-Wdouble-promotion"
#pragma GCC diagnostic ignored "-Wcast-qual"
#pragma GCC diagnostic ignored "-Wimplicit-fallthrough"
#include <stb_image.h>
#pragma GCC diagnostic pop
/* Declared static by STB_IMAGE_STATIC and left out by STBI_ONLY_*: GCC
 * says so at the end of the file, past the pop above. */
#pragma GCC diagnostic ignored "-Wunused-function"

/* Bytes of stb's working memory a pixel: GIF 4 (frame) + 4 (background) +
 * 1 (history) + 4 (the copy it returns); HDR 16 (floats) + 4 (bytes). */
#define GIF_WORK_PER_PIXEL 13u
#define HDR_WORK_PER_PIXEL 20u

int persp__gif_recognised(const unsigned char *data, size_t size)
{
    return size >= 6 && (!memcmp(data, "GIF87a", 6) || !memcmp(data, "GIF89a", 6));
}

int persp__hdr_recognised(const unsigned char *data, size_t size)
{
    return (size >= 11 && !memcmp(data, "#?RADIANCE\n", 11)) || (size >= 7 && !memcmp(data, "#?RGBE\n", 7));
}

persp_status persp__load_stb(persp_context *ctx, const unsigned char *data, size_t size, const char *name,
                             persp_image *out)
{
    memset(out, 0, sizeof *out);
    const int gif = persp__gif_recognised(data, size);
    const char *format = gif ? "GIF" : "Radiance HDR";
    if (size > INT_MAX) return persp__fail(ctx, PERSP_ERR_TOO_LARGE, "%s: a %s file over 2 GiB", name, format);
    int w = 0, h = 0, comp = 0;
    if (!stbi_info_from_memory(data, (int)size, &w, &h, &comp))
        return persp__fail(ctx, PERSP_ERR_FORMAT, "%s: a malformed %s header (%s)", name, format,
                           stbi_failure_reason() ? stbi_failure_reason() : "unreadable");
    persp_status st = persp__image_check_size(ctx, name, w, h);
    if (st != PERSP_OK) return st;
    /* Each byte of the file yields at most so many pixels (GIF: a 12-bit
     * LZW code stands for at most 4096 indices, GIF89a Appendix F; HDR: an
     * RLE run of at most 127 values takes 2 bytes for each of the 4
     * components, Radiance's "new" scanline coding): a header declaring
     * more than the file can hold is refused before stb allocates for it. */
    const uint64_t most = (uint64_t)size * (gif ? 2730u : 31u) + 4096u;
    if ((uint64_t)w * (uint64_t)h > most)
        return persp__fail(ctx, PERSP_ERR_FORMAT, "%s: the %s header declares %dx%d pixels, more than the file's "
                           "%zu bytes can hold", name, format, w, h, size);
    const size_t work = (size_t)w * (size_t)h * (gif ? GIF_WORK_PER_PIXEL : HDR_WORK_PER_PIXEL) + 4096;
    char what[PERSP_ERRMSG_BYTES / 2];
    snprintf(what, sizeof what, "%s: decoding the %s image", name, format);
    st = persp__mem_reserve(ctx, work, what);
    if (st != PERSP_OK) return st;
    int dw = 0, dh = 0;
    unsigned char *px = stbi_load_from_memory(data, (int)size, &dw, &dh, &comp, 4);
    if (!px) {
        persp__mem_release(ctx, work);
        const char *why = stbi_failure_reason();
        if (why && !strcmp(why, "outofmem"))
            return persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "%s: out of memory decoding the %s image", name,
                               format);
        return persp__fail(ctx, PERSP_ERR_FORMAT, "%s: a malformed %s image (%s)", name, format,
                           why ? why : "unreadable");
    }
    if (dw != w || dh != h) {
        stbi_image_free(px);
        persp__mem_release(ctx, work);
        return persp__fail(ctx, PERSP_ERR_FORMAT, "%s: the %s image is %dx%d, its header says %dx%d", name, format,
                           dw, dh, w, h);
    }
    st = persp__decoder_alloc(ctx, name, w, h, out);
    if (st == PERSP_OK) {
        /* stb's rows run top first; persp's row 0 is the bottom. */
        for (int y = 0; y < h; y++)
            memcpy(out->pixels + (size_t)(h - 1 - y) * out->stride, px + (size_t)y * (size_t)w * 4,
                   (size_t)w * 4);
    }
    stbi_image_free(px);
    persp__mem_release(ctx, work);
    return st;
}
