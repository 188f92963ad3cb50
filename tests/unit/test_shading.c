/* Shading: spherical-angular normals ([Romanyuk-PCF] §4.3) and perspective-correct
 * vertex colours against independent double-precision references. */
#include "support.h"

#include "core/fmath.h"
#include "geom/scene.h"
#include "shade/shade.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static void random_unit(test_rng *r, float n[3])
{
    double v[3], l;
    do {
        for (int i = 0; i < 3; i++) v[i] = test_rng_uniform(r, -1, 1);
        l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    } while (l < 0.2 || l > 1.0);
    for (int i = 0; i < 3; i++) n[i] = (float)(v[i] / l);
}

static void test_slerp_unit_length_and_ends(void **state)
{
    (void)state;
    test_rng rng = {99};
    double worst = 0.0;
    for (int i = 0; i < 2000; i++) {
        float a[3], b[3], o[3];
        random_unit(&rng, a);
        random_unit(&rng, b);
        if (a[0] * b[0] + a[1] * b[1] + a[2] * b[2] < -0.95f) continue; /* nearly opposite */
        persp_slerp s;
        persp__slerp_init(&s, a, b, test_rng_uniform(&rng, 0.2, 8.0));
        for (int k = 0; k <= 16; k++)
            for (int p = 0; p < 2; p++) {
                persp__slerp_eval(&s, k / 16.0, p, o);
                double len = sqrt((double)o[0] * o[0] + (double)o[1] * o[1] + (double)o[2] * o[2]);
                worst = fmax(worst, fabs(len - 1.0));
                if (k == 16)
                    for (int c = 0; c < 3; c++) assert_true(fabsf(o[c] - b[c]) < 1e-4f);
                if (k == 0)
                    for (int c = 0; c < 3; c++) assert_true(fabsf(o[c] - a[c]) < 1e-6f);
            }
    }
    print_message("slerp: max | |N| - 1 | = %.3g\n", worst);
    assert_true(worst < 1e-6);
}

static void test_slerp_perspective_is_exact_nlerp(void **state)
{
    (void)state;
    /* The perspective-correct cotangent form equals normalising the linear
     * interpolation with the world-space parameter t_w = t_v/(ħ − t_v(ħ − 1))
     * of (4.7); the screen form is plain slerp (equal angles on screen). */
    test_rng rng = {5};
    for (int i = 0; i < 500; i++) {
        float a[3], b[3], o[3];
        random_unit(&rng, a);
        random_unit(&rng, b);
        if (a[0] * b[0] + a[1] * b[1] + a[2] * b[2] < -0.9f) continue;
        double hbar = test_rng_uniform(&rng, 0.25, 6.0);
        persp_slerp s;
        persp__slerp_init(&s, a, b, hbar);
        for (int k = 1; k < 10; k++) {
            double tv = k / 10.0, tw = tv / (hbar - tv * (hbar - 1.0));
            double m[3], l = 0;
            for (int c = 0; c < 3; c++) m[c] = a[c] + tw * (b[c] - a[c]), l += m[c] * m[c];
            l = sqrt(l);
            persp__slerp_eval(&s, tv, 1, o);
            for (int c = 0; c < 3; c++) assert_true(fabs(o[c] - m[c] / l) < 2e-5);
        }
        persp__slerp_eval(&s, 0.5, 0, o);
        double bis[3], bl = 0;
        for (int c = 0; c < 3; c++) bis[c] = a[c] + b[c], bl += bis[c] * bis[c];
        bl = sqrt(bl);
        for (int c = 0; c < 3; c++) assert_true(fabs(o[c] - bis[c] / bl) < 2e-5);
    }
}

static void test_shading_names(void **state)
{
    (void)state;
    for (int i = 0; i < PERSP_SHADING_COUNT; i++) {
        persp_shading s;
        assert_int_equal(persp_shading_parse(persp_shading_name((persp_shading)i), &s), PERSP_OK);
        assert_int_equal((int)s, i);
    }
    persp_shading s;
    assert_int_equal(persp_shading_parse("glossy", &s), PERSP_ERR_NOT_FOUND);
}

/* Vertex colours through persp_draw are perspective-correct: each pixel's
 * colour matches the barycentric weights of the point where its ray meets the
 * triangle, computed here in double from the eye-space geometry. */
