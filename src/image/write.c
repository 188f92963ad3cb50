/*
 * PNG and JPEG encoding of persp images, to a path or a stdio stream.
 *
 * Both formats store the top row first and persp images are bottom-up
 * (docs/CONVENTIONS.md), so rows are handed to the encoders last to first.
 *
 * A path that names a regular file (or nothing yet) is written through a
 * temporary file in the same folder and renamed over it only once the
 * encoder, the flush and the close have all succeeded: a reader never sees
 * half an image, and a failure leaves the old file (or no file) behind. Any
 * other existing file is written in place, since renaming over /dev/null or
 * a named pipe would replace the device or pipe itself (for root, in /dev).
 */
#define _XOPEN_SOURCE 700 /* stat */
#include "core/internal.h"
#include "io/outfile.h"

#include <errno.h>
#include <setjmp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <jpeglib.h>
#include <jerror.h>
#include <png.h>

static const char *stream_name(const char *name)
{
    return name && name[0] ? name : "<stream>";
}

static persp_status check_image(persp_context *ctx, const char *name, const persp_image *img)
{
    if (!img->pixels) return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "%s: the image has no pixels", name);
    if (img->width <= 0 || img->height <= 0)
        return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "%s: invalid image size %dx%d", name, img->width,
                           img->height);
    if (img->stride < (size_t)img->width * 4u || img->stride > 0x7fffffffu)
        return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "%s: image stride %zu is not 4·width (%d) .. 2^31",
                           name, img->stride, img->width);
    /* What persp_image_load takes back: no file persp writes is one it
     * refuses to read. */
    return persp__image_check_size(ctx, name, img->width, img->height);
}

/* The quality to encode with, 0 standing for the default. */
static persp_status check_quality(persp_context *ctx, const char *name, int quality, int *out)
{
    if (quality == 0) quality = PERSP_JPEG_QUALITY_DEFAULT;
    if (quality < 1 || quality > 100)
        return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "%s: JPEG quality %d is outside 1..100",
                           name, quality);
    *out = quality;
    return PERSP_OK;
}

/* ------------------------------------------------------------------ PNG */

static persp_status encode_png(persp_context *ctx, FILE *f, const char *name,
                               const persp_image *img)
{
    png_image pi;
    memset(&pi, 0, sizeof pi);
    pi.version = PNG_IMAGE_VERSION;
    pi.width = (png_uint_32)img->width;
    pi.height = (png_uint_32)img->height;
    pi.format = PNG_FORMAT_RGBA;
    /* Negative stride: libpng writes the last stored row (the top) first. */
    png_int_32 stride = -(png_int_32)img->stride;
    errno = 0;
    int ok = png_image_write_to_stdio(&pi, f, 0, img->pixels, stride, NULL);
    int err = errno;
    persp_status st = PERSP_OK;
    if (!ok && ferror(f))
        st = persp__fail(ctx, PERSP_ERR_IO, "%s: write failed: %s", name,
                         err ? strerror(err) : pi.message);
    else if (!ok && (strstr(pi.message, "ut of memory") || strstr(pi.message, "insufficient memory")))
        st = persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "%s: out of memory encoding the PNG", name);
    else if (!ok)
        st = persp__fail(ctx, PERSP_ERR_IO, "%s: PNG encoding failed: %s", name, pi.message);
    png_image_free(&pi);
    return st;
}

/* ----------------------------------------------------------------- JPEG */

/* libjpeg's default error handler calls exit(); this one jumps back so that
 * a failure (a short write included) becomes a status code. */
typedef struct jpeg_write_job {
    struct jpeg_compress_struct cinfo;
    struct jpeg_error_mgr pub;
    jmp_buf jump;
    char message[JMSG_LENGTH_MAX];
    int saved_errno, created;
    FILE *f;
    const persp_image *img;
    int quality;
} jpeg_write_job;

static void jpeg_write_error_exit(j_common_ptr cinfo)
{
    jpeg_write_job *job = (jpeg_write_job *)(void *)cinfo;
    job->saved_errno = errno;
    cinfo->err->format_message(cinfo, job->message);
    longjmp(job->jump, 1);
}

