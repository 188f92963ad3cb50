/*
 * Triangle setup: fixed-point edge functions (Pineda 1988) with 8 sub-pixel
 * bits, the top-left fill rule, and the screen-space planes of 1/w, u/w, v/w
 * (Heckbert 1989 §2.3.2: u = (a·x + b·y + c)/(g·x + h·y + i)) that every
 * texture-coordinate method reads from the setup record.
 */
#include "interp/methods.h"
#include "raster/raster.h"
#include "shade/shade.h"

#include <math.h>
#include <string.h>

#define COORD_LIMIT ((double)(1 << 22)) /* |window coordinate| in pixels, far beyond the guard band */

int persp__setup_triangle(const persp_winvert vin[3], int width, int height, int cull, persp_tri *t,
                          persp_rational_vertices *vv)
{
    return persp__setup_triangle_for(vin, width, height, cull, PERSP_SETUP_ALL, t, vv);
}

int persp__setup_triangle_for(const persp_winvert vin[3], int width, int height, int cull, unsigned need,
                              persp_tri *t, persp_rational_vertices *vv)
{
    int64_t X[3], Y[3];
    for (int i = 0; i < 3; i++) {
        if (!(fabs(vin[i].x) < COORD_LIMIT && fabs(vin[i].y) < COORD_LIMIT) || !isfinite(vin[i].z) ||
            !(vin[i].q > 0.0) || !isfinite(vin[i].q))
            return 0;
        X[i] = (int64_t)llround(vin[i].x * PERSP_SUBPIXEL);
        Y[i] = (int64_t)llround(vin[i].y * PERSP_SUBPIXEL);
    }
    persp_tri_edges e;
    if (!persp__tri_edges(X, Y, width, height, cull, &e)) return 0;
    return persp__setup_triangle_edges(vin, &e, need, t, vv);
}

int persp__setup_triangle_edges(const persp_winvert vin[3], const persp_tri_edges *e, unsigned need,
                                persp_tri *t, persp_rational_vertices *vv)
{
    const int64_t *x = e->x, *y = e->y;
    const int *order = e->order;
    const int back = e->back;

    const int shading = (need & PERSP_SETUP_SHADING) != 0;
    /* The record is written field by field, every field the shading needs
     * (bary, lb1, lb2, vattr, light_side) too: clearing all 560 bytes first
     * cost 3 % of a phong-pc frame of the 2M-triangle torus. */
    t->backfacing = back;
    t->xmin = (int)e->bx0, t->xmax = (int)e->bx1, t->ymin = (int)e->by0, t->ymax = (int)e->by1;
    t->cover = e->cover;
    for (int k = 0; k < 3; k++) t->ea[k] = e->ea[k], t->eb[k] = e->eb[k], t->ec[k] = e->ec[k];

    double vx[3], vy[3], q[3], zz[3], uq[3], vq[3], b1[3], b2[3];
    /* Unrolled, so that the per-vertex values stay in registers: stored
     * one by one and read back in pairs by the planes they would miss
     * store-to-load forwarding (~24 % of set-up on the 200k torus). */
#pragma GCC unroll 3
    for (int i = 0; i < 3; i++) {
        const persp_winvert *w = &vin[order[i]];
        vx[i] = (double)x[i] / PERSP_SUBPIXEL;
        vy[i] = (double)y[i] / PERSP_SUBPIXEL;
        q[i] = w->q;
        zz[i] = w->z;
        uq[i] = (double)w->attr[PERSP_A_U] * w->q;
        vq[i] = (double)w->attr[PERSP_A_V] * w->q;
        b1[i] = i == 1 ? w->q : 0.0;
        b2[i] = i == 2 ? w->q : 0.0;
        if (!shading) continue;
        /* Without the back colours (only Gouraud reads them) they are zero. */
        if (need & PERSP_SETUP_BACK_COLOURS) {
            memcpy(t->vattr[i], w->attr, PERSP_A_COUNT * sizeof t->vattr[i][0]);
        } else {
            memcpy(t->vattr[i], w->attr, PERSP_A_BR * sizeof t->vattr[i][0]);
            for (int k = PERSP_A_BR; k < PERSP_A_COUNT; k++) t->vattr[i][k] = 0.0f;
        }
    }
    if (vv) {
        for (int i = 0; i < 3; i++) {
            vv->x[i] = vx[i], vv->y[i] = vy[i], vv->q[i] = q[i];
            vv->s1[i] = vin[order[i]].attr[PERSP_A_U];
            vv->s2[i] = vin[order[i]].attr[PERSP_A_V];
        }
    }
    persp__plane_through(vx, vy, uq, &t->rat.a, &t->rat.b, &t->rat.c);
    persp__plane_through(vx, vy, vq, &t->rat.d, &t->rat.e, &t->rat.f);
    persp__plane_through(vx, vy, q, &t->rat.g, &t->rat.h, &t->rat.i);
    persp__plane_through(vx, vy, zz, &t->zp[0], &t->zp[1], &t->zp[2]);
    t->rat.xmin = t->xmin;
    t->rat.xmax = t->xmax;
    t->rat.ymin = t->ymin;
    t->rat.ymax = t->ymax;
    t->rat.scale1 = t->rat.scale2 = 1.0f;
    t->state = 0;
    t->prep = UINT32_MAX;
    t->poly_lambda = 0.0f;
    t->light_side = 1.0f;
    if (!shading) return 1;
    t->light_side = persp__shade_light_side(t);
    persp__plane_through(vx, vy, b1, &t->bary.a, &t->bary.b, &t->bary.c);
    persp__plane_through(vx, vy, b2, &t->bary.d, &t->bary.e, &t->bary.f);
    t->bary.g = t->rat.g, t->bary.h = t->rat.h, t->bary.i = t->rat.i;
    if (need & PERSP_SETUP_LINEAR) {
        const double e1[3] = {0, 1, 0}, e2[3] = {0, 0, 1};
        persp__plane_through(vx, vy, e1, &t->lb1[0], &t->lb1[1], &t->lb1[2]);
        persp__plane_through(vx, vy, e2, &t->lb2[0], &t->lb2[1], &t->lb2[2]);
    }
    t->bary.xmin = t->xmin;
    t->bary.xmax = t->xmax;
    t->bary.ymin = t->ymin;
    t->bary.ymax = t->ymax;
    t->bary.scale1 = t->bary.scale2 = 1.0f;
    return 1;
}