static void test_vertex_colour_perspective_correct(void **state)
{
    (void)state;
    enum { W = 96, H = 72 };
    persp_context *ctx = test_context();
    uint8_t *color = calloc(W * H, 4);
    float *depth = calloc(W * H, sizeof(float));
    persp_framebuffer fb = {W, H, color, depth};
    persp_framebuffer_clear(&fb, NULL, PERSP_DEPTH_Z);
    const double fovy = 60.0, aspect = (double)W / H;
    persp_vertex v[3];
    memset(v, 0, sizeof v);
    const float P[3][3] = {{-3.0f, -2.0f, -1.5f}, {4.0f, -1.0f, -12.0f}, {-1.0f, 3.5f, -6.0f}};
    for (int k = 0; k < 3; k++) {
        memcpy(v[k].pos, P[k], sizeof v[k].pos);
        v[k].color[k] = 1.0f;
        v[k].color[3] = 1.0f;
    }
    uint32_t idx[3] = {0, 1, 2};
    persp_draw_desc d;
    memset(&d, 0, sizeof d);
    d.mvp = persp_perspective(fovy, aspect, 0.1, 100.0);
    assert_int_equal(persp_draw(ctx, &fb, &d, v, 3, idx, 3), PERSP_OK);
    const double t = tan(fovy * 3.14159265358979323846 / 360.0);
    double e1[3], e2[3], n[3];
    for (int c = 0; c < 3; c++) e1[c] = P[1][c] - P[0][c], e2[c] = P[2][c] - P[0][c];
    n[0] = e1[1] * e2[2] - e1[2] * e2[1], n[1] = e1[2] * e2[0] - e1[0] * e2[2], n[2] = e1[0] * e2[1] - e1[1] * e2[0];
    double area = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
    int checked = 0, worst = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            if (depth[y * W + x] >= 1.0f) continue;
            /* Ray through the pixel centre. */
            double dir[3] = {((x + 0.5) / W * 2 - 1) * t * aspect, ((y + 0.5) / H * 2 - 1) * t, -1.0};
            double s = (n[0] * P[0][0] + n[1] * P[0][1] + n[2] * P[0][2]) / (n[0] * dir[0] + n[1] * dir[1] + n[2] * dir[2]);
            double p[3] = {dir[0] * s, dir[1] * s, dir[2] * s}, w[3];
            for (int k = 0; k < 3; k++) {
                const float *a = P[(k + 1) % 3], *b = P[(k + 2) % 3];
                double u1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, u2[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
                double c[3] = {u1[1] * u2[2] - u1[2] * u2[1], u1[2] * u2[0] - u1[0] * u2[2], u1[0] * u2[1] - u1[1] * u2[0]};
                w[k] = (c[0] * n[0] + c[1] * n[1] + c[2] * n[2]) / area;
            }
            /* Pixels whose centre lies right at an edge can be covered by
             * rounding; skip those where a weight is outside [0,1]. */
            if (w[0] < 0 || w[1] < 0 || w[2] < 0) continue;
            for (int c = 0; c < 3; c++) {
                int want = (int)floor(w[c] * 255.0 + 0.5);
                int got = color[4 * (y * W + x) + c];
                int e = abs(got - want);
                if (e > worst) worst = e;
            }
            checked++;
        }
    print_message("vertex colour: %d pixels, max error %d levels\n", checked, worst);
    assert_true(checked > 500);
    assert_true(worst <= 1);
    free(color);
    free(depth);
    persp_context_destroy(ctx);
}

/* Texture environment ([CS300-TexMap]): replace shows the texel whatever the
 * lighting; modulate multiplies the lit ambient + diffuse colour by it and
 * adds the specular highlight (Blinn–Phong). A uniform texture on a square
 * facing the eye, lit head-on by a directional light, so every term is
 * known: ambient 0.2·0.5 + diffuse 0.6·1 = 0.7; specular 0.25·(N·H)^1 with
 * H ≈ N at the centre pixel. */
