/*
 * Texturing in object space with filtering in screen space ([Romaniuk-ObjSpace]).
 *
 * Per polygon: rotate it into a plane parallel to the screen (two rotations,
 * about x by α and about y by β, [Romaniuk-ObjSpace] (1)–(7)), choose the mip level once
 * for the polygon, walk texel centres of that level over the polygon, rotate
 * each back and project it to the screen, and splat its colour onto the four
 * pixels around it with the area weights S1..S4; each pixel resolves to
 * Σ S_i·I_i / Σ S_i.
 *
 * The paper forms the rotation back and the projection as one matrix per
 * polygon, [P·R_xy⁻¹] ([Romaniuk-ObjSpace], after (7)); the texel walk adds the affine
 * map from texel indices to the rotated plane, so each texel costs one 3×3
 * projective map: three affine rows and one division.
 *
 * Choices the paper leaves open, made here (docs/TEXTURES.md):
 *  - Pixel centres are at +0.5, so the weights are bilinear about centres
 *    (the paper's floor(x) corners shifted by half a pixel).
 *  - Visibility: the screen pipeline's depth test decides which triangle is
 *    visible at each pixel; a splat lands only on pixels where its own
 *    triangle is the visible one (no bleeding across silhouettes).
 *  - Density: the level is chosen so that the projected texel spacing is at
 *    most 0.75 pixel everywhere on the piece (sub-texel steps, reconstructed
 *    by the sampler's in-level filter, when even level 0 is magnified), so
 *    no covered pixel is left without samples.
 *  - Pieces: under strong perspective one level cannot serve a whole polygon
 *    (the corridor's walls span depths 0.1 to 64: a level fine enough for the
 *    near end walks hundreds of texels per pixel at the far end). Each
 *    polygon is therefore cut by the planes of constant eye depth
 *    w = 2^(k/2) into slabs whose depth ratio is at most √2, and the level is
 *    chosen once per slab ("once per polygon" holds per piece); the slab
 *    planes do not depend on the polygon, so neighbouring polygons change
 *    level at the same depths. Pieces are also clipped to the viewport.
 *  - The walk extends MARGIN_PX pixels beyond the triangle's screen edges
 *    (the surface continued), so edge pixels get samples on both sides.
 *  - Bounded work (docs/RELIABILITY.md): the rows walked are those of the
 *    walk region itself, per piece and per tile; the last slab ends at
 *    twice the triangle's farthest depth; the top level is walked with a
 *    stride that keeps the density target; and a frame whose estimated
 *    walk exceeds OS_MAX_WORK is refused before walking.
 *  - Parallelism: the screen is cut into 64×64 tiles, each resolved by one
 *    task that walks, in a fixed order, the samples of every piece that can
 *    reach its pixels. A sample's membership in a piece is decided by the
 *    same arithmetic in every tile, so the image is identical for any number
 *    of threads.
 */
#include "core/internal.h"
#include "core/pool.h"
#include "objspace/objspace.h"
#include "shade/shade.h"
#include "texture/sample.h"

#include <math.h>
#include <string.h>

#define OS_TILE 64
#define SPACING_TARGET 0.75 /* pixels between neighbouring samples, at most */
#define MARGIN_PX 1.5       /* walk this far outside the triangle's screen edges */
#define MAX_SUB 64          /* sub-texel steps per texel when level 0 is magnified */
#define SLAB_STEPS 2        /* slab planes at w = 2^(k / SLAB_STEPS) */
#define MAX_SLABS 96
#define MAX_PLANES 12
#define MAX_POLY 24
#define MAX_INDEX 2.0e9 /* sample indices stay within int */
/* Samples and rows one frame may walk: about 25 s on one core of the
 * machine docs/RELIABILITY.md measures on. */
#define OS_MAX_WORK 5.0e8

/* A half-plane A·i + B·j + C >= 0 in sample-index space. */
typedef struct hplane {
    double a, b, c;
} hplane;

/* A 3×3 projective map. */
typedef struct map3 {
    double m[3][3];
} map3;

typedef struct os_piece {
    int tri;
    int level, sub, nearest, stride;
    map3 H;               /* (i, j, 1) -> (X·w, Y·w, w), window coordinates */
    hplane pl[MAX_PLANES]; /* inside: all >= 0 */
    int planes;
    int j0, j1;            /* sample rows to visit */
    double bx0, by0, bx1, by1; /* window bounding box (reach included) */
    double work;           /* samples and rows in the walk region */
} os_piece;

typedef struct os_job {
    persp_frame *f;
    const persp_capture *cap;
    const os_piece *pieces;
    size_t piece_count;
    float *acc;            /* per worker: OS_TILE² × 5 */
    int tiles_x, tiles_y;
    uint64_t *walked, *splats, *holes, *visited; /* per tile */
} os_job;

/* ---------------------------------------------------------- [Romaniuk-ObjSpace] maths */

/* Rotation of [Romaniuk-ObjSpace] that makes the polygon parallel to the xy plane.
 * With the unit normal N and d = sqrt(Ny² + Nz²):
 *   cos α = Nz/d, sin α = Ny/d (about x), cos β = d, sin β = Nx (about y),
 * and in row-vector form p' = p·[Rxy] ([Romaniuk-ObjSpace] (6)):
 *   x' = x cos β − y sin α sin β − z cos α sin β
 *   y' = y cos α − z sin α
 *   z' = x sin β + y cos β sin α + z cos α cos β = x·Nx + y·Ny + z·Nz
 *   ([Romaniuk-ObjSpace] (7)).
 * Errata (docs/REPRODUCTION.md): the printed d = sqrt(Ny² − Nz²) must be a
 * sum; (7)'s second line prints sin α = Nz/d for Ny/d; [Ry]'s last diagonal
 * entry must be 1. */