static void jpeg_write_output_message(j_common_ptr cinfo)
{
    (void)cinfo;
}

/* Everything the encoder needs after a longjmp lives in *job, not in
 * registers, so nothing it reads there is indeterminate. 0 on success. */
static int run_jpeg_job(jpeg_write_job *job)
{
    if (setjmp(job->jump)) return 1;
    jpeg_create_compress(&job->cinfo);
    job->created = 1;
    jpeg_stdio_dest(&job->cinfo, job->f);
    job->cinfo.image_width = (JDIMENSION)job->img->width;
    job->cinfo.image_height = (JDIMENSION)job->img->height;
    /* libjpeg-turbo's extended colour space reads RGBA and skips the alpha. */
    job->cinfo.input_components = 4;
    job->cinfo.in_color_space = JCS_EXT_RGBA;
    jpeg_set_defaults(&job->cinfo);
    jpeg_set_quality(&job->cinfo, job->quality, TRUE);
    /* Full-resolution chroma: renders have one-pixel colour edges (texel
     * boundaries, polygon edges) that 4:2:0 would smear over two pixels. */
    job->cinfo.comp_info[0].h_samp_factor = 1;
    job->cinfo.comp_info[0].v_samp_factor = 1;
    jpeg_start_compress(&job->cinfo, TRUE);
    while (job->cinfo.next_scanline < job->cinfo.image_height) {
        size_t row = (size_t)(job->cinfo.image_height - 1u - job->cinfo.next_scanline);
        JSAMPROW rp = job->img->pixels + row * job->img->stride;
        jpeg_write_scanlines(&job->cinfo, &rp, 1);
    }
    jpeg_finish_compress(&job->cinfo);
    return 0;
}

static persp_status encode_jpeg(persp_context *ctx, FILE *f, const char *name,
                                const persp_image *img, int quality)
{
    jpeg_write_job *job = persp__calloc(ctx, 1, sizeof *job);
    if (!job) return persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "%s: out of memory", name);
    job->cinfo.err = jpeg_std_error(&job->pub);
    job->pub.error_exit = jpeg_write_error_exit;
    job->pub.output_message = jpeg_write_output_message;
    job->f = f;
    job->img = img;
    job->quality = quality;
    persp_status st = PERSP_OK;
    if (run_jpeg_job(job)) {
        if (job->pub.msg_code == JERR_OUT_OF_MEMORY)
            st = persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "%s: out of memory encoding the JPEG",
                             name);
        else if (ferror(f))
            st = persp__fail(ctx, PERSP_ERR_IO, "%s: write failed: %s", name,
                             job->saved_errno ? strerror(job->saved_errno) : job->message);
        else
            st = persp__fail(ctx, PERSP_ERR_IO, "%s: JPEG encoding failed: %s", name, job->message);
    }
    if (job->created) jpeg_destroy_compress(&job->cinfo);
    persp__free(ctx, job);
    return st;
}

/* ---------------------------------------------------------------- common */

static persp_status encode(persp_context *ctx, FILE *f, const char *name, const persp_image *img,
                           persp_image_format format, int quality)
{
    if (format == PERSP_IMAGE_FORMAT_JPEG) return encode_jpeg(ctx, f, name, img, quality);
    return encode_png(ctx, f, name, img);
}

/* Through persp__outfile: a temporary file renamed on success for a
 * regular file, in place for a device or pipe. */
static persp_status write_file(persp_context *ctx, const char *path, const persp_image *img,
                               persp_image_format format, int quality)
{
    persp_outfile o;
    persp_status st = persp__outfile_open(ctx, path, &o);
    if (st != PERSP_OK) return st;
    return persp__outfile_close(ctx, &o, encode(ctx, o.f, path, img, format, quality));
}

static int ext_is(const char *ext, const char *want)
{
    for (; *ext && *want; ext++, want++) {
        char c = *ext >= 'A' && *ext <= 'Z' ? (char)(*ext - 'A' + 'a') : *ext;
        if (c != *want) return 0;
    }
    return *ext == '\0' && *want == '\0';
}

