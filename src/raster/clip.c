/*
 * Homogeneous clipping (Sutherland–Hodgman in clip space; Blinn & Newell 1978,
 * OpenGL 4.6 §13.7). The near plane and w > 0 are clipped before any divide,
 * so geometry crossing the camera plane (the corridor's walls start behind
 * the near plane) is cut where it becomes visible instead of wrapping through
 * infinity. Left/right/top/bottom are clipped only at a guard band far outside
 * the viewport; the rasterizer's bounding box does the rest exactly.
 */
#include "raster/raster.h"

#include <math.h>
#include <string.h>

/* Smallest w kept (PERSP_CLIP_W_EPSILON): a point with w below it lies at
 * or behind the eye. */
#define W_EPSILON PERSP_CLIP_W_EPSILON

typedef double (*plane_fn)(const persp_clipvert *v, double gx, double gy);

static double p_near(const persp_clipvert *v, double gx, double gy) { (void)gx, (void)gy; return (double)v->clip[2] + v->clip[3]; }
static double p_far(const persp_clipvert *v, double gx, double gy) { (void)gx, (void)gy; return (double)v->clip[3] - v->clip[2]; }
static double p_w(const persp_clipvert *v, double gx, double gy) { (void)gx, (void)gy; return (double)v->clip[3] - W_EPSILON; }
static double p_left(const persp_clipvert *v, double gx, double gy) { (void)gy; return gx * v->clip[3] + v->clip[0]; }
static double p_right(const persp_clipvert *v, double gx, double gy) { (void)gy; return gx * v->clip[3] - v->clip[0]; }
static double p_bottom(const persp_clipvert *v, double gx, double gy) { (void)gx; return gy * v->clip[3] + v->clip[1]; }
static double p_top(const persp_clipvert *v, double gx, double gy) { (void)gx; return gy * v->clip[3] - v->clip[1]; }

/* persp__clip_outcode evaluates the same expressions inline, bit p for
 * planes[p]: keep the two in step. */
static const plane_fn planes[] = {p_w, p_near, p_far, p_left, p_right, p_bottom, p_top};

static void lerp(const persp_clipvert *a, const persp_clipvert *b, double t, persp_clipvert *o)
{
    for (int k = 0; k < 4; k++) o->clip[k] = (float)(a->clip[k] + t * ((double)b->clip[k] - a->clip[k]));
    for (int k = 0; k < PERSP_A_COUNT; k++)
        o->attr[k] = (float)(a->attr[k] + t * ((double)b->attr[k] - a->attr[k]));
}

int persp__clip_triangle(const persp_clipvert in[3], double gx, double gy,
                         persp_clipvert out[PERSP_CLIP_MAX])
{
    for (int i = 0; i < 3; i++) {
        for (int k = 0; k < 4; k++)
            if (!isfinite(in[i].clip[k])) return 0;
        for (int k = 0; k < PERSP_A_COUNT; k++)
            if (!isfinite(in[i].attr[k])) return 0;
    }
    /* Fast path: every vertex inside every plane. */
    int inside = 1;
    for (size_t p = 0; p < sizeof planes / sizeof planes[0] && inside; p++)
        for (int i = 0; i < 3; i++)
            if (planes[p](&in[i], gx, gy) < 0.0) inside = 0;
    memcpy(out, in, 3 * sizeof *in);
    if (inside) return 3;

    persp_clipvert buf[PERSP_CLIP_MAX];
    persp_clipvert *src = out, *dst = buf;
    int n = 3;
    for (size_t p = 0; p < sizeof planes / sizeof planes[0]; p++) {
        int m = 0;
        for (int i = 0; i < n; i++) {
            const persp_clipvert *a = &src[i], *b = &src[(i + 1) % n];
            double da = planes[p](a, gx, gy), db = planes[p](b, gx, gy);
            if (da >= 0.0) dst[m++] = *a;
            if ((da >= 0.0) != (db >= 0.0) && m < PERSP_CLIP_MAX) {
                /* Interpolate from the inside vertex so that the same edge
                 * shared by two triangles is cut at bit-identical points. */
                if (da >= 0.0)
                    lerp(a, b, da / (da - db), &dst[m++]);
                else
                    lerp(b, a, db / (db - da), &dst[m++]);
            }
        }
        n = m;
        if (n < 3) return 0;
        persp_clipvert *t = src;
        src = dst;
        dst = t;
    }
    if (src != out) memcpy(out, src, (size_t)n * sizeof *out);
    return n;
}

unsigned persp__clip_outcode(const persp_clipvert *v, double gx, double gy)
{
    return persp__clip_outcode_packed(v->clip, PERSP_A_COUNT, gx, gy);
}

unsigned persp__clip_outcode_packed(const float *v, int nattr, double gx, double gy)
{
    /* x·0 is 0 for every finite x and NaN otherwise: one sum tests all
     * values without a branch each. */
    float probe = 0.0f;
    for (int k = 0; k < 4 + nattr; k++) probe += v[k] * 0.0f;
    if (probe != 0.0f) return PERSP_CLIP_NONFINITE;
    return persp__clip_outcode_pos(v[0], v[1], v[2], v[3], gx, gy);
}