typedef struct rotation {
    double ca, sa, cb, sb, nx, ny, nz;
} rotation;

static int make_rotation(const double n_in[3], rotation *r)
{
    double l = sqrt(n_in[0] * n_in[0] + n_in[1] * n_in[1] + n_in[2] * n_in[2]);
    if (!(l > 0.0) || !isfinite(l)) return 0;
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

/* The inverse rotation [Rxy]⁻¹ = [Ry]⁻¹·Rx⁻¹ (the transpose) as a matrix
 * acting on column vectors: eye = Rinv · rotated. */
static void rotation_inverse(const rotation *r, double m[3][3])
{
    m[0][0] = r->cb, m[0][1] = 0.0, m[0][2] = r->sb;
    m[1][0] = -r->sa * r->sb, m[1][1] = r->ca, m[1][2] = r->cb * r->sa;
    m[2][0] = -r->ca * r->sb, m[2][1] = -r->sa, m[2][2] = r->ca * r->cb;
}

/* ------------------------------------------------------------- geometry */

static inline double hp_eval(const hplane *p, double x, double y)
{
    return p->a * x + p->b * y + p->c;
}

/* Sutherland–Hodgman clip of a convex polygon (x, y pairs) by one
 * half-plane; returns the new vertex count. */
static int clip_poly(const double *in, int n, const hplane *p, double *out)
{
    int m = 0;
    for (int k = 0; k < n; k++) {
        const double *a = in + 2 * k, *b = in + 2 * ((k + 1) % n);
        double da = hp_eval(p, a[0], a[1]), db = hp_eval(p, b[0], b[1]);
        if (da >= 0.0 && m < MAX_POLY) {
            out[2 * m] = a[0], out[2 * m + 1] = a[1];
            m++;
        }
        if ((da >= 0.0) != (db >= 0.0) && m < MAX_POLY) {
            double t = da / (da - db);
            out[2 * m] = a[0] + t * (b[0] - a[0]);
            out[2 * m + 1] = a[1] + t * (b[1] - a[1]);
            m++;
        }
    }
    return m;
}

/* Rows [j0, j1] of the convex region inside every plane of pl (and of
 * extra): a box of all usable sample indices clipped by them. Returns 0 when
 * the region is empty or reaches the box (unbounded: not walked). */
static int region_rows(const hplane *pl, int np, const hplane *extra, int ne, double *j0, double *j1,
                       double *area)
{
    double a[2 * MAX_POLY], b[2 * MAX_POLY];
    const double B = MAX_INDEX;
    double box[8] = {-B, -B, B, -B, B, B, -B, B};
    memcpy(a, box, sizeof box);
    int n = 4;
    for (int k = 0; k < np + ne && n > 0; k++) {
        n = clip_poly(a, n, k < np ? &pl[k] : &extra[k - np], b);
        memcpy(a, b, sizeof(double) * 2 * (size_t)n);
    }
    if (n < 1) return 0;
    double lo = INFINITY, hi = -INFINITY, twice = 0.0;
    for (int k = 0; k < n; k++) {
        if (!(fabs(a[2 * k]) < B && fabs(a[2 * k + 1]) < B)) return 0;
        const double *p = a + 2 * k, *q = a + 2 * ((k + 1) % n);
        twice += p[0] * q[1] - p[1] * q[0];
        if (a[2 * k + 1] < lo) lo = a[2 * k + 1];
        if (a[2 * k + 1] > hi) hi = a[2 * k + 1];
    }
    /* One row either side absorbs the clip's rounding; the walk tests each
     * row exactly (row_interval). */
    *j0 = floor(lo) - 1.0, *j1 = ceil(hi) + 1.0;
    if (area) *area = 0.5 * fabs(twice);
    return 1;
}

/* Half-plane of the homogeneous window-space plane (ax, ay, aw)·(X·w, Y·w, w)
 * + c·1 >= 0 pulled back through H (rows map (x, y, 1) to X·w, Y·w, w). */
static hplane pull_back(const map3 *M, double ax, double ay, double aw, double c)
{
    const double (*H)[3] = M->m;
    hplane p;
    p.a = ax * H[0][0] + ay * H[1][0] + aw * H[2][0];
    p.b = ax * H[0][1] + ay * H[1][1] + aw * H[2][1];
    p.c = ax * H[0][2] + ay * H[1][2] + aw * H[2][2] + c;
    return p;
}

/* Window position and the two column lengths of the map's Jacobian (pixels
 * per unit step of x and of y) at (x, y). Returns 0 behind the eye. */
static int map_at(const map3 *M, double x, double y, double win[2], double *sx, double *sy)
{
    const double (*H)[3] = M->m;
    double w = H[2][0] * x + H[2][1] * y + H[2][2];
    if (!(w > 0.0)) return 0;
    double X = (H[0][0] * x + H[0][1] * y + H[0][2]) / w;
    double Y = (H[1][0] * x + H[1][1] * y + H[1][2]) / w;
    win[0] = X, win[1] = Y;
    double jxx = (H[0][0] - X * H[2][0]) / w, jyx = (H[1][0] - Y * H[2][0]) / w;
    double jxy = (H[0][1] - X * H[2][1]) / w, jyy = (H[1][1] - Y * H[2][1]) / w;
    *sx = hypot(jxx, jyx);
    *sy = hypot(jxy, jyy);
    return 1;
}

/* ------------------------------------------------------- piece building */

typedef struct tri_setup {
    map3 Huv;           /* (u, v, 1) -> window homogeneous */
    hplane edge[3];     /* in uv, offset by MARGIN_PX in window space */
    hplane view[4];     /* viewport plus reach, in uv */
    double uv[3][2];
    double wmin, wmax;  /* clip w over the (visible) triangle */
} tri_setup;

/* The paper's composed map for one triangle: uv -> rotated plane (affine)
 * -> eye ([Rxy]⁻¹) -> clip (P) -> window (viewport), as one 3×3 matrix. */
static int triangle_setup(const persp_frame *f, int W, int H, const persp_tri *t, tri_setup *ts)
{
    double p[3][3];
    for (int k = 0; k < 3; k++) {
        for (int c = 0; c < 3; c++) p[k][c] = t->vattr[k][PERSP_A_EX + c];
        ts->uv[k][0] = t->vattr[k][PERSP_A_U];
        ts->uv[k][1] = t->vattr[k][PERSP_A_V];
    }
    double e1[3], e2[3], n[3];
    for (int c = 0; c < 3; c++) e1[c] = p[1][c] - p[0][c], e2[c] = p[2][c] - p[0][c];
    n[0] = e1[1] * e2[2] - e1[2] * e2[1];
    n[1] = e1[2] * e2[0] - e1[0] * e2[2];
    n[2] = e1[0] * e2[1] - e1[1] * e2[0];
    rotation rot;
    if (!make_rotation(n, &rot)) return 0;
    double r[3][3];
    for (int k = 0; k < 3; k++) rotate(&rot, p[k], r[k]);
    const double zc = r[0][2]; /* the plane is now z' = zc (the paper: one vertex suffices) */
    double du1 = ts->uv[1][0] - ts->uv[0][0], dv1 = ts->uv[1][1] - ts->uv[0][1];
    double du2 = ts->uv[2][0] - ts->uv[0][0], dv2 = ts->uv[2][1] - ts->uv[0][1];
    double det = du1 * dv2 - du2 * dv1;
    if (!(fabs(det) > 1e-300)) return 0;
    /* Affine uv -> (x', y', zc). */
    double A[3][3];
    for (int c = 0; c < 2; c++) {
        double a1 = r[1][c] - r[0][c], a2 = r[2][c] - r[0][c];
        A[c][0] = (a1 * dv2 - a2 * dv1) / det;
        A[c][1] = (a2 * du1 - a1 * du2) / det;
        A[c][2] = r[0][c] - A[c][0] * ts->uv[0][0] - A[c][1] * ts->uv[0][1];
    }
    A[2][0] = 0.0, A[2][1] = 0.0, A[2][2] = zc;
    double Ri[3][3], E[3][3]; /* E: (u, v, 1) -> eye */
    rotation_inverse(&rot, Ri);
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++) E[a][b] = Ri[a][0] * A[0][b] + Ri[a][1] * A[1][b] + Ri[a][2] * A[2][b];
    /* Window rows: X·w = W/2·(x_c + w_c), Y·w = H/2·(y_c + w_c), w = w_c. */
    const float *m = f->proj.m;
    double P[3][4];
    for (int c = 0; c < 4; c++) {
        P[0][c] = 0.5 * W * ((double)m[c * 4 + 0] + (double)m[c * 4 + 3]);
        P[1][c] = 0.5 * H * ((double)m[c * 4 + 1] + (double)m[c * 4 + 3]);
        P[2][c] = (double)m[c * 4 + 3];
    }
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++) {
            ts->Huv.m[a][b] = P[a][0] * E[0][b] + P[a][1] * E[1][b] + P[a][2] * E[2][b] +
                            (b == 2 ? P[a][3] : 0.0);
        }
    /* Screen edges of the triangle, offset outwards by MARGIN_PX. */
    double win[3][2];
    for (int k = 0; k < 3; k++) {
        double w = ts->Huv.m[2][0] * ts->uv[k][0] + ts->Huv.m[2][1] * ts->uv[k][1] + ts->Huv.m[2][2];
        if (!(w > 0.0)) return 0;
        for (int c = 0; c < 2; c++)
            win[k][c] = (ts->Huv.m[c][0] * ts->uv[k][0] + ts->Huv.m[c][1] * ts->uv[k][1] + ts->Huv.m[c][2]) / w;
        if (k == 0 || w < ts->wmin) ts->wmin = w;
        if (k == 0 || w > ts->wmax) ts->wmax = w;
    }
    double area = (win[1][0] - win[0][0]) * (win[2][1] - win[0][1]) -
                  (win[2][0] - win[0][0]) * (win[1][1] - win[0][1]);
    if (!(fabs(area) > 0.0)) return 0;
    double sgn = area > 0.0 ? 1.0 : -1.0;
    for (int k = 0; k < 3; k++) {
        const double *a = win[(k + 1) % 3], *b = win[(k + 2) % 3];
        double nx = -(b[1] - a[1]) * sgn, ny = (b[0] - a[0]) * sgn; /* inward normal */
        double len = hypot(nx, ny);
        if (!(len > 0.0)) return 0;
        nx /= len, ny /= len;
        double c = -(nx * a[0] + ny * a[1]) + MARGIN_PX;
        ts->edge[k] = pull_back(&ts->Huv, nx, ny, c, 0.0);
    }
    /* Viewport plus the splat reach (pixel centres within one pixel). */
    const double reach = 1.0 + MARGIN_PX;
    ts->view[0] = pull_back(&ts->Huv, 1.0, 0.0, reach, 0.0);               /* X >= -reach */
    ts->view[1] = pull_back(&ts->Huv, -1.0, 0.0, (double)W + reach, 0.0);  /* X <= W + reach */
    ts->view[2] = pull_back(&ts->Huv, 0.0, 1.0, reach, 0.0);
    ts->view[3] = pull_back(&ts->Huv, 0.0, -1.0, (double)H + reach, 0.0);
    return 1;
}

