/*
 * Culling whole clusters of back faces (persp_cluster, src/geom/scene.h),
 * exactly: a cluster is culled only when every one of its triangles would
 * be culled by the rasterizer's own test, the sign of its area in the
 * 1/256-pixel fixed point (persp__tri_edges). So the images, the drawn
 * triangles and the fragments are those of culling triangle by triangle;
 * what is saved is the triangle loop over the cluster and, for the
 * vertices that only culled clusters use, the vertex stage.
 *
 * Why the test below implies the per-triangle one. Let R_x, R_y, R_w be the
 * rows of the model-view-projection matrix acting on (p, 1), and E the
 * 4-vector with u·E = det[u; R_x; R_y; R_w] for every u (the centre of
 * projection in object space, homogeneous). For a triangle p0 p1 p2 with
 * n = (p1 − p0) × (p2 − p0) and plane π = (n, −n·p0), Cauchy–Binet gives
 * det[(R_x·p̃_i, R_y·p̃_i, R_w·p̃_i)]_i = E·π, so its window area, twice and
 * counter-clockwise positive, is
 *     A2 = (W/2)(H/2) E·π / (w0 w1 w2) = −(W/2)(H/2) 2A g / (w0 w1 w2),
 * A its object-space area, g = n̂·(E_w p0 − E_xyz) (any vertex may stand for
 * p0). Over a cluster with sphere (c, r) and normal cone (a, α),
 *     g >= |v| cos(θ + α) − |E_w| r,  v = E_w c − E_xyz, θ the angle of v to a.
 * Snapping the vertices to 1/256 pixel moves each coordinate by at most
 * ε = 1/512 (plus the float rounding of the clip coordinates, bounded
 * below), which changes A2 by at most 2ε(|e1|₁ + |e2|₁) + 8ε² for the edges
 * e1, e2 from p0; inside the planes |x| <= t w, |y| <= t w an edge of
 * object length L spans |e|₁ <= K L / w_min in the window,
 * K = (W/2)(|R_x| + t|R_w|) + (H/2)(|R_y| + t|R_w|) (norms of the rows'
 * xyz parts; t for x and for y the least bound on |x/w|, |y/w| known for
 * the cluster's sphere). With 2A >= h L (h: the least height over the
 * longest edge), the snapped area is negative, and the triangle culled,
 * whenever
 *     (W/2)(H/2) h g_min / w_max³ > 4εK / w_min + 8ε² / L_min,
 * and the test asks for twice that margin. The sphere inside every clip
 * plane (with margin for the float clip coordinates) puts every vertex in
 * the vertex stage's fast path (outcode 0), which tests exactly that area.
 */
#include "raster/raster.h"

#include <math.h>
#include <string.h>

static double det3(const double a[3], const double b[3], const double c[3])
{
    return a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
           a[2] * (b[0] * c[1] - b[1] * c[0]);
}

