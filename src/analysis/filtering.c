/*
 * persp accuracy --filter: every texture filter of the screen pipeline and
 * the object-space pipeline of [Romaniuk-ObjSpace] against a supersampled reference.
 *
 * The reference approximates the ideal image of the textured scene: the
 * texture (reconstructed bilinearly on level 0, the continuous image the
 * mip chain and every filter approximate) integrated over each pixel's
 * square by samples × samples point samples of the exact perspective
 * mapping (Heckbert 1989 §2.3.2, the exact method) and a box filter. Where
 * more than about `samples` texels fall into a pixel along one axis the
 * reference itself is only an estimate of that integral (the far end of
 * `floor`); its convergence is checked in tests/unit/test_filtering.c.
 *
 * Metrics over the pixels the scene covers: PSNR of R, G, B; SSIM of luma
 * (Wang, Bovik, Sheikh, Simoncelli 2004, 8×8 windows at stride 4, the
 * constants C1 = (0.01·255)², C2 = (0.03·255)²); the largest and mean
 * absolute channel error; the texels each filter reads per pixel (counted by
 * persp__sampler_fetches with the same decisions as the span samplers; for
 * the object-space pipeline the samples it walks); and the render time.
 */
#include "analysis/filtering.h"

#include "analysis/analysis.h"
#include "core/internal.h"
#include "geom/scene.h"
#include "render/render.h"
#include "texture/texture.h"

#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#define FA_DEFAULT_W 256
#define FA_DEFAULT_H 192
#define FA_DEFAULT_SAMPLES 16
#define FA_DEFAULT_REPEATS 3
#define FA_REF_TILE_PX 512 /* reference pixels per tile side, at most */
#define FA_OBJECT "object"

struct persp_filter_accuracy_result {
    persp_context *ctx;
    persp_filter_accuracy_row *rows;
    size_t count, cap;
};

static const char *const default_filters[] = {
    "nearest",   "bilinear", "nearest-mip-nearest", "bilinear-mip-nearest", "nearest-mip-linear",
    "trilinear", "aniso:16", "aniso-window:16",     "ewa",                  FA_OBJECT};

static const struct {
    const char *name;
    double degrees;
} tilts[] = {{"tilt-0", 0.0}, {"tilt-45", 45.0}, {"tilt-70", 70.0}, {"tilt-80", 80.0}, {"tilt-85", 85.0}};
#define TILT_COUNT (sizeof tilts / sizeof tilts[0])

/* ------------------------------------------------------------------ cases */

size_t persp_filter_accuracy_case_count(void)
{
    return persp_builtin_scene_count() + TILT_COUNT;
}

const char *persp_filter_accuracy_case_name(size_t i)
{
    size_t nb = persp_builtin_scene_count();
    if (i < nb) return persp_builtin_scene_name(i);
    return i - nb < TILT_COUNT ? tilts[i - nb].name : NULL;
}

const char *persp_filter_accuracy_case_summary(size_t i)
{
    size_t nb = persp_builtin_scene_count();
    if (i < nb) return persp_builtin_scene_summary(i);
    return i - nb < TILT_COUNT ? "checkered plane at distance 3, tilted about x by that many degrees"
                               : NULL;
}

persp_status persp_filter_accuracy_case_check(const char *name)
{
    if (!name) return PERSP_ERR_INVALID_ARGUMENT;
    for (size_t i = 0; i < persp_filter_accuracy_case_count(); i++)
        if (!strcmp(name, persp_filter_accuracy_case_name(i))) return PERSP_OK;
    return PERSP_ERR_NOT_FOUND;
}

persp_status persp_filter_accuracy_filter_check(const char *name)
{
    if (!name) return PERSP_ERR_INVALID_ARGUMENT;
    if (!strcmp(name, FA_OBJECT)) return PERSP_OK;
    persp_filter f;
    return persp_filter_parse(name, &f, NULL);
}

/* A 16-texel checker with one-texel dark lines: edges at every frequency,
 * so aliasing and over-blurring both show. */
