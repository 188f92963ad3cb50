/*
 * Texturing in object space with filtering in screen space (seed 004).
 *
 * Per polygon: rotate it into a plane parallel to the screen (two rotations,
 * about x by α and about y by β, seed 004 (1)–(7)), choose the mip level once
 * for the polygon, walk texel centres of that level over the polygon, rotate
 * each back and project it to the screen, and splat its colour onto the four
 * pixels around it with the area weights S1..S4; each pixel resolves to
 * Σ S_i·I_i / Σ S_i.
 *
 * Choices the seed leaves open, made here:
 *  - Pixel centres are at +0.5, so the weights are bilinear about centres
 *    (the seed's floor(x) corners shifted by half a pixel).
 *  - Visibility: the screen pipeline's depth test decides which triangle is
 *    visible at each pixel; a splat lands only on pixels where its own
 *    triangle is the visible one (no bleeding across silhouettes).
 *  - Density: the level is chosen so the projected texel spacing is at most
 *    0.75 pixel at the polygon's nearest point (sub-texel steps when even
 *    level 0 is magnified), so no covered pixel is left without samples.
 *    A polygon whose spacing varies by more than 4× over its area (strong
 *    perspective, e.g. the corridor's walls) is split at its edge midpoints,
 *    recursively, so "one level per polygon" holds per piece.
 *  - Accumulation uses 64-bit integer sums with atomic adds, so the result is
 *    the same for any order of polygons and any number of threads.
 */
#include "core/internal.h"
#include "core/pool.h"
#include "raster/frame.h"
#include "shade/shade.h"

#include <math.h>
#include <stdatomic.h>
#include <string.h>

#define MAX_SPLIT_DEPTH 10
#define SPACING_TARGET 0.75  /* pixels between neighbouring samples, at most */
#define SPLIT_RATIO 4.0      /* largest spacing ratio over one polygon */
#define MARGIN_PX 1.5        /* walk this far outside the polygon's edges */
#define WEIGHT_ONE 4096.0    /* fixed-point scale of the weights S_i */

typedef struct accum {
    _Atomic uint64_t w, r, g, b, a;
} accum;

typedef struct job {
    persp_frame *f;
    const persp_capture *cap;
    accum *acc;
    persp_mat4 proj;
    _Atomic uint64_t walked, splats, splits;
} job;

/* A polygon piece in eye space with its texture coordinates. */
typedef struct piece {
    double p[3][3];
    double uv[3][2];
} piece;

/* Window position of eye-space point e; returns 0 behind the eye. */
static int project(const persp_mat4 *P, int W, int H, const double e[3], double out[2])
{
    const float *m = P->m;
    double cx = m[0] * e[0] + m[4] * e[1] + m[8] * e[2] + m[12];
    double cy = m[1] * e[0] + m[5] * e[1] + m[9] * e[2] + m[13];
    double cw = m[3] * e[0] + m[7] * e[1] + m[11] * e[2] + m[15];
    if (!(cw > 1e-9)) return 0;
    out[0] = (cx / cw + 1.0) * 0.5 * W;
    out[1] = (cy / cw + 1.0) * 0.5 * H;
    return 1;
}

/* Rotation of seed 004 that makes the polygon parallel to the xy plane.
 * With the unit normal N and d = sqrt(Ny² + Nz²):
 *   cos α = Nz/d, sin α = Ny/d (about x), cos β = d, sin β = Nx (about y),
 * and in row-vector form p' = p·[Rxy] (seed (6)):
 *   x' = x cos β − y sin α sin β − z cos α sin β
 *   y' = y cos α − z sin α
 *   z' = x sin β + y cos β sin α + z cos α cos β = x·Nx + y·Ny + z·Nz  (seed (7)).
 * Errata: the printed d = sqrt(Ny² − Nz²) must be a sum; (7)'s second line
 * prints sin α = Nz/d for Ny/d; [Ry]'s last diagonal entry must be 1. */
