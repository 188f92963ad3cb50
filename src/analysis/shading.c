/*
 * Shading accuracy (see shading.h): [Romanyuk-PCF] §4.2 (ΔI of screen-linear
 * Gouraud), §4.3 (t_w and its polynomial approximations, spherical-angular
 * normals), measured on the renderer's own span shaders.
 */
#include "analysis/shading.h"

#include "analysis/analysis.h"
#include "core/internal.h"
#include "geom/scene.h"
#include "raster/frame.h"
#include "shade/shade.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846

/* ------------------------------------------------------------ §4.2: ΔI */

double persp__delta_factor(double u, double r)
{
    return u * (1.0 - 1.0 / (r + u * (1.0 - r)));
}

double persp__delta_extremum(double r, double *argmax)
{
    double sr = sqrt(r);
    if (argmax) *argmax = sr / (1.0 + sr);
    return (sr - 1.0) / (sr + 1.0);
}

/* ---------------------------------------------------- §4.3: t_w polynomials */

double persp__tw_exact(double tv, double hbar)
{
    return tv / (hbar - tv * (hbar - 1.0));
}

void persp__tw_coeffs(persp_approx_kind kind, double hbar, int piece, double c[4])
{
    const double h = hbar;
    c[0] = c[1] = c[2] = c[3] = 0.0;
    switch (kind) {
    case PERSP_APPROX_PWQUAD:
        if (!piece) {
            /* Through (0, 0), (1/4, 1/(3ħ + 1)), (1/2, 1/(ħ + 1)). */
            double d = (h + 1.0) * (3.0 * h + 1.0);
            c[1] = 2.0 * (h + 3.0) / d;
            c[2] = 8.0 * (h - 1.0) / d;
        } else {
            /* Through (1/2, 1/(ħ + 1)), (3/4, 3/(ħ + 3)), (1, 1). */
            double d = (h + 1.0) * (h + 3.0);
            c[0] = 3.0 * (h - 1.0) * (h - 1.0) / d;
            c[1] = 2.0 * h * (9.0 - 5.0 * h) / d;
            c[2] = 8.0 * h * (h - 1.0) / d;
        }
        break;
    case PERSP_APPROX_CUBIC: {
        /* Through t_v = 0, 1/3, 2/3, 1: t_w = 0, 1/(2ħ + 1), 2/(ħ + 2), 1. */
        double d = (2.0 * h + 1.0) * (h + 2.0);
        c[1] = (2.0 * h * h - 4.0 * h + 11.0) / d;
        c[2] = -9.0 * (h - 1.0) * (h - 2.0) / d;
        c[3] = 9.0 * (h - 1.0) * (h - 1.0) / d;
        break;
    }
    case PERSP_APPROX_QUAD:
    default:
        /* Through t_v = 0, 1/2, 1: t_w = 0, 1/(ħ + 1), 1 (as printed). */
        c[1] = (3.0 - h) / (h + 1.0);
        c[2] = 2.0 * (h - 1.0) / (h + 1.0);
        break;
    }
}

#define TW_SAMPLES 3073 /* L = 3072 = 12·256: every node of every kind is a sample */

void persp__tw_error(persp_approx_kind kind, double hbar, persp_tw_error *out)
{
    float p[TW_SAMPLES];
    const int n = TW_SAMPLES;
    const double L = (double)(n - 1);
    /* t_w at t_v = k/L as a rational in k: k / (ħ·L − (ħ − 1)·k). */
    persp_rat1 f = {1.0, 0.0, -(hbar - 1.0), hbar * L};
    persp__approx_span(&f, kind, 0.5, n, p, NULL);
    memset(out, 0, sizeof *out);
    for (int k = 1; k < n; k++) {
        double tv = k / L, tw = persp__tw_exact(tv, hbar), e = fabs((double)p[k] - tw);
        if (e > out->abs_max) out->abs_max = e;
        if (e / tw > out->rel_max) out->rel_max = e / tw;
        if (3 * k >= n - 1 && e / tw > out->rel_third) out->rel_third = e / tw;
    }
}

/* ------------------------------------------------- random lit triangles */

/* Double-precision Blinn–Phong, the same model as src/shade/shade.c
 * (two-sided, ambient + diffuse + specular, attenuated point lights),
 * written independently as the reference. */
