/* Images as users have them: 16-bit PNGs with and without gamma
 * information, CMYK JPEGs (Adobe-inverted and plain), the Exif orientation
 * of JPEGs, and texture alpha kept out of rendered images. The JPEGs are
 * encoded here with libjpeg so each case is exactly the one under test. */
#include "support.h"

#include "core/internal.h"
#include "geom/scene.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <jpeglib.h>

static void load_source(persp_context *ctx, const char *rel, persp_image *img)
{
    char path[1024];
    test_source_path(path, sizeof path, rel);
    persp_status st = persp_image_load(ctx, path, img);
    if (st != PERSP_OK) fail_msg("%s: %s", rel, persp_context_error(ctx));
}

static const uint8_t *px(const persp_image *img, int x, int y_from_top)
{
    return img->pixels + (size_t)(img->height - 1 - y_from_top) * img->stride + 4 * (size_t)x;
}

static void test_png16_matches_8bit(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    persp_image a, b, lin;
    load_source(ctx, "tests/data/images/ramp8.png", &a);
    load_source(ctx, "tests/data/images/ramp16.png", &b);
    load_source(ctx, "tests/data/images/ramp16_linear.png", &lin);
    assert_int_equal(a.width, b.width);
    int brighter = 0;
    for (int y = 0; y < a.height; y++)
        for (int x = 0; x < a.width; x++)
            for (int c = 0; c < 4; c++) {
                int d = px(&a, x, y)[c] - px(&b, x, y)[c];
                if (d < -1 || d > 1)
                    fail_msg("(%d, %d) channel %d: 8-bit %d, 16-bit %d", x, y, c, px(&a, x, y)[c],
                             px(&b, x, y)[c]);
                /* gAMA 1.0 says linear light: encoded to sRGB, mid-tones rise */
                if (c < 3 && px(&lin, x, y)[c] > px(&a, x, y)[c] + 8) brighter++;
            }
    assert_true(brighter > 0);
    persp_image_free(ctx, &a);
    persp_image_free(ctx, &b);
    persp_image_free(ctx, &lin);
    persp_context_destroy(ctx);
}

/* A JPEG of w x h built by fill(x, y, sample[components]); app1 (may be
 * NULL) is written as an APP1 segment. Returns a malloc'd buffer. */
typedef void (*fill_fn)(int x, int y, JSAMPLE *out);

static unsigned char *encode_jpeg(int w, int h, J_COLOR_SPACE space, int comps, int adobe,
                                  fill_fn fill, const unsigned char *app1, unsigned app1_len,
                                  unsigned long *size)
{
    struct jpeg_compress_struct c;
    struct jpeg_error_mgr err;
    c.err = jpeg_std_error(&err);
    jpeg_create_compress(&c);
    unsigned char *buf = NULL;
    *size = 0;
    jpeg_mem_dest(&c, &buf, size);
    c.image_width = (JDIMENSION)w;
    c.image_height = (JDIMENSION)h;
    c.input_components = comps;
    c.in_color_space = space;
    jpeg_set_defaults(&c);
    jpeg_set_quality(&c, 98, TRUE);
    if (space == JCS_CMYK) {
        jpeg_set_colorspace(&c, JCS_CMYK);
        c.write_Adobe_marker = adobe ? TRUE : FALSE;
    }
    for (int i = 0; i < c.num_components; i++)
        c.comp_info[i].h_samp_factor = c.comp_info[i].v_samp_factor = 1;
    jpeg_start_compress(&c, TRUE);
    if (app1) jpeg_write_marker(&c, JPEG_APP0 + 1, app1, app1_len);
    JSAMPLE *row = malloc((size_t)w * (size_t)comps);
    assert_non_null(row);
    while (c.next_scanline < c.image_height) {
        for (int x = 0; x < w; x++)
            fill(x, (int)c.next_scanline, row + x * comps);
        JSAMPROW rp = row;
        jpeg_write_scanlines(&c, &rp, 1);
    }
    free(row);
    jpeg_finish_compress(&c);
    jpeg_destroy_compress(&c);
    return buf;
}

/* Ink: left half red (M + Y), right half black (K). */
static void fill_cmyk_ink(int x, int y, JSAMPLE *o)
{
    (void)y;
    o[0] = 0, o[1] = x < 8 ? 255 : 0, o[2] = x < 8 ? 255 : 0, o[3] = x < 8 ? 0 : 255;
}

static void fill_cmyk_adobe(int x, int y, JSAMPLE *o)
{
    fill_cmyk_ink(x, y, o);
    for (int i = 0; i < 4; i++)
        o[i] = (JSAMPLE)(255 - o[i]);
}

static int near(int a, int b)
{
    return abs(a - b) <= 6;
}

static void test_cmyk_jpeg(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    for (int adobe = 0; adobe < 2; adobe++) {
        unsigned long size;
        unsigned char *jpg = encode_jpeg(16, 8, JCS_CMYK, 4, adobe,
                                         adobe ? fill_cmyk_adobe : fill_cmyk_ink, NULL, 0, &size);
        persp_image img;
        persp_status st = persp_image_load_memory(ctx, jpg, size, "cmyk.jpg", &img);
        if (st != PERSP_OK) fail_msg("adobe %d: %s", adobe, persp_context_error(ctx));
        assert_int_equal(img.width, 16);
        const uint8_t *red = px(&img, 2, 2), *black = px(&img, 13, 5);
        if (!near(red[0], 255) || !near(red[1], 0) || !near(red[2], 0) || red[3] != 255)
            fail_msg("adobe %d: red came out %d %d %d %d", adobe, red[0], red[1], red[2], red[3]);
        assert_true(near(black[0], 0) && near(black[1], 0) && near(black[2], 0) && black[3] == 255);
        persp_image_free(ctx, &img);
        free(jpg);
    }
    persp_context_destroy(ctx);
}