typedef struct rotation {
    double ca, sa, cb, sb, nx, ny, nz;
} rotation;

static int make_rotation(const double n_in[3], rotation *r)
{
    double l = sqrt(n_in[0] * n_in[0] + n_in[1] * n_in[1] + n_in[2] * n_in[2]);
    if (!(l > 0.0)) return 0;
    r->nx = n_in[0] / l, r->ny = n_in[1] / l, r->nz = n_in[2] / l;
    double d = sqrt(r->ny * r->ny + r->nz * r->nz);
    if (d > 1e-12) {
        r->ca = r->nz / d, r->sa = r->ny / d;
    } else {
        r->ca = 1.0, r->sa = 0.0; /* normal along x: no rotation about x needed */
    }
    r->cb = d, r->sb = r->nx;
    return 1;
}

static void rotate(const rotation *r, const double p[3], double o[3])
{
    o[0] = p[0] * r->cb - p[1] * r->sa * r->sb - p[2] * r->ca * r->sb;
    o[1] = p[1] * r->ca - p[2] * r->sa;
    o[2] = p[0] * r->nx + p[1] * r->ny + p[2] * r->nz;
}

/* Inverse rotation: the transpose (seed 004, [Rxy]^-1 = [Ry]^-1 Rx^-1). */
static void rotate_back(const rotation *r, const double p[3], double o[3])
{
    o[0] = p[0] * r->cb + p[2] * r->sb;
    o[1] = -p[0] * r->sa * r->sb + p[1] * r->ca + p[2] * r->cb * r->sa;
    o[2] = -p[0] * r->ca * r->sb - p[1] * r->sa + p[2] * r->ca * r->cb;
}

/* Pixels per level-0 texel at uv corner k: length of the projected texel
 * steps along u and v. */
static double spacing_at(const piece *pc, int k, const persp_mat4 *P, int W, int H, double tw,
                         double th)
{
    /* Eye position as an affine function of uv over the piece. */
    double du1 = pc->uv[1][0] - pc->uv[0][0], dv1 = pc->uv[1][1] - pc->uv[0][1];
    double du2 = pc->uv[2][0] - pc->uv[0][0], dv2 = pc->uv[2][1] - pc->uv[0][1];
    double det = du1 * dv2 - du2 * dv1;
    if (fabs(det) < 1e-300) return INFINITY;
    double dpdu[3], dpdv[3];
    for (int c = 0; c < 3; c++) {
        double e1 = pc->p[1][c] - pc->p[0][c], e2 = pc->p[2][c] - pc->p[0][c];
        dpdu[c] = (e1 * dv2 - e2 * dv1) / det;
        dpdv[c] = (e2 * du1 - e1 * du2) / det;
    }
    double a[2], b[2], c2[2], e[3];
    if (!project(P, W, H, pc->p[k], a)) return INFINITY;
    for (int c = 0; c < 3; c++) e[c] = pc->p[k][c] + dpdu[c] / tw;
    if (!project(P, W, H, e, b)) return INFINITY;
    for (int c = 0; c < 3; c++) e[c] = pc->p[k][c] + dpdv[c] / th;
    if (!project(P, W, H, e, c2)) return INFINITY;
    double su = hypot(b[0] - a[0], b[1] - a[1]), sv = hypot(c2[0] - a[0], c2[1] - a[1]);
    return su > sv ? su : sv;
}