static void light_ref(const persp_draw_state *ds, const double n_in[3], const double e[3],
                      double out[3])
{
    const persp_material *m = &ds->material;
    const persp_lighting *L = &ds->lighting;
    double n[3] = {n_in[0], n_in[1], n_in[2]};
    if (n[0] * e[0] + n[1] * e[1] + n[2] * e[2] > 0.0)
        for (int i = 0; i < 3; i++) n[i] = -n[i];
    double el = sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
    double v[3] = {-e[0] / el, -e[1] / el, -e[2] / el};
    for (int c = 0; c < 3; c++) out[c] = (double)L->ambient[c] * m->ambient[c];
    for (int i = 0; i < L->count; i++) {
        const persp_eye_light *l = &L->light[i];
        double d[3], att = 1.0;
        for (int c = 0; c < 3; c++) d[c] = l->pos[c];
        if (l->type != PERSP_LIGHT_DIRECTIONAL) {
            for (int c = 0; c < 3; c++) d[c] -= e[c];
            double dist = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
            for (int c = 0; c < 3; c++) d[c] /= dist;
            att = 1.0 / (l->atten[0] + l->atten[1] * dist + l->atten[2] * dist * dist);
        }
        double ndl = n[0] * d[0] + n[1] * d[1] + n[2] * d[2];
        if (ndl <= 0.0) continue;
        double h[3] = {d[0] + v[0], d[1] + v[1], d[2] + v[2]};
        double hl = sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
        double ndh = (n[0] * h[0] + n[1] * h[1] + n[2] * h[2]) / hl;
        double sp = ndh > 0.0 ? pow(ndh, m->shininess) : 0.0;
        for (int c = 0; c < 3; c++)
            out[c] += att * l->color[c] * (m->diffuse[c] * ndl + m->specular[c] * sp);
    }
}

static double level(double c)
{
    return 255.0 * (c < 0.0 ? 0.0 : c > 1.0 ? 1.0 : c);
}

/* Worst channel of |packed − 255·ref| in 8-bit levels. */
static double colour_err(uint32_t px, const double ref[3])
{
    double w = 0.0;
    for (int c = 0; c < 3; c++) {
        double e = fabs((double)((px >> (8 * c)) & 255u) - level(ref[c]));
        if (e > w) w = e;
    }
    return w;
}

static void unit3(double v[3])
{
    double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int i = 0; i < 3; i++) v[i] /= l;
}

/* The light set and material of the random-triangle case: a white point
 * light above and to the right of the eye, a warm attenuated point light to
 * the left, a directional fill light, and a glossy material so that normal
 * errors show in the highlights. */
static void random_case_state(persp_draw_state *ds)
{
    memset(ds, 0, sizeof *ds);
    persp_material *m = &ds->material;
    const float diff[3] = {0.8f, 0.7f, 0.6f};
    for (int c = 0; c < 3; c++) {
        m->ambient[c] = 0.1f;
        m->diffuse[c] = diff[c];
        m->specular[c] = 0.5f;
        ds->lighting.ambient[c] = 1.0f;
    }
    m->shininess = 24.0f;
    m->texture = m->specular_texture = -1;
    ds->lighting.count = 3;
    persp_eye_light *p = &ds->lighting.light[0], *q = &ds->lighting.light[1], *d = &ds->lighting.light[2];
    p->type = q->type = PERSP_LIGHT_POINT;
    p->pos[0] = 2.0f, p->pos[1] = 4.0f, p->pos[2] = -1.0f;
    p->atten[0] = 1.0f;
    q->pos[0] = -3.0f, q->pos[1] = 0.5f, q->pos[2] = -2.0f;
    q->atten[0] = 0.6f, q->atten[1] = 0.05f, q->atten[2] = 0.01f;
    const float warm[3] = {0.5f, 0.35f, 0.2f};
    for (int c = 0; c < 3; c++) p->color[c] = 0.7f, q->color[c] = warm[c], d->color[c] = 0.3f;
    d->type = PERSP_LIGHT_DIRECTIONAL;
    double dir[3] = {-0.3, 0.6, 0.7};
    unit3(dir);
    for (int c = 0; c < 3; c++) d->pos[c] = (float)dir[c];
}

/* A random unit normal within about 40° of `around` (unit). */
static void perturbed(persp_rng *rng, const double around[3], double out[3])
{
    for (;;) {
        double r[3];
        for (int i = 0; i < 3; i++) r[i] = persp__rng_uniform(rng, -1.0, 1.0);
        if (r[0] * r[0] + r[1] * r[1] + r[2] * r[2] > 1.0) continue;
        for (int i = 0; i < 3; i++) out[i] = around[i] + 0.7 * r[i];
        unit3(out);
        return;
    }
}

