/*
 * The double-precision arbiter of the differential test (diffref.h).
 *
 * It returns, per channel, the interval of values OpenGL allows at a pixel,
 * not one value: GL leaves some latitude, and each widening below names the
 * rule that grants it.
 *
 *   - Vertex snapping. Window coordinates are snapped to the sub-pixel grid
 *     (GL 4.6 §14.5, SUBPIXEL_BITS; 8 bits in persp, docs/CONVENTIONS.md,
 *     and in llvmpipe), and both interpolate from the snapped vertices. A
 *     vertex moves by at most 1/512 pixel per axis. snap_latitude() moves
 *     each coordinate of the fan triangle holding the pixel (the clipped
 *     polygon's, as the renderer draws it) by that much and sums the
 *     changes of u, v and rho, doubled for the higher-order terms: this is
 *     large exactly where it matters, on slivers and where one pixel spans
 *     many texels.
 *   - Floating point. GL 4.6 §2.3.4.1 asks results to about 1 part in
 *     1e5: the position box gets 1e-5 of |u| and DIFF_REF_TEXEL_MARGIN
 *     texel (4 times the 5e-4 texel persp's exact method is asserted to,
 *     docs/METHODS.md); rho gets 1e-5 of the magnitudes of the terms a
 *     renderer subtracts to form each derivative (large where they nearly
 *     cancel), and lambda DIFF_REF_LOD_MARGIN.
 *   - Coverage and visibility. Snapping moves an edge by at most
 *     1/512 · √2 pixel, and float clipping moves a clipped vertex by far
 *     less, so a pixel centre within DIFF_REF_EDGE_MARGIN (1/100 pixel,
 *     3.5 times that) of an edge or clip line of a triangle may go either
 *     way; so may depths closer than DEPTH_TIE, 2^-21 of the window depth
 *     range (the peer's buffer has 24 bits, and both interpolate depth in
 *     float). The nearest triangle that surely covers the centre hides the
 *     rest; every triangle in front of it or tied with it that reaches
 *     within the margin is a candidate, evaluated at the centre (its planes
 *     extended); with no sure cover, "no triangle" is a candidate too.
 *
 * Inside these boxes the extremes are exact: nearest takes every texel the
 * box touches; bilinear is bilinear inside each texel cell, so its extremes
 * lie at the box corners and where the box crosses cell lines, all of which
 * are evaluated (beyond 8 cells per axis, the aliasing regime, the hull of
 * the touched texels, which contains every bilinear value); linear level
 * blending is linear in frac(lambda), so its extremes lie at the ends of the
 * lambda interval and at the integers inside it.
 */
#include "diffref.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define MAX_CELLS 8
#define DEPTH_TIE 1e-6 /* of z_ndc in [-1, 1]: about 2^-21 of the window depth range */

typedef struct ref_tri {
    double c[3][4];   /* clip coordinates */
    double uv[3][2];
    double rgb[3][3]; /* untextured colour (vertex colour × diffuse), 0..255 */
    int object;
    size_t first_index; /* in the object's index list */
    double xmin, xmax, ymin, ymax; /* window box when every w > 0; else unbounded */
} ref_tri;

typedef struct ref_level {
    int w, h;
    size_t stride;
    const uint8_t *px;
} ref_level;

typedef struct ref_object {
    int textured;
    int mirrored; /* the model matrix's linear part has a negative determinant */
    persp_sampler_desc sampler;
    int levels;
    ref_level *level;
} ref_object;

struct diff_ref {
    int width, height;
    persp_filter filter;
    int cull;
    ref_tri *tris;
    size_t ntris;
    ref_object *objects;
    size_t nobjects;
    /* Triangles whose window box (widened by a pixel) meets each tile of
     * TILE × TILE pixels, in drawing order: tile_start[k] .. tile_start[k+1]
     * of tile_tris. */
    int tiles_x, tiles_y;
    size_t *tile_start;
    uint32_t *tile_tris;
};

#define TILE 16

static void mat_mul(const double a[16], const double b[16], double out[16])
{
    for (int c = 0; c < 4; c++)
        for (int r = 0; r < 4; r++) {
            double s = 0.0;
            for (int k = 0; k < 4; k++) s += a[k * 4 + r] * b[c * 4 + k];
            out[c * 4 + r] = s;
        }
}

static void to_double(persp_mat4 m, double out[16])
{
    for (int i = 0; i < 16; i++) out[i] = (double)m.m[i];
}

/* Tile range of t's box widened by a pixel (beyond DIFF_REF_EDGE_MARGIN). */
static void tile_range(const diff_ref *r, const ref_tri *t, int *x0, int *x1, int *y0, int *y1)
{
    double a = floor((t->xmin - 1.0) / TILE), b = floor((t->xmax + 1.0) / TILE);
    double c = floor((t->ymin - 1.0) / TILE), d = floor((t->ymax + 1.0) / TILE);
    *x0 = a < 0.0 ? 0 : (int)a, *y0 = c < 0.0 ? 0 : (int)c;
    *x1 = b >= r->tiles_x - 1 ? r->tiles_x - 1 : (int)b, *y1 = d >= r->tiles_y - 1 ? r->tiles_y - 1 : (int)d;
}