static void splat(job *j, int tri_index, double x, double y, const uint8_t rgba[4])
{
    const persp_capture *cap = j->cap;
    const int W = cap->width, H = cap->height;
    double fx = x - 0.5, fy = y - 0.5;
    double ix = floor(fx), iy = floor(fy);
    double tx = fx - ix, ty = fy - iy;
    const double w4[4] = {(1 - tx) * (1 - ty), tx * (1 - ty), (1 - tx) * ty, tx * ty};
    const int ox[4] = {0, 1, 0, 1}, oy[4] = {0, 0, 1, 1};
    uint64_t n = 0;
    for (int k = 0; k < 4; k++) {
        double px = ix + ox[k], py = iy + oy[k];
        if (px < 0 || py < 0 || px >= W || py >= H) continue;
        size_t idx = (size_t)py * (size_t)W + (size_t)px;
        if (cap->tri[idx] != tri_index) continue;
        uint64_t wq = (uint64_t)(w4[k] * WEIGHT_ONE + 0.5);
        if (!wq) continue;
        accum *a = &j->acc[idx];
        atomic_fetch_add_explicit(&a->w, wq, memory_order_relaxed);
        atomic_fetch_add_explicit(&a->r, wq * rgba[0], memory_order_relaxed);
        atomic_fetch_add_explicit(&a->g, wq * rgba[1], memory_order_relaxed);
        atomic_fetch_add_explicit(&a->b, wq * rgba[2], memory_order_relaxed);
        atomic_fetch_add_explicit(&a->a, wq * rgba[3], memory_order_relaxed);
        n++;
    }
    if (n) atomic_fetch_add_explicit(&j->splats, n, memory_order_relaxed);
}