persp_status persp_image_format_from_path(const char *path, persp_image_format *out)
{
    if (!path || !out) return PERSP_ERR_INVALID_ARGUMENT;
    const char *base = strrchr(path, '/');
    base = base ? base + 1 : path;
    const char *dot = strrchr(base, '.');
    if (!dot || dot == base) return PERSP_ERR_UNSUPPORTED;
    if (ext_is(dot + 1, "png"))
        *out = PERSP_IMAGE_FORMAT_PNG;
    else if (ext_is(dot + 1, "jpg") || ext_is(dot + 1, "jpeg"))
        *out = PERSP_IMAGE_FORMAT_JPEG;
    else
        return PERSP_ERR_UNSUPPORTED;
    return PERSP_OK;
}

persp_status persp_image_write(persp_context *ctx, const char *path, const persp_image *img,
                               const persp_image_write_desc *desc)
{
    if (!ctx) return PERSP_ERR_INVALID_ARGUMENT;
    persp__clear_error(ctx);
    if (!path || !img) return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "image write: no path or image");
    persp_image_write_desc d = {PERSP_IMAGE_FORMAT_DEFAULT, 0};
    if (desc) d = *desc;
    persp_status st = check_image(ctx, path, img);
    if (st != PERSP_OK) return st;
    struct stat sb;
    int in_place = stat(path, &sb) == 0 && !S_ISREG(sb.st_mode);
    if (d.format == PERSP_IMAGE_FORMAT_DEFAULT &&
        persp_image_format_from_path(path, &d.format) != PERSP_OK) {
        /* A device or pipe is a stream with a name; a folder is refused as
         * one with an extension is (persp.h). */
        if (in_place && S_ISDIR(sb.st_mode))
            return persp__fail(ctx, PERSP_ERR_IO, "%s: is a directory", path);
        if (in_place)
            d.format = PERSP_IMAGE_FORMAT_PNG;
        else
            return persp__fail(ctx, PERSP_ERR_UNSUPPORTED,
                               "%s: unknown image file extension (expected .png, .jpg or .jpeg)",
                               path);
    }
    if (d.format != PERSP_IMAGE_FORMAT_PNG && d.format != PERSP_IMAGE_FORMAT_JPEG)
        return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "%s: unknown image format %d", path,
                           (int)d.format);
    int quality = 0;
    if (d.format == PERSP_IMAGE_FORMAT_JPEG &&
        (st = check_quality(ctx, path, d.quality, &quality)) != PERSP_OK)
        return st;
    return write_file(ctx, path, img, d.format, quality);
}

persp_status persp_image_write_jpeg(persp_context *ctx, const char *path, const persp_image *img,
                                    int quality)
{
    persp_image_write_desc d = {PERSP_IMAGE_FORMAT_JPEG, quality};
    return persp_image_write(ctx, path, img, &d);
}

persp_status persp_image_write_stream(persp_context *ctx, void *stream, const char *name,
                                      const persp_image *img, const persp_image_write_desc *desc)
{
    if (!ctx || !stream || !img) return PERSP_ERR_INVALID_ARGUMENT;
    persp__clear_error(ctx);
    name = stream_name(name);
    persp_image_write_desc d = {PERSP_IMAGE_FORMAT_PNG, 0};
    if (desc) d = *desc;
    if (d.format == PERSP_IMAGE_FORMAT_DEFAULT) d.format = PERSP_IMAGE_FORMAT_PNG;
    persp_status st = check_image(ctx, name, img);
    if (st != PERSP_OK) return st;
    if (d.format != PERSP_IMAGE_FORMAT_PNG && d.format != PERSP_IMAGE_FORMAT_JPEG)
        return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "%s: unknown image format %d", name,
                           (int)d.format);
    int quality = 0;
    if (d.format == PERSP_IMAGE_FORMAT_JPEG &&
        (st = check_quality(ctx, name, d.quality, &quality)) != PERSP_OK)
        return st;
    FILE *f = stream;
    st = encode(ctx, f, name, img, d.format, quality);
    if (st == PERSP_OK && (fflush(f) != 0 || ferror(f)))
        st = persp__fail(ctx, PERSP_ERR_IO, "%s: write failed: %s", name, strerror(errno));
    return st;
}
