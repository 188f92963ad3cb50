/*
 * RGBA8 images: PNG and JPEG decoding, and the choice of decoder (by the
 * content; TGA, which has no signature, also by the name); TGA, BMP and
 * Netpbm are decoded in tga.c, bmp.c and pnm.c, GIF and Radiance HDR in
 * stb.c; encoding is in write.c, allocation in src/core/image_alloc.c.
 *
 * Rows are stored bottom-to-top (row 0 = bottom of the displayed image,
 * docs/CONVENTIONS.md); both file formats store the top row first, so every
 * decode and encode flips. Sizes read from a file header are checked against
 * PERSP_IMAGE_MAX_SIDE / PERSP_IMAGE_MAX_PIXELS before anything is allocated,
 * so a forged header cannot make persp allocate gigabytes.
 */
#include "core/internal.h"
#include "image/decoders.h"
#include "io/text.h"

#include <errno.h>
#include <limits.h>
#include <setjmp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

#include <jpeglib.h>
#include <jerror.h>
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

/* libpng reports a failed allocation through its error message only
 * (png_malloc's "Out of memory", the chunk readers' "insufficient memory");
 * the simplified API keeps no separate code. */
static int png_out_of_memory(const char *message)
{
    for (const char *p = message; *p; p++)
        if (!strncasecmp(p, "out of memory", 13) || !strncasecmp(p, "insufficient memory", 19))
            return 1;
    return 0;
}

static persp_status png_failure(persp_context *ctx, const char *name, const char *what,
                                const char *message)
{
    if (png_out_of_memory(message))
        return persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "%s: out of memory decoding the PNG",
                           display_name(name));
    return persp__fail(ctx, PERSP_ERR_FORMAT, "%s: %s: %s", display_name(name), what, message);
}

/* A paletted PNG whose pixels name entries past the end of PLTE is invalid
 * (PNG specification §11.2.3: "the number of palette entries shall not
 * exceed ... and pixels shall not index beyond"); libpng's simplified RGBA
 * reader maps such pixels to black without a word. Read through the
 * colour-map format instead, which hands over the indices themselves, check
 * them, and expand them here. */
static persp_status finish_png_palette(persp_context *ctx, png_image *pi, const char *name,
                                       persp_image *out)
{
    size_t w = pi->width, h = pi->height;
    uint8_t *idx = persp__calloc(ctx, w, h);
    if (!idx)
        return persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "%s: out of memory",
                           display_name(name));
    uint8_t map[256 * 4];
    pi->format = PNG_FORMAT_RGBA_COLORMAP;
    persp_status st = PERSP_OK;
    if (!png_image_finish_read(pi, NULL, idx, 0, map)) {
        st = png_failure(ctx, name, "corrupt or truncated PNG", pi->message);
    } else {
        for (size_t y = 0; y < h && st == PERSP_OK; y++) {
            const uint8_t *row = idx + y * w; /* top row first */
            uint8_t *dst = out->pixels + (h - 1 - y) * out->stride;
            for (size_t x = 0; x < w; x++) {
                if (row[x] >= pi->colormap_entries) {
                    st = persp__fail(ctx, PERSP_ERR_FORMAT,
                                     "%s: invalid PNG: pixel (%zu, %zu) uses palette index %u, "
                                     "the palette has %u entries",
                                     display_name(name), x, y, (unsigned)row[x],
                                     (unsigned)pi->colormap_entries);
                    break;
                }
                memcpy(dst + 4 * x, map + 4 * (size_t)row[x], 4);
            }
        }
    }
    persp__free(ctx, idx);
    return st;
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
        persp_status st = png_failure(ctx, name, "invalid PNG", pi.message);
        png_image_free(&pi);
        return st;
    }
    persp_status st = check_size(ctx, name, (long long)pi.width, (long long)pi.height);
    if (st != PERSP_OK) {
        png_image_free(&pi);
        return st;
    }
    const int paletted = (pi.format & PNG_FORMAT_FLAG_COLORMAP) != 0;
    pi.format = PNG_FORMAT_RGBA;
    /* libpng's simplified reader takes 16-bit samples without gAMA, sRGB or
     * iCCP for linear light and gamma-encodes them on the way to 8 bits,
     * brightening them. Such files nearly always hold the same sRGB values
     * as their 8-bit originals (image editors write them that way), so they
     * are read as sRGB; a gAMA chunk still says otherwise. */
    pi.flags |= PNG_IMAGE_FLAG_16BIT_sRGB;
    /* libpng's simplified API allocates with malloc and takes no hooks; what
     * it holds while reading is its state, zlib's inflate window and a few
     * rows (libpng 1.6 pngrutil.c png_read_start_row: the row and previous
     * row, and one more for the simplified API's conversions), at most 8
     * bytes per pixel of the widest format, reserved before it starts. */
    size_t work = 4u * (8u * (size_t)pi.width + 64u) + (size_t)256 * 1024;
    char what[PERSP_ERRMSG_BYTES / 2];
    snprintf(what, sizeof what, "%s: decoding the %ux%u PNG", display_name(name),
             (unsigned)pi.width, (unsigned)pi.height);
    if ((st = persp__mem_reserve(ctx, work, what)) != PERSP_OK) {
        png_image_free(&pi);
        return st;
    }
    st = persp_image_alloc(ctx, (int)pi.width, (int)pi.height, out);
    if (st != PERSP_OK) {
        persp__mem_release(ctx, work);
        png_image_free(&pi);
        return st;
    }
    /* A negative row stride makes libpng store the file's first (top) row
     * last, which is exactly the bottom-up layout of persp_image. */
    png_int_32 stride = -(png_int_32)out->stride;
    if (paletted) {
        st = finish_png_palette(ctx, &pi, name, out);
        png_image_free(&pi);
        if (st != PERSP_OK) persp_image_free(ctx, out);
        return st;
    }
    if (!png_image_finish_read(&pi, NULL, out->pixels, stride, NULL)) {
        st = png_failure(ctx, name, "corrupt or truncated PNG", pi.message);
        png_image_free(&pi);
        persp__mem_release(ctx, work);
        persp_image_free(ctx, out);
        return st;
    }
    png_image_free(&pi);
    persp__mem_release(ctx, work);
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
    size_t reserved; /* of the memory budget, for libjpeg's working memory */
    persp_image img;
} jpeg_job;

