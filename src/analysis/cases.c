/*
 * Measurement cases of persp accuracy (docs/WORKLOADS.md): the paper quad of
 * [Romanyuk-PCF] §4.6 Fig. 4.10 and seeded random triangles grouped by depth ratio.
 */
#include "analysis/analysis.h"
#include "core/internal.h"

#include <math.h>
#include <string.h>

const double persp__paper_quad_x[4] = {1.0, 32.0, 96.0, 128.0};
const double persp__paper_quad_y[4] = {1.0, 96.0, 128.0, 32.0};

const double persp__hbar_groups[PERSP_HBAR_COUNT] = {1.25, 1.5, 2.0, 3.0, 4.0, 5.0, 8.0};

int persp__square_to_quad(const double x[4], const double y[4], double fwd[9], double inv[9])
{
    /* Heckbert 1989 §2.2.3 ("square to quadrilateral"): with
     * Σx = x0 - x1 + x2 - x3 and Σy likewise, the map is affine when both
     * vanish; otherwise g, h solve the 2×2 system of the corner at (1,1). */
    double sx = x[0] - x[1] + x[2] - x[3], sy = y[0] - y[1] + y[2] - y[3];
    double a, b, c, d, e, f, g, h;
    if (sx == 0.0 && sy == 0.0) {
        a = x[1] - x[0], b = x[2] - x[1], c = x[0];
        d = y[1] - y[0], e = y[2] - y[1], f = y[0];
        g = h = 0.0;
    } else {
        double dx1 = x[1] - x[2], dx2 = x[3] - x[2], dy1 = y[1] - y[2], dy2 = y[3] - y[2];
        double den = dx1 * dy2 - dx2 * dy1;
        if (den == 0.0) return 0;
        g = (sx * dy2 - dx2 * sy) / den;
        h = (dx1 * sy - sx * dy1) / den;
        a = x[1] - x[0] + g * x[1], b = x[3] - x[0] + h * x[3], c = x[0];
        d = y[1] - y[0] + g * y[1], e = y[3] - y[0] + h * y[3], f = y[0];
    }
    /* [x·w  y·w  w] = [u v 1] · M, M = |a d g; b e h; c f 1|. */
    const double M[9] = {a, d, g, b, e, h, c, f, 1.0};
    for (int k = 0; k < 9; k++) fwd[k] = M[k];
    /* [u·q  v·q  q] = [x y 1] · adj(M): adj(M) has rows
     * (A D G; B E H; C F I) in Heckbert's notation. */
    double A = e * 1.0 - f * h, B = c * h - b * 1.0, C = b * f - c * e;
    double D = f * g - d * 1.0, E = a * 1.0 - c * g, F = c * d - a * f;
    double G = d * h - e * g, H = b * g - a * h, I = a * e - b * d;
    double det = a * A + d * B + g * C;
    if (det == 0.0 || !isfinite(det)) return 0;
    /* Orient so that q > 0 inside the quad (methods assume 1/w > 0). */
    double cxq = 0.25 * (x[0] + x[1] + x[2] + x[3]), cyq = 0.25 * (y[0] + y[1] + y[2] + y[3]);
    double s = G * cxq + H * cyq + I < 0.0 ? -1.0 : 1.0;
    const double R[9] = {A, B, C, D, E, F, G, H, I};
    for (int k = 0; k < 9; k++) inv[k] = s * R[k];
    return 1;
}

/* Heckbert's a..i of paper-quad in the chapter's screen coordinates. */
static void paper_quad_planes(double p[9])
{
    double fwd[9];
    persp__square_to_quad(persp__paper_quad_x, persp__paper_quad_y, fwd, p);
}

static void eval_planes(const double p[9], double X, double Y, double *u, double *v, double *q)
{
    *q = p[6] * X + p[7] * Y + p[8];
    *u = (p[0] * X + p[1] * Y + p[2]) / *q;
    *v = (p[3] * X + p[4] * Y + p[5]) / *q;
}