/* The piece's walk planes in uv: the triangle's edges (with the margin),
 * the viewport with the splat reach and the slab wlo <= w <= whi; returns
 * their number. */
static int piece_planes(const tri_setup *ts, double wlo, double whi, hplane uvp[MAX_PLANES])
{
    int np = 0;
    for (int k = 0; k < 3; k++) uvp[np++] = ts->edge[k];
    for (int k = 0; k < 4; k++) uvp[np++] = ts->view[k];
    uvp[np++] = pull_back(&ts->Huv, 0.0, 0.0, 1.0, -wlo); /* w >= wlo */
    uvp[np++] = pull_back(&ts->Huv, 0.0, 0.0, -1.0, whi); /* w <= whi */
    return np;
}

/* The piece's polygon in uv, for the level choice: the triangle itself (no
 * margin) cut by the slab and the viewport (uvp[3..np), the planes after
 * the edges); returns its vertex count. */
static int piece_polygon(const tri_setup *ts, const hplane *uvp, int np, double poly[2 * MAX_POLY])
{
    double tmp[2 * MAX_POLY];
    int n = 3;
    for (int k = 0; k < 3; k++) poly[2 * k] = ts->uv[k][0], poly[2 * k + 1] = ts->uv[k][1];
    for (int k = 3; k < np && n > 0; k++) {
        n = clip_poly(poly, n, &uvp[k], tmp);
        memcpy(poly, tmp, sizeof(double) * 2 * (size_t)n);
    }
    return n;
}