static persp_status tilt_texture(persp_context *ctx, persp_image *img)
{
    persp_status st = persp_image_alloc(ctx, 256, 256, img);
    if (st != PERSP_OK) return st;
    for (int y = 0; y < 256; y++)
        for (int x = 0; x < 256; x++) {
            uint8_t *p = img->pixels + (size_t)y * img->stride + 4 * (size_t)x;
            int cell = ((x / 16) ^ (y / 16)) & 1;
            p[0] = cell ? 225 : 40, p[1] = cell ? 90 : 150, p[2] = cell ? 40 : 225, p[3] = 255;
            if (x % 16 == 0 || y % 16 == 0) p[0] = p[1] = p[2] = 15;
        }
    return PERSP_OK;
}

persp_status persp__tilt_scene(persp_context *ctx, double degrees, persp_scene **out)
{
    *out = NULL;
    persp_scene *s = NULL;
    persp_status st = persp__scene_new(ctx, &s);
    if (st != PERSP_OK) return st;
    s->clear[0] = s->clear[1] = s->clear[2] = 20;
    s->shading = PERSP_SHADING_NONE;
    persp_image img;
    persp_texture *tex = NULL;
    int ti = -1, mi = -1, me = -1;
    if ((st = tilt_texture(ctx, &img)) != PERSP_OK) goto fail;
    st = persp_texture_create(ctx, &img, &tex);
    persp_image_free(ctx, &img);
    if (st != PERSP_OK) goto fail;
    if ((st = persp__scene_add_texture(s, tex, &ti)) != PERSP_OK) goto fail;
    persp_material mat = persp__material_default();
    mat.texture = ti;
    mat.sampler.filter = PERSP_FILTER_BILINEAR;
    if ((st = persp__scene_add_material(s, &mat, &mi)) != PERSP_OK) goto fail;
    /* A 16 × 16 square, the texture repeated 8 times along each side. */
    persp_mesh m;
    memset(&m, 0, sizeof m);
    m.vertices = persp__calloc(ctx, 4, sizeof *m.vertices);
    m.indices = persp__calloc(ctx, 6, sizeof *m.indices);
    if (!m.vertices || !m.indices) {
        persp__mesh_free(ctx, &m);
        st = persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "tilt case: out of memory");
        goto fail;
    }
    static const float corner[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    for (int k = 0; k < 4; k++) {
        persp_vertex *v = &m.vertices[k];
        v->pos[0] = 8.0f * corner[k][0], v->pos[1] = 8.0f * corner[k][1], v->pos[2] = 0.0f;
        v->uv[0] = 4.0f * (corner[k][0] + 1.0f), v->uv[1] = 4.0f * (corner[k][1] + 1.0f);
        v->color[0] = v->color[1] = v->color[2] = v->color[3] = 1.0f;
    }
    static const uint32_t idx[6] = {0, 1, 2, 0, 2, 3};
    memcpy(m.indices, idx, sizeof idx);
    m.vertex_count = 4;
    m.index_count = 6;
    persp__mesh_compute_normals(&m);
    if ((st = persp__scene_add_mesh(s, &m, &me)) != PERSP_OK) goto fail;
    persp_object o;
    memset(&o, 0, sizeof o);
    o.mesh = me;
    o.material = mi;
    /* At distance 3, the top edge tilted away from the viewer, and turned
     * 20 degrees in the image plane so that the footprints' major axes are
     * not aligned with the texture's. */
    o.model = persp_mat4_mul(persp_mat4_translate(0.0f, 0.0f, -3.0f),
                             persp_mat4_mul(persp_mat4_rotate((float)-degrees, 1.0f, 0.0f, 0.0f),
                                            persp_mat4_rotate(20.0f, 0.0f, 0.0f, 1.0f)));
    if ((st = persp__scene_add_object(s, &o)) != PERSP_OK) goto fail;
    *out = s;
    return PERSP_OK;
fail:
    persp_scene_destroy(s);
    return st;
}

static persp_status case_scene(persp_context *ctx, const char *name, persp_scene **out)
{
    for (size_t i = 0; i < TILT_COUNT; i++)
        if (!strcmp(name, tilts[i].name)) return persp__tilt_scene(ctx, tilts[i].degrees, out);
    return persp_scene_builtin(ctx, name, out);
}

/* -------------------------------------------------------------- reference */

