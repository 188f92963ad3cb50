/*
 * Image encoding: JPEG written top row first and read back close to the
 * source, the format chosen by extension or by the desc, PNG and JPEG to a
 * stdio stream, quality bounds, write errors on a full device (to a path and
 * to a stream) reported as PERSP_ERR_IO, and files replaced atomically: no
 * temporary left behind, a link's target replaced and the link kept, a
 * device written in place rather than replaced.
 */
#include "support.h"

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <jpeglib.h>

static char tmpdir[256];

static int setup_dir(void **state)
{
    (void)state;
    return test_tmpdir_make(tmpdir, sizeof tmpdir, "image-write");
}

static int remove_dir(void **state)
{
    (void)state;
    return test_tmpdir_remove(tmpdir);
}

static void path_in(char *buf, size_t size, const char *name)
{
    snprintf(buf, size, "%s/%s", tmpdir, name);
}

static long file_size(const char *path)
{
    struct stat sb;
    return stat(path, &sb) == 0 ? (long)sb.st_size : -1;
}

static void read_head(const char *path, unsigned char *head, size_t n)
{
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    assert_int_equal(fread(head, 1, n, f), n);
    fclose(f);
}

static int is_png(const char *path)
{
    unsigned char h[8];
    read_head(path, h, 8);
    return !memcmp(h, "\x89PNG\r\n\x1a\n", 8);
}

static int is_jpeg(const char *path)
{
    unsigned char h[3];
    read_head(path, h, 3);
    return h[0] == 0xff && h[1] == 0xd8 && h[2] == 0xff;
}

/* No "*.tmp-*" file is left in the test folder. */
static void assert_no_temporaries(void)
{
    DIR *d = opendir(tmpdir);
    assert_non_null(d);
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        if (strstr(e->d_name, ".tmp-")) fail_msg("temporary file left behind: %s", e->d_name);
    }
    closedir(d);
}

/* A smooth W×H test image (JPEG keeps smooth content close): red rises to
 * the right, green to the top, blue along the diagonal; row 0 = bottom. */
static persp_image smooth_image(persp_context *ctx, int w, int h)
{
    persp_image img;
    assert_int_equal(persp_image_alloc(ctx, w, h, &img), PERSP_OK);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            uint8_t *p = img.pixels + (size_t)y * img.stride + 4u * (size_t)x;
            p[0] = (uint8_t)(255 * x / (w - 1));
            p[1] = (uint8_t)(255 * y / (h - 1));
            p[2] = (uint8_t)(255 * (x + y) / (w + h - 2));
            p[3] = 255;
        }
    return img;
}

/* Largest and mean RGB difference of two images of equal size. */
static void rgb_diff(const persp_image *a, const persp_image *b, int *max_abs, double *mean_abs)
{
    assert_int_equal(a->width, b->width);
    assert_int_equal(a->height, b->height);
    long sum = 0;
    *max_abs = 0;
    for (int y = 0; y < a->height; y++)
        for (int x = 0; x < a->width; x++)
            for (int c = 0; c < 3; c++) {
                int d = abs((int)a->pixels[(size_t)y * a->stride + 4u * (size_t)x + (size_t)c] -
                            (int)b->pixels[(size_t)y * b->stride + 4u * (size_t)x + (size_t)c]);
                sum += d;
                if (d > *max_abs) *max_abs = d;
            }
    *mean_abs = (double)sum / (3.0 * a->width * a->height);
}