/* The largest projected level-0 texel step *smax over the polygon's
 * vertices and centroid, and their window bounding box (box: x0, y0, x1,
 * y1); 0 when a vertex does not map or the step is not a positive number. */
static int piece_footprint(const tri_setup *ts, const persp_texture *tex, const double *poly, int n,
                           double *smax_out, double box[4])
{
    double tw = tex->width, th = tex->height;
    double smax = 0.0, bx0 = INFINITY, by0 = INFINITY, bx1 = -INFINITY, by1 = -INFINITY;
    double cu = 0.0, cv = 0.0;
    for (int k = 0; k <= n; k++) {
        double u, v;
        if (k < n) {
            u = poly[2 * k], v = poly[2 * k + 1];
            cu += u / n, cv += v / n;
        } else {
            u = cu, v = cv; /* and the centroid */
        }
        double win[2], su, sv;
        if (!map_at(&ts->Huv, u, v, win, &su, &sv)) return 0;
        su /= tw, sv /= th;
        double s = su > sv ? su : sv;
        if (s > smax) smax = s;
        if (win[0] < bx0) bx0 = win[0];
        if (win[0] > bx1) bx1 = win[0];
        if (win[1] < by0) by0 = win[1];
        if (win[1] > by1) by1 = win[1];
    }
    if (!(smax > 0.0) || !isfinite(smax)) return 0;
    *smax_out = smax;
    box[0] = bx0, box[1] = by0, box[2] = bx1, box[3] = by1;
    return 1;
}

/* One level for the piece ([Romaniuk-ObjSpace]: "LOD once per polygon"):
 * the coarsest whose projected texel step stays within SPACING_TARGET (at
 * most the top), with sub samples a texel where even level 0's step
 * exceeds it; *spacing: the chosen level's step. */
static void piece_level(const persp_texture *tex, double smax, int *level_out, int *sub_out,
                        double *spacing_out)
{
    int top = tex->levels - 1, level = 0;
    if (smax < SPACING_TARGET) level = (int)floor(log2(SPACING_TARGET / smax));
    if (level > top) level = top;
    double spacing = smax * ldexp(1.0, level);
    int sub = 1;
    if (spacing > SPACING_TARGET) {
        double s = ceil(spacing / SPACING_TARGET);
        sub = s > MAX_SUB ? MAX_SUB : (int)s;
    }
    *level_out = level, *sub_out = sub, *spacing_out = spacing;
}