/* Adobe applications write CMYK (and YCCK) JPEGs with inverted samples
 * (255 = no ink) and mark them with an APP14 "Adobe" segment; plain CMYK is
 * taken as ink amounts. Converted without a colour profile:
 * R = (1 - C)(1 - K), and so on. */
static void cmyk_to_rgba(uint8_t *px, size_t n, int inverted)
{
    for (size_t i = 0; i < n; i++, px += 4) {
        unsigned c = px[0], m = px[1], y = px[2], k = px[3];
        if (!inverted) c = 255 - c, m = 255 - m, y = 255 - y, k = 255 - k;
        px[0] = (uint8_t)((c * k + 127) / 255);
        px[1] = (uint8_t)((m * k + 127) / 255);
        px[2] = (uint8_t)((y * k + 127) / 255);
        px[3] = 255;
    }
}

static unsigned rd16(const unsigned char *p, int le)
{
    return le ? (unsigned)p[0] | (unsigned)p[1] << 8 : (unsigned)p[0] << 8 | (unsigned)p[1];
}

static uint32_t rd32(const unsigned char *p, int le)
{
    return le ? (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24
              : (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | (uint32_t)p[3];
}

/* The Orientation tag (0x0112) of an APP1 Exif segment's first IFD (TIFF
 * 6.0 / Exif 2.3 §4.6.4), 1..8; 1 (as stored) when absent or malformed. */
static int exif_orientation(const struct jpeg_decompress_struct *cinfo)
{
    for (jpeg_saved_marker_ptr m = cinfo->marker_list; m; m = m->next) {
        if (m->marker != JPEG_APP0 + 1 || m->data_length < 14 ||
            memcmp(m->data, "Exif\0\0", 6) != 0)
            continue;
        const unsigned char *t = m->data + 6;
        size_t n = m->data_length - 6;
        int le = t[0] == 'I' && t[1] == 'I';
        if (!le && !(t[0] == 'M' && t[1] == 'M')) continue;
        if (rd16(t + 2, le) != 42) continue;
        uint32_t ifd = rd32(t + 4, le);
        if (ifd > n - 2 || n < 2) continue;
        unsigned count = rd16(t + ifd, le);
        for (unsigned i = 0; i < count; i++) {
            size_t e = (size_t)ifd + 2 + 12 * (size_t)i;
            if (e + 12 > n) break;
            /* SHORT (type 3), one value, left-justified in the value field */
            if (rd16(t + e, le) == 0x0112 && rd16(t + e + 2, le) == 3) {
                unsigned o = rd16(t + e + 8, le);
                return o >= 1 && o <= 8 ? (int)o : 1;
            }
        }
    }
    return 1;
}

/* Turns img (rows bottom-up, as decoded) the way the Exif orientation says
 * the picture is meant to be seen. */
static persp_status apply_orientation(persp_context *ctx, int orient, persp_image *img)
{
    if (orient == 1) return PERSP_OK;
    const int W = img->width, H = img->height;
    const int swap = orient >= 5;
    persp_image out;
    persp_status st = persp_image_alloc(ctx, swap ? H : W, swap ? W : H, &out);
    if (st != PERSP_OK) return st;
    const int OW = out.width, OH = out.height;
    for (int y = 0; y < OH; y++) { /* displayed row, top first */
        uint32_t *dst = (uint32_t *)(void *)(out.pixels + (size_t)(OH - 1 - y) * out.stride);
        for (int x = 0; x < OW; x++) {
            int sx, sy; /* stored pixel, top-first rows */
            switch (orient) {
            case 2:
                sx = W - 1 - x, sy = y;
                break;
            case 3:
                sx = W - 1 - x, sy = H - 1 - y;
                break;
            case 4:
                sx = x, sy = H - 1 - y;
                break;
            case 5:
                sx = y, sy = x;
                break;
            case 6:
                sx = y, sy = H - 1 - x;
                break;
            case 7:
                sx = W - 1 - y, sy = H - 1 - x;
                break;
            default:
                sx = W - 1 - y, sy = x;
                break; /* 8 */
            }
            const uint32_t *src =
                (const uint32_t *)(const void *)(img->pixels + (size_t)(H - 1 - sy) * img->stride);
            dst[x] = src[sx];
        }
    }
    persp_image_free(ctx, img);
    *img = out;
    return PERSP_OK;
}

/* The setjmp lives in its own function whose locals are all in *job (not in
 * registers), so nothing it needs after a longjmp is indeterminate. */
static persp_status decode_jpeg(persp_context *ctx, const unsigned char *data, size_t size,
                                const char *name, jpeg_job *job)
{
    if (setjmp(job->err.jump)) {
        persp_image_free(ctx, &job->img);
        /* libjpeg's memory manager fails with JERR_OUT_OF_MEMORY (jerror.h),
         * which is no fault of the file. */
        if (job->err.pub.msg_code == JERR_OUT_OF_MEMORY)
            return persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "%s: out of memory decoding the JPEG",
                               display_name(name));
        return persp__fail(ctx, PERSP_ERR_FORMAT, "%s: corrupt JPEG: %s",
                                  display_name(name), job->err.message);
    }
    jpeg_create_decompress(&job->cinfo);
    jpeg_mem_src(&job->cinfo, data, (unsigned long)size);
    jpeg_save_markers(&job->cinfo, JPEG_APP0 + 1, 0xffff);
    jpeg_read_header(&job->cinfo, TRUE);
    persp_status st = check_size(ctx, name, (long long)job->cinfo.image_width,
                                 (long long)job->cinfo.image_height);
    if (st != PERSP_OK) return st;
    /* libjpeg-turbo's extended colour spaces convert grey and YCbCr input
     * straight to RGBA with an opaque alpha. */
    const int cmyk =
        job->cinfo.jpeg_color_space == JCS_CMYK || job->cinfo.jpeg_color_space == JCS_YCCK;
    job->cinfo.out_color_space = cmyk ? JCS_CMYK : JCS_EXT_RGBA;
    /* libjpeg allocates its working memory itself (no per-call allocator):
     * a progressive or multi-scan file keeps every DCT coefficient of the
     * image (64 × 2 bytes per block of each component, libjpeg's
     * jdcoefct.c), a baseline file one row of blocks per component, plus
     * sample and colour-conversion rows. That is reserved from the budget
     * before jpeg_start_decompress asks for it, with the image itself (4
     * bytes per pixel), and libjpeg's own limit (max_memory_to_use, which
     * without a backing store makes it fail rather than exceed it) is set to
     * the rest as a backstop. */
    size_t blocks = 0, widest = 0;
    for (int c = 0; c < job->cinfo.num_components; c++) {
        const jpeg_component_info *ci = &job->cinfo.comp_info[c];
        size_t row = (size_t)ci->width_in_blocks * (size_t)(ci->v_samp_factor > 0 ? ci->v_samp_factor : 1);
        blocks += jpeg_has_multiple_scans(&job->cinfo)
                      ? (size_t)ci->width_in_blocks * (size_t)ci->height_in_blocks
                      : row;
        widest += row;
    }
    size_t work = blocks * 128u + widest * 64u * 4u + (size_t)job->cinfo.image_width * 4u * 16u +
                  (size_t)256 * 1024;
    size_t pixels = (size_t)job->cinfo.image_width * (size_t)job->cinfo.image_height * 4u;
    char what[PERSP_ERRMSG_BYTES / 2];
    snprintf(what, sizeof what, "%s: decoding the %ux%u JPEG", display_name(name),
             (unsigned)job->cinfo.image_width, (unsigned)job->cinfo.image_height);
    if ((st = persp__mem_reserve(ctx, work + pixels, what)) != PERSP_OK) return st;
    persp__mem_release(ctx, pixels); /* the image is counted when it is allocated */
    job->reserved = work;
    if (ctx->max_memory) {
        size_t left = persp__mem_available(ctx) + work;
        job->cinfo.mem->max_memory_to_use = left > (size_t)LONG_MAX ? LONG_MAX : (long)left;
    }
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
        if (jpeg_read_scanlines(&job->cinfo, &rp, 1) == 1 && cmyk)
            cmyk_to_rgba(rp, job->cinfo.output_width, job->cinfo.saw_Adobe_marker);
    }
    /* Saved markers go with the image's memory at the finish. */
    const int orient = exif_orientation(&job->cinfo);
    jpeg_finish_decompress(&job->cinfo);
    if (job->err.warnings > 0) {
        persp_image_free(ctx, &job->img);
        return persp__fail(ctx, PERSP_ERR_FORMAT, "%s: corrupt JPEG: %s",
                                  display_name(name), job->err.message);
    }
    return apply_orientation(ctx, orient, &job->img);
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
    persp__mem_release(ctx, job->reserved);
    if (st == PERSP_OK) {
        *out = job->img;
    } else {
        persp_image_free(ctx, &job->img);
    }
    persp__free(ctx, job);
    return st;
}