static int bin_triangles(diff_ref *r)
{
    r->tiles_x = (r->width + TILE - 1) / TILE, r->tiles_y = (r->height + TILE - 1) / TILE;
    size_t ntiles = (size_t)r->tiles_x * (size_t)r->tiles_y;
    r->tile_start = calloc(ntiles + 1, sizeof *r->tile_start);
    if (!r->tile_start) return -1;
    for (int pass = 0; pass < 2; pass++) {
        for (size_t i = 0; i < r->ntris; i++) {
            int x0, x1, y0, y1;
            tile_range(r, &r->tris[i], &x0, &x1, &y0, &y1);
            for (int ty = y0; ty <= y1; ty++)
                for (int tx = x0; tx <= x1; tx++) {
                    size_t k = (size_t)ty * (size_t)r->tiles_x + (size_t)tx;
                    if (pass == 0)
                        r->tile_start[k + 1]++;
                    else
                        r->tile_tris[r->tile_start[k]++] = (uint32_t)i;
                }
        }
        if (pass == 0) {
            for (size_t k = 0; k < ntiles; k++) r->tile_start[k + 1] += r->tile_start[k];
            r->tile_tris = malloc((r->tile_start[ntiles] ? r->tile_start[ntiles] : 1) * sizeof *r->tile_tris);
            if (!r->tile_tris) return -1;
        } else {
            /* The fill advanced each start to the next tile's: shift back. */
            for (size_t k = ntiles; k > 0; k--) r->tile_start[k] = r->tile_start[k - 1];
            r->tile_start[0] = 0;
        }
    }
    return 0;
}

diff_ref *diff_ref_create(const persp_scene *scene, int width, int height, persp_filter filter)
{
    diff_ref *r = calloc(1, sizeof *r);
    if (!r) return NULL;
    r->width = width, r->height = height, r->filter = filter;
    persp_scene_info info;
    persp_scene_get_info(scene, &info);
    r->cull = info.cull_backfaces;
    persp_mat4 view, proj;
    persp_scene_get_camera(scene, width, height, &view, &proj);
    double V[16], P[16], PV[16];
    to_double(view, V);
    to_double(proj, P);
    mat_mul(P, V, PV);
    r->nobjects = persp_scene_object_count(scene);
    r->objects = calloc(r->nobjects ? r->nobjects : 1, sizeof *r->objects);
    size_t total = 0;
    for (size_t o = 0; o < r->nobjects; o++) {
        persp_scene_object so;
        persp_scene_get_object(scene, o, &so);
        total += so.index_count / 3;
    }
    r->tris = calloc(total ? total : 1, sizeof *r->tris);
    if (!r->objects || !r->tris) {
        diff_ref_destroy(r);
        return NULL;
    }
    for (size_t o = 0; o < r->nobjects; o++) {
        persp_scene_object so;
        persp_scene_get_object(scene, o, &so);
        ref_object *ro = &r->objects[o];
        ro->textured = so.material.texture >= 0;
        ro->sampler = so.material.sampler;
        if (ro->textured) {
            const persp_texture *t = persp_scene_get_texture(scene, so.material.texture);
            ro->levels = persp_texture_levels(t);
            ro->level = calloc((size_t)ro->levels, sizeof *ro->level);
            if (!ro->level) {
                diff_ref_destroy(r);
                return NULL;
            }
            for (int l = 0; l < ro->levels; l++) {
                persp_image_view v;
                persp_texture_level(t, l, &v);
                ro->level[l] = (ref_level){v.width, v.height, v.stride, v.pixels};
            }
        }
        /* The object's texture coordinates as persp draws them (its
         * texgen applied: persp_scene_object_texcoords); the reference
         * judges rasterization and filtering, the generation itself is
         * test_texgen's. */
        float *uv = malloc((so.vertex_count ? so.vertex_count : 1) * 2 * sizeof(float));
        if (!uv) {
            diff_ref_destroy(r);
            return NULL;
        }
        persp_scene_object_texcoords(scene, o, &view, uv);
        double M[16], MVP[16];
        to_double(so.model, M);
        /* Culling follows the winding a mirror reverses (docs/SCENES.md,
         * `cull`): the sign of the linear part's determinant. */
        ro->mirrored = M[0] * (M[5] * M[10] - M[9] * M[6]) - M[4] * (M[1] * M[10] - M[9] * M[2]) +
                           M[8] * (M[1] * M[6] - M[5] * M[2]) <
                       0.0;
        mat_mul(PV, M, MVP);
        for (size_t i = 0; i + 2 < so.index_count; i += 3) {
            ref_tri *t = &r->tris[r->ntris++];
            t->object = (int)o;
            t->first_index = i;
            int bounded = 1;
            t->xmin = t->ymin = INFINITY, t->xmax = t->ymax = -INFINITY;
            for (int k = 0; k < 3; k++) {
                const persp_vertex *v = &so.vertices[so.indices[i + (size_t)k]];
                double p[4] = {v->pos[0], v->pos[1], v->pos[2], 1.0};
                for (int row = 0; row < 4; row++) {
                    double s = 0.0;
                    for (int c = 0; c < 4; c++) s += MVP[c * 4 + row] * p[c];
                    t->c[k][row] = s;
                }
                const size_t vi = so.indices[i + (size_t)k];
                t->uv[k][0] = uv[2 * vi], t->uv[k][1] = uv[2 * vi + 1];
                for (int c = 0; c < 3; c++) t->rgb[k][c] = 255.0 * v->color[c] * so.material.diffuse[c];
                if (t->c[k][3] > 0.0) {
                    double x = (t->c[k][0] / t->c[k][3] + 1.0) * 0.5 * width;
                    double y = (t->c[k][1] / t->c[k][3] + 1.0) * 0.5 * height;
                    t->xmin = fmin(t->xmin, x), t->xmax = fmax(t->xmax, x);
                    t->ymin = fmin(t->ymin, y), t->ymax = fmax(t->ymax, y);
                } else {
                    bounded = 0;
                }
            }
            if (!bounded) t->xmin = t->ymin = -INFINITY, t->xmax = t->ymax = INFINITY;
        }
        free(uv);
    }
    if (bin_triangles(r)) {
        diff_ref_destroy(r);
        return NULL;
    }
    return r;
}

