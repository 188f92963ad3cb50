/*
 * RGBA8 images: PNG and JPEG decoding (format detected from the content);
 * encoding is in image_write.c, allocation in src/core/image.c.
 *
 * Rows are stored bottom-to-top (row 0 = bottom of the displayed image,
 * docs/CONVENTIONS.md); both file formats store the top row first, so every
 * decode and encode flips. Sizes read from a file header are checked against
 * PERSP_IMAGE_MAX_SIDE / PERSP_IMAGE_MAX_PIXELS before anything is allocated,
 * so a forged header cannot make persp allocate gigabytes.
 */
#include "core/internal.h"
#include "io/text.h"

#include <errno.h>
#include <setjmp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <jpeglib.h>
#include <png.h>

static const char *display_name(const char *name)
{
    return name && name[0] ? name : "<memory>";
}

static persp_status check_size(persp_context *ctx, const char *name, long long w, long long h)
{
    return persp__image_check_size(ctx, display_name(name), w, h);
}

/* ------------------------------------------------------------------ PNG */

static uint32_t be32(const unsigned char *p)
{
    return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | (uint32_t)p[3];
}

/* Walks the chunk structure (PNG specification §5.3: length, type, data,
 * CRC) from the signature to IEND. The IHDR size is checked here, before
 * libpng sees the file, so a forged header is refused whatever follows it;
 * and a file cut anywhere, even after the last image data (which libpng's
 * simplified reader accepts), is reported as truncated. */
static persp_status check_png_structure(persp_context *ctx, const unsigned char *b, size_t size,
                                        const char *name)
{
    size_t pos = 8;
    int first = 1;
    for (;;) {
        if (size - pos < 12)
            return persp__fail(ctx, PERSP_ERR_FORMAT,
                                      "%s: truncated PNG: the file ends inside a chunk at byte %zu "
                                      "(no IEND chunk)",
                                      display_name(name), pos);
        uint32_t len = be32(b + pos);
        const unsigned char *type = b + pos + 4;
        if (len > 0x7fffffffu)
            return persp__fail(ctx, PERSP_ERR_FORMAT, "%s: invalid PNG: chunk length %u at byte %zu",
                                      display_name(name), (unsigned)len, pos);
        if (first) {
            if (memcmp(type, "IHDR", 4) != 0 || len != 13)
                return persp__fail(ctx, PERSP_ERR_FORMAT,
                                          "%s: invalid PNG: the first chunk is not IHDR",
                                          display_name(name));
            if (size - pos < 20)
                return persp__fail(ctx, PERSP_ERR_FORMAT, "%s: truncated PNG header",
                                          display_name(name));
            persp_status st = check_size(ctx, name, (long long)be32(b + pos + 8),
                                         (long long)be32(b + pos + 12));
            if (st != PERSP_OK) return st;
            first = 0;
        }
        if ((size - pos - 12) < (size_t)len)
            return persp__fail(ctx, PERSP_ERR_FORMAT,
                                      "%s: truncated PNG: chunk %.4s at byte %zu needs %u bytes, "
                                      "%zu remain",
                                      display_name(name), (const char *)type, pos, (unsigned)len,
                                      size - pos - 12);
        if (memcmp(type, "IEND", 4) == 0) return PERSP_OK;
        pos += 12 + (size_t)len;
    }
}

static persp_status load_png(persp_context *ctx, const void *data, size_t size, const char *name,
                             persp_image *out)
{
    persp_status cst = check_png_structure(ctx, data, size, name);
    if (cst != PERSP_OK) return cst;
    png_image pi;
    memset(&pi, 0, sizeof pi);
    pi.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_memory(&pi, data, size)) {
        persp_status st = persp__fail(ctx, PERSP_ERR_FORMAT, "%s: invalid PNG: %s",
                                             display_name(name), pi.message);
        png_image_free(&pi);
        return st;
    }
    persp_status st = check_size(ctx, name, (long long)pi.width, (long long)pi.height);
    if (st != PERSP_OK) {
        png_image_free(&pi);
        return st;
    }
    pi.format = PNG_FORMAT_RGBA;
    st = persp_image_alloc(ctx, (int)pi.width, (int)pi.height, out);
    if (st != PERSP_OK) {
        png_image_free(&pi);
        return st;
    }
    /* A negative row stride makes libpng store the file's first (top) row
     * last, which is exactly the bottom-up layout of persp_image. */
    png_int_32 stride = -(png_int_32)out->stride;
    if (!png_image_finish_read(&pi, NULL, out->pixels, stride, NULL)) {
        st = persp__fail(ctx, PERSP_ERR_FORMAT, "%s: corrupt or truncated PNG: %s",
                                display_name(name), pi.message);
        png_image_free(&pi);
        persp_image_free(ctx, out);
        return st;
    }
    png_image_free(&pi);
    return PERSP_OK;
}

/* ----------------------------------------------------------------- JPEG */

/* libjpeg's default error handler calls exit(); this one jumps back to the
 * decoder so a corrupt file becomes a status code. Warnings (e.g. premature
 * end of data, which libjpeg pads with grey) are counted and reported as
 * errors too: a silently patched image is not the file the user gave. */
typedef struct jpeg_err {
    struct jpeg_error_mgr pub;
    jmp_buf jump;
    char message[JMSG_LENGTH_MAX];
    int warnings;
} jpeg_err;

static void jpeg_error_exit(j_common_ptr cinfo)
{
    jpeg_err *e = (jpeg_err *)(void *)cinfo->err;
    cinfo->err->format_message(cinfo, e->message);
    longjmp(e->jump, 1);
}