/* Stored: left half red, right half blue, 16 x 8. */
static void fill_rgb(int x, int y, JSAMPLE *o)
{
    (void)y;
    o[0] = x < 8 ? 255 : 0, o[1] = 0, o[2] = x < 8 ? 0 : 255;
}

static void test_exif_orientation(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    /* Exif header, big-endian TIFF, IFD0 with one entry: Orientation. */
    unsigned char exif[] = {'E',  'x',  'i', 'f', 0, 0, 'M', 'M', 0, 42, 0, 0, 0, 8, 0, 1,
                            0x01, 0x12, 0,   3,   0, 0, 0,   1,   0, 0,  0, 0, 0, 0, 0, 0};
    /* orientation -> (width, height), colour of the displayed top-left and
     * bottom-right pixels ('r' red, 'b' blue) */
    static const struct {
        int o, w, h;
        char tl, br;
    } cases[] = {{1, 16, 8, 'r', 'b'}, {2, 16, 8, 'b', 'r'}, {3, 16, 8, 'b', 'r'},
                 {4, 16, 8, 'r', 'b'}, {5, 8, 16, 'r', 'b'}, {6, 8, 16, 'r', 'b'},
                 {7, 8, 16, 'b', 'r'}, {8, 8, 16, 'b', 'r'}};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        exif[24] = 0, exif[25] = (unsigned char)cases[i].o;
        unsigned long size;
        unsigned char *jpg = encode_jpeg(16, 8, JCS_RGB, 3, 0, fill_rgb, exif, sizeof exif, &size);
        persp_image img;
        assert_int_equal(persp_image_load_memory(ctx, jpg, size, "exif.jpg", &img), PERSP_OK);
        if (img.width != cases[i].w || img.height != cases[i].h)
            fail_msg("orientation %d: %dx%d", cases[i].o, img.width, img.height);
        const uint8_t *tl = px(&img, 0, 0), *br = px(&img, img.width - 1, img.height - 1);
        char got_tl = tl[0] > 128 ? 'r' : 'b', got_br = br[0] > 128 ? 'r' : 'b';
        if (got_tl != cases[i].tl || got_br != cases[i].br)
            fail_msg("orientation %d: top-left %c, bottom-right %c", cases[i].o, got_tl, got_br);
        persp_image_free(ctx, &img);
        free(jpg);
    }
    /* orientation 6 (rotate 90 clockwise): the stored left half is on top */
    exif[25] = 6;
    unsigned long size;
    unsigned char *jpg = encode_jpeg(16, 8, JCS_RGB, 3, 0, fill_rgb, exif, sizeof exif, &size);
    persp_image img;
    assert_int_equal(persp_image_load_memory(ctx, jpg, size, "exif.jpg", &img), PERSP_OK);
    assert_true(px(&img, 0, 1)[0] > 200 && px(&img, 7, 1)[0] > 200 && px(&img, 4, 14)[2] > 200);
    persp_image_free(ctx, &img);
    free(jpg);
    persp_context_destroy(ctx);
}

/* Texture alpha does not reach the rendered image: persp draws opaque
 * surfaces, with replace and with modulate. */
static void test_render_output_opaque(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    char path[1024];
    test_source_path(path, sizeof path, "tests/data/images/translucent.png");
    char dir[] = "/tmp/persp_alpha_XXXXXX", scene_path[1100];
    assert_non_null(mkdtemp(dir));
    snprintf(scene_path, sizeof scene_path, "%s/s.json", dir);
    const char *envs[] = {"replace", "modulate"};
    for (int e = 0; e < 2; e++) {
        FILE *f = fopen(scene_path, "w");
        assert_non_null(f);
        fprintf(f,
                "{\"materials\": {\"m\": {\"texture\": \"%s\", \"env\": \"%s\"}},\n"
                " \"objects\": [{\"mesh\": \"plane\", \"material\": \"m\",\n"
                "               \"transform\": {\"rotate\": [90, 1, 0, 0], \"translate\": [0, 0, "
                "-1]}}]}\n",
                path, envs[e]);
        fclose(f);
        persp_scene *s = NULL;
        /* The texture stays in the source tree, outside the scene's folder. */
        persp_scene_load_desc load = {.any_folder = PERSP_TOGGLE_ON};
        persp_status st = persp_scene_load_ex(ctx, scene_path, &load, &s);
        if (st != PERSP_OK) fail_msg("%s", persp_context_error(ctx));
        uint8_t color[16 * 16 * 4];
        float depth[16 * 16];
        persp_framebuffer fb = {16, 16, color, depth};
        persp_render_stats stats;
        assert_int_equal(persp_render(ctx, s, NULL, &fb, &stats), PERSP_OK);
        assert_true(stats.pixels_written > 0);
        for (int i = 0; i < 16 * 16; i++)
            if (color[4 * i + 3] != 255)
                fail_msg("%s: pixel %d has alpha %d", envs[e], i, color[4 * i + 3]);
        persp_scene_destroy(s);
    }
    remove(scene_path);
    rmdir(dir);
    persp_context_destroy(ctx);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_png16_matches_8bit),
        cmocka_unit_test(test_cmyk_jpeg),
        cmocka_unit_test(test_exif_orientation),
        cmocka_unit_test(test_render_output_opaque),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