/* Builds the piece of slab [wlo, whi) of a triangle; returns 0 if empty. */
static int make_piece(const tri_setup *ts, const persp_texture *tex, const persp_sampler_state *ss,
                      int tri, double wlo, double whi, os_piece *pc)
{
    hplane uvp[MAX_PLANES];
    const int np = piece_planes(ts, wlo, whi, uvp);
    double poly[2 * MAX_POLY];
    int n = piece_polygon(ts, uvp, np, poly);
    if (n < 3) return 0;
    double smax, box[4], spacing;
    if (!piece_footprint(ts, tex, poly, n, &smax, box)) return 0;
    int level, sub;
    piece_level(tex, smax, &level, &sub, &spacing);
    const int top = tex->levels - 1;
    const double lw = tex->level[level].w, lh = tex->level[level].h;
    const double step_u = 1.0 / (lw * sub), step_v = 1.0 / (lh * sub);
    /* Sample (i, j) sits at u = (i + 1/2)·step_u, v = (j + 1/2)·step_v: the
     * level's texel centres (or sub-texel positions). */
    double S[3][3] = {{step_u, 0.0, 0.5 * step_u}, {0.0, step_v, 0.5 * step_v}, {0.0, 0.0, 1.0}};
    memset(pc, 0, sizeof *pc);
    pc->tri = tri;
    pc->level = level;
    pc->sub = sub;
    pc->nearest = ss->desc.filter == PERSP_FILTER_NEAREST ||
                  ss->desc.filter == PERSP_FILTER_NEAREST_MIP_NEAREST ||
                  ss->desc.filter == PERSP_FILTER_NEAREST_MIP_LINEAR;
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++)
            pc->H.m[a][b] = ts->Huv.m[a][0] * S[0][b] + ts->Huv.m[a][1] * S[1][b] + ts->Huv.m[a][2] * S[2][b];
    for (int k = 0; k < np; k++) {
        hplane q = uvp[k];
        pc->pl[k].a = q.a * step_u;
        pc->pl[k].b = q.b * step_v;
        pc->pl[k].c = q.a * 0.5 * step_u + q.b * 0.5 * step_v + q.c;
    }
    pc->planes = np;
    /* Rows: those of the walk region itself (the planes above), found by
     * clipping a box of every representable sample index, so the rows
     * walked follow the triangle's screen footprint plus the margin. */
    double jlo, jhi, region;
    if (!region_rows(pc->pl, np, NULL, 0, &jlo, &jhi, &region)) return 0;
    pc->j0 = (int)jlo, pc->j1 = (int)jhi;
    const double reach = MARGIN_PX + 2.0;
    pc->bx0 = box[0] - reach, pc->bx1 = box[2] + reach, pc->by0 = box[1] - reach, pc->by1 = box[3] + reach;
    /* At the top of the pyramid the level cannot coarsen with the
     * minification, so its samples may lie far closer than SPACING_TARGET;
     * every sample there has the one texel's colour, so walking every
     * stride-th sample in i and j keeps the density target (stride ×
     * spacing <= SPACING_TARGET) and the image, with work proportional to
     * the piece's pixels rather than to the texture's repeats. */
    pc->stride = 1;
    if (level == top && sub == 1 && spacing > 0.0) {
        double s = floor(SPACING_TARGET / spacing);
        pc->stride = s > 1.0 ? (s < 65536.0 ? (int)s : 65536) : 1;
    }
    /* The walk's work: the region's samples on the stride grid and its rows. */
    pc->work = region / ((double)pc->stride * pc->stride) + (jhi - jlo + 1.0) / pc->stride;
    return 1;
}

/* The object-space pipeline produces texture colour; it applies to
 * textured, unlit ("replace") draws and leaves lit ones to the screen
 * pipeline. */
static int objspace_applies(const persp_draw_state *ds)
{
    return ds->tex && ds->shading == PERSP_SHADING_NONE && ds->shade_is_texel;
}