void diff_ref_destroy(diff_ref *r)
{
    if (!r) return;
    for (size_t o = 0; o < r->nobjects; o++) free(r->objects[o].level);
    free(r->objects);
    free(r->tris);
    free(r->tile_start);
    free(r->tile_tris);
    free(r);
}

/* Barycentrics of the point of t's plane seen through window point (x, y):
 * Σ b_k (c_k.x - xn c_k.w) = 0, Σ b_k (c_k.y - yn c_k.w) = 0, Σ b_k = 1.
 * Returns 0 when the plane is seen edge-on. */
static int solve(const diff_ref *r, const ref_tri *t, double x, double y, double b[3])
{
    double xn = 2.0 * x / r->width - 1.0, yn = 2.0 * y / r->height - 1.0;
    double m[3][3];
    for (int k = 0; k < 3; k++) {
        m[0][k] = t->c[k][0] - xn * t->c[k][3];
        m[1][k] = t->c[k][1] - yn * t->c[k][3];
        m[2][k] = 1.0;
    }
    double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                 m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                 m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    if (det == 0.0 || !isfinite(det)) return 0;
    /* Cramer's rule with right-hand side (0, 0, 1). */
    b[0] = (m[0][1] * m[1][2] - m[0][2] * m[1][1]) / det;
    b[1] = (m[0][2] * m[1][0] - m[0][0] * m[1][2]) / det;
    b[2] = (m[0][0] * m[1][1] - m[0][1] * m[1][0]) / det;
    return 1;
}

/* The five functions whose signs bound the visible part of t at window
 * point (x, y): the three barycentrics, z + w (near) and w - z (far). */
static int bounds_at(const diff_ref *r, const ref_tri *t, double x, double y, double f[5], double *z)
{
    double b[3];
    if (!solve(r, t, x, y, b)) return 0;
    double cz = 0.0, cw = 0.0;
    for (int k = 0; k < 3; k++) cz += b[k] * t->c[k][2], cw += b[k] * t->c[k][3];
    f[0] = b[0], f[1] = b[1], f[2] = b[2], f[3] = cz + cw, f[4] = cw - cz;
    if (z) *z = cw > 0.0 ? cz / cw : INFINITY;
    return 1;
}

enum { MISS, EDGE, SOLID };

/* Whether t covers window point (x, y): SOLID when the point lies more than
 * DIFF_REF_EDGE_MARGIN pixels inside every bound, EDGE when within that
 * distance of one, else MISS; z is t's depth at the point. */