/* One random lit triangle of depth ratio hbar, as cases.c's random
 * triangles (corridor projection at 1024×768, 100..100000 pixels), with
 * smooth vertex normals facing the eye. Vertex colours are lit per vertex
 * for the Gouraud modes. Returns 0 if none was found. */
static int random_lit_triangle(persp_rng *rng, double hbar, const persp_draw_state *gouraud,
                               persp_clipvert cv[3], persp_tri *t)
{
    const double W = PERSP_RT_WIDTH, H = PERSP_RT_HEIGHT, aspect = W / H;
    const double tn = tan(30.0 * PI / 180.0), n = 0.1, f = 100.0;
    for (int attempt = 0; attempt < 1000; attempt++) {
        double d[3] = {persp__rng_uniform(rng, 0.5, 10.0), 0, 0};
        d[1] = d[0] * hbar;
        d[2] = persp__rng_uniform(rng, d[0], d[1]);
        for (int i = 2; i > 0; i--) {
            int j = (int)(persp__rng_next(rng) % (uint64_t)(i + 1));
            double tmp = d[i];
            d[i] = d[j], d[j] = tmp;
        }
        double radius = exp(persp__rng_uniform(rng, log(6.0), log(380.0)));
        double cx = persp__rng_uniform(rng, 0.0, W), cy = persp__rng_uniform(rng, 0.0, H);
        persp_winvert v[3];
        double eye[3][3];
        int inside = 1;
        for (int i = 0; i < 3; i++) {
            double th = persp__rng_uniform(rng, 0.0, 2.0 * PI);
            double rr = radius * persp__rng_uniform(rng, 0.4, 1.0);
            double wx = cx + rr * cos(th), wy = cy + rr * sin(th);
            if (wx < 0.0 || wx > W || wy < 0.0 || wy > H) inside = 0;
            eye[i][0] = (2.0 * wx / W - 1.0) * tn * aspect * d[i];
            eye[i][1] = (2.0 * wy / H - 1.0) * tn * d[i];
            eye[i][2] = -d[i];
            v[i].x = wx, v[i].y = wy;
            v[i].z = 0.5 * (((f + n) * d[i] - 2.0 * f * n) / ((f - n) * d[i]) + 1.0);
            v[i].q = 1.0 / d[i];
        }
        if (!inside) continue;
        /* Face normal towards the eye, vertex normals scattered around it. */
        double e1[3], e2[3], fn[3];
        for (int c = 0; c < 3; c++) e1[c] = eye[1][c] - eye[0][c], e2[c] = eye[2][c] - eye[0][c];
        fn[0] = e1[1] * e2[2] - e1[2] * e2[1];
        fn[1] = e1[2] * e2[0] - e1[0] * e2[2];
        fn[2] = e1[0] * e2[1] - e1[1] * e2[0];
        if (!(fn[0] * fn[0] + fn[1] * fn[1] + fn[2] * fn[2] > 0.0)) continue;
        unit3(fn);
        if (fn[0] * eye[0][0] + fn[1] * eye[0][1] + fn[2] * eye[0][2] > 0.0)
            for (int c = 0; c < 3; c++) fn[c] = -fn[c];
        int facing = 1;
        for (int i = 0; i < 3; i++) {
            double nn[3];
            perturbed(rng, fn, nn);
            /* Keep every interpolated normal on the eye's side, so that the
             * two-sided flip never separates a method from the reference. */
            double el = sqrt(eye[i][0] * eye[i][0] + eye[i][1] * eye[i][1] + eye[i][2] * eye[i][2]);
            if (-(nn[0] * eye[i][0] + nn[1] * eye[i][1] + nn[2] * eye[i][2]) / el < 0.25) facing = 0;
            memset(&cv[i], 0, sizeof cv[i]);
            for (int c = 0; c < 3; c++) {
                cv[i].attr[PERSP_A_NX + c] = (float)nn[c];
                cv[i].attr[PERSP_A_EX + c] = (float)eye[i][c];
            }
            cv[i].attr[PERSP_A_U] = (float)persp__rng_uniform(rng, 0.0, 1.0);
            cv[i].attr[PERSP_A_V] = (float)persp__rng_uniform(rng, 0.0, 1.0);
            cv[i].clip[3] = (float)d[i];
        }
        if (!facing) continue;
        persp__shade_vertices(gouraud, cv, 3);
        for (int i = 0; i < 3; i++) v[i].attr = cv[i].attr;
        if (!persp__setup_triangle(v, (int)W, (int)H, 0, t, NULL)) continue;
        uint64_t px = persp__tri_pixels(t);
        if (px < PERSP_RT_MIN_PIXELS || px > PERSP_RT_MAX_PIXELS) continue;
        return 1;
    }
    return 0;
}

