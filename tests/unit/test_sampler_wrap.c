/*
 * Wrap modes and the nearest / bilinear filters against the OpenGL rules
 * (GL 4.6 §8.14.2, Table 8.20), written out here independently of
 * src/texture: with u' = s·W the nearest texel is wrap(floor(u')); the
 * linear filter blends texels wrap(floor(u' − ½)) and the next one with
 * weight frac(u' − ½); clamp-to-border reads the border colour for indices
 * outside [0, W). Coordinates: texel centres, texel edges, and values far
 * outside [0, 1] on both sides, on a 5×3 texture (sizes that are not powers
 * of two, so a mask instead of a modulo would fail). Row 0 of the image is
 * t = 0 (docs/CONVENTIONS.md).
 */
#include "support.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { TW = 5, TH = 3 };
static const uint8_t border[4] = {201, 7, 99, 33};

static void texel_colour(int i, int j, uint8_t c[4])
{
    c[0] = (uint8_t)(10 + 40 * i);
    c[1] = (uint8_t)(20 + 60 * j);
    c[2] = (uint8_t)(7 * i + 13 * j);
    c[3] = (uint8_t)(255 - 9 * i);
}

/* Table 8.20, -1 meaning the border colour. */
static int ref_wrap(persp_wrap mode, int i, int size)
{
    switch (mode) {
    case PERSP_WRAP_REPEAT:
        return ((i % size) + size) % size;
    case PERSP_WRAP_CLAMP_TO_EDGE:
        return i < 0 ? 0 : (i > size - 1 ? size - 1 : i);
    case PERSP_WRAP_MIRRORED_REPEAT: {
        int k = ((i % (2 * size)) + 2 * size) % (2 * size);
        return k < size ? k : 2 * size - 1 - k;
    }
    case PERSP_WRAP_CLAMP_TO_BORDER:
        return (i < 0 || i >= size) ? -1 : i;
    case PERSP_WRAP_DEFAULT:
        return ref_wrap(PERSP_WRAP_REPEAT, i, size);
    }
    return -2;
}

static void ref_texel(persp_wrap ws, persp_wrap wt, int i, int j, double out[4])
{
    int x = ref_wrap(ws, i, TW), y = ref_wrap(wt, j, TH);
    uint8_t c[4];
    if (x < 0 || y < 0)
        memcpy(c, border, 4);
    else
        texel_colour(x, y, c);
    for (int k = 0; k < 4; k++)
        out[k] = c[k];
}

static persp_texture *make_texture(persp_context *ctx)
{
    persp_image img;
    assert_int_equal(persp_image_alloc(ctx, TW, TH, &img), PERSP_OK);
    for (int j = 0; j < TH; j++)
        for (int i = 0; i < TW; i++)
            texel_colour(i, j, img.pixels + (size_t)j * img.stride + 4u * (size_t)i);
    persp_texture *tex = NULL;
    assert_int_equal(persp_texture_create(ctx, &img, &tex), PERSP_OK);
    persp_image_free(ctx, &img);
    return tex;
}

static const persp_wrap modes[] = {PERSP_WRAP_REPEAT, PERSP_WRAP_CLAMP_TO_EDGE,
                                   PERSP_WRAP_MIRRORED_REPEAT, PERSP_WRAP_CLAMP_TO_BORDER};

/* Coordinates along one axis of size n: centres and edges of texels from
 * -2n to 3n, plus some arbitrary points far outside. */
static size_t coords(int n, float *out)
{
    size_t k = 0;
    for (int i = -2 * n; i <= 3 * n; i++) {
        out[k++] = ((float)i + 0.5f) / (float)n; /* centre */
        out[k++] = (float)i / (float)n;          /* edge */
        out[k++] = ((float)i + 0.23f) / (float)n;
    }
    out[k++] = -1000.37f;
    out[k++] = 777.61f;
    return k;
}