static void test_jpeg_round_trip_and_orientation(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    persp_image img = smooth_image(ctx, 64, 48);
    char path[300];
    path_in(path, sizeof path, "smooth.jpg");
    assert_int_equal(persp_image_write_jpeg(ctx, path, &img, 0), PERSP_OK);
    assert_true(is_jpeg(path));
    persp_image back;
    assert_int_equal(persp_image_load(ctx, path, &back), PERSP_OK);
    int max_abs;
    double mean_abs;
    rgb_diff(&img, &back, &max_abs, &mean_abs);
    assert_true(mean_abs < 2.0);
    assert_true(max_abs <= 24);
    for (int y = 0; y < back.height; y++)
        for (int x = 0; x < back.width; x++)
            assert_int_equal(back.pixels[(size_t)y * back.stride + 4u * (size_t)x + 3u], 255);

    /* Read with libjpeg directly, without persp's flip: the file's first row
     * is the top of the image (green near 255), its last the bottom. */
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    struct jpeg_decompress_struct c;
    struct jpeg_error_mgr err;
    c.err = jpeg_std_error(&err);
    jpeg_create_decompress(&c);
    jpeg_stdio_src(&c, f);
    jpeg_read_header(&c, TRUE);
    c.out_color_space = JCS_RGB;
    jpeg_start_decompress(&c);
    assert_int_equal(c.output_width, 64);
    assert_int_equal(c.output_height, 48);
    unsigned char row[64 * 3];
    int first_green = -1, last_green = -1;
    while (c.output_scanline < c.output_height) {
        JSAMPROW rp = row;
        jpeg_read_scanlines(&c, &rp, 1);
        if (c.output_scanline == 1) first_green = row[3 * 32 + 1];
        last_green = row[3 * 32 + 1];
    }
    jpeg_finish_decompress(&c);
    jpeg_destroy_decompress(&c);
    fclose(f);
    assert_true(first_green > 230);
    assert_true(last_green < 25);

    persp_image_free(ctx, &back);
    persp_image_free(ctx, &img);
    persp_context_destroy(ctx);
}

static void test_jpeg_quality(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    persp_image img = smooth_image(ctx, 96, 64);
    /* Noise makes the size depend strongly on the quality. */
    test_rng rng = {12345};
    for (int y = 0; y < img.height; y++)
        for (int x = 0; x < img.width; x++)
            img.pixels[(size_t)y * img.stride + 4u * (size_t)x] =
                (uint8_t)(test_rng_next(&rng) & 255u);
    char lo[300], hi[300], bad[300];
    path_in(lo, sizeof lo, "q20.jpg");
    path_in(hi, sizeof hi, "q95.jpeg");
    assert_int_equal(persp_image_write_jpeg(ctx, lo, &img, 20), PERSP_OK);
    assert_int_equal(persp_image_write_jpeg(ctx, hi, &img, 95), PERSP_OK);
    assert_true(file_size(lo) > 0);
    assert_true(file_size(hi) > file_size(lo));
    path_in(bad, sizeof bad, "q101.jpg");
    assert_int_equal(persp_image_write_jpeg(ctx, bad, &img, 101), PERSP_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(persp_context_error(ctx), "quality 101"));
    assert_int_equal(persp_image_write_jpeg(ctx, bad, &img, -1), PERSP_ERR_INVALID_ARGUMENT);
    assert_int_equal(access(bad, F_OK), -1);
    persp_image_free(ctx, &img);
    persp_context_destroy(ctx);
}

static void test_format_from_path(void **state)
{
    (void)state;
    persp_image_format fmt = PERSP_IMAGE_FORMAT_DEFAULT;
    assert_int_equal(persp_image_format_from_path("a/b.png", &fmt), PERSP_OK);
    assert_int_equal(fmt, PERSP_IMAGE_FORMAT_PNG);
    assert_int_equal(persp_image_format_from_path("x.JPG", &fmt), PERSP_OK);
    assert_int_equal(fmt, PERSP_IMAGE_FORMAT_JPEG);
    assert_int_equal(persp_image_format_from_path("x.tar.jpeg", &fmt), PERSP_OK);
    assert_int_equal(fmt, PERSP_IMAGE_FORMAT_JPEG);
    assert_int_equal(persp_image_format_from_path("x.bmp", &fmt), PERSP_ERR_UNSUPPORTED);
    assert_int_equal(persp_image_format_from_path("x", &fmt), PERSP_ERR_UNSUPPORTED);
    assert_int_equal(persp_image_format_from_path("dir.png/x", &fmt), PERSP_ERR_UNSUPPORTED);
    assert_int_equal(persp_image_format_from_path(".png", &fmt), PERSP_ERR_UNSUPPORTED);
    assert_int_equal(persp_image_format_from_path("x.pngx", &fmt), PERSP_ERR_UNSUPPORTED);
    assert_int_equal(persp_image_format_from_path(NULL, &fmt), PERSP_ERR_INVALID_ARGUMENT);
}