/* Exact per-pixel quantities of one span, in double. */
typedef struct span_ref {
    double n[PERSP_SPAN_MAX][3];   /* unit normal of the exact barycentric blend */
    double col[PERSP_SPAN_MAX][3]; /* exact Phong colour */
    double gcol[PERSP_SPAN_MAX][3];/* perspective-correct Gouraud colour */
} span_ref;

static void reference_span(const persp_draw_state *ds, const persp_tri *t, int x0, int y, int n,
                           span_ref *r)
{
    for (int k = 0; k < n; k++) {
        double b[3], e[3] = {0, 0, 0};
        persp__rational_eval(&t->bary, x0 + k, y, &b[1], &b[2]);
        b[0] = 1.0 - b[1] - b[2];
        for (int c = 0; c < 3; c++) {
            r->n[k][c] = 0.0, r->gcol[k][c] = 0.0;
            for (int v = 0; v < 3; v++) {
                r->n[k][c] += b[v] * t->vattr[v][PERSP_A_NX + c];
                e[c] += b[v] * t->vattr[v][PERSP_A_EX + c];
                r->gcol[k][c] += b[v] * t->vattr[v][PERSP_A_R + c];
            }
        }
        unit3(r->n[k]);
        light_ref(ds, r->n[k], e, r->col[k]);
    }
}

typedef struct mode_acc {
    double col_sum, ang_sum;
    uint64_t over;
} mode_acc;

static void measure_span(const persp_draw_state *ds, const persp_tri *t, const persp_frag_batch *b,
                         const span_ref *r, persp_shade_err *e, mode_acc *acc)
{
    uint32_t out[PERSP_SPAN_MAX];
    float nrm[PERSP_SPAN_MAX][3], eye[PERSP_SPAN_MAX][3];
    ds->shade(ds, t, b, NULL, NULL, out);
    int has_n = persp__shade_normals(ds, t, b, nrm, eye);
    e->has_normals = has_n;
    const int gouraud = persp__shade_is_gouraud(ds);
    for (int k = 0; k < b->n; k++) {
        double ce = colour_err(out[k], r->col[k]);
        e->col_max = fmax(e->col_max, ce);
        acc->col_sum += ce;
        if (ce > 1.0) acc->over++;
        e->own_max = fmax(e->own_max, gouraud ? colour_err(out[k], r->gcol[k]) : ce);
        if (!has_n) continue;
        double len = sqrt((double)nrm[k][0] * nrm[k][0] + (double)nrm[k][1] * nrm[k][1] +
                          (double)nrm[k][2] * nrm[k][2]);
        double dot = (nrm[k][0] * r->n[k][0] + nrm[k][1] * r->n[k][1] + nrm[k][2] * r->n[k][2]) / len;
        double ang = acos(dot > 1.0 ? 1.0 : dot < -1.0 ? -1.0 : dot) * 180.0 / PI;
        e->ang_max = fmax(e->ang_max, ang);
        acc->ang_sum += ang;
        e->len_max = fmax(e->len_max, fabs(len - 1.0));
    }
    e->pixels += (uint64_t)b->n;
}

static void finish(persp_shade_err *e, const mode_acc *acc)
{
    if (!e->pixels) return;
    e->col_mean = acc->col_sum / (double)e->pixels;
    e->ang_mean = acc->ang_sum / (double)e->pixels;
    e->col_over = (double)acc->over / (double)e->pixels;
}