static int hit(const diff_ref *r, const ref_tri *t, double x, double y, double *z, double *gz)
{
    const double e = DIFF_REF_EDGE_MARGIN, h = 1e-3;
    if (x < t->xmin - e || x > t->xmax + e || y < t->ymin - e || y > t->ymax + e) return MISS;
    if (r->cull) {
        /* Orientation of the visible part: sign of det(x, y, w). */
        const double(*c)[4] = t->c;
        double d = c[0][0] * (c[1][1] * c[2][3] - c[1][3] * c[2][1]) -
                   c[0][1] * (c[1][0] * c[2][3] - c[1][3] * c[2][0]) +
                   c[0][3] * (c[1][0] * c[2][1] - c[1][1] * c[2][0]);
        if (r->objects[t->object].mirrored ? d > 0.0 : d < 0.0) return MISS;
    }
    double f[5], fx[5], fy[5], zx, zy;
    if (!bounds_at(r, t, x, y, f, z) || !bounds_at(r, t, x + h, y, fx, &zx) || !bounds_at(r, t, x, y + h, fy, &zy))
        return MISS;
    if (!isfinite(*z) || !isfinite(zx) || !isfinite(zy)) return MISS;
    *gz = hypot(zx - *z, zy - *z) / h;
    int solid = 1;
    for (int k = 0; k < 5; k++) {
        /* Distance to the bound's zero line, to first order. */
        double g = hypot(fx[k] - f[k], fy[k] - f[k]) / h;
        if (f[k] < -e * g) return MISS;
        if (f[k] < e * g) solid = 0;
    }
    return solid ? SOLID : EDGE;
}

/* ------------------------------------------------------------- sampling */

typedef struct interval {
    double lo[3], hi[3];
} interval;

static void iv_empty(interval *iv)
{
    for (int c = 0; c < 3; c++) iv->lo[c] = INFINITY, iv->hi[c] = -INFINITY;
}

static void iv_add(interval *iv, const double v[3])
{
    for (int c = 0; c < 3; c++) iv->lo[c] = fmin(iv->lo[c], v[c]), iv->hi[c] = fmax(iv->hi[c], v[c]);
}

static void iv_union(interval *iv, const interval *o)
{
    for (int c = 0; c < 3; c++) iv->lo[c] = fmin(iv->lo[c], o->lo[c]), iv->hi[c] = fmax(iv->hi[c], o->hi[c]);
}

/* GL 4.6 Table 8.20 on an integer texel index; -1 is the border. */
static int wrap(persp_wrap w, int i, int size)
{
    switch (w) {
    case PERSP_WRAP_CLAMP_TO_EDGE: return i < 0 ? 0 : i >= size ? size - 1 : i;
    case PERSP_WRAP_CLAMP_TO_BORDER: return i < 0 || i >= size ? -1 : i;
    case PERSP_WRAP_MIRRORED_REPEAT: {
        int m = i % (2 * size);
        if (m < 0) m += 2 * size;
        int a = m - size;
        int mirror = a >= 0 ? a : -(1 + a);
        return size - 1 - mirror;
    }
    default: {
        int m = i % size;
        return m < 0 ? m + size : m;
    }
    }
}

static void texel(const ref_object *o, int level, int i, int j, double out[3])
{
    const ref_level *l = &o->level[level];
    int wi = wrap(o->sampler.wrap_s, i, l->w), wj = wrap(o->sampler.wrap_t, j, l->h);
    if (wi < 0 || wj < 0) {
        for (int c = 0; c < 3; c++) out[c] = o->sampler.border[c];
        return;
    }
    const uint8_t *p = l->px + (size_t)wj * l->stride + 4 * (size_t)wi;
    for (int c = 0; c < 3; c++) out[c] = p[c];
}

static int clamp_index(double v)
{
    return v < -1e9 ? -1000000000 : v > 1e9 ? 1000000000 : (int)floor(v);
}

/* Values of nearest filtering on a level over the texel-space box
 * [u0, u1] × [v0, v1]: every texel the box touches. */
static void nearest_box(const ref_object *o, int level, double u0, double u1, double v0, double v1, interval *iv)
{
    int i0 = clamp_index(u0), i1 = clamp_index(u1), j0 = clamp_index(v0), j1 = clamp_index(v1);
    const ref_level *l = &o->level[level];
    if (i1 - i0 > 2 * l->w + 2) i0 = 0, i1 = 2 * l->w + 1; /* covers every texel of any wrap */
    if (j1 - j0 > 2 * l->h + 2) j0 = 0, j1 = 2 * l->h + 1;
    double t[3];
    for (int j = j0; j <= j1; j++)
        for (int i = i0; i <= i1; i++) {
            texel(o, level, i, j, t);
            iv_add(iv, t);
        }
    if (o->sampler.wrap_s == PERSP_WRAP_CLAMP_TO_BORDER || o->sampler.wrap_t == PERSP_WRAP_CLAMP_TO_BORDER) {
        /* The widened ranges above stand for "anything": add the border. */
        if (i1 - i0 > 2 * l->w || j1 - j0 > 2 * l->h) {
            for (int c = 0; c < 3; c++) t[c] = o->sampler.border[c];
            iv_add(iv, t);
        }
    }
}