persp_status persp__filter_reference(persp_context *ctx, const persp_scene *scene, int width,
                                     int height, int samples, int tile, float *out)
{
    if (!ctx || !scene || !out || width <= 0 || height <= 0 || samples < 1 || samples > 64 ||
        tile < 1)
        return PERSP_ERR_INVALID_ARGUMENT;
    persp_mat4 proj, view;
    persp_status cst = persp_scene_get_camera(scene, width, height, &view, &proj);
    if (cst != PERSP_OK) return cst;
    /* The same scene with an explicit camera; its arrays stay the
     * original's (the copy is never destroyed). */
    persp_scene sub = *scene;
    sub.camera.use_matrix = 1;
    sub.camera.view = view;
    const int S = samples, T = tile;
    size_t side = (size_t)T * (size_t)S;
    persp_framebuffer fb = {0, 0, persp__calloc(ctx, side * side, 4),
                            persp__calloc(ctx, side * side, sizeof(float))};
    if (!fb.color || !fb.depth) {
        persp__free(ctx, fb.color);
        persp__free(ctx, fb.depth);
        return persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY,
                                  "filter reference: out of memory for %zux%zu samples", side, side);
    }
    persp_render_desc rd;
    memset(&rd, 0, sizeof rd);
    rd.method = "exact";
    rd.filter = PERSP_FILTER_BILINEAR;
    const double BW = (double)width * S, BH = (double)height * S;
    persp_status st = PERSP_OK;
    for (int ty = 0; ty < height && st == PERSP_OK; ty += T)
        for (int tx = 0; tx < width && st == PERSP_OK; tx += T) {
            int tw = width - tx < T ? width - tx : T, th = height - ty < T ? height - ty : T;
            double X0 = (double)tx * S, Y0 = (double)ty * S, TW = (double)tw * S, TH = (double)th * S;
            /* NDC of the big image -> NDC of this tile's window:
             * x' = (BW/TW)·x + ((BW - 2·X0)/TW - 1)·w, y likewise. */
            persp_mat4 M = persp_mat4_identity();
            M.m[0] = (float)(BW / TW);
            M.m[12] = (float)((BW - 2.0 * X0) / TW - 1.0);
            M.m[5] = (float)(BH / TH);
            M.m[13] = (float)((BH - 2.0 * Y0) / TH - 1.0);
            sub.camera.projection = persp_mat4_mul(M, proj);
            fb.width = tw * S;
            fb.height = th * S;
            st = persp_render(ctx, &sub, &rd, &fb, NULL);
            if (st != PERSP_OK) break;
            const double inv = 1.0 / ((double)S * S);
            for (int y = 0; y < th; y++)
                for (int x = 0; x < tw; x++) {
                    double acc[4] = {0.0, 0.0, 0.0, 0.0};
                    for (int sy = 0; sy < S; sy++) {
                        const uint8_t *row = fb.color + 4 * ((size_t)(y * S + sy) * (size_t)fb.width +
                                                             (size_t)x * (size_t)S);
                        for (int sx = 0; sx < S; sx++)
                            for (int c = 0; c < 4; c++) acc[c] += row[4 * sx + c];
                    }
                    float *o = out + 4 * ((size_t)(ty + y) * (size_t)width + (size_t)(tx + x));
                    for (int c = 0; c < 4; c++) o[c] = (float)(acc[c] * inv);
                }
        }
    persp__free(ctx, fb.color);
    persp__free(ctx, fb.depth);
    return st;
}

/* ---------------------------------------------------------------- metrics */