static void jpeg_emit_message(j_common_ptr cinfo, int level)
{
    jpeg_err *e = (jpeg_err *)(void *)cinfo->err;
    if (level < 0 && e->warnings++ == 0) cinfo->err->format_message(cinfo, e->message);
}

static void jpeg_output_message(j_common_ptr cinfo)
{
    (void)cinfo;
}

typedef struct jpeg_job {
    struct jpeg_decompress_struct cinfo;
    jpeg_err err;
    persp_image img;
} jpeg_job;

/* The setjmp lives in its own function whose locals are all in *job (not in
 * registers), so nothing it needs after a longjmp is indeterminate. */
static persp_status decode_jpeg(persp_context *ctx, const unsigned char *data, size_t size,
                                const char *name, jpeg_job *job)
{
    if (setjmp(job->err.jump)) {
        persp_image_free(ctx, &job->img);
        return persp__fail(ctx, PERSP_ERR_FORMAT, "%s: corrupt JPEG: %s",
                                  display_name(name), job->err.message);
    }
    jpeg_create_decompress(&job->cinfo);
    jpeg_mem_src(&job->cinfo, data, (unsigned long)size);
    jpeg_read_header(&job->cinfo, TRUE);
    persp_status st = check_size(ctx, name, (long long)job->cinfo.image_width,
                                 (long long)job->cinfo.image_height);
    if (st != PERSP_OK) return st;
    /* libjpeg-turbo's extended colour spaces convert grey and YCbCr input
     * straight to RGBA with an opaque alpha. */
    job->cinfo.out_color_space = JCS_EXT_RGBA;
    jpeg_start_decompress(&job->cinfo);
    if (job->cinfo.output_components != 4)
        return persp__fail(ctx, PERSP_ERR_UNSUPPORTED, "%s: unsupported JPEG colour layout",
                                  display_name(name));
    st = persp_image_alloc(ctx, (int)job->cinfo.output_width, (int)job->cinfo.output_height,
                           &job->img);
    if (st != PERSP_OK) return st;
    while (job->cinfo.output_scanline < job->cinfo.output_height) {
        size_t row = (size_t)(job->cinfo.output_height - 1u - job->cinfo.output_scanline);
        JSAMPROW rp = job->img.pixels + row * job->img.stride;
        jpeg_read_scanlines(&job->cinfo, &rp, 1);
    }
    jpeg_finish_decompress(&job->cinfo);
    if (job->err.warnings > 0) {
        persp_image_free(ctx, &job->img);
        return persp__fail(ctx, PERSP_ERR_FORMAT, "%s: corrupt JPEG: %s",
                                  display_name(name), job->err.message);
    }
    return PERSP_OK;
}

static persp_status load_jpeg(persp_context *ctx, const void *data, size_t size, const char *name,
                              persp_image *out)
{
    jpeg_job *job = persp__calloc(ctx, 1, sizeof *job);
    if (!job) return persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "%s: out of memory",
                                        display_name(name));
    job->cinfo.err = jpeg_std_error(&job->err.pub);
    job->err.pub.error_exit = jpeg_error_exit;
    job->err.pub.emit_message = jpeg_emit_message;
    job->err.pub.output_message = jpeg_output_message;
    persp_status st = decode_jpeg(ctx, data, size, name, job);
    jpeg_destroy_decompress(&job->cinfo);
    if (st == PERSP_OK) {
        *out = job->img;
    } else {
        persp_image_free(ctx, &job->img);
    }
    persp__free(ctx, job);
    return st;
}

/* ----------------------------------------------------------------- entry */

persp_status persp_image_load_memory(persp_context *ctx, const void *data, size_t size,
                                     const char *name, persp_image *out)
{
    if (!ctx || !out || (!data && size)) return PERSP_ERR_INVALID_ARGUMENT;
    persp__clear_error(ctx);
    memset(out, 0, sizeof *out);
    static const unsigned char png_sig[8] = {0x89, 'P', 'N', 'G', 0x0d, 0x0a, 0x1a, 0x0a};
    const unsigned char *b = data;
    if (size >= 8 && memcmp(b, png_sig, 8) == 0) return load_png(ctx, data, size, name, out);
    if (size >= 3 && b[0] == 0xff && b[1] == 0xd8 && b[2] == 0xff)
        return load_jpeg(ctx, data, size, name, out);
    return persp__fail(ctx, PERSP_ERR_FORMAT, "%s: not a PNG or JPEG image",
                              display_name(name));
}

persp_status persp_image_load(persp_context *ctx, const char *path, persp_image *out)
{
    if (!ctx || !path || !out) return PERSP_ERR_INVALID_ARGUMENT;
    persp__clear_error(ctx);
    memset(out, 0, sizeof *out);
    /* A directory opens and seeks on some systems and then reports a
     * nonsense size; name the problem instead. */
    struct stat sb;
    if (stat(path, &sb) == 0 && S_ISDIR(sb.st_mode))
        return persp__fail(ctx, PERSP_ERR_IO, "%s: is a directory, not an image file", path);
    char *data = NULL;
    size_t size = 0;
    persp_status st = persp__read_file(ctx, path, &data, &size);
    if (st != PERSP_OK) return st;
    st = persp_image_load_memory(ctx, data, size, path, out);
    persp__free(ctx, data);
    return st;
}

persp_status persp_image_write_png(persp_context *ctx, const char *path, const persp_image *img)
{
    persp_image_write_desc desc = {PERSP_IMAGE_FORMAT_PNG, 0};
    return persp_image_write(ctx, path, img, &desc);
}
