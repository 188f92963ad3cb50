/* Object-space texturing with screen-space filtering ([Romaniuk-ObjSpace],
 * src/objspace/objspace.c): thread independence, no holes, no bleeding. */
/* ctest-labels: threads (renders with several worker threads) */
/* ctest-split: each (minutes in all under ThreadSanitizer and qemu-user) */
#include "support.h"

#include "core/internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct os_render {
    uint8_t *color;
    persp_render_stats stats;
    int w, h;
} os_render;

static void render_object(const char *scene_name, const persp_image *tex, int threads, int w, int h,
                          os_render *out)
{
    persp_context *ctx = test_context_threads(threads);
    persp_scene *scene = NULL;
    assert_int_equal(persp_scene_builtin(ctx, scene_name, &scene), PERSP_OK);
    if (tex) assert_int_equal(persp_scene_set_texture(scene, tex), PERSP_OK);
    out->w = w, out->h = h;
    out->color = malloc((size_t)w * h * 4);
    float *depth = malloc((size_t)w * h * sizeof(float));
    assert_non_null(out->color);
    assert_non_null(depth);
    persp_framebuffer fb = {w, h, out->color, depth};
    persp_render_desc d;
    memset(&d, 0, sizeof d);
    d.pipeline = PERSP_PIPELINE_OBJECT;
    d.shading = PERSP_SHADING_NONE;
    persp_status s = persp_render(ctx, scene, &d, &fb, &out->stats);
    if (s != PERSP_OK) fail_msg("render: %s", persp_context_error(ctx));
    free(depth);
    persp_scene_destroy(scene);
    persp_context_destroy(ctx);
}

/* Tiles are resolved independently and each sample's membership in a
 * piece is decided by the same arithmetic in every tile, so the image must
 * not depend on the thread count; the odd size leaves partial tiles. */
static void test_threads_bit_identical(void **state)
{
    (void)state;
    const char *scenes[] = {"corridor", "floor", "cube"};
    for (int i = 0; i < 3; i++) {
        os_render a, b, c;
        render_object(scenes[i], NULL, 1, 333, 257, &a);
        render_object(scenes[i], NULL, 2, 333, 257, &b);
        render_object(scenes[i], NULL, 5, 333, 257, &c);
        assert_memory_equal(a.color, b.color, (size_t)333 * 257 * 4);
        assert_memory_equal(a.color, c.color, (size_t)333 * 257 * 4);
        assert_true(a.stats.objspace_samples == c.stats.objspace_samples);
        free(a.color), free(b.color), free(c.color);
    }
}

/* Texel density >= 1 per pixel on every piece: no covered pixel may be
 * left without a sample ([Romaniuk-ObjSpace]'s "holes"), at several sizes, including
 * the corridor's strongly magnified near end and minified far end. */
static void test_no_holes(void **state)
{
    (void)state;
    const char *scenes[] = {"corridor", "floor", "cube"};
    const int sizes[][2] = {{64, 48}, {320, 240}, {1024, 768}};
    for (int i = 0; i < 3; i++)
        for (int k = 0; k < 3; k++) {
            if (k == 2 && i != 0) continue; /* full size: the corridor only */
            os_render r;
            render_object(scenes[i], NULL, 2, sizes[k][0], sizes[k][1], &r);
            if (r.stats.objspace_holes != 0)
                fail_msg("%s %dx%d: %llu holes", scenes[i], sizes[k][0], sizes[k][1],
                         (unsigned long long)r.stats.objspace_holes);
            assert_true(r.stats.objspace_pieces > 0);
            assert_true(r.stats.objspace_samples > 0);
            free(r.color);
        }
}

/* A constant texture: each pixel is Σ S_i·I / Σ S_i = I exactly, and a
 * splat only lands on pixels whose visible triangle is its own, so no
 * covered pixel may take any of the background's colour. */