double persp__ssim(const float *a, const float *b, const uint8_t *mask, int w, int h)
{
    const double C1 = (0.01 * 255.0) * (0.01 * 255.0), C2 = (0.03 * 255.0) * (0.03 * 255.0);
    const int N = 8, step = 4;
    double sum = 0.0;
    size_t windows = 0;
    for (int y0 = 0; y0 + N <= h; y0 += step)
        for (int x0 = 0; x0 + N <= w; x0 += step) {
            double sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0;
            int any = !mask;
            for (int y = y0; y < y0 + N; y++)
                for (int x = x0; x < x0 + N; x++) {
                    size_t i = (size_t)y * (size_t)w + (size_t)x;
                    if (mask && mask[i]) any = 1;
                    double p = a[i], q = b[i];
                    sa += p, sb += q, saa += p * p, sbb += q * q, sab += p * q;
                }
            if (!any) continue;
            double n = (double)(N * N), ma = sa / n, mb = sb / n;
            double va = saa / n - ma * ma, vb = sbb / n - mb * mb, cov = sab / n - ma * mb;
            sum += ((2 * ma * mb + C1) * (2 * cov + C2)) / ((ma * ma + mb * mb + C1) * (va + vb + C2));
            windows++;
        }
    return windows ? sum / (double)windows : 1.0;
}

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static persp_status add_row(persp_filter_accuracy_result *res, const persp_filter_accuracy_row *row)
{
    if (persp__grow(res->ctx, (void **)&res->rows, &res->cap, res->count + 1, sizeof *res->rows) !=
        PERSP_OK)
        return persp__fail(res->ctx, PERSP_ERR_OUT_OF_MEMORY, "filter accuracy: out of memory");
    res->rows[res->count++] = *row;
    return PERSP_OK;
}

/* Buffers of one case, allocated once and reused for every filter. */
typedef struct fa_case {
    int w, h;
    float *ref, *ref_luma, *luma, *err;
    uint8_t *mask, *color;
    float *depth;
    persp_capture cap;
} fa_case;

static void case_free(persp_context *ctx, fa_case *c)
{
    persp__free(ctx, c->ref);
    persp__free(ctx, c->ref_luma);
    persp__free(ctx, c->luma);
    persp__free(ctx, c->err);
    persp__free(ctx, c->mask);
    persp__free(ctx, c->color);
    persp__free(ctx, c->depth);
    persp__capture_free(ctx, &c->cap);
}

static inline float luma(float r, float g, float b)
{
    return 0.299f * r + 0.587f * g + 0.114f * b;
}

/* Texels read per covered pixel by a screen-pipeline filter, from the same
 * per-pixel span inputs the renderer builds (rational form at the pixel
 * centre, analytic derivatives, per-polygon lambda). */
static double count_fetches(const fa_case *c, const persp_sampler_state *ss, uint64_t *pixels)
{
    double total = 0.0;
    uint64_t n = 0;
    for (int y = 0; y < c->h; y++)
        for (int x = 0; x < c->w; x++) {
            int32_t t = c->cap.tri[(size_t)y * (size_t)c->w + (size_t)x];
            if (t < 0 || (size_t)t >= c->cap.rat_count) continue;
            const persp_rational *r = &c->cap.rats[t];
            double X = x + 0.5, Y = y + 0.5;
            double q = r->g * X + r->h * Y + r->i;
            if (!(q > 0.0)) continue;
            float u = (float)((r->a * X + r->b * Y + r->c) / q);
            float v = (float)((r->d * X + r->e * Y + r->f) / q);
            float qf = (float)q;
            const persp_rational_vertices *rv = &c->cap.rat_vertices[t];
            persp_tex_span_in in = {.n = 1, .u = &u, .v = &v, .q = &qf,
                                    .a = (float)r->a, .b = (float)r->b, .d = (float)r->d,
                                    .e = (float)r->e, .g = (float)r->g, .h = (float)r->h,
                                    .poly_lambda = persp__polygon_lambda(ss->tex, rv->x, rv->y, rv->s1, rv->s2)};
            total += persp__sampler_fetches(ss, &in, 0);
            n++;
        }
    *pixels = n;
    return n ? total / (double)n : 0.0;
}

/* Times d->repeats renders of the case's image with rd, the fastest kept
 * (ms and ns a pixel in row); *stats: the last render's. */
static persp_status time_renders(persp_context *ctx, const persp_filter_accuracy_desc *d,
                                 const persp_scene *scene, const persp_render_desc *rd, fa_case *c,
                                 persp_render_stats *stats, persp_filter_accuracy_row *row)
{
    persp_framebuffer fb = {c->w, c->h, c->color, c->depth};
    double best = INFINITY;
    for (int k = 0; k < d->repeats; k++) {
        double t0 = now_seconds();
        persp_status st = persp_render(ctx, scene, rd, &fb, stats);
        double t1 = now_seconds();
        if (st != PERSP_OK) return st;
        if (t1 - t0 < best) best = t1 - t0;
    }
    row->ms = best * 1e3;
    row->ns_px = best * 1e9 / ((double)c->w * (double)c->h);
    return PERSP_OK;
}

