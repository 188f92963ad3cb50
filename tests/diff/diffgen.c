/*
 * Scene generator of the differential test (diffgen.h). Every choice comes
 * from one SplitMix64 stream seeded by the case's seed, so a seed names the
 * same scene on every machine.
 *
 * What is varied, and why:
 *   - textures of 1..300 texels a side, half of them not powers of two,
 *     filled with per-texel noise (the worst case for any difference in
 *     filter weights), checkers (sampling ties on texel edges) or smooth
 *     ramps; alpha is always 1 (see the clear colour below);
 *   - every wrap mode of GL 4.6 Table 8.20 per axis, border colours;
 *   - texture coordinates from the meshes (uv) or from object-linear planes
 *     with random scale and offset, which reach far outside [0, 1] so that
 *     the wrap modes act;
 *   - the built-in primitives under random scale / rotation / translation,
 *     about one in fourteen mirrored (a negative scale: its front faces
 *     wind clockwise, which culling must follow),
 *     a large floor seen at grazing angles that runs behind the camera (it
 *     crosses the near plane), sometimes the camera inside an object;
 *   - image sizes that are not multiples of the 64-pixel tiles nor of
 *     llvmpipe's;
 *   - depth modes z and 1/w, culling on and off.
 * Shading is always `none` with GL_REPLACE: lit results differ between GL
 * and persp by design (docs/PERFORMANCE.md, "Where GL's conventions and
 * persp's differ").
 *
 * The clear colour has alpha 0 while every texel and border has alpha 1,
 * so that each side's coverage can be read from its image alone (GL's
 * colour buffer holds the fragment's alpha, GL 4.6 §17.3).
 */
#include "diffgen.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const persp_filter diff_filters[DIFF_FILTER_COUNT] = {
    PERSP_FILTER_NEAREST,
    PERSP_FILTER_BILINEAR,
    PERSP_FILTER_NEAREST_MIP_NEAREST,
    PERSP_FILTER_BILINEAR_MIP_NEAREST,
    PERSP_FILTER_NEAREST_MIP_LINEAR,
    PERSP_FILTER_TRILINEAR,
};

typedef struct rng {
    uint64_t s;
} rng;

/* SplitMix64 (Steele, Lea, Flood, "Fast splittable pseudorandom number
 * generators", OOPSLA 2014). */