static void bilinear_at(const ref_object *o, int level, double u, double v, double out[3])
{
    double a = u - 0.5, b = v - 0.5;
    double fi = floor(a), fj = floor(b);
    double al = a - fi, be = b - fj;
    int i = clamp_index(fi), j = clamp_index(fj);
    double t00[3], t10[3], t01[3], t11[3];
    texel(o, level, i, j, t00);
    texel(o, level, i + 1, j, t10);
    texel(o, level, i, j + 1, t01);
    texel(o, level, i + 1, j + 1, t11);
    for (int c = 0; c < 3; c++)
        out[c] = (1 - al) * (1 - be) * t00[c] + al * (1 - be) * t10[c] + (1 - al) * be * t01[c] + al * be * t11[c];
}

/* Values of bilinear filtering over the texel-space box: corners, cell-line
 * crossings and cell corners inside (exact extremes of a piecewise
 * bilinear function); the hull of the touched texels beyond MAX_CELLS. */
static void bilinear_box(const ref_object *o, int level, double u0, double u1, double v0, double v1, interval *iv)
{
    double a0 = u0 - 0.5, a1 = u1 - 0.5, b0 = v0 - 0.5, b1 = v1 - 0.5;
    if (floor(a1) - floor(a0) > MAX_CELLS || floor(b1) - floor(b0) > MAX_CELLS) {
        nearest_box(o, level, floor(a0), floor(a1) + 1.0, floor(b0), floor(b1) + 1.0, iv);
        return;
    }
    double us[MAX_CELLS + 3], vs[MAX_CELLS + 3];
    int nu = 0, nv = 0;
    us[nu++] = u0;
    for (double k = floor(a0) + 1.0; k <= a1; k += 1.0) us[nu++] = k + 0.5;
    us[nu++] = u1;
    vs[nv++] = v0;
    for (double k = floor(b0) + 1.0; k <= b1; k += 1.0) vs[nv++] = k + 0.5;
    vs[nv++] = v1;
    double c[3];
    for (int j = 0; j < nv; j++)
        for (int i = 0; i < nu; i++) {
            bilinear_at(o, level, us[i], vs[j], c);
            iv_add(iv, c);
        }
}

typedef struct sample_in {
    double u, v;   /* normalised */
    double mu, mv; /* half-widths of the position box, normalised */
    double lambda, mlambda;
} sample_in;

/* In-level filter (nearest or bilinear) on one level over the box. */
static void level_box(const ref_object *o, int level, int linear, const sample_in *s, interval *iv)
{
    const ref_level *l = &o->level[level];
    double u0 = (s->u - s->mu) * l->w, u1 = (s->u + s->mu) * l->w;
    double v0 = (s->v - s->mv) * l->h, v1 = (s->v + s->mv) * l->h;
    if (linear)
        bilinear_box(o, level, u0, u1, v0, v1, iv);
    else
        nearest_box(o, level, u0, u1, v0, v1, iv);
}

/* GL 4.6 §8.14.3 at one lambda, the position box included. */
static void filter_at(const diff_ref *r, const ref_object *o, const sample_in *s, double lam, interval *iv)
{
    persp_filter f = r->filter;
    int linear = f == PERSP_FILTER_BILINEAR || f == PERSP_FILTER_BILINEAR_MIP_NEAREST || f == PERSP_FILTER_TRILINEAR;
    int q = o->levels - 1;
    if (f == PERSP_FILTER_NEAREST || f == PERSP_FILTER_BILINEAR || lam <= 0.0) {
        level_box(o, 0, linear, s, iv);
        return;
    }
    if (f == PERSP_FILTER_NEAREST_MIP_NEAREST || f == PERSP_FILTER_BILINEAR_MIP_NEAREST) {
        int d = lam <= 0.5 ? 0 : (int)(ceil(lam + 0.5) - 1.0);
        level_box(o, d > q ? q : d, linear, s, iv);
        return;
    }
    double fl = floor(lam);
    if (fl >= q) {
        level_box(o, q, linear, s, iv);
        return;
    }
    int d = (int)fl;
    double w = lam - fl;
    interval a, b;
    iv_empty(&a), iv_empty(&b);
    level_box(o, d, linear, s, &a);
    level_box(o, d + 1, linear, s, &b);
    interval m;
    for (int c = 0; c < 3; c++) {
        m.lo[c] = (1 - w) * a.lo[c] + w * b.lo[c];
        m.hi[c] = (1 - w) * a.hi[c] + w * b.hi[c];
    }
    iv_union(iv, &m);
}

/* u, v and q = 1/w at window point (x, y) of t's plane. */
static void uvq_at(const diff_ref *r, const ref_tri *t, double x, double y, double out[3])
{
    double b[3] = {1.0 / 3, 1.0 / 3, 1.0 / 3};
    solve(r, t, x, y, b);
    double w = b[0] * t->c[0][3] + b[1] * t->c[1][3] + b[2] * t->c[2][3];
    out[0] = b[0] * t->uv[0][0] + b[1] * t->uv[1][0] + b[2] * t->uv[2][0];
    out[1] = b[0] * t->uv[0][1] + b[1] * t->uv[1][1] + b[2] * t->uv[2][1];
    out[2] = 1.0 / w;
}