static void test_constant_texture_no_bleeding(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    persp_image img;
    assert_int_equal(persp_image_alloc(ctx, 16, 16, &img), PERSP_OK);
    for (int y = 0; y < 16; y++)
        for (int x = 0; x < 16; x++) {
            uint8_t *p = img.pixels + (size_t)y * img.stride + 4 * (size_t)x;
            p[0] = 200, p[1] = 17, p[2] = 99, p[3] = 255;
        }
    os_render r;
    render_object("cube", &img, 1, 200, 150, &r);
    persp_image_free(ctx, &img);
    persp_context_destroy(ctx);
    /* The background is the first pixel (a corner outside the cube). */
    uint8_t bg[4];
    memcpy(bg, r.color, 4);
    assert_false(bg[0] == 200 && bg[1] == 17 && bg[2] == 99);
    size_t covered = 0;
    for (size_t i = 0; i < (size_t)200 * 150; i++) {
        const uint8_t *p = r.color + 4 * i;
        if (!memcmp(p, bg, 4)) continue;
        covered++;
        if (p[0] != 200 || p[1] != 17 || p[2] != 99 || p[3] != 255)
            fail_msg("pixel %zu is %d,%d,%d,%d", i, p[0], p[1], p[2], p[3]);
    }
    assert_true(covered > 1000);
    free(r.color);
}

/* [Romaniuk-ObjSpace]'s rotation and projection, checked numerically (the erratum is
 * recorded in docs/REPRODUCTION.md): with cos α = Nz/d, sin α = Ny/d,
 * cos β = d, sin β = Nx, d = sqrt(Ny² + Nz²) (printed with a minus), the
 * rotation takes N to the z axis, and the product (x, y, z, 1)·[Rxy]⁻¹·P
 * with the one-point projection P (r = -1/zc) has the denominator
 * 1 − r·sin α·y + r·Nz·z − r·cos α·sin β·x, not the printed
 * 1 − r·sin α·y + r·Nz·z − r·Ny·x (cos α·sin β = Nx·Nz/d is not Ny). */
static void test_rotation_errata(void **state)
{
    (void)state;
    test_rng rng = {61};
    int printed_wrong = 0;
    for (int it = 0; it < 200; it++) {
        double n[3];
        for (int k = 0; k < 3; k++) n[k] = test_rng_uniform(&rng, -1, 1);
        double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (l < 0.1) continue;
        for (int k = 0; k < 3; k++) n[k] /= l;
        double d = sqrt(n[1] * n[1] + n[2] * n[2]);
        if (d < 1e-3) continue;
        double ca = n[2] / d, sa = n[1] / d, cb = d, sb = n[0];
        /* [Rxy] of the paper (row vectors): rows (cb, 0, sb), (-sa·sb, ca, cb·sa), (-ca·sb, -sa, ca·cb). */
        double R[3][3] = {{cb, 0, sb}, {-sa * sb, ca, cb * sa}, {-ca * sb, -sa, ca * cb}};
        double Nr[3];
        for (int c = 0; c < 3; c++) Nr[c] = n[0] * R[0][c] + n[1] * R[1][c] + n[2] * R[2][c];
        assert_true(fabs(Nr[0]) < 1e-12 && fabs(Nr[1]) < 1e-12 && fabs(Nr[2] - 1.0) < 1e-12);
        /* Inverse: the transpose, as the paper prints it. */
        double r = -1.0 / test_rng_uniform(&rng, 1, 5);
        double x = test_rng_uniform(&rng, -2, 2), y = test_rng_uniform(&rng, -2, 2),
               z = test_rng_uniform(&rng, -2, 2);
        double e[3];
        for (int c = 0; c < 3; c++) e[c] = x * R[c][0] + y * R[c][1] + z * R[c][2];
        double w = 1.0 + r * e[2];
        double corrected = 1.0 - r * sa * y + r * n[2] * z - r * ca * sb * x;
        double printed = 1.0 - r * sa * y + r * n[2] * z - r * n[1] * x;
        assert_true(fabs(w - corrected) < 1e-12);
        /* The printed numerators of x'' and y'' are right. */
        assert_true(fabs(e[0] - (cb * x + sb * z)) < 1e-12);
        assert_true(fabs(e[1] - (ca * y + n[1] * z - sa * sb * x)) < 1e-12);
        if (fabs(w - printed) > 1e-6) printed_wrong++;
    }
    assert_true(printed_wrong > 100);
}