static void test_write_by_extension_or_desc(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    persp_image img = smooth_image(ctx, 16, 8);
    char path[300];
    path_in(path, sizeof path, "e.png");
    assert_int_equal(persp_image_write(ctx, path, &img, NULL), PERSP_OK);
    assert_true(is_png(path));
    path_in(path, sizeof path, "e.JPG");
    assert_int_equal(persp_image_write(ctx, path, &img, NULL), PERSP_OK);
    assert_true(is_jpeg(path));
    /* Unknown extension: refused, nothing created. */
    path_in(path, sizeof path, "e.bmp");
    assert_int_equal(persp_image_write(ctx, path, &img, NULL), PERSP_ERR_UNSUPPORTED);
    assert_non_null(strstr(persp_context_error(ctx), "e.bmp"));
    assert_int_equal(access(path, F_OK), -1);
    /* An explicit format overrides the name. */
    persp_image_write_desc d = {PERSP_IMAGE_FORMAT_JPEG, 80};
    path_in(path, sizeof path, "e.dat");
    assert_int_equal(persp_image_write(ctx, path, &img, &d), PERSP_OK);
    assert_true(is_jpeg(path));
    /* Replacing an existing file: PNG over the JPEG, no temporary left. */
    d.format = PERSP_IMAGE_FORMAT_PNG;
    assert_int_equal(persp_image_write(ctx, path, &img, &d), PERSP_OK);
    assert_true(is_png(path));
    d.format = (persp_image_format)42;
    assert_int_equal(persp_image_write(ctx, path, &img, &d), PERSP_ERR_INVALID_ARGUMENT);
    assert_true(is_png(path));
    assert_no_temporaries();
    persp_image_free(ctx, &img);
    persp_context_destroy(ctx);
}

static void test_write_to_stream(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    persp_image img = smooth_image(ctx, 40, 30);
    for (int format = PERSP_IMAGE_FORMAT_DEFAULT; format <= PERSP_IMAGE_FORMAT_JPEG; format++) {
        FILE *f = tmpfile();
        assert_non_null(f);
        persp_image_write_desc d = {(persp_image_format)format, 0};
        assert_int_equal(persp_image_write_stream(ctx, f, "test stream", &img, &d), PERSP_OK);
        long n = ftell(f);
        assert_true(n > 8);
        rewind(f);
        unsigned char *data = malloc((size_t)n);
        assert_non_null(data);
        assert_int_equal(fread(data, 1, (size_t)n, f), (size_t)n);
        fclose(f);
        if (format == PERSP_IMAGE_FORMAT_JPEG)
            assert_int_equal(data[0], 0xff);
        else
            assert_memory_equal(data, "\x89PNG", 4);
        persp_image back;
        assert_int_equal(persp_image_load_memory(ctx, data, (size_t)n, "back", &back), PERSP_OK);
        int max_abs;
        double mean_abs;
        rgb_diff(&img, &back, &max_abs, &mean_abs);
        if (format == PERSP_IMAGE_FORMAT_JPEG)
            assert_true(mean_abs < 2.0);
        else
            assert_int_equal(max_abs, 0); /* PNG is lossless */
        persp_image_free(ctx, &back);
        free(data);
    }
    assert_int_equal(persp_image_write_stream(ctx, NULL, NULL, &img, NULL),
                     PERSP_ERR_INVALID_ARGUMENT);
    persp_image_free(ctx, &img);
    persp_context_destroy(ctx);
}

