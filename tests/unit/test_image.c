/*
 * Image files: PNG written top row first and read back flipped (row 0 = the
 * bottom row of the displayed image, docs/CONVENTIONS.md), JPEG decoded the
 * same way, and every kind of bad file turned into a status code and a
 * message that names the file and the problem: truncated PNG and JPEG, a
 * PNG whose header claims 100000×100000 pixels, a file that is no image, an
 * empty file, a missing file, a directory, and an unwritable output path
 * (which must leave nothing behind).
 */
#include "support.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <jpeglib.h>
#include <png.h>

static char tmpdir[256];

static int setup_dir(void **state)
{
    (void)state;
    return test_tmpdir_make(tmpdir, sizeof tmpdir, "image");
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

static void write_bytes(const char *path, const void *data, size_t size)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(data, 1, size, f), size);
    assert_int_equal(fclose(f), 0);
}

static unsigned char *read_bytes(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    assert_int_equal(fseek(f, 0, SEEK_END), 0);
    long n = ftell(f);
    assert_true(n > 0);
    rewind(f);
    unsigned char *b = malloc((size_t)n);
    assert_non_null(b);
    assert_int_equal(fread(b, 1, (size_t)n, f), (size_t)n);
    fclose(f);
    *size = (size_t)n;
    return b;
}

/* Pixel (x, y) of a W×H test pattern, y counted from the bottom. */
static void pattern(int x, int y, uint8_t px[4])
{
    px[0] = (uint8_t)(40 * x + 3);
    px[1] = (uint8_t)(50 * y + 7);
    px[2] = (uint8_t)(x * y + 11);
    px[3] = (uint8_t)(255 - 10 * x);
}

/* Writes a 5×3 pattern PNG with persp; returns its path in buf. */
static void write_pattern_png(persp_context *ctx, char *buf, size_t size)
{
    persp_image img;
    assert_int_equal(persp_image_alloc(ctx, 5, 3, &img), PERSP_OK);
    for (int y = 0; y < 3; y++)
        for (int x = 0; x < 5; x++)
            pattern(x, y, img.pixels + (size_t)y * img.stride + 4u * (size_t)x);
    path_in(buf, size, "pattern.png");
    assert_int_equal(persp_image_write_png(ctx, buf, &img), PERSP_OK);
    persp_image_free(ctx, &img);
}

static void test_png_round_trip_and_orientation(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    char path[300];
    write_pattern_png(ctx, path, sizeof path);
    /* Read with libpng directly, without persp's flip: the file's first row
     * is the top of the image, i.e. persp's row 2. */
    png_image pi;
    memset(&pi, 0, sizeof pi);
    pi.version = PNG_IMAGE_VERSION;
    assert_true(png_image_begin_read_from_file(&pi, path));
    assert_int_equal(pi.width, 5);
    assert_int_equal(pi.height, 3);
    pi.format = PNG_FORMAT_RGBA;
    uint8_t raw[5 * 3 * 4];
    assert_true(png_image_finish_read(&pi, NULL, raw, 0, NULL));
    for (int fy = 0; fy < 3; fy++)
        for (int x = 0; x < 5; x++) {
            uint8_t want[4];
            pattern(x, 2 - fy, want);
            assert_memory_equal(raw + (fy * 5 + x) * 4, want, 4);
        }
    /* persp reads it back into the same bottom-up layout. */
    persp_image back;
    assert_int_equal(persp_image_load(ctx, path, &back), PERSP_OK);
    assert_int_equal(back.width, 5);
    assert_int_equal(back.height, 3);
    for (int y = 0; y < 3; y++)
        for (int x = 0; x < 5; x++) {
            uint8_t want[4];
            pattern(x, y, want);
            assert_memory_equal(back.pixels + (size_t)y * back.stride + 4u * (size_t)x, want, 4);
        }
    persp_image_free(ctx, &back);
    persp_context_destroy(ctx);
}