/* The rendered image against the reference over covered pixels: PSNR,
 * mean and largest channel error, SSIM of luma (the case's luma and
 * per-pixel error buffers are filled on the way); the covered pixels'
 * count in row->pixels. */
static void score_image(fa_case *c, persp_filter_accuracy_row *row)
{
    double se = 0.0, sa = 0.0, mx = 0.0;
    uint64_t n = 0;
    for (size_t i = 0; i < (size_t)c->w * (size_t)c->h; i++) {
        const uint8_t *p = c->color + 4 * i;
        const float *q = c->ref + 4 * i;
        c->luma[i] = luma(p[0], p[1], p[2]);
        if (!c->mask[i]) {
            c->err[i] = NAN;
            continue;
        }
        double e = 0.0;
        for (int k = 0; k < 3; k++) {
            double dd = (double)p[k] - (double)q[k];
            se += dd * dd;
            sa += fabs(dd);
            if (fabs(dd) > e) e = fabs(dd);
        }
        if (e > mx) mx = e;
        c->err[i] = (float)e;
        n++;
    }
    row->pixels = n;
    if (n) {
        double mse = se / (3.0 * (double)n);
        row->psnr = mse > 0.0 ? 10.0 * log10(255.0 * 255.0 / mse) : INFINITY;
        row->mean_err = sa / (3.0 * (double)n);
        row->max_err = mx;
    }
    row->ssim = persp__ssim(c->luma, c->ref_luma, c->mask, c->w, c->h);
}

/* Texels read per covered pixel by a screen filter: the sampler of the
 * first material with texture 0, with rd's filter and level-of-detail
 * settings; 0 when that sampler does not build. */
static double screen_fetches(const fa_case *c, const persp_scene *scene, const persp_texture *tex,
                             const persp_render_desc *rd)
{
    persp_sampler_desc sd = scene->materials[0].sampler;
    for (size_t k = 0; k < scene->material_count; k++)
        if (scene->materials[k].texture == 0) {
            sd = scene->materials[k].sampler;
            break;
        }
    sd.filter = rd->filter;
    sd.max_aniso = rd->max_aniso;
    sd.lod_mode = rd->lod_mode;
    sd.lod_bias += rd->lod_bias;
    persp_sampler_state ss;
    if (persp__sampler_init(&ss, tex, &sd) != PERSP_OK) return 0.0;
    uint64_t px;
    return count_fetches(c, &ss, &px);
}

/* The per-pixel error of filter fname on case cname as a heat map,
 * DIR/filter_CASE_FILTER.png (':' of "aniso:16" as '-'). */
static persp_status write_filter_heatmap(persp_context *ctx, const char *dir, const char *cname,
                                         const char *fname, const fa_case *c)
{
    char path[1024], safe[32];
    snprintf(safe, sizeof safe, "%s", fname);
    for (char *s = safe; *s; s++)
        if (*s == ':') *s = '-';
    int len = snprintf(path, sizeof path, "%s/filter_%s_%s.png", dir, cname, safe);
    if (len < 0 || (size_t)len >= sizeof path)
        return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "filter accuracy: heat-map path too long");
    return persp__heatmap_write(ctx, path, c->err, c->w, c->h, PERSP_HEATMAP_LEVELS,
                                PERSP_HEATMAP_LEVELS_TOP);
}