/* A full device: every write fails with ENOSPC once the data leaves stdio's
 * buffer, so both a large image (the encoder's own writes fail) and a small
 * one (only the final flush fails) are covered. The device itself must stay a
 * device: it is written, not replaced by a renamed file. */
static void test_write_errors_on_full_device(void **state)
{
    (void)state;
    struct stat before;
    if (stat("/dev/full", &before) != 0 || !S_ISCHR(before.st_mode)) skip();
    persp_context *ctx = test_context();
    persp_image big = smooth_image(ctx, 300, 200), small = smooth_image(ctx, 4, 4);
    const persp_image *imgs[2] = {&big, &small};
    for (int i = 0; i < 2; i++)
        for (int format = PERSP_IMAGE_FORMAT_PNG; format <= PERSP_IMAGE_FORMAT_JPEG; format++) {
            persp_image_write_desc d = {(persp_image_format)format, 0};
            FILE *f = fopen("/dev/full", "wb");
            assert_non_null(f);
            assert_int_equal(persp_image_write_stream(ctx, f, "full stream", imgs[i], &d),
                             PERSP_ERR_IO);
            assert_non_null(strstr(persp_context_error(ctx), "full stream: write failed"));
            fclose(f);
            assert_int_equal(persp_image_write(ctx, "/dev/full", imgs[i], &d), PERSP_ERR_IO);
            assert_non_null(strstr(persp_context_error(ctx), "/dev/full: write failed"));
        }
    struct stat after;
    assert_int_equal(stat("/dev/full", &after), 0);
    assert_true(S_ISCHR(after.st_mode));
    assert_int_equal(after.st_rdev, before.st_rdev);
    persp_image_free(ctx, &big);
    persp_image_free(ctx, &small);
    persp_context_destroy(ctx);
}

static void test_failed_write_leaves_nothing(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    persp_image img = smooth_image(ctx, 8, 8);
    char path[300];
    path_in(path, sizeof path, "no/such/dir/out.jpg");
    assert_int_equal(persp_image_write(ctx, path, &img, NULL), PERSP_ERR_IO);
    assert_non_null(strstr(persp_context_error(ctx), path));
    assert_int_equal(access(path, F_OK), -1);
    /* A folder named like an image is not replaced. */
    path_in(path, sizeof path, "folder.jpg");
    assert_int_equal(mkdir(path, 0755), 0);
    assert_int_equal(persp_image_write(ctx, path, &img, NULL), PERSP_ERR_IO);
    struct stat sb;
    assert_int_equal(stat(path, &sb), 0);
    assert_true(S_ISDIR(sb.st_mode));
    assert_no_temporaries();
    persp_image_free(ctx, &img);
    persp_context_destroy(ctx);
}

static void test_write_through_link(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    persp_image img = smooth_image(ctx, 8, 8);
    char real[300], link[300];
    path_in(real, sizeof real, "real.png");
    path_in(link, sizeof link, "link.jpg");
    assert_int_equal(persp_image_write_png(ctx, real, &img), PERSP_OK);
    assert_int_equal(symlink("real.png", link), 0);
    persp_image_write_desc d = {PERSP_IMAGE_FORMAT_JPEG, 0};
    assert_int_equal(persp_image_write(ctx, link, &img, &d), PERSP_OK);
    struct stat sb;
    assert_int_equal(lstat(link, &sb), 0);
    assert_true(S_ISLNK(sb.st_mode));
    assert_true(is_jpeg(real));
    assert_no_temporaries();
    persp_image_free(ctx, &img);
    persp_context_destroy(ctx);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_jpeg_round_trip_and_orientation),
        cmocka_unit_test(test_jpeg_quality),
        cmocka_unit_test(test_format_from_path),
        cmocka_unit_test(test_write_by_extension_or_desc),
        cmocka_unit_test(test_write_to_stream),
        cmocka_unit_test(test_write_errors_on_full_device),
        cmocka_unit_test(test_failed_write_leaves_nothing),
        cmocka_unit_test(test_write_through_link),
    };
    return cmocka_run_group_tests(tests, setup_dir, remove_dir);
}