/* ------------------------------------------------------ vertex snapping */

/* One vertex as the rasterizer sees it: window position, q = 1/w, (u, v). */
typedef struct win_vert {
    double x, y, q, u, v;
} win_vert;

/* The visible part of t (clipped at w > 0, the near and the far plane,
 * GL 4.6 §13.7) in window space, as a convex polygon; its fan from the
 * first vertex is what a renderer rasterizes. Returns the vertex count. */
static int visible_polygon(const diff_ref *r, const ref_tri *t, win_vert out[9])
{
    double poly[2][9][6];
    int n = 3, cur = 0;
    for (int k = 0; k < 3; k++) {
        for (int c = 0; c < 4; c++) poly[0][k][c] = t->c[k][c];
        poly[0][k][4] = t->uv[k][0], poly[0][k][5] = t->uv[k][1];
    }
    for (int plane = 0; plane < 3; plane++) {
        int m = 0;
        for (int i = 0; i < n && m < 9; i++) {
            const double *a = poly[cur][i], *b = poly[cur][(i + 1) % n];
            double da = plane == 0 ? a[3] - 1e-6 : plane == 1 ? a[2] + a[3] : a[3] - a[2];
            double db = plane == 0 ? b[3] - 1e-6 : plane == 1 ? b[2] + b[3] : b[3] - b[2];
            if (da >= 0.0) memcpy(poly[!cur][m++], a, sizeof poly[0][0]);
            if ((da >= 0.0) != (db >= 0.0) && m < 9) {
                double f = da / (da - db);
                for (int c = 0; c < 6; c++) poly[!cur][m][c] = a[c] + f * (b[c] - a[c]);
                m++;
            }
        }
        n = m;
        cur = !cur;
        if (n < 3) return 0;
    }
    for (int k = 0; k < n; k++) {
        const double *v = poly[cur][k];
        out[k].x = (v[0] / v[3] + 1.0) * 0.5 * r->width;
        out[k].y = (v[1] / v[3] + 1.0) * 0.5 * r->height;
        out[k].q = 1.0 / v[3];
        out[k].u = v[4], out[k].v = v[5];
    }
    return n;
}

/* u, v and their window derivatives at (x, y) from a window-space triangle
 * (perspective-correct: screen-linear barycentrics weighted by q). */
static int win_eval(const win_vert v[3], double x, double y, double out[6])
{
    double px[3] = {x, x + 1e-3, x}, py[3] = {y, y, y + 1e-3};
    double d = (v[1].x - v[0].x) * (v[2].y - v[0].y) - (v[2].x - v[0].x) * (v[1].y - v[0].y);
    if (d == 0.0) return 0;
    double uv[3][2];
    for (int k = 0; k < 3; k++) {
        double l1 = ((px[k] - v[0].x) * (v[2].y - v[0].y) - (v[2].x - v[0].x) * (py[k] - v[0].y)) / d;
        double l2 = ((v[1].x - v[0].x) * (py[k] - v[0].y) - (px[k] - v[0].x) * (v[1].y - v[0].y)) / d;
        double l0 = 1.0 - l1 - l2;
        double w0 = l0 * v[0].q, w1 = l1 * v[1].q, w2 = l2 * v[2].q, s = w0 + w1 + w2;
        uv[k][0] = (w0 * v[0].u + w1 * v[1].u + w2 * v[2].u) / s;
        uv[k][1] = (w0 * v[0].v + w1 * v[1].v + w2 * v[2].v) / s;
    }
    out[0] = uv[0][0], out[1] = uv[0][1];
    out[2] = (uv[1][0] - uv[0][0]) / 1e-3, out[3] = (uv[2][0] - uv[0][0]) / 1e-3;
    out[4] = (uv[1][1] - uv[0][1]) / 1e-3, out[5] = (uv[2][1] - uv[0][1]) / 1e-3;
    return 1;
}

/* How far u, v (du, dv) and rho (drho, in level-0 texels) may move when
 * the vertices of the fan triangle holding (x, y) move by the half step of
 * the 8-bit sub-pixel grid, 1/512 pixel per axis: the sum of the changes
 * from each coordinate moved alone, doubled for the terms of higher order. */