static uint64_t next(rng *r)
{
    uint64_t z = (r->s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

static double uni(rng *r, double lo, double hi)
{
    return lo + (hi - lo) * (double)(next(r) >> 11) * (1.0 / 9007199254740992.0);
}

static int irange(rng *r, int lo, int hi) /* inclusive */
{
    return lo + (int)(next(r) % (uint64_t)(hi - lo + 1));
}

static int texture_side(rng *r)
{
    int pot = (int)(next(r) & 1);
    int band = irange(r, 0, 2);
    int lo = band == 0 ? 1 : band == 1 ? 9 : 65, hi = band == 0 ? 8 : band == 1 ? 64 : 300;
    int n = irange(r, lo, hi);
    if (pot) {
        int p = 1;
        while (p * 2 <= n) p *= 2;
        n = p;
    }
    return n;
}

static int write_texture(persp_context *ctx, rng *r, const char *path, char *err, size_t err_size)
{
    int w = texture_side(r), h = texture_side(r);
    persp_image img;
    if (persp_image_alloc(ctx, w, h, &img) != PERSP_OK) {
        snprintf(err, err_size, "%s", persp_context_error(ctx));
        return -1;
    }
    int kind = irange(r, 0, 2);
    int period = irange(r, 1, 8);
    uint8_t a[3], b[3];
    for (int c = 0; c < 3; c++) a[c] = (uint8_t)irange(r, 0, 255), b[c] = (uint8_t)irange(r, 0, 255);
    double fx = uni(r, 0.5, 6.0), fy = uni(r, 0.5, 6.0);
    for (int y = 0; y < h; y++) {
        uint8_t *row = img.pixels + (size_t)y * img.stride;
        for (int x = 0; x < w; x++) {
            uint8_t *p = row + 4 * x;
            for (int c = 0; c < 3; c++) {
                double v;
                switch (kind) {
                case 0: v = (double)(next(r) & 255); break;
                case 1: v = ((x / period + y / period) & 1) ? a[c] : b[c]; break;
                default:
                    v = 127.5 + 127.5 * sin(6.283185307179586 * (fx * (x + 0.5) / w + (c + 1) * fy * (y + 0.5) / h));
                    break;
                }
                p[c] = (uint8_t)(v < 0 ? 0 : v > 255 ? 255 : v);
            }
            p[3] = 255;
        }
    }
    persp_status st = persp_image_write_png(ctx, path, &img);
    persp_image_free(ctx, &img);
    if (st != PERSP_OK) {
        snprintf(err, err_size, "%s", persp_context_error(ctx));
        return -1;
    }
    return 0;
}

static const char *const wraps[] = {"repeat", "clamp-to-edge", "mirrored-repeat", "clamp-to-border"};

static void rotation(rng *r, FILE *f)
{
    double ax[3];
    do {
        for (int i = 0; i < 3; i++) ax[i] = uni(r, -1, 1);
    } while (ax[0] * ax[0] + ax[1] * ax[1] + ax[2] * ax[2] < 0.01);
    fprintf(f, "[%.6g, %.6g, %.6g, %.6g]", uni(r, -180, 180), ax[0], ax[1], ax[2]);
}

static void texgen(rng *r, FILE *f)
{
    if (next(r) & 1) {
        fprintf(f, "\"uv\"");
        return;
    }
    double k = uni(r, 0.3, 4.0);
    fprintf(f, "{\"mode\": \"planar\", \"s\": [%.6g, %.6g, %.6g, %.6g], \"t\": [%.6g, %.6g, %.6g, %.6g]}",
            k * uni(r, -1, 1), k * uni(r, -1, 1), k * uni(r, -1, 1), uni(r, -2, 2), k * uni(r, -1, 1),
            k * uni(r, -1, 1), k * uni(r, -1, 1), uni(r, -2, 2));
}

int diff_generate(persp_context *ctx, uint64_t seed, const char *dir, diff_case *out, char *err,
                  size_t err_size)
{
    rng r = {seed};
    diff_case c;
    c.seed = seed;
    c.width = irange(&r, 48, 320);
    c.height = irange(&r, 36, 240);
    c.filter = diff_filters[irange(&r, 0, DIFF_FILTER_COUNT - 1)];
    c.depth = (next(&r) & 1) ? PERSP_DEPTH_INVW : PERSP_DEPTH_Z;

    char path[4096];
    int ntex = irange(&r, 1, 3);
    for (int t = 0; t < ntex; t++) {
        snprintf(path, sizeof path, "%s/tex%d.png", dir, t);
        if (write_texture(ctx, &r, path, err, err_size)) return -1;
    }
    snprintf(path, sizeof path, "%s/scene.json", dir);
    FILE *f = fopen(path, "w");
    if (!f) {
        snprintf(err, err_size, "%s: %s", path, strerror(errno));
        return -1;
    }
    double eye[3] = {uni(&r, -3, 3), uni(&r, -2, 3), uni(&r, -3, 3)};
    double at[3] = {uni(&r, -1, 1), uni(&r, -1, 1), uni(&r, -1, 1)};
    int grazing = (int)(next(&r) % 3 == 0);
    if (grazing) at[1] = eye[1] + uni(&r, -0.6, 0.05); /* looking almost level */
    if (fabs(at[0] - eye[0]) + fabs(at[2] - eye[2]) < 0.2) at[0] = eye[0] + 1.0;
    fprintf(f, "{\n  \"comment\": \"persp-difftest seed=%llu depth=%s\",\n", (unsigned long long)seed,
            c.depth == PERSP_DEPTH_INVW ? "invw" : "z");
    fprintf(f,
            "  \"camera\": {\"position\": [%.6g, %.6g, %.6g], \"target\": [%.6g, %.6g, %.6g], \"fov\": %.6g, "
            "\"near\": %.6g, \"far\": %.6g},\n",
            eye[0], eye[1], eye[2], at[0], at[1], at[2], uni(&r, 25, 110), uni(&r, 0.05, 0.6), uni(&r, 20, 80));
    fprintf(f,
            "  \"render\": {\"size\": [%d, %d], \"filter\": \"%s\", \"shading\": \"none\", \"cull\": %s, "
            "\"clear\": [%.6g, %.6g, %.6g, 0]},\n",
            c.width, c.height, persp_filter_name(c.filter), (next(&r) & 1) ? "true" : "false", uni(&r, 0, 1),
            uni(&r, 0, 1), uni(&r, 0, 1));
    fprintf(f, "  \"materials\": {\n");
    for (int t = 0; t < ntex; t++) {
        fprintf(f,
                "    \"m%d\": {\"env\": \"replace\", \"texture\": {\"file\": \"tex%d.png\", \"wrap\": [\"%s\", \"%s\"], "
                "\"border\": [%.6g, %.6g, %.6g, 1]}}%s\n",
                t, t, wraps[irange(&r, 0, 3)], wraps[irange(&r, 0, 3)], uni(&r, 0, 1), uni(&r, 0, 1), uni(&r, 0, 1),
                t + 1 < ntex ? "," : "");
    }
    fprintf(f, "  },\n  \"objects\": [\n");
    static const char *const prims[] = {"plane", "cube", "sphere", "cylinder", "torus"};
    int nobj = irange(&r, 1, 4);
    int floor = grazing || (next(&r) % 3 == 0);
    for (int o = 0; o < nobj + floor; o++) {
        int is_floor = floor && o == nobj;
        const char *prim = is_floor ? "plane" : prims[irange(&r, 0, 4)];
        fprintf(f, "    {\"mesh\": ");
        if (!strcmp(prim, "plane"))
            fprintf(f, "{\"primitive\": \"plane\", \"subdivisions\": %d}", irange(&r, 1, 4));
        else if (!strcmp(prim, "sphere"))
            fprintf(f, "{\"primitive\": \"sphere\", \"slices\": %d, \"stacks\": %d}", irange(&r, 3, 24),
                    irange(&r, 2, 12));
        else if (!strcmp(prim, "cylinder"))
            fprintf(f, "{\"primitive\": \"cylinder\", \"slices\": %d}", irange(&r, 3, 24));
        else if (!strcmp(prim, "torus"))
            fprintf(f, "{\"primitive\": \"torus\", \"major\": 1, \"minor\": %.6g, \"slices\": %d, \"rings\": %d}",
                    uni(&r, 0.1, 0.6), irange(&r, 3, 24), irange(&r, 3, 12));
        else
            fprintf(f, "\"%s\"", prim);
        /* Objects without a material keep the default one: untextured,
         * drawn in the vertex colour times the diffuse colour. */
        if (is_floor || irange(&r, 0, 5) > 0) fprintf(f, ", \"material\": \"m%d\"", irange(&r, 0, ntex - 1));
        fprintf(f, ", \"texgen\": ");
        if (is_floor) {
            double k = uni(&r, 1, 12);
            fprintf(f, "{\"mode\": \"planar\", \"s\": [%.6g, 0, 0, %.6g], \"t\": [0, 0, %.6g, %.6g]}", k,
                    uni(&r, -1, 1), k, uni(&r, -1, 1));
            fprintf(f, ", \"transform\": {\"scale\": %.6g, \"translate\": [%.6g, %.6g, %.6g]}}",
                    uni(&r, 10, 40), eye[0] + uni(&r, -2, 2), eye[1] - uni(&r, 0.05, 1.0), eye[2] + uni(&r, -2, 2));
        } else {
            texgen(&r, f);
            double s[3] = {uni(&r, 0.2, 1.6), uni(&r, 0.2, 1.6), uni(&r, 0.2, 1.6)};
            if (next(&r) & 1) s[1] = s[2] = s[0];
            /* Mirrored, decided from the draws above so that every other
             * choice of a seed stays as it was. */
            if (s[0] > 1.5) s[0] = -s[0];
            /* Now and then the object sits on the camera: the near plane
             * cuts it, and without culling its inside is seen. */
            int on_eye = next(&r) % 6 == 0;
            double p[3];
            for (int i = 0; i < 3; i++) p[i] = on_eye ? eye[i] + uni(&r, -0.3, 0.3) : at[i] + uni(&r, -1.5, 1.5);
            fprintf(f, ", \"transform\": {\"scale\": [%.6g, %.6g, %.6g], \"rotate\": ", s[0], s[1], s[2]);
            rotation(&r, f);
            fprintf(f, ", \"translate\": [%.6g, %.6g, %.6g]}}", p[0], p[1], p[2]);
        }
        fprintf(f, "%s\n", o + 1 < nobj + floor ? "," : "");
    }
    fprintf(f, "  ]\n}\n");
    if (fclose(f) != 0) {
        snprintf(err, err_size, "%s: %s", path, strerror(errno));
        return -1;
    }
    if (out) *out = c;
    return 0;
}

int diff_case_read(const char *scene_path, diff_case *out, char *err, size_t err_size)
{
    FILE *f = fopen(scene_path, "rb");
    if (!f) {
        snprintf(err, err_size, "%s: %s", scene_path, strerror(errno));
        return -1;
    }
    char text[8192];
    size_t n = fread(text, 1, sizeof text - 1, f);
    fclose(f);
    text[n] = 0;
    memset(out, 0, sizeof *out);
    const char *s = strstr(text, "persp-difftest seed=");
    const char *d = strstr(text, "depth=");
    const char *z = strstr(text, "\"size\": [");
    const char *fl = strstr(text, "\"filter\": \"");
    unsigned long long seed = 0;
    char filter[64] = "";
    if (!s || !d || !z || !fl || sscanf(s, "persp-difftest seed=%llu", &seed) != 1 ||
        sscanf(z, "\"size\": [%d, %d]", &out->width, &out->height) != 2 ||
        sscanf(fl, "\"filter\": \"%63[^\"]\"", filter) != 1) {
        snprintf(err, err_size, "%s: not a scene written by the difftest generator", scene_path);
        return -1;
    }
    int aniso = 0;
    if (persp_filter_parse(filter, &out->filter, &aniso) != PERSP_OK) {
        snprintf(err, err_size, "%s: unknown filter '%s'", scene_path, filter);
        return -1;
    }
    out->seed = seed;
    out->depth = !strncmp(d, "depth=invw", 10) ? PERSP_DEPTH_INVW : PERSP_DEPTH_Z;
    return 0;
}