/* Pieces of every triangle, in triangle order then slab order. */
static persp_status build_pieces(persp_frame *f, const persp_capture *cap, os_piece **out,
                                 size_t *count, uint64_t *split, double *work_out)
{
    persp_context *ctx = f->ctx;
    size_t cap_n = 0, n = 0;
    os_piece *pcs = NULL;
    const persp_tri *tris = persp__frame_tris(f);
    size_t kept = 0;
    *split = 0;
    for (size_t ti = 0; ti < f->tri_count; ti++) {
        const persp_tri *t = &tris[ti];
        const persp_draw_state *ds = persp__frame_state(f, t->state);
        if (!objspace_applies(ds)) {
            kept++;
            continue;
        }
        tri_setup ts;
        memset(&ts, 0, sizeof ts);
        if (!triangle_setup(f, cap->width, cap->height, t, &ts)) continue;
        /* Slab planes w = 2^(k / SLAB_STEPS) covering [wmin, wmax]. */
        double k0 = floor(log2(ts.wmin) * SLAB_STEPS), k1 = ceil(log2(ts.wmax) * SLAB_STEPS);
        if (!(k1 >= k0)) continue;
        if (k1 - k0 > MAX_SLABS) k0 = k1 - MAX_SLABS;
        size_t made = 0;
        for (double k = k0; k < k1 || k == k0; k += 1.0) {
            double wlo = k == k0 ? 0.0 : exp2(k / SLAB_STEPS);
            double whi = k + 1.0 >= k1 ? INFINITY : exp2((k + 1.0) / SLAB_STEPS);
            if (persp__grow(ctx, (void **)&pcs, &cap_n, n + 1, sizeof *pcs) != PERSP_OK) {
                persp__free(ctx, pcs);
                return persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY,
                                          "object-space pipeline: out of memory");
            }
            /* The last slab ends at twice the triangle's farthest depth:
             * beyond it only the margin continues the surface, and towards
             * the horizon it would continue without end. */
            if (!isfinite(whi)) whi = 2.0 * ts.wmax;
            if (make_piece(&ts, ds->tex, &ds->sampler, (int)ti, wlo, whi, &pcs[n])) {
                n++;
                made++;
            }
            if (k + 1.0 >= k1) break;
        }
        if (made > 1) (*split)++;
    }
    /* Said rather than left to be noticed: a lit model (models default to
     * phong) would otherwise come out exactly as the screen pipeline draws
     * it, with "0 pieces" as the only hint. */
    if (kept)
        persp__warn(ctx,
                    "object-space pipeline: %zu of %zu triangles are lit or untextured and keep the "
                    "screen pipeline's colour (it applies to textured draws with shading none)",
                    kept, f->tri_count);
    /* An explicit bound on the walk (docs/RELIABILITY.md): refused before
     * any sample is walked rather than running for minutes. */
    double work = 0.0;
    for (size_t k = 0; k < n; k++) work += pcs[k].work;
    const double limit = ctx->objspace_max_work > 0.0 ? ctx->objspace_max_work : OS_MAX_WORK;
    if (work > limit) {
        persp__free(ctx, pcs);
        return persp__fail(ctx, PERSP_ERR_TOO_LARGE,
                           "object-space pipeline: about %.3g samples and rows to walk, over its "
                           "limit of %.3g (use the screen pipeline, or a smaller texture or image)",
                           work, limit);
    }
    *work_out = work;
    *out = pcs;
    *count = n;
    return PERSP_OK;
}

/* ------------------------------------------------------------- the walk */

/* Row interval [lo, hi] of samples inside all planes at row j; empty when
 * lo > hi. */
static void row_interval(const hplane *pl, int np, double j, double *lo, double *hi)
{
    double l = -INFINITY, h = INFINITY;
    for (int k = 0; k < np; k++) {
        double r = pl[k].b * j + pl[k].c;
        if (pl[k].a > 0.0) {
            double x = -r / pl[k].a;
            if (x > l) l = x;
        } else if (pl[k].a < 0.0) {
            double x = -r / pl[k].a;
            if (x < h) h = x;
        } else if (r < 0.0) {
            l = INFINITY;
        }
    }
    *lo = l, *hi = h;
}

/* What the walk of one piece over one tile reads at every sample. */
typedef struct walk_tile {
    const os_piece *pc;
    const persp_sampler_state *ss;
    const persp_tex_level *lv;
    const int32_t *owner; /* the triangle that owns each pixel */
    float *acc;           /* the tile's accumulators, 5 a pixel */
    int ws, wt, W;
    int tx0, ty0, tx1, ty1;
    double inv_u, inv_v;
} walk_tile;

/* Sample rows [*jstart, *jend] whose samples can reach the tile (planes tp,
 * the tile's reach); 0 when none. Rows stay on the piece's stride grid
 * (j0 + k·stride) so that every tile walks the same samples. */
static int tile_rows(const os_piece *pc, const hplane tp[4], int *jstart, int *jend)
{
    double tj0, tj1;
    if (!region_rows(pc->pl, pc->planes, tp, 4, &tj0, &tj1, NULL)) return 0;
    int js = pc->j0, je = pc->j1;
    if (tj0 > (double)js) {
        long long k = ((long long)tj0 - pc->j0) / pc->stride;
        js = (int)(pc->j0 + k * pc->stride);
    }
    if (tj1 < (double)je) je = (int)tj1;
    *jstart = js, *jend = je;
    return 1;
}

/* Samples [*i0, *i1] of row jj inside the piece and the tile's reach, i0 on
 * the stride grid; 0 when none. */
static int row_samples(const os_piece *pc, const hplane tp[4], int jj, int *i0, int *i1)
{
    double lo, hi, tlo, thi;
    row_interval(pc->pl, pc->planes, (double)jj, &lo, &hi);
    if (!(lo <= hi)) return 0;
    row_interval(tp, 4, (double)jj, &tlo, &thi);
    if (tlo > lo) lo = tlo;
    if (thi < hi) hi = thi;
    if (!(lo <= hi) || lo > 2e9 || hi < -2e9) return 0;
    int a = (int)ceil(lo < -2e9 ? -2e9 : lo), b = (int)floor(hi > 2e9 ? 2e9 : hi);
    if (pc->stride > 1) a -= ((a % pc->stride) + pc->stride) % pc->stride;
    *i0 = a, *i1 = b;
    return 1;
}

/* The texel of sample ii on a row: at sub == 1 the level's texel, read from
 * the row (row NULL with rowb: the row is the border; xr: the column
 * already wrapped when step_wrap), else the filtered colour at the
 * sub-texel position (u, v). */
static inline uint32_t sample_texel(const walk_tile *w, const uint32_t *row, int rowb, int step_wrap,
                                    int xr, int ii, double v)
{
    const os_piece *pc = w->pc;
    if (pc->sub == 1) {
        if (rowb) return w->ss->border;
        int xi = step_wrap ? xr : persp__wrap_index(w->ws, ii, w->lv->w);
        return xi < 0 ? w->ss->border : row[xi];
    }
    float c[4];
    float u = (float)(((double)ii + 0.5) * w->inv_u);
    if (pc->nearest) persp__nearest(w->ss, 0, w->ws, w->wt, u, (float)v, c);
    else persp__bilinear(w->ss, 0, w->ws, w->wt, u, (float)v, c);
    return persp__pack(c);
}