static void snap_latitude(const diff_ref *r, const ref_tri *t, double x, double y, double W, double H,
                          double *du, double *dv, double *drho)
{
    *du = *dv = *drho = 0.0;
    win_vert poly[9];
    int n = visible_polygon(r, t, poly);
    /* The fan triangle whose barycentrics at (x, y) are least negative. */
    int best = -1;
    double best_min = -INFINITY;
    for (int k = 1; k + 1 < n; k++) {
        const win_vert *a = &poly[0], *b = &poly[k], *c = &poly[k + 1];
        double d = (b->x - a->x) * (c->y - a->y) - (c->x - a->x) * (b->y - a->y);
        if (d == 0.0) continue;
        double l1 = ((x - a->x) * (c->y - a->y) - (c->x - a->x) * (y - a->y)) / d;
        double l2 = ((b->x - a->x) * (y - a->y) - (x - a->x) * (b->y - a->y)) / d;
        double mn = fmin(fmin(l1, l2), 1.0 - l1 - l2);
        if (mn > best_min) best_min = mn, best = k;
    }
    if (best < 0) return;
    win_vert v[3] = {poly[0], poly[best], poly[best + 1]};
    double base[6];
    if (!win_eval(v, x, y, base)) return;
    double rho0 = fmax(hypot(base[2] * W, base[4] * H), hypot(base[3] * W, base[5] * H));
    const double step = 1.0 / 512.0;
    for (int k = 0; k < 3; k++)
        for (int axis = 0; axis < 2; axis++) {
            win_vert m[3] = {v[0], v[1], v[2]};
            if (axis == 0)
                m[k].x += step;
            else
                m[k].y += step;
            double e[6];
            if (!win_eval(m, x, y, e)) continue;
            double rho = fmax(hypot(e[2] * W, e[4] * H), hypot(e[3] * W, e[5] * H));
            *du += 2.0 * fabs(e[0] - base[0]);
            *dv += 2.0 * fabs(e[1] - base[1]);
            *drho += 2.0 * fabs(rho - rho0);
        }
}

/* The interval of t's colour at the pixel centre (x, y). */
static void tri_interval(const diff_ref *r, const ref_tri *t, double x, double y, interval *iv)
{
    const ref_object *o = &r->objects[t->object];
    if (!o->textured) {
        double b[3] = {1.0 / 3, 1.0 / 3, 1.0 / 3}, c[3] = {0, 0, 0};
        solve(r, t, x, y, b);
        for (int k = 0; k < 3; k++)
            for (int ch = 0; ch < 3; ch++) c[ch] += b[k] * t->rgb[k][ch];
        iv_add(iv, c);
        return;
    }
    /* Derivatives by central differences of the exact rational mapping
     * (error O(h^2), far below the margins). */
    const double h = 1.0 / 64.0;
    double c0[3], px[3], mx[3], py[3], my[3];
    uvq_at(r, t, x, y, c0);
    uvq_at(r, t, x + h, y, px);
    uvq_at(r, t, x - h, y, mx);
    uvq_at(r, t, x, y + h, py);
    uvq_at(r, t, x, y - h, my);
    double W = o->level[0].w, H = o->level[0].h;
    double ux = (px[0] - mx[0]) / (2 * h), vx = (px[1] - mx[1]) / (2 * h);
    double uy = (py[0] - my[0]) / (2 * h), vy = (py[1] - my[1]) / (2 * h);
    double rho = fmax(sqrt(ux * W * ux * W + vx * H * vx * H), sqrt(uy * W * uy * W + vy * H * vy * H));
    double lam = rho > 0.0 ? log2(rho) : -1000.0;
    lam += o->sampler.lod_bias;
    /* GL 4.6 §2.3.4.1 asks floating-point results to about 1 part in 1e5.
     * A renderer evaluates ∂u/∂x from the planes of u·q and q (q = 1/w) as
     * (∂(uq)/∂x - u ∂q/∂x) / q, so 1e-5 of the magnitudes of those two
     * terms is the latitude of each derivative; it matters where they
     * nearly cancel (large triangles seen at a grazing angle). */
    double q = c0[2], dqx = (px[2] - mx[2]) / (2 * h), dqy = (py[2] - my[2]) / (2 * h);
    double mux = (fabs(ux * q + c0[0] * dqx) + fabs(c0[0] * dqx)) / q * W;
    double muy = (fabs(uy * q + c0[0] * dqy) + fabs(c0[0] * dqy)) / q * W;
    double mvx = (fabs(vx * q + c0[1] * dqx) + fabs(c0[1] * dqx)) / q * H;
    double mvy = (fabs(vy * q + c0[1] * dqy) + fabs(c0[1] * dqy)) / q * H;
    double drho = 1e-5 * fmax(sqrt(mux * mux + mvx * mvx), sqrt(muy * muy + mvy * mvy));
    sample_in s;
    s.u = c0[0], s.v = c0[1];
    double snap_u, snap_v, snap_rho;
    snap_latitude(r, t, x, y, W, H, &snap_u, &snap_v, &snap_rho);
    s.mu = DIFF_REF_TEXEL_MARGIN / W + 1e-5 * fabs(c0[0]) + snap_u;
    s.mv = DIFF_REF_TEXEL_MARGIN / H + 1e-5 * fabs(c0[1]) + snap_v;
    drho += snap_rho;
    s.mlambda = DIFF_REF_LOD_MARGIN + (rho > 0.0 && drho < rho ? log2(1.0 + drho / rho) : 1.0);
    s.lambda = lam;
    double l0 = lam - s.mlambda, l1 = lam + s.mlambda;
    filter_at(r, o, &s, l0, iv);
    filter_at(r, o, &s, lam, iv);
    filter_at(r, o, &s, l1, iv);
    /* Switch points inside [l0, l1]: the integers (linear blends, and 0,
     * magnification) and the half-integers (nearest level choice), each
     * approached from both sides. */
    for (double k = ceil(l0 * 2.0) / 2.0; k <= l1; k += 0.5) {
        filter_at(r, o, &s, k - 1e-9, iv);
        filter_at(r, o, &s, k + 1e-9, iv);
    }
}