static void render_env(persp_context *ctx, persp_texenv env, int spec_tex, persp_shading shading, uint8_t px[4])
{
    enum { W = 64, H = 64 };
    persp_scene *s = NULL;
    assert_int_equal(persp__scene_new(ctx, &s), PERSP_OK);
    s->camera.eye = (persp_vec3){0, 0, 3};
    s->camera.target = (persp_vec3){0, 0, 0};
    s->camera.fovy_deg = 40.0f;
    for (int c = 0; c < 3; c++) s->ambient[c] = 0.2f;
    s->light_count = 1;
    s->lights[0].type = PERSP_LIGHT_DIRECTIONAL;
    s->lights[0].position[2] = 1.0f;
    for (int c = 0; c < 3; c++) s->lights[0].color[c] = 1.0f;
    persp_image img;
    assert_int_equal(persp_image_alloc(ctx, 4, 4, &img), PERSP_OK);
    for (int y = 0; y < 4; y++)
        for (int x = 0; x < 4; x++) {
            uint8_t *p = img.pixels + (size_t)y * img.stride + 4 * (size_t)x;
            p[0] = 200, p[1] = 100, p[2] = 50, p[3] = 255;
        }
    persp_texture *tex = NULL;
    assert_int_equal(persp_texture_create(ctx, &img, &tex), PERSP_OK);
    persp_image_free(ctx, &img);
    int ti, mi, me;
    assert_int_equal(persp__scene_add_texture(s, tex, &ti), PERSP_OK);
    persp_material m = persp__material_default();
    for (int c = 0; c < 3; c++) m.ambient[c] = 0.5f, m.diffuse[c] = 0.6f, m.specular[c] = 0.25f;
    m.shininess = 1.0f;
    m.texture = ti;
    m.specular_texture = spec_tex ? ti : -1;
    m.env = env;
    assert_int_equal(persp__scene_add_material(s, &m, &mi), PERSP_OK);
    persp_mesh mesh;
    assert_int_equal(persp__mesh_plane(ctx, 1, &mesh), PERSP_OK);
    assert_int_equal(persp__scene_add_mesh(s, &mesh, &me), PERSP_OK);
    persp_object o;
    memset(&o, 0, sizeof o);
    o.mesh = me, o.material = mi;
    o.model = persp_mat4_rotate(90.0f, 1.0f, 0.0f, 0.0f); /* normal +y -> +z, facing the eye */
    assert_int_equal(persp__scene_add_object(s, &o), PERSP_OK);
    uint8_t *color = calloc(W * H, 4);
    float *depth = calloc(W * H, sizeof(float));
    persp_framebuffer fb = {W, H, color, depth};
    persp_render_desc d;
    memset(&d, 0, sizeof d);
    d.shading = shading;
    assert_int_equal(persp_render(ctx, s, &d, &fb, NULL), PERSP_OK);
    memcpy(px, color + 4 * ((H / 2) * W + W / 2), 4);
    free(color);
    free(depth);
    persp_scene_destroy(s);
}

static void test_texture_env(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    const persp_shading modes[] = {PERSP_SHADING_FLAT, PERSP_SHADING_PHONG_PC, PERSP_SHADING_PHONG_SLERP};
    /* Gouraud's vertex colour carries its specular term, which modulate
     * then scales by the texel: only replace has the texel to check. */
    const persp_shading gouraud[] = {PERSP_SHADING_GOURAUD, PERSP_SHADING_GOURAUD_PC};
    for (size_t i = 0; i < sizeof gouraud / sizeof gouraud[0]; i++) {
        uint8_t px[4];
        render_env(ctx, PERSP_TEXENV_REPLACE, 1, gouraud[i], px);
        assert_true(px[0] == 200 && px[1] == 100 && px[2] == 50);
    }
    for (size_t i = 0; i < sizeof modes / sizeof modes[0]; i++) {
        uint8_t px[4];
        render_env(ctx, PERSP_TEXENV_REPLACE, 1, modes[i], px);
        assert_true(px[0] == 200 && px[1] == 100 && px[2] == 50);
        for (int st = 0; st < 2; st++) {
            render_env(ctx, PERSP_TEXENV_MODULATE, st, modes[i], px);
            /* 0.7·texel + 0.25·255 (0.25·texel when the texture is also the
             * specular colour), within a level: N·H at the centre pixel
             * differs from 1 by less than 1e-3. */
            const double tex[3] = {200, 100, 50};
            for (int c = 0; c < 3; c++) {
                double want = 0.7 * tex[c] + 0.25 * (st ? tex[c] : 255.0);
                if (fabs(px[c] - want) > 1.0)
                    fail_msg("%s modulate (specular texture %d): channel %d = %d, expected %.2f",
                             persp_shading_name(modes[i]), st, c, px[c], want);
            }
        }
    }
    persp_context_destroy(ctx);
}