/* Adds a sample at window position (X, Y) with colour texel to the tile's
 * pixels among the four around it that the piece's triangle owns;
 * returns how many it reached. [Romaniuk-ObjSpace]'s S1..S4: the sample's
 * share of the four pixels around it (pixel centres at +0.5). */
static inline uint64_t splat(const walk_tile *w, double X, double Y, uint32_t texel)
{
    /* floor() without a library call: X, Y are in a small range. */
    int px0 = (int)X, py0 = (int)Y;
    px0 -= (double)px0 > X;
    py0 -= (double)py0 > Y;
    const double fx = (double)px0, fy = (double)py0;
    const float cr = (float)(texel & 0xffu), cg = (float)(texel >> 8 & 0xffu);
    const float cb = (float)(texel >> 16 & 0xffu), ca = (float)(texel >> 24);
    const float ax = (float)(X - fx), ay = (float)(Y - fy);
    const int tw = w->tx1 - w->tx0;
    uint64_t n = 0;
    for (int k = 0; k < 4; k++) {
        int px = px0 + (k & 1), py = py0 + (k >> 1);
        if (px < w->tx0 || px >= w->tx1 || py < w->ty0 || py >= w->ty1) continue;
        if (w->owner[(size_t)py * (size_t)w->W + (size_t)px] != w->pc->tri) continue;
        float s = ((k & 1) ? ax : 1.0f - ax) * ((k >> 1) ? ay : 1.0f - ay);
        float *a = w->acc + 5 * ((size_t)(py - w->ty0) * (size_t)tw + (size_t)(px - w->tx0));
        a[0] += s;
        a[1] += s * cr;
        a[2] += s * cg;
        a[3] += s * cb;
        a[4] += s * ca;
        n++;
    }
    return n;
}

static void walk_piece(const os_job *j, const os_piece *pc, int tx0, int ty0, int tx1, int ty1,
                       float *acc, uint64_t *walked, uint64_t *splats, uint64_t *visited)
{
    const persp_tri *t = &persp__frame_tris(j->f)[pc->tri];
    const persp_draw_state *ds = persp__frame_state(j->f, t->state);
    const persp_tex_level *lv = &ds->tex->level[pc->level];
    const walk_tile w = {
        .pc = pc, .ss = &ds->sampler, .lv = lv, .owner = j->cap->tri, .acc = acc,
        .ws = (int)ds->sampler.desc.wrap_s, .wt = (int)ds->sampler.desc.wrap_t, .W = j->cap->width,
        .tx0 = tx0, .ty0 = ty0, .tx1 = tx1, .ty1 = ty1,
        .inv_u = 1.0 / ((double)lv->w * pc->sub), .inv_v = 1.0 / ((double)lv->h * pc->sub),
    };
    /* The tile's reach: samples within one pixel of its pixel centres. */
    hplane tp[4] = {
        pull_back(&pc->H, 1.0, 0.0, -(double)tx0 + 1.0, 0.0),
        pull_back(&pc->H, -1.0, 0.0, (double)tx1 + 1.0, 0.0),
        pull_back(&pc->H, 0.0, 1.0, -(double)ty0 + 1.0, 0.0),
        pull_back(&pc->H, 0.0, -1.0, (double)ty1 + 1.0, 0.0),
    };
    uint64_t nw = 0, ns = 0, nv = 0;
    int jstart, jend;
    if (!tile_rows(pc, tp, &jstart, &jend)) return;
    for (int jj = jstart; jj <= jend; jj += pc->stride) {
        nv++;
        int i0, i1;
        if (!row_samples(pc, tp, jj, &i0, &i1)) continue;
        /* Texel row of this sample row (sub == 1: the level's row j). */
        const uint32_t *row = NULL;
        int rowb = 0;
        if (pc->sub == 1) {
            int y = persp__wrap_index(w.wt, jj, lv->h);
            if (y < 0) rowb = 1;
            else row = lv->texels + (size_t)y * (size_t)lv->w;
        }
        const double v = ((double)jj + 0.5) * w.inv_v;
        /* The projective map's rows are affine in ii: stepped along the row. */
        const double y = (double)jj, sx = (double)pc->stride;
        double nx = pc->H.m[0][0] * (double)i0 + pc->H.m[0][1] * y + pc->H.m[0][2];
        double ny = pc->H.m[1][0] * (double)i0 + pc->H.m[1][1] * y + pc->H.m[1][2];
        double nz = pc->H.m[2][0] * (double)i0 + pc->H.m[2][1] * y + pc->H.m[2][2];
        const double dx = pc->H.m[0][0] * sx, dy = pc->H.m[1][0] * sx, dz = pc->H.m[2][0] * sx;
        /* Repeat-wrapped texel column, stepped too (no division per texel). */
        const int step_wrap = row && w.ws == PERSP_WRAP_REPEAT && pc->stride == 1;
        int xr = step_wrap ? persp__wrap_index(w.ws, i0, lv->w) : 0;
        for (int ii = i0; ii <= i1; ii += pc->stride, nx += dx, ny += dy, nz += dz,
                 xr = xr + 1 == lv->w ? 0 : xr + 1) {
            nv++;
            double wh = nz;
            if (!(wh > 0.0)) continue;
            double iw = 1.0 / wh;
            double X = nx * iw - 0.5;
            double Y = ny * iw - 0.5;
            /* Only samples whose 2×2 pixel neighbourhood meets the tile; the
             * range test also keeps splat's int conversions defined. */
            if (!(X >= (double)tx0 - 1.0 && X < (double)tx1 && Y >= (double)ty0 - 1.0 &&
                  Y < (double)ty1))
                continue;
            nw++;
            ns += splat(&w, X, Y, sample_texel(&w, row, rowb, step_wrap, xr, ii, v));
        }
    }
    *walked += nw;
    *splats += ns;
    *visited += nv;
}