/* Writes a bumpy grid of cols x rows quads (two triangles each) with a
 * material whose texture is a 64x64 checker, as OBJ + MTL + PNG in dir:
 * neighbouring triangles face different ways, many nearly edge-on. */
static void write_bumpy_grid(const char *dir, int cols, int rows, double bump, char *obj, size_t n)
{
    char path[400];
    persp_context *ctx = test_context();
    persp_image img;
    assert_int_equal(persp_image_alloc(ctx, 64, 64, &img), PERSP_OK);
    for (int y = 0; y < 64; y++)
        for (int x = 0; x < 64; x++) {
            uint8_t *p = img.pixels + (size_t)y * img.stride + 4 * (size_t)x;
            uint8_t c = ((x / 8 + y / 8) & 1) ? 230 : 40;
            p[0] = c, p[1] = (uint8_t)(255 - c), p[2] = (uint8_t)(x * 4), p[3] = 255;
        }
    snprintf(path, sizeof path, "%s/checker.png", dir);
    assert_int_equal(persp_image_write_png(ctx, path, &img), PERSP_OK);
    persp_image_free(ctx, &img);
    persp_context_destroy(ctx);
    snprintf(path, sizeof path, "%s/grid.mtl", dir);
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fprintf(f, "newmtl grid\nKd 1 1 1\nmap_Kd checker.png\n");
    assert_int_equal(fclose(f), 0);
    snprintf(obj, n, "%s/grid.obj", dir);
    f = fopen(obj, "w");
    assert_non_null(f);
    fprintf(f, "mtllib grid.mtl\nusemtl grid\n");
    const double pi = 3.14159265358979, aspect = (double)rows / cols;
    for (int j = 0; j <= rows; j++)
        for (int i = 0; i <= cols; i++) {
            double s = (double)i / cols, t = (double)j / rows;
            fprintf(f, "v %.6f %.6f %.6f\n", 2 * s - 1, (2 * t - 1) * aspect,
                    bump * sin(8 * pi * s) * sin(8 * pi * t));
        }
    for (int j = 0; j <= rows; j++)
        for (int i = 0; i <= cols; i++) fprintf(f, "vt %.6f %.6f\n", (double)i / cols, (double)j / rows);
    for (int j = 0; j < rows; j++)
        for (int i = 0; i < cols; i++) {
            int p = j * (cols + 1) + i + 1, q = p + 1, r = p + cols + 2, s = p + cols + 1;
            fprintf(f, "f %d/%d %d/%d %d/%d\nf %d/%d %d/%d %d/%d\n", p, p, q, q, r, r, p, p, r, r, s, s);
        }
    assert_int_equal(fclose(f), 0);
}

static persp_status render_file(const char *path, int threads, int w, int h, persp_render_stats *stats)
{
    persp_context *ctx = test_context_threads(threads);
    persp_scene *scene = NULL;
    assert_int_equal(persp_scene_load(ctx, path, &scene), PERSP_OK);
    persp_framebuffer fb = test_framebuffer(w, h);
    persp_render_desc d;
    memset(&d, 0, sizeof d);
    d.pipeline = PERSP_PIPELINE_OBJECT;
    d.shading = PERSP_SHADING_NONE;
    persp_status s = persp_render(ctx, scene, &d, &fb, stats);
    test_framebuffer_free(&fb);
    persp_scene_destroy(scene);
    persp_context_destroy(ctx);
    return s;
}