persp_status persp__shading_random(persp_context *ctx, uint64_t seed, double hbar, int triangles,
                                   persp_shade_err out[PERSP_SHADE_MODES])
{
    if (!ctx || !out || triangles < 1 || !(hbar >= 1.0)) return PERSP_ERR_INVALID_ARGUMENT;
    /* The draw states are large; keep them off the stack. */
    persp_draw_state *ds = persp__calloc(ctx, PERSP_SHADE_MODES, sizeof *ds);
    if (!ds) return persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "shading accuracy: out of memory");
    mode_acc acc[PERSP_SHADE_MODES];
    memset(acc, 0, sizeof acc);
    persp_status st = PERSP_OK;
    for (int i = 0; i < PERSP_SHADE_MODES && st == PERSP_OK; i++) {
        random_case_state(&ds[i]);
        ds[i].shading = (persp_shading)(PERSP_SHADING_FLAT + i);
        st = persp__shade_resolve(ctx, &ds[i]);
        memset(&out[i], 0, sizeof out[i]);
        out[i].mode = ds[i].shading;
    }
    persp_rng rng = {seed * 0x9E3779B97F4A7C15ull + (uint64_t)(hbar * 1000.0)};
    span_ref ref;
    for (int tri = 0; tri < triangles && st == PERSP_OK; tri++) {
        persp_clipvert cv[3];
        persp_tri t;
        if (!random_lit_triangle(&rng, hbar, &ds[PERSP_SHADING_GOURAUD - PERSP_SHADING_FLAT], cv, &t)) break;
        for (int y = t.ymin; y <= t.ymax; y++) {
            int lo, hi;
            if (!persp__tri_row_range(&t, y, t.xmin, t.xmax, &lo, &hi)) continue;
            /* Spans as the renderer cuts them: one row inside one tile. */
            for (int x = lo; x <= hi;) {
                int end = (x / PERSP_TILE) * PERSP_TILE + PERSP_TILE - 1;
                if (end > hi) end = hi;
                persp_frag_batch b = {.n = end - x + 1, .x0 = x, .y = y};
                reference_span(&ds[0], &t, x, y, b.n, &ref);
                for (int i = 0; i < PERSP_SHADE_MODES; i++) measure_span(&ds[i], &t, &b, &ref, &out[i], &acc[i]);
                x = end + 1;
            }
        }
    }
    for (int i = 0; i < PERSP_SHADE_MODES; i++) finish(&out[i], &acc[i]);
    persp__free(ctx, ds);
    return st;
}

/* ------------------------------------------------------------ lit scene */

static persp_status add_object(persp_scene *s, persp_mesh *mesh, const float diffuse[3],
                               float specular, float shininess, persp_mat4 model)
{
    int mi, ma;
    persp_status st = persp__scene_add_mesh(s, mesh, &mi);
    if (st != PERSP_OK) return st;
    persp_material m = persp__material_default();
    for (int c = 0; c < 3; c++) {
        m.diffuse[c] = diffuse[c];
        m.ambient[c] = diffuse[c];
        m.specular[c] = specular;
    }
    m.shininess = shininess;
    st = persp__scene_add_material(s, &m, &ma);
    if (st != PERSP_OK) return st;
    persp_object o;
    memset(&o, 0, sizeof o);
    o.mesh = mi, o.material = ma, o.model = model;
    o.texgen = PERSP_TEXGEN_UV;
    return persp__scene_add_object(s, &o);
}