/* With a texture and the environment replace the colour is the texel
 * whatever the lighting, so every shading mode's span is the texel itself
 * (shade_is_texel): the renderer then samples straight into the
 * destination and lights nothing — vertices, set-up's shading fields and
 * pixels (a lit corridor, all replace, drew 1.3–1.6 times slower before). Not
 * with modulate, nor without a texture. */
static void test_replace_is_texel(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    persp_image img;
    assert_int_equal(persp_image_alloc(ctx, 4, 4, &img), PERSP_OK);
    memset(img.pixels, 0x80, (size_t)img.stride * 4);
    persp_texture *tex = NULL;
    assert_int_equal(persp_texture_create(ctx, &img, &tex), PERSP_OK);
    persp_image_free(ctx, &img);
    int lit_modes = 0;
    for (int mode = PERSP_SHADING_NONE; mode <= PERSP_SHADING_PHONG_SLERP_SCREEN; mode++)
        for (int env = 0; env < 2; env++)
            for (int textured = 0; textured < 2; textured++) {
                persp_draw_state ds;
                memset(&ds, 0, sizeof ds);
                ds.shading = (persp_shading)mode;
                ds.material = persp__material_default();
                ds.material.env = env ? PERSP_TEXENV_REPLACE : PERSP_TEXENV_MODULATE;
                ds.tex = textured ? tex : NULL;
                assert_int_equal(persp__method_resolve(ctx, "exact", &ds.method), PERSP_OK);
                assert_int_equal(persp__shade_resolve(ctx, &ds), PERSP_OK);
                const int want = textured && (env || mode == PERSP_SHADING_NONE);
                if (ds.shade_is_texel != want)
                    fail_msg("%s, %s, %s: shade_is_texel %d, expected %d", persp_shading_name(ds.shading),
                             env ? "replace" : "modulate", textured ? "textured" : "untextured",
                             ds.shade_is_texel, want);
                lit_modes += mode != PERSP_SHADING_NONE && want;
            }
    assert_true(lit_modes >= 10);
    persp_texture_destroy(tex);
    persp_context_destroy(ctx);
}

/* Two-sided Gouraud lighting picks the front or back vertex colours per
 * triangle, as OpenGL does by polygon facing. A triangle facing the eye
 * whose vertex normal at v1 turns away from the eye and the light (a
 * silhouette vertex of a smooth mesh) must keep v1 dark: lighting v1's
 * flipped normal instead (a per-vertex choice of side) lit a bright rim
 * on the dark side of curved objects. The back face of the same triangle
 * takes the back colours. */