/* Fills r from planes p expressed in the chapter's coordinates (X, Y) where the
 * window pixel centre (px, py) maps to X = x0 + sx·(px - 0.5),
 * Y = y0 + (py - 0.5); vertices are quad corners k[0..2]. */
static void rational_from_planes(const double p[9], double x0, double sx, double y0, const int k[3],
                                 double scale, persp_rational *r, persp_rational_vertices *rv)
{
    memset(r, 0, sizeof *r);
    double *dst[3][3] = {{&r->a, &r->b, &r->c}, {&r->d, &r->e, &r->f}, {&r->g, &r->h, &r->i}};
    for (int row = 0; row < 3; row++) {
        double P = p[3 * row], Q = p[3 * row + 1], S = p[3 * row + 2];
        *dst[row][0] = P * sx;
        *dst[row][1] = Q;
        *dst[row][2] = P * (x0 - 0.5 * sx) + Q * (y0 - 0.5) + S;
    }
    double xmin = 1e300, xmax = -1e300, ymin = 1e300, ymax = -1e300;
    for (int j = 0; j < 3; j++) {
        double X = persp__paper_quad_x[k[j]], Y = persp__paper_quad_y[k[j]];
        double u, v, q;
        eval_planes(p, X, Y, &u, &v, &q);
        rv->x[j] = (X - x0) / sx + 0.5;
        rv->y[j] = Y - y0 + 0.5;
        rv->s1[j] = u;
        rv->s2[j] = v;
        rv->q[j] = q;
        xmin = fmin(xmin, rv->x[j]), xmax = fmax(xmax, rv->x[j]);
        ymin = fmin(ymin, rv->y[j]), ymax = fmax(ymax, rv->y[j]);
    }
    r->xmin = (int)ceil(xmin - 0.5), r->xmax = (int)floor(xmax - 0.5);
    r->ymin = (int)ceil(ymin - 0.5), r->ymax = (int)floor(ymax - 0.5);
    r->scale1 = r->scale2 = (float)scale;
}

void persp__paper_quad_rational(int k0, int k1, int k2, double scale, persp_rational *r,
                                persp_rational_vertices *v)
{
    double p[9];
    paper_quad_planes(p);
    const int k[3] = {k0, k1, k2};
    rational_from_planes(p, 0.0, 1.0, 0.0, k, scale, r, v);
}

void persp__paper_quad_line(int n, double scale, persp_rational *r, persp_rational_vertices *v,
                            double *x_left, double *x_right)
{
    const double Y = PERSP_PAPER_QUAD_LINE_Y;
    double xl = 1e300, xr = -1e300;
    for (int j = 0; j < 4; j++) {
        double xa = persp__paper_quad_x[j], ya = persp__paper_quad_y[j];
        double xb = persp__paper_quad_x[(j + 1) % 4], yb = persp__paper_quad_y[(j + 1) % 4];
        if ((ya - Y) * (yb - Y) > 0.0 || ya == yb) continue;
        double x = xa + (xb - xa) * (Y - ya) / (yb - ya);
        xl = fmin(xl, x), xr = fmax(xr, x);
    }
    double p[9];
    paper_quad_planes(p);
    if (n < 2) n = 2;
    /* Triangle (c0, c1, c3) of the quad contains the whole line: its left
     * end lies on edge c0c1 and its right end is c3. */
    const int k[3] = {0, 1, 3};
    rational_from_planes(p, xl, (xr - xl) / (double)(n - 1), Y, k, scale, r, v);
    r->xmin = 0, r->xmax = n - 1, r->ymin = r->ymax = 0;
    if (x_left) *x_left = xl;
    if (x_right) *x_right = xr;
}