static void walk_piece(job *j, int tri_index, const persp_draw_state *ds, const piece *pc, int depth)
{
    const persp_texture *tex = ds->tex;
    const int W = j->cap->width, H = j->cap->height;
    const double tw = tex->width, th = tex->height;
    double smax = 0.0, smin = INFINITY;
    for (int k = 0; k < 3; k++) {
        double s = spacing_at(pc, k, &j->proj, W, H, tw, th);
        if (s > smax) smax = s;
        if (s < smin) smin = s;
    }
    if (!isfinite(smax) || !(smin > 0.0)) return;
    if (smax > SPLIT_RATIO * smin && depth < MAX_SPLIT_DEPTH) {
        /* Split at the edge midpoints into four pieces. */
        piece m;
        for (int k = 0; k < 3; k++) {
            int l = (k + 1) % 3;
            for (int c = 0; c < 3; c++) m.p[k][c] = 0.5 * (pc->p[k][c] + pc->p[l][c]);
            for (int c = 0; c < 2; c++) m.uv[k][c] = 0.5 * (pc->uv[k][c] + pc->uv[l][c]);
        }
        atomic_fetch_add_explicit(&j->splits, 1, memory_order_relaxed);
        for (int k = 0; k < 3; k++) {
            piece s;
            int prev = (k + 2) % 3;
            memcpy(s.p[0], pc->p[k], sizeof s.p[0]);
            memcpy(s.uv[0], pc->uv[k], sizeof s.uv[0]);
            memcpy(s.p[1], m.p[k], sizeof s.p[1]);
            memcpy(s.uv[1], m.uv[k], sizeof s.uv[1]);
            memcpy(s.p[2], m.p[prev], sizeof s.p[2]);
            memcpy(s.uv[2], m.uv[prev], sizeof s.uv[2]);
            walk_piece(j, tri_index, ds, &s, depth + 1);
        }
        walk_piece(j, tri_index, ds, &m, depth + 1);
        return;
    }
    /* One level for the whole piece (seed 004: "LOD once per polygon"). */
    int level = 0;
    if (smax < SPACING_TARGET) level = (int)floor(log2(SPACING_TARGET / smax));
    if (level > tex->levels - 1) level = tex->levels - 1;
    double spacing = smax * ldexp(1.0, level);
    int sub = spacing > SPACING_TARGET ? (int)ceil(spacing / SPACING_TARGET) : 1;
    if (sub > 64) sub = 64;
    const double lw = tex->level[level].w, lh = tex->level[level].h;
    const double step_u = 1.0 / (lw * sub), step_v = 1.0 / (lh * sub);

    /* The rotation into a screen-parallel plane and the affine map from uv
     * to the rotated plane's (x', y'). */
    double e1[3], e2[3], n[3];
    for (int c = 0; c < 3; c++) e1[c] = pc->p[1][c] - pc->p[0][c], e2[c] = pc->p[2][c] - pc->p[0][c];
    n[0] = e1[1] * e2[2] - e1[2] * e2[1];
    n[1] = e1[2] * e2[0] - e1[0] * e2[2];
    n[2] = e1[0] * e2[1] - e1[1] * e2[0];
    rotation rot;
    if (!make_rotation(n, &rot)) return;
    double r[3][3];
    for (int k = 0; k < 3; k++) rotate(&rot, pc->p[k], r[k]);
    const double zc = r[0][2]; /* equal for all three: the plane is now z' = zc */
    double du1 = pc->uv[1][0] - pc->uv[0][0], dv1 = pc->uv[1][1] - pc->uv[0][1];
    double du2 = pc->uv[2][0] - pc->uv[0][0], dv2 = pc->uv[2][1] - pc->uv[0][1];
    double det = du1 * dv2 - du2 * dv1;
    if (fabs(det) < 1e-300) return;
    double dxdu = ((r[1][0] - r[0][0]) * dv2 - (r[2][0] - r[0][0]) * dv1) / det;
    double dxdv = ((r[2][0] - r[0][0]) * du1 - (r[1][0] - r[0][0]) * du2) / det;
    double dydu = ((r[1][1] - r[0][1]) * dv2 - (r[2][1] - r[0][1]) * dv1) / det;
    double dydv = ((r[2][1] - r[0][1]) * du1 - (r[1][1] - r[0][1]) * du2) / det;

    /* Barycentrics in uv, with the walk extended MARGIN_PX beyond each edge
     * (converted to barycentric units with the piece's smallest spacing). */
    double margin_uv = MARGIN_PX / (smin * (tw > th ? tw : th));
    double umin = INFINITY, umax = -INFINITY, vmin = INFINITY, vmax = -INFINITY;
    for (int k = 0; k < 3; k++) {
        umin = fmin(umin, pc->uv[k][0]), umax = fmax(umax, pc->uv[k][0]);
        vmin = fmin(vmin, pc->uv[k][1]), vmax = fmax(vmax, pc->uv[k][1]);
    }
    double el[3];
    for (int k = 0; k < 3; k++) {
        int a = (k + 1) % 3, b = (k + 2) % 3;
        el[k] = hypot(pc->uv[b][0] - pc->uv[a][0], pc->uv[b][1] - pc->uv[a][1]);
    }
    double eps[3];
    for (int k = 0; k < 3; k++) eps[k] = el[k] > 0 ? margin_uv * el[k] / fabs(det) : 0.0;
    umin -= margin_uv, umax += margin_uv, vmin -= margin_uv, vmax += margin_uv;
    /* Sample positions on the level's texel-centre grid (sub-steps if magnified). */
    double u0 = (floor(umin / step_u - 0.5) + 0.5) * step_u;
    double v0 = (floor(vmin / step_v - 0.5) + 0.5) * step_v;
    long nu = (long)ceil((umax - u0) / step_u) + 1, nv = (long)ceil((vmax - v0) / step_v) + 1;
    if (nu <= 0 || nv <= 0 || (double)nu * (double)nv > 1e8) return;

    persp_sampler_desc sd = ds->sampler.desc;
    sd.filter = sub > 1 ? PERSP_FILTER_BILINEAR_MIP_NEAREST : PERSP_FILTER_NEAREST_MIP_NEAREST;
    sd.min_lod = sd.max_lod = (float)level;
    sd.lod_bias = 0.0f;
    sd.lod_mode = PERSP_LOD_PIXEL;
    /* Derivatives that select exactly `level`. */
    const float dsel = (float)(ldexp(1.0, level) / tw);
    uint64_t walked = 0;
    for (long jv = 0; jv < nv; jv++) {
        double v = v0 + (double)jv * step_v;
        for (long iu = 0; iu < nu; iu++) {
            double u = u0 + (double)iu * step_u;
            double pu = u - pc->uv[0][0], pv = v - pc->uv[0][1];
            double b1 = (pu * dv2 - du2 * pv) / det, b2 = (du1 * pv - pu * dv1) / det;
            double b0 = 1.0 - b1 - b2;
            if (b0 < -eps[0] || b1 < -eps[1] || b2 < -eps[2]) continue;
            double rp[3] = {r[0][0] + dxdu * pu + dxdv * pv, r[0][1] + dydu * pu + dydv * pv, zc};
            double ep[3], win[2];
            rotate_back(&rot, rp, ep);
            if (!project(&j->proj, W, H, ep, win)) continue;
            uint8_t rgba[4];
            persp_texture_sample(tex, &sd, (float)u, (float)v, dsel, 0.0f, 0.0f, dsel, rgba);
            splat(j, tri_index, win[0], win[1], rgba);
            walked++;
        }
    }
    atomic_fetch_add_explicit(&j->walked, walked, memory_order_relaxed);
}