/* A W×H JPEG whose top half is red and bottom half blue, encoded by libjpeg. */
static unsigned char *make_jpeg(int w, int h, unsigned long *size)
{
    struct jpeg_compress_struct c;
    struct jpeg_error_mgr err;
    c.err = jpeg_std_error(&err);
    jpeg_create_compress(&c);
    unsigned char *out = NULL;
    jpeg_mem_dest(&c, &out, size);
    c.image_width = (JDIMENSION)w;
    c.image_height = (JDIMENSION)h;
    c.input_components = 3;
    c.in_color_space = JCS_RGB;
    jpeg_set_defaults(&c);
    jpeg_set_quality(&c, 95, TRUE);
    jpeg_start_compress(&c, TRUE);
    unsigned char *row = malloc((size_t)w * 3);
    assert_non_null(row);
    while (c.next_scanline < c.image_height) {
        int top = c.next_scanline < (JDIMENSION)(h / 2);
        for (int x = 0; x < w; x++) {
            row[3 * x + 0] = top ? 220 : 20;
            row[3 * x + 1] = 30;
            row[3 * x + 2] = top ? 20 : 220;
        }
        JSAMPROW rp = row;
        jpeg_write_scanlines(&c, &rp, 1);
    }
    jpeg_finish_compress(&c);
    jpeg_destroy_compress(&c);
    free(row);
    return out;
}

static void test_jpeg_decode_and_orientation(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    unsigned long size = 0;
    unsigned char *jpg = make_jpeg(32, 16, &size);
    char path[300];
    path_in(path, sizeof path, "photo.jpg");
    write_bytes(path, jpg, size);
    persp_image img;
    assert_int_equal(persp_image_load(ctx, path, &img), PERSP_OK);
    assert_int_equal(img.width, 32);
    assert_int_equal(img.height, 16);
    /* Row 0 is the bottom of the displayed image: blue; row 15 red; alpha opaque. */
    const uint8_t *bottom = img.pixels + 4 * 16, *top = img.pixels + 15 * img.stride + 4 * 16;
    assert_true(bottom[2] > 180 && bottom[0] < 60);
    assert_true(top[0] > 180 && top[2] < 60);
    assert_int_equal(bottom[3], 255);
    assert_int_equal(top[3], 255);
    persp_image_free(ctx, &img);

    /* The same file with its frame header (SOF0) claiming 60000×60000:
     * refused from the header, before anything is allocated. */
    unsigned char *big = malloc(size);
    assert_non_null(big);
    memcpy(big, jpg, size);
    int patched = 0;
    for (unsigned long i = 0; i + 9 < size && !patched; i++)
        if (big[i] == 0xff && big[i + 1] == 0xc0) {
            big[i + 5] = 0xea, big[i + 6] = 0x60; /* height 60000 */
            big[i + 7] = 0xea, big[i + 8] = 0x60; /* width 60000 */
            patched = 1;
        }
    assert_true(patched);
    assert_int_equal(persp_image_load_memory(ctx, big, size, "big.jpg", &img), PERSP_ERR_TOO_LARGE);
    assert_non_null(strstr(persp_context_error(ctx), "big.jpg: image size 60000x60000"));
    assert_null(img.pixels);
    free(big);

    /* Truncated JPEG: libjpeg would pad it with grey; persp refuses it. */
    for (unsigned long cut = 2; cut < size; cut += size / 7 + 1) {
        persp_status st = persp_image_load_memory(ctx, jpg, cut, "cut.jpg", &img);
        if (st == PERSP_OK) fail_msg("a JPEG cut to %lu of %lu bytes was accepted", cut, size);
        assert_int_equal(st, PERSP_ERR_FORMAT);
        assert_non_null(strstr(persp_context_error(ctx), "cut.jpg: "));
        assert_null(img.pixels);
    }
    free(jpg);
    persp_context_destroy(ctx);
}

/* CRC-32 of PNG chunks (ISO 3309, as in the PNG specification Annex D). */
static uint32_t crc32_of(const unsigned char *p, size_t n)
{
    uint32_t c = 0xffffffffu;
    for (size_t i = 0; i < n; i++) {
        c ^= p[i];
        for (int k = 0; k < 8; k++)
            c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
    }
    return c ^ 0xffffffffu;
}

static void put32(unsigned char *p, uint32_t v)
{
    p[0] = (unsigned char)(v >> 24), p[1] = (unsigned char)(v >> 16);
    p[2] = (unsigned char)(v >> 8), p[3] = (unsigned char)v;
}