static void test_nearest_every_wrap(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    persp_texture *tex = make_texture(ctx);
    float us[128], vs[128];
    size_t nu = coords(TW, us), nv = coords(TH, vs);
    long checked = 0;
    for (size_t ms = 0; ms < 4; ms++)
        for (size_t mt = 0; mt < 4; mt++) {
            persp_sampler_desc sd;
            memset(&sd, 0, sizeof sd);
            sd.wrap_s = modes[ms], sd.wrap_t = modes[mt];
            sd.filter = PERSP_FILTER_NEAREST;
            memcpy(sd.border, border, 4);
            for (size_t a = 0; a < nu; a++)
                for (size_t b = 0; b < nv; b++) {
                    uint8_t got[4];
                    persp_texture_sample(tex, &sd, us[a], vs[b], 0, 0, 0, 0, got);
                    double want[4];
                    ref_texel(sd.wrap_s, sd.wrap_t, (int)floorf(us[a] * (float)TW),
                              (int)floorf(vs[b] * (float)TH), want);
                    for (int k = 0; k < 4; k++)
                        if (got[k] != (uint8_t)want[k])
                            fail_msg("nearest %s/%s at (%g, %g): channel %d got %u, expected %u",
                                     persp_wrap_name(sd.wrap_s), persp_wrap_name(sd.wrap_t),
                                     (double)us[a], (double)vs[b], k, got[k], (unsigned)want[k]);
                    checked++;
                }
        }
    assert_true(checked > 10000);
    persp_texture_destroy(tex);
    persp_context_destroy(ctx);
}

static void test_bilinear_every_wrap(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    persp_texture *tex = make_texture(ctx);
    float us[128], vs[128];
    size_t nu = coords(TW, us), nv = coords(TH, vs);
    long exact_centres = 0;
    for (size_t m = 0; m < 4; m++) {
        persp_sampler_desc sd;
        memset(&sd, 0, sizeof sd);
        sd.wrap_s = sd.wrap_t = modes[m];
        sd.filter = PERSP_FILTER_BILINEAR;
        memcpy(sd.border, border, 4);
        for (size_t a = 0; a < nu; a++)
            for (size_t b = 0; b < nv; b++) {
                double x = (double)(us[a] * (float)TW) - 0.5, y = (double)(vs[b] * (float)TH) - 0.5;
                int i0 = (int)floor(x), j0 = (int)floor(y);
                double al = x - i0, be = y - j0, want[4] = {0, 0, 0, 0}, t[4];
                for (int dj = 0; dj < 2; dj++)
                    for (int di = 0; di < 2; di++) {
                        double w = (di ? al : 1 - al) * (dj ? be : 1 - be);
                        ref_texel(sd.wrap_s, sd.wrap_t, i0 + di, j0 + dj, t);
                        for (int k = 0; k < 4; k++)
                            want[k] += w * t[k];
                    }
                uint8_t got[4];
                persp_texture_sample(tex, &sd, us[a], vs[b], 0, 0, 0, 0, got);
                /* The filter works in float and rounds once: within one unit. */
                for (int k = 0; k < 4; k++)
                    if (fabs(got[k] - want[k]) > 1.0)
                        fail_msg("bilinear %s at (%g, %g): channel %d got %u, expected %.2f",
                                 persp_wrap_name(sd.wrap_s), (double)us[a], (double)vs[b], k,
                                 got[k], want[k]);
                /* At a texel centre the result is that texel, unblended. */
                if (al == 0.0 && be == 0.0) {
                    exact_centres++;
                    for (int k = 0; k < 4; k++)
                        assert_int_equal(got[k], (uint8_t)want[k]);
                }
            }
    }
    assert_true(exact_centres > 100);
    persp_texture_destroy(tex);
    persp_context_destroy(ctx);
}

static void test_names_and_orientation(void **state)
{
    (void)state;
    const char *names[] = {"repeat", "clamp-to-edge", "mirrored-repeat", "clamp-to-border"};
    for (size_t i = 0; i < 4; i++) {
        persp_wrap w;
        assert_int_equal(persp_wrap_parse(names[i], &w), PERSP_OK);
        assert_int_equal(w, modes[i]);
        assert_string_equal(persp_wrap_name(w), names[i]);
    }
    persp_wrap w;
    assert_int_not_equal(persp_wrap_parse("clamp", &w), PERSP_OK);
    assert_int_not_equal(persp_wrap_parse("", &w), PERSP_OK);
    /* Image row 0 is t in [0, 1/H): the bottom of the displayed image. */
    persp_context *ctx = test_context();
    persp_texture *tex = make_texture(ctx);
    persp_sampler_desc sd;
    memset(&sd, 0, sizeof sd);
    uint8_t got[4], want[4];
    persp_texture_sample(tex, &sd, 0.5f / TW, 0.5f / TH, 0, 0, 0, 0, got);
    texel_colour(0, 0, want);
    assert_memory_equal(got, want, 4);
    persp_texture_sample(tex, &sd, 4.5f / TW, 2.5f / TH, 0, 0, 0, 0, got);
    texel_colour(4, 2, want);
    assert_memory_equal(got, want, 4);
    persp_texture_destroy(tex);
    persp_context_destroy(ctx);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_nearest_every_wrap),
        cmocka_unit_test(test_bilinear_every_wrap),
        cmocka_unit_test(test_names_and_orientation),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