uint64_t persp__rng_next(persp_rng *r)
{
    /* splitmix64 (Steele, Lea, Flood 2014). */
    uint64_t z = (r->s += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

double persp__rng_uniform(persp_rng *r, double lo, double hi)
{
    return lo + (hi - lo) * ((double)(persp__rng_next(r) >> 11) * (1.0 / 9007199254740992.0));
}

uint64_t persp__tri_pixels(const persp_tri *t)
{
    uint64_t n = 0;
    for (int y = t->ymin; y <= t->ymax; y++) {
        int lo, hi;
        if (persp__tri_row_range(t, y, t->xmin, t->xmax, &lo, &hi)) n += (uint64_t)(hi - lo + 1);
    }
    return n;
}

uint64_t persp__random_triangle(persp_rng *rng, double hbar, persp_tri *t, persp_rational_vertices *rv,
                                float attr[3][PERSP_A_COUNT])
{
    const double W = PERSP_RT_WIDTH, H = PERSP_RT_HEIGHT, aspect = W / H;
    /* Corridor projection (docs/WORKLOADS.md): glFrustum with t = n·tan 30°,
     * n = 0.1, f = 100; eye x at depth d projects to x/(tan30°·a·d). */
    const double tn = tan(30.0 * 3.14159265358979323846 / 180.0), n = 0.1, f = 100.0;
    for (int attempt = 0; attempt < 1000; attempt++) {
        double dnear = persp__rng_uniform(rng, 0.5, 10.0);
        double d[3] = {dnear, dnear * hbar, persp__rng_uniform(rng, dnear, dnear * hbar)};
        /* Random vertex order, so the nearest vertex is not always first. */
        for (int i = 2; i > 0; i--) {
            int j = (int)(persp__rng_next(rng) % (uint64_t)(i + 1));
            double tmp = d[i];
            d[i] = d[j];
            d[j] = tmp;
        }
        /* Screen size log-uniform so pixel counts spread over 100..100000. */
        double radius = exp(persp__rng_uniform(rng, log(6.0), log(380.0)));
        double cx = persp__rng_uniform(rng, 0.0, W), cy = persp__rng_uniform(rng, 0.0, H);
        persp_winvert v[3];
        int inside = 1;
        for (int i = 0; i < 3; i++) {
            double th = persp__rng_uniform(rng, 0.0, 2.0 * 3.14159265358979323846);
            double rr = radius * persp__rng_uniform(rng, 0.4, 1.0);
            double wx = cx + rr * cos(th), wy = cy + rr * sin(th);
            if (wx < 0.0 || wx > W || wy < 0.0 || wy > H) inside = 0;
            /* The eye-space point at depth d[i] that projects to (wx, wy). */
            double xe = (2.0 * wx / W - 1.0) * tn * aspect * d[i];
            double ye = (2.0 * wy / H - 1.0) * tn * d[i];
            double ndc_z = ((f + n) * d[i] - 2.0 * f * n) / ((f - n) * d[i]);
            v[i].x = (xe / (tn * aspect * d[i]) + 1.0) * 0.5 * W;
            v[i].y = (ye / (tn * d[i]) + 1.0) * 0.5 * H;
            v[i].z = 0.5 * (ndc_z + 1.0);
            v[i].q = 1.0 / d[i];
            memset(attr[i], 0, sizeof(float) * PERSP_A_COUNT);
            attr[i][PERSP_A_U] = (float)persp__rng_uniform(rng, 0.0, 1.0);
            attr[i][PERSP_A_V] = (float)persp__rng_uniform(rng, 0.0, 1.0);
            v[i].attr = attr[i];
        }
        if (!inside) continue;
        if (!persp__setup_triangle(v, (int)W, (int)H, 0, t, rv)) continue;
        uint64_t px = persp__tri_pixels(t);
        if (px < PERSP_RT_MIN_PIXELS || px > PERSP_RT_MAX_PIXELS) continue;
        t->rat.scale1 = t->rat.scale2 = 256.0f;
        return px;
    }
    return 0;
}