/* Renders one filter of one case, measures it and appends its row. */
static persp_status measure(persp_context *ctx, const persp_filter_accuracy_desc *d, const char *cname,
                            const persp_scene *scene, fa_case *c, const char *fname,
                            persp_filter_accuracy_result *res)
{
    persp_filter_accuracy_row row;
    memset(&row, 0, sizeof row);
    int object = !strcmp(fname, FA_OBJECT);
    snprintf(row.filter, sizeof row.filter, "%s", fname);
    snprintf(row.pipeline, sizeof row.pipeline, "%s", object ? "object" : "screen");
    snprintf(row.case_name, sizeof row.case_name, "%s", cname);
    row.samples = d->samples;
    const persp_texture *tex = scene->texture_count ? scene->textures[0] : NULL;
    if (tex) {
        row.tex_width = tex->width, row.tex_height = tex->height, row.tex_levels = tex->levels;
        row.mip_overhead = (double)tex->bytes_all / (double)tex->bytes_base - 1.0;
    }
    persp_render_desc rd;
    memset(&rd, 0, sizeof rd);
    rd.method = "exact";
    rd.lod_mode = d->lod_mode;
    rd.lod_bias = d->lod_bias;
    if (object) {
        rd.pipeline = PERSP_PIPELINE_OBJECT;
    } else {
        persp_status ps = persp_filter_parse(fname, &rd.filter, &rd.max_aniso);
        if (ps != PERSP_OK)
            return persp__fail(ctx, ps, "filter accuracy: unknown filter '%s'", fname);
    }
    persp_render_stats stats;
    persp_status st = time_renders(ctx, d, scene, &rd, c, &stats, &row);
    if (st != PERSP_OK) return st;
    score_image(c, &row);
    /* Object space: samples walked per covered pixel. */
    if (object)
        row.fetches_px = row.pixels ? (double)stats.objspace_samples / (double)row.pixels : 0.0;
    else if (tex)
        row.fetches_px = screen_fetches(c, scene, tex, &rd);
    if (d->heatmap_dir && (st = write_filter_heatmap(ctx, d->heatmap_dir, cname, fname, c)) != PERSP_OK)
        return st;
    return add_row(res, &row);
}