static void test_png_claiming_huge_size(void **state)
{
    (void)state;
    /* Signature + a valid IHDR chunk (CRC correct) for 100000×100000 RGBA8,
     * then nothing: the size must be refused before anything is allocated. */
    unsigned char f[8 + 25] = {0x89, 'P', 'N', 'G', 0x0d, 0x0a, 0x1a, 0x0a};
    unsigned char *ch = f + 8;
    put32(ch, 13);
    memcpy(ch + 4, "IHDR", 4);
    put32(ch + 8, 100000);
    put32(ch + 12, 100000);
    ch[16] = 8, ch[17] = 6, ch[18] = 0, ch[19] = 0, ch[20] = 0;
    put32(ch + 21, crc32_of(ch + 4, 17));
    persp_context *ctx = test_context();
    persp_image img;
    assert_int_equal(persp_image_load_memory(ctx, f, sizeof f, "huge.png", &img),
                     PERSP_ERR_TOO_LARGE);
    const char *msg = persp_context_error(ctx);
    print_message("%s\n", msg);
    assert_non_null(strstr(msg, "huge.png: "));
    assert_non_null(strstr(msg, "100000x100000"));
    assert_null(img.pixels);
    persp_context_destroy(ctx);
}

static void test_truncated_png(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    char path[300];
    write_pattern_png(ctx, path, sizeof path);
    size_t size = 0;
    unsigned char *png = read_bytes(path, &size);
    persp_image img;
    /* Every cut, from inside the signature to just before the end chunk's CRC. */
    for (size_t cut = 0; cut < size; cut++) {
        persp_status st = persp_image_load_memory(ctx, png, cut, "cut.png", &img);
        if (st == PERSP_OK) fail_msg("a PNG cut to %zu of %zu bytes was accepted", cut, size);
        assert_int_equal(st, PERSP_ERR_FORMAT);
        const char *msg = persp_context_error(ctx);
        assert_non_null(strstr(msg, "cut.png: "));
        assert_true(strstr(msg, "truncated") || strstr(msg, "invalid PNG") ||
                    strstr(msg, "not an image persp reads"));
        assert_null(img.pixels);
    }
    free(png);
    persp_context_destroy(ctx);
}

static void expect_load_error(persp_context *ctx, const char *path, persp_status want,
                              const char *problem)
{
    persp_image img;
    persp_status st = persp_image_load(ctx, path, &img);
    const char *msg = persp_context_error(ctx);
    print_message("%s -> %s\n", path, msg);
    assert_int_equal(st, want);
    assert_non_null(strstr(msg, path));
    if (!strstr(msg, problem)) fail_msg("message '%s' lacks '%s'", msg, problem);
    assert_null(img.pixels);
}

static void test_not_an_image_missing_empty_directory(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    char path[300];
    path_in(path, sizeof path, "notes.png");
    const char text[] = "This is a text file with a .png name.\n";
    write_bytes(path, text, sizeof text - 1);
    expect_load_error(ctx, path, PERSP_ERR_FORMAT, "not an image persp reads");
    path_in(path, sizeof path, "empty.png");
    write_bytes(path, "", 0);
    expect_load_error(ctx, path, PERSP_ERR_FORMAT, "not an image persp reads");
    path_in(path, sizeof path, "missing.png");
    expect_load_error(ctx, path, PERSP_ERR_IO, "cannot open");
    path_in(path, sizeof path, "folder.png");
    assert_int_equal(mkdir(path, 0755), 0);
    expect_load_error(ctx, path, PERSP_ERR_IO, "is a directory");
    persp_context_destroy(ctx);
}

static void test_failed_write_leaves_nothing(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    persp_image img;
    assert_int_equal(persp_image_alloc(ctx, 4, 4, &img), PERSP_OK);
    char path[300];
    path_in(path, sizeof path, "no/such/dir/out.png");
    assert_int_equal(persp_image_write_png(ctx, path, &img), PERSP_ERR_IO);
    assert_non_null(strstr(persp_context_error(ctx), path));
    assert_int_equal(access(path, F_OK), -1);
    /* An invalid image is refused before any file is created. */
    persp_image bad = img;
    bad.width = 0;
    path_in(path, sizeof path, "bad.png");
    assert_int_equal(persp_image_write_png(ctx, path, &bad), PERSP_ERR_INVALID_ARGUMENT);
    assert_int_equal(access(path, F_OK), -1);
    persp_image_free(ctx, &img);
    persp_context_destroy(ctx);
}