persp_status persp__shading_test_scene(persp_context *ctx, persp_scene **out)
{
    persp_scene *s = NULL;
    persp_status st = persp__scene_new(ctx, &s);
    if (st != PERSP_OK) return st;
    s->camera.eye = (persp_vec3){0.0f, 1.2f, 3.5f};
    s->camera.target = (persp_vec3){0.0f, 0.5f, -4.0f};
    s->camera.fovy_deg = 55.0f;
    s->camera.znear = 0.1f, s->camera.zfar = 80.0f;
    s->width = 640, s->height = 480;
    s->clear[0] = 40, s->clear[1] = 40, s->clear[2] = 48;
    s->shading = PERSP_SHADING_PHONG_PC;
    s->cull_backfaces = 1;
    for (int c = 0; c < 3; c++) s->ambient[c] = 0.12f;
    s->light_count = 2;
    persp_light *p = &s->lights[0], *d = &s->lights[1];
    p->type = PERSP_LIGHT_POINT;
    p->position[0] = 1.5f, p->position[1] = 3.0f, p->position[2] = 1.0f;
    p->attenuation[0] = 1.0f;
    d->type = PERSP_LIGHT_DIRECTIONAL;
    d->position[0] = -0.4f, d->position[1] = 0.7f, d->position[2] = 0.5f;
    for (int c = 0; c < 3; c++) p->color[c] = 0.95f, d->color[c] = 0.3f;
    persp_mesh m;
    const float grey[3] = {0.6f, 0.6f, 0.62f}, red[3] = {0.8f, 0.25f, 0.2f},
                blue[3] = {0.25f, 0.45f, 0.85f}, gold[3] = {0.85f, 0.7f, 0.3f};
    /* Floor (flat: all normal schemes agree there), a coarse sphere near the
     * eye, a torus, and a long coarse cylinder lying along the view
     * direction: its spans cross strong depth ratios with varying normals. */
    if (st == PERSP_OK && (st = persp__mesh_plane(ctx, 8, &m)) == PERSP_OK)
        st = add_object(s, &m, grey, 0.4f, 30.0f, persp_mat4_scale(30.0f, 1.0f, 30.0f));
    if (st == PERSP_OK && (st = persp__mesh_sphere(ctx, 16, 8, &m)) == PERSP_OK)
        st = add_object(s, &m, red, 0.7f, 60.0f,
                        persp_mat4_mul(persp_mat4_translate(0.6f, 0.8f, 0.6f), persp_mat4_scale(0.8f, 0.8f, 0.8f)));
    if (st == PERSP_OK && (st = persp__mesh_torus(ctx, 1.0f, 0.35f, 20, 10, &m)) == PERSP_OK)
        st = add_object(s, &m, gold, 0.8f, 80.0f,
                        persp_mat4_mul(persp_mat4_translate(2.2f, 0.9f, -3.0f),
                                       persp_mat4_rotate(60.0f, 1.0f, 0.0f, 0.0f)));
    if (st == PERSP_OK && (st = persp__mesh_cylinder(ctx, 10, &m)) == PERSP_OK)
        st = add_object(s, &m, blue, 0.8f, 50.0f,
                        persp_mat4_mul(persp_mat4_translate(-1.6f, 0.6f, -12.0f),
                                       persp_mat4_mul(persp_mat4_rotate(90.0f, 1.0f, 0.0f, 0.0f),
                                                      persp_mat4_scale(0.6f, 12.0f, 0.6f))));
    if (st != PERSP_OK) {
        persp_scene_destroy(s);
        return st;
    }
    *out = s;
    return PERSP_OK;
}

persp_status persp__shading_scene_compare(persp_context *ctx, const persp_scene *scene, int w,
                                          int h, persp_shade_err out[PERSP_SHADE_MODES])
{
    if (!ctx || !scene || !out || w < 1 || h < 1 || w > 8192 || h > 8192)
        return PERSP_ERR_INVALID_ARGUMENT;
    size_t px = (size_t)w * (size_t)h;
    uint8_t *ref = persp__calloc(ctx, px, 4), *img = persp__calloc(ctx, px, 4);
    float *depth = persp__calloc(ctx, px, sizeof(float)), *rdepth = persp__calloc(ctx, px, sizeof(float));
    persp_status st = PERSP_OK;
    if (!ref || !img || !depth || !rdepth) {
        st = persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "shading accuracy: out of memory");
        goto done;
    }
    persp_render_desc d;
    memset(&d, 0, sizeof d);
    d.shading = PERSP_SHADING_PHONG_PC;
    persp_framebuffer rfb = {w, h, ref, rdepth};
    if ((st = persp_render(ctx, scene, &d, &rfb, NULL)) != PERSP_OK) goto done;
    for (int i = 0; i < PERSP_SHADE_MODES; i++) {
        persp_shade_err *e = &out[i];
        memset(e, 0, sizeof *e);
        e->mode = d.shading = (persp_shading)(PERSP_SHADING_FLAT + i);
        persp_framebuffer fb = {w, h, img, depth};
        if ((st = persp_render(ctx, scene, &d, &fb, NULL)) != PERSP_OK) goto done;
        double sum = 0.0;
        uint64_t over = 0;
        for (size_t p = 0; p < px; p++) {
            if (!(rdepth[p] < 1.0f)) continue; /* background */
            double worst = 0.0;
            for (int c = 0; c < 3; c++) worst = fmax(worst, fabs((double)img[4 * p + (size_t)c] - ref[4 * p + (size_t)c]));
            e->col_max = fmax(e->col_max, worst);
            sum += worst;
            over += worst > 1.0;
            e->pixels++;
        }
        e->own_max = e->col_max;
        if (e->pixels) e->col_mean = sum / (double)e->pixels, e->col_over = (double)over / (double)e->pixels;
    }
done:
    persp__free(ctx, ref);
    persp__free(ctx, img);
    persp__free(ctx, depth);
    persp__free(ctx, rdepth);
    return st;
}