persp_status persp_filter_accuracy_run(persp_context *ctx, const persp_filter_accuracy_desc *desc_in,
                                       persp_filter_accuracy_result **out)
{
    if (!ctx) return PERSP_ERR_INVALID_ARGUMENT;
    persp__clear_error(ctx);
    if (!desc_in || !out) return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "filter accuracy: no desc or result");
    *out = NULL;
    persp_filter_accuracy_desc d = *desc_in;
    if (!d.width && !d.height) d.width = FA_DEFAULT_W, d.height = FA_DEFAULT_H;
    if (!d.samples) d.samples = FA_DEFAULT_SAMPLES;
    if (!d.repeats) d.repeats = FA_DEFAULT_REPEATS;
    if (d.width <= 0 || d.height <= 0 || d.width > 4096 || d.height > 4096)
        return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT,
                                  "filter accuracy: size %dx%d out of range (1..4096)", d.width, d.height);
    const char *bad = d.samples < 1 || d.samples > 64                 ? "samples (1..64)"
                      : d.repeats < 1 || d.repeats > 100              ? "repeats (1..100)"
                      : (unsigned)d.lod_mode > PERSP_LOD_POLYGON      ? "lod_mode"
                      : !isfinite(d.lod_bias)                         ? "lod_bias (finite)"
                                                                      : NULL;
    if (bad)
        return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT,
                           "filter accuracy: persp_filter_accuracy_desc.%s is out of range", bad);
    /* "NULL or none": a NULL list is none, whatever its count says. */
    const char *const *filters = d.filters && d.filter_count ? d.filters : default_filters;
    size_t nf = d.filters && d.filter_count ? d.filter_count : sizeof default_filters / sizeof default_filters[0];
    static const char *const default_cases[] = {"corridor", "floor",   "tilt-0", "tilt-45",
                                                "tilt-70",  "tilt-80", "tilt-85"};
    const char *const *cases = d.cases && d.case_count ? d.cases : default_cases;
    size_t nc = d.cases && d.case_count ? d.case_count : sizeof default_cases / sizeof default_cases[0];
    for (size_t i = 0; i < nf; i++) {
        /* The status persp_filter_parse gives: an unknown name, or a bad
         * count ("aniso:99") as INVALID_ARGUMENT. */
        const persp_status fst = persp_filter_accuracy_filter_check(filters[i]);
        if (fst != PERSP_OK)
            return persp__fail(ctx, fst, "filter accuracy: %s filter '%s'",
                               fst == PERSP_ERR_NOT_FOUND ? "unknown" : "bad",
                               filters[i] ? filters[i] : "(null)");
    }
    for (size_t i = 0; i < nc; i++)
        if (!cases[i] || persp_filter_accuracy_case_check(cases[i]) != PERSP_OK)
            return persp__fail(ctx, PERSP_ERR_NOT_FOUND, "filter accuracy: unknown case '%s'",
                                      cases[i] ? cases[i] : "(null)");
    persp_filter_accuracy_result *res = persp__calloc(ctx, 1, sizeof *res);
    if (!res) return persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "filter accuracy: out of memory");
    res->ctx = ctx;
    persp_status st = PERSP_OK;
    const size_t np = (size_t)d.width * (size_t)d.height;
    for (size_t ci = 0; ci < nc && st == PERSP_OK; ci++) {
        persp_scene *scene = NULL;
        fa_case c;
        memset(&c, 0, sizeof c);
        c.w = d.width, c.h = d.height;
        st = case_scene(ctx, cases[ci], &scene);
        if (st != PERSP_OK) break;
        c.ref = persp__calloc(ctx, np * 4, sizeof(float));
        c.ref_luma = persp__calloc(ctx, np, sizeof(float));
        c.luma = persp__calloc(ctx, np, sizeof(float));
        c.err = persp__calloc(ctx, np, sizeof(float));
        c.mask = persp__calloc(ctx, np, 1);
        c.color = persp__calloc(ctx, np, 4);
        c.depth = persp__calloc(ctx, np, sizeof(float));
        if (!c.ref || !c.ref_luma || !c.luma || !c.err || !c.mask || !c.color || !c.depth)
            st = persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "filter accuracy: out of memory");
        if (st == PERSP_OK) {
            int tile = FA_REF_TILE_PX / d.samples;
            st = persp__filter_reference(ctx, scene, d.width, d.height, d.samples, tile < 1 ? 1 : tile,
                                         c.ref);
        }
        if (st == PERSP_OK) {
            persp_render_desc cd;
            memset(&cd, 0, sizeof cd);
            cd.method = "exact";
            st = persp__render_capture(ctx, scene, &cd, d.width, d.height, &c.cap);
        }
        if (st == PERSP_OK) {
            for (size_t i = 0; i < np; i++) {
                c.mask[i] = c.cap.tri[i] >= 0;
                c.ref_luma[i] = luma(c.ref[4 * i], c.ref[4 * i + 1], c.ref[4 * i + 2]);
            }
            for (size_t fi = 0; fi < nf && st == PERSP_OK; fi++)
                st = measure(ctx, &d, cases[ci], scene, &c, filters[fi], res);
        }
        case_free(ctx, &c);
        persp_scene_destroy(scene);
    }
    if (st != PERSP_OK) {
        persp_filter_accuracy_destroy(res);
        return st;
    }
    *out = res;
    return PERSP_OK;
}

size_t persp_filter_accuracy_row_count(const persp_filter_accuracy_result *res)
{
    return res ? res->count : 0;
}

const persp_filter_accuracy_row *persp_filter_accuracy_row_at(const persp_filter_accuracy_result *res,
                                                              size_t index)
{
    return res && index < res->count ? &res->rows[index] : NULL;
}

void persp_filter_accuracy_destroy(persp_filter_accuracy_result *res)
{
    if (!res) return;
    persp__free(res->ctx, res->rows);
    persp__free(res->ctx, res);
}

/* ----------------------------------------------------------------- report */

static void fmt_psnr(char *buf, size_t n, double p)
{
    if (isinf(p)) snprintf(buf, n, "inf");
    else snprintf(buf, n, "%.2f", p);
}