static void tile_task(void *user, int task, int worker)
{
    os_job *j = user;
    const int W = j->cap->width, H = j->cap->height;
    int tx = task % j->tiles_x, ty = task / j->tiles_x;
    int x0 = tx * OS_TILE, y0 = ty * OS_TILE;
    int x1 = x0 + OS_TILE < W ? x0 + OS_TILE : W, y1 = y0 + OS_TILE < H ? y0 + OS_TILE : H;
    float *acc = j->acc + (size_t)worker * OS_TILE * OS_TILE * 5;
    memset(acc, 0, sizeof(float) * OS_TILE * OS_TILE * 5);
    uint64_t walked = 0, splats = 0, holes = 0, visited = 0;
    for (size_t k = 0; k < j->piece_count; k++) {
        const os_piece *pc = &j->pieces[k];
        if (pc->bx1 < (double)x0 - 1.0 || pc->bx0 > (double)x1 + 1.0 || pc->by1 < (double)y0 - 1.0 ||
            pc->by0 > (double)y1 + 1.0)
            continue;
        walk_piece(j, pc, x0, y0, x1, y1, acc, &walked, &splats, &visited);
    }
    uint32_t *color = (uint32_t *)(void *)j->f->fb->color;
    const persp_tri *tris = persp__frame_tris(j->f);
    const int tw = x1 - x0;
    for (int y = y0; y < y1; y++)
        for (int x = x0; x < x1; x++) {
            size_t i = (size_t)y * (size_t)W + (size_t)x;
            int32_t t = j->cap->tri[i];
            if (t < 0 || !objspace_applies(persp__frame_state(j->f, tris[t].state))) continue;
            const float *a = acc + 5 * ((size_t)(y - y0) * (size_t)tw + (size_t)(x - x0));
            if (!(a[0] > 0.0f)) {
                holes++; /* keeps the screen pipeline's colour */
                continue;
            }
            float c[4];
            float inv = 1.0f / a[0];
            for (int m = 0; m < 4; m++) c[m] = a[1 + m] * inv;
            color[i] = persp__pack(c);
        }
    j->walked[task] = walked;
    j->splats[task] = splats;
    j->holes[task] = holes;
    j->visited[task] = visited;
}

persp_status persp__objspace_resolve(persp_frame *f, const persp_capture *cap,
                                     persp_objspace_stats *stats)
{
    persp_context *ctx = f->ctx;
    os_job j;
    memset(&j, 0, sizeof j);
    j.f = f;
    j.cap = cap;
    uint64_t split = 0;
    os_piece *pieces = NULL;
    size_t npieces = 0;
    double work = 0.0;
    persp_status st = build_pieces(f, cap, &pieces, &npieces, &split, &work);
    if (st != PERSP_OK) return st;
    j.pieces = pieces;
    j.piece_count = npieces;

    j.tiles_x = (cap->width + OS_TILE - 1) / OS_TILE;
    j.tiles_y = (cap->height + OS_TILE - 1) / OS_TILE;
    int tiles = j.tiles_x * j.tiles_y, workers = persp__pool_workers(ctx);
    j.acc = persp__calloc(ctx, (size_t)workers * OS_TILE * OS_TILE * 5, sizeof(float));
    j.walked = persp__calloc(ctx, (size_t)tiles, sizeof(uint64_t));
    j.splats = persp__calloc(ctx, (size_t)tiles, sizeof(uint64_t));
    j.holes = persp__calloc(ctx, (size_t)tiles, sizeof(uint64_t));
    j.visited = persp__calloc(ctx, (size_t)tiles, sizeof(uint64_t));
    if (!j.acc || !j.walked || !j.splats || !j.holes || !j.visited) {
        st = persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "object-space pipeline: out of memory");
    } else {
        st = persp__pool_run(ctx, tiles, tile_task, &j);
    }
    if (st == PERSP_OK && stats) {
        memset(stats, 0, sizeof *stats);
        for (int k = 0; k < tiles; k++) {
            stats->texels_walked += j.walked[k];
            stats->splats += j.splats[k];
            stats->holes += j.holes[k];
            stats->visited += j.visited[k];
        }
        stats->triangles_split = split;
        stats->pieces = npieces;
        stats->work_estimate = work;
    }
    persp__free(ctx, j.acc);
    persp__free(ctx, j.walked);
    persp__free(ctx, j.splats);
    persp__free(ctx, j.holes);
    persp__free(ctx, j.visited);
    persp__free(ctx, pieces);
    return st;
}