/* The walk follows each triangle's screen footprint: an 80x20 bumpy grid
 * (3 200 triangles, many nearly edge-on) at 256x192 once walked thousands
 * of rows per small triangle (its margin came from the smallest singular
 * value of the mapping, capped at 1e8 rows) and did not finish in ten
 * minutes; bounded by the region's own rows it visits about 1.7e7 samples
 * and rows. */
static void test_bumpy_grid_work_bounded(void **state)
{
    (void)state;
    char dir[256], obj[400];
    assert_int_equal(test_tmpdir_make(dir, sizeof dir, "objspace"), 0);
    write_bumpy_grid(dir, 80, 20, 0.3, obj, sizeof obj);
    persp_render_stats st;
    assert_int_equal(render_file(obj, 2, 256, 192, &st), PERSP_OK);
    print_message("bumpy grid 256x192: %llu pieces, %llu samples walked, %llu visited, %llu holes\n",
                  (unsigned long long)st.objspace_pieces, (unsigned long long)st.objspace_samples,
                  (unsigned long long)st.objspace_visited, (unsigned long long)st.objspace_holes);
    assert_true(st.objspace_pieces >= 3000);
    assert_true(st.objspace_samples > 0);
    assert_true(st.objspace_visited >= st.objspace_samples);
    assert_true(st.objspace_visited <= 50000000u);
    test_tmpdir_remove(dir);
}

/* At the top of the mip pyramid the floor's far end once walked 1.35e8
 * samples for 64x48 pixels (78 000 per pixel, the texture's repeats); the
 * stride that keeps the density target bounds it by the pixels. */
static void test_small_image_work_bounded(void **state)
{
    (void)state;
    os_render r;
    render_object("floor", NULL, 1, 64, 48, &r);
    print_message("floor 64x48: %llu samples walked, %llu visited, %llu holes\n",
                  (unsigned long long)r.stats.objspace_samples,
                  (unsigned long long)r.stats.objspace_visited,
                  (unsigned long long)r.stats.objspace_holes);
    assert_int_equal(r.stats.objspace_holes, 0);
    assert_true(r.stats.objspace_samples > 0);
    assert_true(r.stats.objspace_samples <= 64u * 48u * 100u);
    assert_true(r.stats.objspace_visited <= 64u * 48u * 400u);
    free(r.color);
}

/* Work over the limit is refused before any sample is walked, with a
 * message that says so and what to do. */
static void test_work_limit_refused(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    ctx->objspace_max_work = 1e5;
    persp_scene *scene = NULL;
    assert_int_equal(persp_scene_builtin(ctx, "corridor", &scene), PERSP_OK);
    const int w = 320, h = 240;
    persp_framebuffer fb = test_framebuffer(w, h);
    persp_render_desc d;
    memset(&d, 0, sizeof d);
    d.pipeline = PERSP_PIPELINE_OBJECT;
    assert_int_equal(persp_render(ctx, scene, &d, &fb, NULL), PERSP_ERR_TOO_LARGE);
    const char *e = persp_context_error(ctx);
    if (!strstr(e, "object-space pipeline: about") || !strstr(e, "over its limit of 1e+05"))
        fail_msg("detail: %s", e);
    /* The default limit lets the same frame through. */
    ctx->objspace_max_work = 0.0;
    assert_int_equal(persp_render(ctx, scene, &d, &fb, NULL), PERSP_OK);
    test_framebuffer_free(&fb);
    persp_scene_destroy(scene);
    persp_context_destroy(ctx);
}

int main(int argc, char **argv)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_threads_bit_identical),
        cmocka_unit_test(test_no_holes),
        cmocka_unit_test(test_constant_texture_no_bleeding),
        cmocka_unit_test(test_rotation_errata),
        cmocka_unit_test(test_bumpy_grid_work_bounded),
        cmocka_unit_test(test_small_image_work_bounded),
        cmocka_unit_test(test_work_limit_refused),
    };
    return TEST_RUN(argc, argv, tests);
}