static void test_gouraud_two_sided_per_triangle(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    persp_draw_state ds;
    memset(&ds, 0, sizeof ds);
    ds.shading = PERSP_SHADING_GOURAUD_PC;
    assert_int_equal(persp__method_resolve(ctx, "exact", &ds.method), PERSP_OK);
    for (int c = 0; c < 3; c++) {
        ds.material.diffuse[c] = 1.0f;
        ds.lighting.light[0].color[c] = 1.0f;
    }
    ds.material.texture = ds.material.specular_texture = -1;
    ds.lighting.count = 1;
    ds.lighting.light[0].type = PERSP_LIGHT_DIRECTIONAL;
    ds.lighting.light[0].pos[2] = 1.0f; /* towards +z: behind the eye */
    assert_int_equal(persp__shade_resolve(ctx, &ds), PERSP_OK);

    /* Eye-space triangle in the plane z = -5, facing the eye (+z). */
    const float P[3][3] = {{-1.0f, -1.0f, -5.0f}, {1.0f, -1.0f, -5.0f}, {0.0f, 1.0f, -5.0f}};
    const float N[3][3] = {{0.0f, 0.0f, 1.0f}, {0.9f, 0.0f, -0.43589f}, {0.0f, 0.0f, 1.0f}};
    persp_clipvert cv[3];
    memset(cv, 0, sizeof cv);
    for (int k = 0; k < 3; k++)
        for (int c = 0; c < 3; c++) {
            cv[k].attr[PERSP_A_NX + c] = N[k][c];
            cv[k].attr[PERSP_A_EX + c] = P[k][c];
        }
    persp__shade_vertices(&ds, cv, 3);
    /* Front colour of v1: N·L < 0, no ambient: black. Back colour: lit. */
    assert_true(cv[1].attr[PERSP_A_R] == 0.0f);
    assert_true(cv[1].attr[PERSP_A_BR] > 0.4f);
    assert_true(cv[0].attr[PERSP_A_R] > 0.99f);

    for (int facing = 0; facing < 2; facing++) {
        persp_tri t;
        memset(&t, 0, sizeof t);
        for (int k = 0; k < 3; k++) {
            memcpy(t.vattr[k], cv[k].attr, sizeof t.vattr[k]);
            if (facing) /* the back side: every normal reversed */
                for (int c = 0; c < 3; c++) t.vattr[k][PERSP_A_NX + c] = -N[k][c];
        }
        t.light_side = persp__shade_light_side(&t); /* as set-up does */
        /* Screen-linear barycentrics b1 = x / 10, b2 = y / 10 on a 10x10 area. */
        t.lb1[0] = 0.1;
        t.lb2[1] = 0.1;
        t.bary.g = 0.0, t.bary.h = 0.0, t.bary.i = 1.0;
        t.bary.a = 0.1, t.bary.e = 0.1;
        float q[PERSP_SPAN_MAX];
        uint32_t out[PERSP_SPAN_MAX];
        for (int k = 0; k < PERSP_SPAN_MAX; k++) q[k] = 1.0f;
        /* Pixel (9, 0): b1 = 0.95, nearly all of v1. */
        persp_frag_batch b = {.n = 1, .x0 = 9, .y = 0};
        ds.shade(&ds, &t, &b, q, NULL, out);
        int red = (int)(out[0] & 0xffu);
        if (facing == 0 && red > 20) fail_msg("front face near its turned-away vertex: red %d, expected dark", red);
        if (facing == 1 && red < 20) fail_msg("back face near v1: red %d, expected v1's back colour", red);
    }
    persp_context_destroy(ctx);
}

/* The specular power replaces libm's powf. What reaches an 8-bit colour is
 * the absolute error (x^s <= 1 scales a light colour), which stays below
 * 1e-6 (0.0003 of a level); relative to x^s it stays below 1e-5 wherever
 * x^s >= 1e-3 for shininess up to GL's 128. Exact 1 at x = 1, and 0 for
 * x <= 0 and far underflow. */
static void test_powf_unit(void **state)
{
    (void)state;
    double worst_abs = 0.0, worst_rel = 0.0;
    const float shin[] = {0.5f, 1.0f, 2.0f, 7.3f, 32.0f, 60.0f, 128.0f, 1000.0f};
    for (size_t si = 0; si < sizeof shin / sizeof *shin; si++)
        for (int k = 1; k <= 100000; k++) {
            float x = (float)k / 100000.0f;
            double want = pow((double)x, (double)shin[si]);
            double got = persp__powf_unit(x, shin[si]);
            double a = fabs(got - want);
            if (a > worst_abs) worst_abs = a;
            if (want >= 1e-3 && shin[si] <= 128.0f && a / want > worst_rel) worst_rel = a / want;
        }
    print_message("powf_unit: max absolute error %.3g, relative %.3g\n", worst_abs, worst_rel);
    assert_true(worst_abs < 1e-6);
    assert_true(worst_rel < 1e-5);
    assert_true(persp__powf_unit(1.0f, 60.0f) == 1.0f);
    assert_true(persp__powf_unit(0.0f, 60.0f) == 0.0f);
    assert_true(persp__powf_unit(-0.5f, 3.0f) == 0.0f);
    assert_true(persp__powf_unit(1e-20f, 100.0f) == 0.0f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_slerp_unit_length_and_ends),
        cmocka_unit_test(test_slerp_perspective_is_exact_nlerp),
        cmocka_unit_test(test_shading_names),
        cmocka_unit_test(test_powf_unit),
        cmocka_unit_test(test_vertex_colour_perspective_correct),
        cmocka_unit_test(test_texture_env),
        cmocka_unit_test(test_replace_is_texel),
        cmocka_unit_test(test_gouraud_two_sided_per_triangle),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