static double norm3(const double *v)
{
    return sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

void persp__cluster_view_init(persp_cluster_view *cv, const persp_mat4 *mvp, int width, int height,
                              double gx, double gy, int cull)
{
    for (int r = 0; r < 4; r++)
        for (int c = 0; c < 4; c++)
            cv->row[r][c] = mvp->m[4 * c + r];
    for (int k = 0; k < 4; k++) {
        double m[3][3];
        for (int i = 0; i < 3; i++) {
            const double *src = cv->row[i == 2 ? 3 : i];
            for (int c = 0, d = 0; c < 4; c++)
                if (c != k) m[i][d++] = src[c];
        }
        /* Culling counter-clockwise triangles (a mirrored object) asks for
         * A2 > 0: the same test with E negated, which negates g and A2. */
        cv->E[k] = (k % 2 ? -1.0 : 1.0) * (cull == PERSP_CULL_CCW ? -1.0 : 1.0) * det3(m[0], m[1], m[2]);
    }
    cv->cull = cull;
    cv->regions = cv->tiles_x = 0;
    cv->tx = fmin(gx, 2.0), cv->ty = fmin(gy, 2.0);
    cv->W2 = 0.5 * width, cv->H2 = 0.5 * height;
    for (int i = 0; i < 4; i++)
        cv->row_norm[i] = norm3(cv->row[i]);
    /* The planes a cluster's sphere must be inside: w >= PERSP_CLIP_W_EPSILON,
     * −w <= z <= w and |x| <= tx·w, |y| <= ty·w (tx, ty at most the guard
     * band's), as coefficients of the rows x, y, z, w and a constant; and
     * the length of each plane's normal in object space. */
    const double planes[7][5] = {
        {0, 0, 0, 1, -PERSP_CLIP_W_EPSILON},
        {0, 0, 1, 1, 0},
        {0, 0, -1, 1, 0},
        {1, 0, 0, cv->tx, 0},
        {-1, 0, 0, cv->tx, 0},
        {0, 1, 0, cv->ty, 0},
        {0, -1, 0, cv->ty, 0},
    };
    memcpy(cv->plane, planes, sizeof planes);
    for (int p = 0; p < 7; p++) {
        double co[3] = {0, 0, 0};
        for (int i = 0; i < 4; i++)
            for (int d = 0; d < 3; d++)
                co[d] += planes[p][i] * cv->row[i][d];
        cv->plane_norm[p] = norm3(co);
    }
    /* The clip coordinates are floats: relative 2^-24 in x/w and y/w,
     * times 6 here. */
    cv->eps = 1.0 / (2.0 * PERSP_SUBPIXEL) + (cv->W2 * cv->tx + cv->H2 * cv->ty) * 4e-7;
}

/* The window interval along one axis (row 0 x, 1 y; half the window's
 * size along it) that the cluster projects into, widened by a margin; 0
 * when the cluster is not wholly in front of the eye. The bounds of the
 * axis's coordinate and of w over the cluster are those of the rows at its
 * centre plus and minus the lesser of two reaches: the radius times the
 * row's length (its sphere), and the sum of the row's entries' magnitudes
 * times the box's half sizes (its box; for a strip of quads, which a
 * cluster of a fine mesh is, much the tighter: its sphere projects to a
 * square as wide as the strip is long). x/w and y/w are monotonic along a
 * segment with w > 0, so every triangle of the cluster and every piece
 * clipping makes of one lies within. The margin of two pixels and a part in
 * 10^4 covers the float clip coordinates and the snapping to 1/256 pixel. */
static int window_span(const persp_cluster_view *cv, const persp_cluster *cl, int axis, double half, double *lo,
                       double *hi)
{
    const double(*row)[4] = cv->row;
    const double *c = cl->center, r = cl->radius, *h = cl->half;
    double at[2], reach[2];
    const int rows[2] = {axis, 3};
    for (int i = 0; i < 2; i++) {
        const double *m = row[rows[i]];
        at[i] = m[0] * c[0] + m[1] * c[1] + m[2] * c[2] + m[3];
        reach[i] = fmin(cv->row_norm[rows[i]] * r, fabs(m[0]) * h[0] + fabs(m[1]) * h[1] + fabs(m[2]) * h[2]);
    }
    const double w_lo = at[1] - reach[1], w_hi = at[1] + reach[1];
    if (!(w_lo > PERSP_CLIP_W_EPSILON)) return 0;
    const double a_lo = at[0] - reach[0], a_hi = at[0] + reach[0];
    const double ndc_lo = a_lo >= 0.0 ? a_lo / w_hi : a_lo / w_lo;
    const double ndc_hi = a_hi >= 0.0 ? a_hi / w_lo : a_hi / w_hi;
    const double margin = 2.0 + 1e-4 * half * (1.0 + fmax(fabs(ndc_lo), fabs(ndc_hi)));
    *lo = (ndc_lo + 1.0) * half - margin;
    *hi = (ndc_hi + 1.0) * half + margin;
    return *lo <= *hi && isfinite(*lo) && isfinite(*hi);
}

/* Whether no point of the cluster projects onto a pixel of a tile of the
 * view's region: then every triangle of it has a box the region's frame
 * drops (frame.c, region_touches). */
static int outside_region(const persp_cluster_view *cv, const persp_cluster *cl)
{
    double xlo, xhi, ylo, yhi;
    if (!window_span(cv, cl, 0, cv->W2, &xlo, &xhi) || !window_span(cv, cl, 1, cv->H2, &ylo, &yhi)) return 0;
    /* Beyond the window: nothing of it is drawn. */
    if (xhi < 0.0 || xlo > 2.0 * cv->W2 || yhi < 0.0 || ylo > 2.0 * cv->H2) return 1;
    const int64_t tx0 = (int64_t)fmax(0.0, xlo) / PERSP_TILE, ty0 = (int64_t)fmax(0.0, ylo) / PERSP_TILE;
    const int64_t tx1 = xhi < 2.0 * cv->W2 ? (int64_t)xhi / PERSP_TILE : (int64_t)cv->tiles_x - 1;
    const int64_t ty1 = (int64_t)yhi / PERSP_TILE;
    return !persp__box_reaches_run(&cv->run, tx0, tx1, ty0, ty1);
}

size_t persp__clusters_cull(const persp_cluster_view *cv, const persp_cluster *clusters,
                            size_t count, uint8_t *culled)
{
    size_t n = 0;
    for (size_t k = 0; k < count; k++) {
        const int back = persp__cluster_back_facing(cv, &clusters[k]);
        culled[k] = back ? 1 : cv->regions && clusters[k].usable && outside_region(cv, &clusters[k]) ? 2 : 0;
        n += (size_t)back;
    }
    return n;
}

int persp__cluster_back_facing(const persp_cluster_view *cv, const persp_cluster *cl)
{
    const double(*row)[4] = cv->row;
    const double *E = cv->E, *rn = cv->row_norm;
    if (!cl->usable || !cv->cull) return 0;
    const double *c = cl->center, r = cl->radius;
    const double v[3] = {E[3] * c[0] - E[0], E[3] * c[1] - E[1], E[3] * c[2] - E[2]};
    const double vl = norm3(v);
    if (!(vl > 0.0)) return 0;
    const double cos_t = (v[0] * cl->axis[0] + v[1] * cl->axis[1] + v[2] * cl->axis[2]) / vl;
    const double sin_t = sqrt(fmax(0.0, 1.0 - cos_t * cos_t));
    const double g_min = vl * (cos_t * cl->cos_a - sin_t * cl->sin_a) - fabs(E[3]) * r;
    if (!(g_min > 0.0)) return 0;
    /* Each row at the centre, and how far it can move over the sphere;
     * mag bounds |row·p̃| there, for the margins of float rounding. */
    double at[4], mag[4];
    const double cn = norm3(c) + r;
    for (int i = 0; i < 4; i++) {
        at[i] = row[i][0] * c[0] + row[i][1] * c[1] + row[i][2] * c[2] + row[i][3];
        mag[i] = rn[i] * cn + fabs(row[i][3]);
    }
    int inside = 1;
    for (int p = 0; p < 7 && inside; p++) {
        const double *pl = cv->plane[p];
        double val = pl[4], mg = 0.0;
        for (int i = 0; i < 4; i++) {
            val += pl[i] * at[i];
            mg += fabs(pl[i]) * mag[i];
        }
        inside = val - cv->plane_norm[p] * r - 1e-6 * mg > 0.0;
    }
    if (!inside) return 0;
    const double w_min = at[3] - rn[3] * r, w_max = at[3] + rn[3] * r;
    if (!(w_min > 0.0)) return 0;
    /* K with this cluster's own bounds on |x/w| and |y/w| where they
     * are tighter than the planes' (a cluster on screen: about 1 against
     * 2, a third off K). */
    const double rx = rn[0], ry = rn[1], rw = rn[3];
    const double ux = fmin(cv->tx, (fabs(at[0]) + rx * r) / w_min);
    const double uy = fmin(cv->ty, (fabs(at[1]) + ry * r) / w_min);
    const double K = cv->W2 * (rx + ux * rw) + cv->H2 * (ry + uy * rw);
    const double lhs = cv->W2 * cv->H2 * cl->alt_min * g_min / (w_max * w_max * w_max);
    const double rhs =
        2.0 * (4.0 * cv->eps * K / w_min + 8.0 * cv->eps * cv->eps / cl->edge_min);
    return lhs > rhs;
}

void persp__clusters_vertex_need(const persp_mesh *mesh, const uint8_t *culled, size_t block,
                                 uint8_t *need)
{
    const size_t blocks = (mesh->vertex_count + block - 1) / block;
    memset(need, 0, blocks);
    for (size_t k = 0; k < mesh->cluster_count; k++) {
        if (culled[k]) continue;
        const persp_cluster *cl = &mesh->clusters[k];
        if (!cl->runs) {
            memset(need, 1, blocks);
            return;
        }
        for (int i = 0; i < cl->runs; i++)
            memset(need + cl->run[i][0] / block, 1,
                   (cl->run[i][1] - 1) / block - cl->run[i][0] / block + 1);
    }
}