diff_ref_pixel diff_ref_eval(const diff_ref *r, int x, int y)
{
    diff_ref_pixel out;
    memset(&out, 0, sizeof out);
    double cx = x + 0.5, cy = y + 0.5;
    /* The nearest triangle that surely covers the centre hides everything
     * behind it (beyond the depth tie); every triangle in front of it, or
     * tied with it, whose edge or clip line passes within the margin may
     * own the pixel; with no such triangle, the background may. */
    double front = INFINITY, front_gz = 0.0;
    const size_t tile = (size_t)(y / TILE) * (size_t)r->tiles_x + (size_t)(x / TILE);
    const uint32_t *list = r->tile_tris + r->tile_start[tile];
    const size_t count = r->tile_start[tile + 1] - r->tile_start[tile];
    for (size_t j = 0; j < count; j++) {
        double z, gz;
        if (hit(r, &r->tris[list[j]], cx, cy, &z, &gz) == SOLID && z < front) front = z, front_gz = gz;
    }
    interval iv;
    iv_empty(&iv);
    for (size_t j = 0; j < count; j++) {
        const size_t i = list[j];
        double z, gz;
        if (hit(r, &r->tris[i], cx, cy, &z, &gz) == MISS) continue;
        /* Where two surfaces cross, the line where they swap moves with
         * snapping like an edge: the tie widens by the margin times both
         * depth slopes. */
        if (z > front + DEPTH_TIE + DIFF_REF_EDGE_MARGIN * (gz + front_gz)) continue;
        tri_interval(r, &r->tris[i], cx, cy, &iv);
        out.covered = 1;
    }
    out.background_ok = isinf(front);
    for (int c = 0; c < 3; c++) out.lo[c] = iv.lo[c], out.hi[c] = iv.hi[c];
    return out;
}

int diff_ref_front(const diff_ref *r, int x, int y, diff_ref_hit *out)
{
    double cx = x + 0.5, cy = y + 0.5;
    double front = INFINITY, front_gz = 0.0;
    const ref_tri *best = NULL;
    const size_t tile = (size_t)(y / TILE) * (size_t)r->tiles_x + (size_t)(x / TILE);
    const uint32_t *list = r->tile_tris + r->tile_start[tile];
    const size_t count = r->tile_start[tile + 1] - r->tile_start[tile];
    for (size_t j = 0; j < count; j++) {
        const ref_tri *t = &r->tris[list[j]];
        double z, gz;
        if (hit(r, t, cx, cy, &z, &gz) == SOLID && z < front) front = z, front_gz = gz, best = t;
    }
    if (!best) return 0;
    /* Any other triangle that diff_ref_eval would also let own the pixel
     * makes it ambiguous. */
    for (size_t j = 0; j < count; j++) {
        const ref_tri *t = &r->tris[list[j]];
        double z, gz;
        if (t == best || hit(r, t, cx, cy, &z, &gz) == MISS) continue;
        if (z > front + DEPTH_TIE + DIFF_REF_EDGE_MARGIN * (gz + front_gz)) continue;
        return 0;
    }
    memset(out, 0, sizeof *out);
    out->object = best->object;
    out->first_index = best->first_index;
    if (!solve(r, best, cx, cy, out->b)) return 0;
    double wx[3], wy[3];
    out->screen_ok = 1;
    for (int k = 0; k < 3; k++) {
        if (!(best->c[k][3] > 0.0)) out->screen_ok = 0;
        wx[k] = (best->c[k][0] / best->c[k][3] + 1.0) * 0.5 * r->width;
        wy[k] = (best->c[k][1] / best->c[k][3] + 1.0) * 0.5 * r->height;
    }
    double area = (wx[1] - wx[0]) * (wy[2] - wy[0]) - (wx[2] - wx[0]) * (wy[1] - wy[0]);
    if (out->screen_ok && area != 0.0) {
        out->screen_b[1] = ((cx - wx[0]) * (wy[2] - wy[0]) - (wx[2] - wx[0]) * (cy - wy[0])) / area;
        out->screen_b[2] = ((wx[1] - wx[0]) * (cy - wy[0]) - (cx - wx[0]) * (wy[1] - wy[0])) / area;
        out->screen_b[0] = 1.0 - out->screen_b[1] - out->screen_b[2];
    } else {
        out->screen_ok = 0;
    }
    return 1;
}