/* ----------------------------------------------------------------- entry */

/* ".tga" (Truevision's extension; ".icb", ".vda" and ".vst" of its older
 * boards are not seen today), in any case. */
static int has_tga_name(const char *name)
{
    size_t n = name ? strlen(name) : 0;
    return n > 4 && strcasecmp(name + n - 4, ".tga") == 0;
}

persp_status persp_image_load_memory(persp_context *ctx, const void *data, size_t size,
                                     const char *name, persp_image *out)
{
    if (!ctx) return PERSP_ERR_INVALID_ARGUMENT;
    persp__clear_error(ctx);
    if (!out || (!data && size))
        return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "%s: no data or no image to fill", name ? name : "image");
    memset(out, 0, sizeof *out);
    static const unsigned char png_sig[8] = {0x89, 'P', 'N', 'G', 0x0d, 0x0a, 0x1a, 0x0a};
    const unsigned char *b = data;
    if (size >= 8 && memcmp(b, png_sig, 8) == 0) return load_png(ctx, data, size, name, out);
    if (size >= 3 && b[0] == 0xff && b[1] == 0xd8 && b[2] == 0xff)
        return load_jpeg(ctx, data, size, name, out);
    if (size >= 2 && b[0] == 'B' && b[1] == 'M')
        return persp__load_bmp(ctx, b, size, display_name(name), out);
    if (persp__gif_recognised(b, size) || persp__hdr_recognised(b, size))
        return persp__load_stb(ctx, b, size, display_name(name), out);
    if (persp__pnm_recognised(b, size)) return persp__load_pnm(ctx, b, size, display_name(name), out);
    /* TGA has no signature: a file named .tga is read as one (its errors
     * then say what is wrong with it); any other only when its header is a
     * consistent TGA header. */
    if (has_tga_name(name) || persp__tga_recognised(b, size))
        return persp__load_tga(ctx, b, size, display_name(name), out);
    return persp__fail(ctx, PERSP_ERR_FORMAT,
                       "%s: not an image persp reads (PNG, JPEG, TGA, BMP, GIF, Netpbm, Radiance HDR)",
                              display_name(name));
}

persp_status persp_image_load(persp_context *ctx, const char *path, persp_image *out)
{
    return persp__image_load_inside(ctx, NULL, path, out);
}

persp_status persp__image_load_inside(persp_context *ctx, const char *root, const char *path,
                                      persp_image *out)
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
    persp_status st = persp__read_file_inside(ctx, root, path, &data, &size);
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