/* persp_image_alloc: zeroed pixels on a 64-byte boundary whatever the size,
 * freed through persp_image_free (ASan checks the block header's use). */
static void test_alloc_alignment(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    const int sizes[][2] = {{1, 1}, {3, 5}, {17, 2}, {1024, 768}};
    for (size_t i = 0; i < sizeof sizes / sizeof *sizes; i++) {
        persp_image img;
        assert_int_equal(persp_image_alloc(ctx, sizes[i][0], sizes[i][1], &img), PERSP_OK);
        assert_true(((uintptr_t)img.pixels & 63u) == 0);
        for (size_t b = 0; b < img.stride * (size_t)img.height; b++) assert_true(img.pixels[b] == 0);
        persp_image_free(ctx, &img);
        assert_null(img.pixels);
    }
    persp_image none = {0, 0, 0, NULL};
    persp_image_free(ctx, &none);
    persp_context_destroy(ctx);
}

/* An allocator that frees only what it handed out and counts the frees it
 * was asked for. */
typedef struct frees {
    int asked, unknown;
    void *given[8];
} frees;

static void *counting_alloc(void *user, size_t size)
{
    frees *f = user;
    void *p = malloc(size);
    for (int i = 0; p && i < 8; i++)
        if (!f->given[i]) {
            f->given[i] = p;
            break;
        }
    return p;
}

static void counting_free(void *user, void *ptr)
{
    frees *f = user;
    f->asked++;
    for (int i = 0; i < 8; i++)
        if (f->given[i] == ptr) {
            f->given[i] = NULL;
            free(ptr);
            return;
        }
    f->unknown++;
}

/* An image the caller filled in (borrowed pixels) handed to
 * persp_image_free: nothing is freed or read in front of the pixels (here
 * a pointer-sized value that a freeing function reading a hidden header
 * would pass to free), the pixels and the struct stay as they were, and the
 * context says why. An owned image is freed as before. */
static void test_free_borrowed(void **state)
{
    (void)state;
    frees f;
    memset(&f, 0, sizeof f);
    persp_allocator al = {counting_alloc, counting_free, &f};
    persp_context_desc cd = {.allocator = &al, .threads = 1};
    persp_context *ctx = NULL;
    assert_int_equal(persp_context_create(&cd, &ctx), PERSP_OK);
    int asked0 = f.asked;
    _Alignas(64) uint8_t buf[64 + 16];
    void *decoy = &f;
    memcpy(buf + 64 - sizeof decoy, &decoy, sizeof decoy);
    memset(buf + 64, 7, 16);
    persp_image borrowed = {2, 2, 8, buf + 64};
    persp_image_free(ctx, &borrowed);
    assert_int_equal(f.asked, asked0);
    assert_ptr_equal(borrowed.pixels, buf + 64);
    assert_int_equal(borrowed.width, 2);
    for (int i = 0; i < 16; i++) assert_int_equal(buf[64 + i], 7);
    assert_non_null(strstr(persp_context_error(ctx), "not allocated"));
    persp_image owned;
    assert_int_equal(persp_image_alloc(ctx, 2, 2, &owned), PERSP_OK);
    persp_image copy = owned;
    persp_image_free(ctx, &copy);
    assert_int_equal(f.asked, asked0 + 1);
    assert_int_equal(f.unknown, 0);
    assert_null(copy.pixels);
    persp_context_destroy(ctx);
    assert_int_equal(f.unknown, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_alloc_alignment),
        cmocka_unit_test(test_free_borrowed),
        cmocka_unit_test(test_png_round_trip_and_orientation),
        cmocka_unit_test(test_jpeg_decode_and_orientation),
        cmocka_unit_test(test_png_claiming_huge_size),
        cmocka_unit_test(test_truncated_png),
        cmocka_unit_test(test_not_an_image_missing_empty_directory),
        cmocka_unit_test(test_failed_write_leaves_nothing),
    };
    return cmocka_run_group_tests(tests, setup_dir, remove_dir);
}