int persp__tri_row_range(const persp_tri *t, int y, int x0, int x1, int *lo, int *hi)
{
    if (y < t->ymin || y > t->ymax) return 0;
    int64_t l = x0 > t->xmin ? x0 : t->xmin;
    int64_t h = x1 < t->xmax ? x1 : t->xmax;
    const int64_t Y = (int64_t)y * PERSP_SUBPIXEL + PERSP_SUBPIXEL / 2;
    for (int k = 0; k < 3 && l <= h; k++) {
        int64_t A = t->ea[k];
        /* Edge value at pixel px's centre: A·256·px + R, R = B·Y + C + 128·A. */
        int64_t R = t->eb[k] * Y + t->ec[k] + A * (PERSP_SUBPIXEL / 2);
        if (A > 0) {
            int64_t m = persp__ceil_div(-R, A * PERSP_SUBPIXEL);
            if (m > l) l = m;
        } else if (A < 0) {
            int64_t m = persp__floor_div(R, -A * PERSP_SUBPIXEL);
            if (m < h) h = m;
        } else if (R < 0) {
            return 0;
        }
    }
    if (l > h) return 0;
    *lo = (int)l;
    *hi = (int)h;
    return 1;
}

void persp__row_walk_init(persp_row_walk *w, const persp_tri *t, int y, int rows, int x0, int x1)
{
    w->lo = x0 > t->xmin ? x0 : t->xmin;
    w->hi = x1 < t->xmax ? x1 : t->xmax;
    w->bw = 0;
    if (t->cover) {
        w->bw = t->xmax - t->xmin + 1;
        w->x = t->xmin;
        /* Starting below the box, or with columns outside the window:
         * nothing (and no shift past the mask's width). */
        const int inside = w->lo <= w->hi && y <= t->ymax;
        w->bits = inside ? t->cover >> ((y - t->ymin) * w->bw) : 0;
        w->cols = inside ? ((2u << (w->hi - w->x)) - 1) & ~((1u << (w->lo - w->x)) - 1) : 0;
        return;
    }
    const int64_t Y = (int64_t)y * PERSP_SUBPIXEL + PERSP_SUBPIXEL / 2;
    for (int k = 0; k < 3; k++) {
        const int64_t A = t->ea[k];
        /* As in persp__tri_row_range: pixel px of the row is inside edge k
         * when A·256·px + R >= 0; the next row adds S = 256·B to R. */
        const int64_t R = t->eb[k] * Y + t->ec[k] + A * (PERSP_SUBPIXEL / 2);
        const int64_t S = t->eb[k] * PERSP_SUBPIXEL;
        if (A == 0) {
            w->sign[k] = 0;
            w->R[k] = R;
            w->s[k] = S;
            w->d[k] = w->m[k] = w->r[k] = w->q[k] = 0;
            continue;
        }
        const int64_t d = (A > 0 ? A : -A) * PERSP_SUBPIXEL;
        w->d[k] = d;
        w->R[k] = 0;
        if (A > 0) {
            /* Smallest m with d·m + R >= 0; r = d·m + R in [0, d). A step
             * adds S to R, so m falls by floor((r + S) / d). */
            w->sign[k] = 1;
            w->m[k] = persp__ceil_div(-R, d);
            w->r[k] = d * w->m[k] + R;
        } else {
            /* Largest m with d·m <= R; r = R − d·m in [0, d). A step adds
             * S to R, so m rises by floor((r + S) / d). */
            w->sign[k] = -1;
            w->m[k] = persp__floor_div(R, d);
            w->r[k] = R - d * w->m[k];
        }
        /* A walk of one row never steps: its division is saved (half the
         * tile rows of a triangle of two pixels). */
        w->q[k] = rows > 1 ? persp__floor_div(S, d) : 0;
        w->s[k] = rows > 1 ? S - d * w->q[k] : 0;
    }
}