persp_status persp_filter_accuracy_write(persp_context *ctx, const persp_filter_accuracy_result *res,
                                         persp_report_format format, void *stream)
{
    FILE *f = stream;
    if (!ctx) return PERSP_ERR_INVALID_ARGUMENT;
    persp__clear_error(ctx);
    if (!res || !f) return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "filter accuracy: no result or stream");
    if ((unsigned)format > PERSP_REPORT_JSON)
        return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "filter accuracy: unknown format %d", (int)format);
    char ps[16];
    if (format == PERSP_REPORT_CSV) {
        fprintf(f, "case,pipeline,filter,pixels,samples,psnr_db,ssim,max_err,mean_err,fetches_px,ms,ns_px,"
                   "tex_width,tex_height,tex_levels,mip_overhead\n");
        for (size_t i = 0; i < res->count; i++) {
            const persp_filter_accuracy_row *r = &res->rows[i];
            fmt_psnr(ps, sizeof ps, r->psnr);
            fprintf(f, "%s,%s,%s,%llu,%d,%s,%.5f,%.2f,%.4f,%.3f,%.3f,%.2f,%d,%d,%d,%.5f\n", r->case_name,
                    r->pipeline, r->filter, (unsigned long long)r->pixels, r->samples, ps, r->ssim,
                    r->max_err, r->mean_err, r->fetches_px, r->ms, r->ns_px, r->tex_width, r->tex_height,
                    r->tex_levels, r->mip_overhead);
        }
    } else if (format == PERSP_REPORT_JSON) {
        fprintf(f, "[");
        for (size_t i = 0; i < res->count; i++) {
            const persp_filter_accuracy_row *r = &res->rows[i];
            /* JSON has no infinity: a lossless filter's PSNR is null. */
            if (isinf(r->psnr)) snprintf(ps, sizeof ps, "null");
            else snprintf(ps, sizeof ps, "%.4f", r->psnr);
            fprintf(f,
                    "%s\n  {\"case\": \"%s\", \"pipeline\": \"%s\", \"filter\": \"%s\", \"pixels\": %llu, "
                    "\"samples\": %d, \"psnr_db\": %s, \"ssim\": %.6f, \"max_err\": %.3f, "
                    "\"mean_err\": %.5f, \"fetches_px\": %.4f, \"ms\": %.4f, \"ns_px\": %.3f, "
                    "\"texture\": {\"width\": %d, \"height\": %d, \"levels\": %d, "
                    "\"mip_overhead\": %.6f}}",
                    i ? "," : "", r->case_name, r->pipeline, r->filter, (unsigned long long)r->pixels,
                    r->samples, ps, r->ssim, r->max_err, r->mean_err, r->fetches_px, r->ms, r->ns_px,
                    r->tex_width, r->tex_height, r->tex_levels, r->mip_overhead);
        }
        fprintf(f, "\n]\n");
    } else {
        const char *last = "";
        for (size_t i = 0; i < res->count; i++) {
            const persp_filter_accuracy_row *r = &res->rows[i];
            if (strcmp(last, r->case_name)) {
                fprintf(f, "%s%s: %llu pixels, reference %dx%d samples per pixel; texture %dx%d, %d levels, "
                           "mip chain +%.1f%% memory\n",
                        i ? "\n" : "", r->case_name, (unsigned long long)r->pixels, r->samples, r->samples,
                        r->tex_width, r->tex_height, r->tex_levels, 100.0 * r->mip_overhead);
                fprintf(f, "  %-8s %-20s %8s %7s %7s %7s %9s %9s\n", "pipeline", "filter", "PSNR dB", "SSIM",
                        "max", "mean", "fetch/px", "ns/px");
                last = r->case_name;
            }
            fmt_psnr(ps, sizeof ps, r->psnr);
            fprintf(f, "  %-8s %-20s %8s %7.4f %7.1f %7.2f %9.2f %9.1f\n", r->pipeline, r->filter, ps, r->ssim,
                    r->max_err, r->mean_err, r->fetches_px, r->ns_px);
        }
        fprintf(f, "\nPSNR: 10·log10(255² / mean squared R,G,B error) over covered pixels, against the\n"
                   "  supersampled reference (exact mapping, bilinear on level 0, box filter).\n"
                   "SSIM: mean structural similarity of luma, 8x8 windows at stride 4.\n"
                   "max, mean: absolute channel error in 8-bit levels.\n"
                   "fetch/px: texels read per covered pixel (object: samples walked per pixel).\n"
                   "ns/px: fastest of the timed renders, per image pixel.\n");
    }
    if (ferror(f)) return persp__fail(ctx, PERSP_ERR_IO, "filter accuracy: write failed");
    return PERSP_OK;
}