/* The object-space pipeline produces texture colour; it applies to
 * textured, unlit ("replace") draws and leaves lit ones to the screen
 * pipeline. */
static int objspace_applies(const persp_draw_state *ds)
{
    return ds->tex && ds->shading == PERSP_SHADING_NONE;
}

static void walk_task(void *user, int task, int worker)
{
    (void)worker;
    job *j = user;
    const persp_tri *t = &persp__frame_tris(j->f)[task];
    const persp_draw_state *ds = persp__frame_state(j->f, t->state);
    if (!objspace_applies(ds)) return;
    piece pc;
    for (int k = 0; k < 3; k++) {
        for (int c = 0; c < 3; c++) pc.p[k][c] = t->vattr[k][PERSP_A_EX + c];
        pc.uv[k][0] = t->vattr[k][PERSP_A_U];
        pc.uv[k][1] = t->vattr[k][PERSP_A_V];
    }
    walk_piece(j, task, ds, &pc, 0);
}

persp_status persp__objspace_resolve(persp_frame *f, const persp_capture *cap,
                                     persp_objspace_stats *stats)
{
    persp_context *ctx = f->ctx;
    const size_t n = (size_t)cap->width * (size_t)cap->height;
    job *j = persp__calloc(ctx, 1, sizeof *j);
    accum *acc = persp__calloc(ctx, n, sizeof *acc);
    if (!j || !acc) {
        persp_free(ctx, j);
        persp_free(ctx, acc);
        return persp_context_fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "object-space pipeline: out of memory");
    }
    j->f = f;
    j->cap = cap;
    j->acc = acc;
    j->proj = f->proj;
    persp_status st = persp__pool_run(ctx, (int)f->tri_count, walk_task, j);
    uint64_t holes = 0;
    if (st == PERSP_OK) {
        uint32_t *color = (uint32_t *)(void *)f->fb->color;
        const persp_tri *tris = persp__frame_tris(f);
        for (size_t i = 0; i < n; i++) {
            int32_t t = cap->tri[i];
            if (t < 0 || !objspace_applies(persp__frame_state(f, tris[t].state))) continue;
            uint64_t w = atomic_load_explicit(&acc[i].w, memory_order_relaxed);
            if (!w) {
                holes++; /* keeps the screen pipeline's colour */
                continue;
            }
            uint64_t h = w / 2;
            uint32_t r = (uint32_t)((acc[i].r + h) / w), g = (uint32_t)((acc[i].g + h) / w);
            uint32_t b = (uint32_t)((acc[i].b + h) / w), a = (uint32_t)((acc[i].a + h) / w);
            color[i] = r | g << 8 | b << 16 | a << 24;
        }
    }
    if (stats) {
        stats->splats = j->splats;
        stats->texels_walked = j->walked;
        stats->triangles_split = j->splits;
        stats->holes = holes;
    }
    persp_free(ctx, acc);
    persp_free(ctx, j);
    return st;
}
