/*
 * C models of hw/rtl/window_one.v, window_two.v ([Romanyuk-PCF] §4.8) and
 * tw_exact.v, tw_quadratic.v, tw_pwquad.v, tw_cubic.v (§4.3); declarations
 * and formats in hw_models.h and docs/HARDWARE.md. Every integer step here
 * is one the Verilog makes, in the same order.
 */
#include "hw_models.h"

#include "interp/poly.h"

#include <math.h>
#include <string.h>

/* ----------------------------------------------------------- the windows */

int persp__hw_window_setup(const double J[4], double u, double v, int max_aniso, persp_hw_window *w, int *level)
{
    memset(w, 0, sizeof *w);
    *level = 0;
    /* persp__window_setup (src/texture/window.c) with the level's size
     * 2^-level of level 0's: the same major axis, mip level nearest to
     * lambda' − 1, slope, length, rows and corner. */
    const double ux = J[0], vx = J[1], uy = J[2], vy = J[3];
    const double px2 = ux * ux + vx * vx, py2 = uy * uy + vy * vy;
    const int major_x = px2 >= py2;
    double mu = major_x ? ux : uy, mv = major_x ? vx : vy;
    const double len = sqrt(major_x ? px2 : py2);
    if (!(len > 1.0) || !(len < 1e30) || max_aniso < 1) return 0;
    const double det = fabs(ux * vy - uy * vx), width = det / len;
    double n = (double)max_aniso;
    if (width * n > len) n = ceil(len / width);
    const double lam = log2(len / n) - 1.0;
    int lv = 0;
    if (lam > 0.5) lv = (int)(ceil(lam + 0.5) - 1.0);
    if (lv > 20) return 0;
    const double sc = ldexp(1.0, -lv);
    mu *= sc, mv *= sc;
    const double llen = sqrt(mu * mu + mv * mv), lwidth = llen > 0.0 ? det * sc * sc / llen : 0.0;
    const double amu = fabs(mu), amv = fabs(mv);
    w->x_major = amu >= amv;
    w->sx = mu < 0.0 ? -1 : 1;
    w->sy = mv < 0.0 ? -1 : 1;
    const double t = w->x_major ? (amu > 0.0 ? amv / amu : 0.0) : (amv > 0.0 ? amu / amv : 0.0);
    w->t = t;
    w->dy = (int)lround(t * PERSP_HW_WINDOW_DX);
    if (w->dy > PERSP_HW_WINDOW_DX) w->dy = PERSP_HW_WINDOW_DX;
    const double step = sqrt(1.0 + t * t), cap = 2.0 * max_aniso + 1.0;
    const double nl = floor(llen / step + 0.5), nr = floor(lwidth / step + 0.5);
    if (cap > PERSP_HW_WINDOW_MAX) return 0;
    w->len = nl < 1.0 ? 1 : nl > cap ? (int)cap : (int)nl;
    w->rows = nr < 1.0 ? 1 : nr > cap ? (int)cap : (int)nr;
    const double ex = u * sc, ey = v * sc;
    const double px = w->x_major ? w->sx : w->sx * t, py = w->x_major ? w->sy * t : w->sy;
    const double hl = 0.5 * (w->len - 1), hr = 0.5 * (w->rows - 1);
    const double x0 = floor(ex - hl * px + hr * py), y0 = floor(ey - hl * py - hr * px);
    /* Every texel of the window within the coordinates' bits. */
    const double lim = ldexp(1.0, PERSP_HW_WINDOW_XBITS - 1) - 2.0 * PERSP_HW_WINDOW_MAX;
    if (!(fabs(x0) < lim) || !(fabs(y0) < lim)) return 0;
    w->x0 = (int)x0, w->y0 = (int)y0;
    *level = lv;
    return 1;
}

/* The unit step of the digital line along the major axis: axial, or
 * diagonal when the pattern's bit is set (window.c's window_step). */
static void hw_step(const persp_hw_window *w, int diagonal, int *x, int *y)
{
    *x = w->x_major ? w->sx : diagonal ? w->sx : 0;
    *y = w->x_major ? (diagonal ? w->sy : 0) : w->sy;
}

/* One Bresenham step: the running numerator passes 2·dx exactly when the
 * minor coordinate floor((2k·dy + dx) / (2dx)) grows (window.c). */
static int hw_bresenham(int *num, int dy)
{
    *num += 2 * dy;
    if (*num >= 2 * PERSP_HW_WINDOW_DX) {
        *num -= 2 * PERSP_HW_WINDOW_DX;
        return 1;
    }
    return 0;
}

static void hw_put(int *xy, int *ij, size_t cap, size_t k, int x, int y, int i, int r)
{
    if (k >= cap) return;
    if (xy) xy[2 * k] = x, xy[2 * k + 1] = y;
    if (ij) ij[2 * k] = i, ij[2 * k + 1] = r;
}

size_t persp__hw_window_one(const persp_hw_window *w, int *xy, int *ij, size_t cap)
{
    /* The interpolator runs once, one step per clock from the load, and
     * each step's bit is remembered: bit k is produced in clock k − 1 and
     * is never needed earlier (row 0 uses bit i for its texel i, row r's
     * end uses bit r + 1 ≤ its clock), §4.8 "daisy chain". */
    const int steps = (w->len > w->rows ? w->len : w->rows) - 1;
    uint64_t pat = 0;
    int num = PERSP_HW_WINDOW_DX;
    for (int k = 1; k <= steps; k++)
        if (hw_bresenham(&num, w->dy)) pat |= (uint64_t)1 << k;
    int x = w->x0, y = w->y0;
    size_t count = 0;
    for (int r = 0; r < w->rows; r++) {
        const int forward = (r & 1) == 0;
        for (int i = 0; i < w->len; i++) {
            if (i > 0) {
                const int k = forward ? i : w->len - i;
                int ddx, ddy;
                hw_step(w, (int)(pat >> k & 1u), &ddx, &ddy);
                x += forward ? ddx : -ddx;
                y += forward ? ddy : -ddy;
            }
            hw_put(xy, ij, cap, count++, x, y, forward ? i : w->len - 1 - i, r);
        }
        if (r + 1 < w->rows) {
            /* The row's offset: the (r + 1)-th remembered step rotated by
             * +90 degrees (AB and AC have the same inclination, Fig. 4.16). */
            int ddx, ddy;
            hw_step(w, (int)(pat >> (r + 1) & 1u), &ddx, &ddy);
            x += -ddy;
            y += ddx;
        }
    }
    return count;
}

size_t persp__hw_window_two(const persp_hw_window *w, int *xy, int *ij, size_t cap)
{
    /* The baseline: one interpolator along each side, the row's restarted
     * at every row, the column's stepped once a row. */
    int xr = w->x0, yr = w->y0, numr = PERSP_HW_WINDOW_DX;
    size_t count = 0;
    for (int r = 0; r < w->rows; r++) {
        int x = xr, y = yr, numi = PERSP_HW_WINDOW_DX;
        for (int i = 0; i < w->len; i++) {
            hw_put(xy, ij, cap, count++, x, y, i, r);
            if (i + 1 < w->len) {
                int ddx, ddy;
                hw_step(w, hw_bresenham(&numi, w->dy), &ddx, &ddy);
                x += ddx, y += ddy;
            }
        }
        if (r + 1 < w->rows) {
            int ddx, ddy;
            hw_step(w, hw_bresenham(&numr, w->dy), &ddx, &ddy);
            xr += -ddy, yr += ddx;
        }
    }
    return count;
}

/* ---------------------------------------------------------------- t_w */

/* Floor division by 2^k without the implementation-defined >> of negative values. */
static int64_t tw_asr(int64_t v, int k) { return v >= 0 ? v >> k : -(((-v) + ((int64_t)1 << k) - 1) >> k); }

static int tw_fits(int64_t v) { return v < ((int64_t)1 << (PERSP_HW_TW_DBITS - 1)) && v >= -((int64_t)1 << (PERSP_HW_TW_DBITS - 1)); }

/* Fits the polynomial through t_w at the nodes and quantises its forward
 * differences at pixel k0 (step 1) to DFRAC fraction bits. */
static int tw_piece(const persp_rat1 *f, const double *nodes, int count, int k0, int64_t *d)
{
    double y[4];
    for (int j = 0; j < count; j++) y[j] = persp__rat1_eval(f, nodes[j]);
    persp_poly p;
    persp_fd fd;
    persp__poly_interp(nodes, y, count, &p, NULL);
    persp__fd_init(&p, (double)k0, 1.0, &fd, NULL);
    for (int j = 0; j < count; j++) {
        const double x = ldexp(fd.d[j], PERSP_HW_TW_DFRAC);
        if (!(fabs(x) < ldexp(1.0, PERSP_HW_TW_DBITS - 1))) return 0;
        d[j] = (int64_t)llround(x);
    }
    return 1;
}

int persp__hw_tw_setup(persp_hw_tw_kind kind, double q0, double q1, int n, persp_hw_tw_span *s)
{
    memset(s, 0, sizeof *s);
    if (n < 1 || n > PERSP_HW_TW_MAXN || !(q0 > 0.0) || !(q1 > 0.0) || !isfinite(q0) || !isfinite(q1)) return 0;
    s->n = n;
    const int L = n - 1;
    if (kind == PERSP_HW_TW_EXACT) {
        /* q0, q1 normalised together to 16 bits: only their ratio matters. */
        int e;
        (void)frexp(q0 > q1 ? q0 : q1, &e);
        for (int j = 0; j < 2; j++) {
            int64_t Q = (int64_t)llround(ldexp(j ? q1 : q0, PERSP_HW_TW_QBITS - e));
            s->a[j] = Q < 1 ? 1 : Q > 65535 ? 65535 : Q;
        }
        return 1;
    }
    if (L == 0) return 1; /* t_w(0) = 0: all differences zero */
    /* t_w(k) = k·q1 / (L·q0 + k·(q1 − q0)): persp_rat1 in k. */
    const persp_rat1 f = {q1, 0.0, q1 - q0, (double)L * q0};
    const double Ld = (double)L;
    int ok;
    if (kind == PERSP_HW_TW_CUBIC) {
        const double nodes[4] = {0.0, Ld / 3.0, 2.0 * Ld / 3.0, Ld};
        ok = tw_piece(&f, nodes, 4, 0, s->a);
    } else if (kind == PERSP_HW_TW_PWQUAD) {
        const double a[3] = {0.0, Ld / 4.0, Ld / 2.0}, b[3] = {Ld / 2.0, 3.0 * Ld / 4.0, Ld};
        s->m = L / 2;
        ok = tw_piece(&f, a, 3, 0, s->a) && tw_piece(&f, b, 3, s->m + 1, s->b);
    } else {
        const double nodes[3] = {0.0, Ld / 2.0, Ld};
        ok = tw_piece(&f, nodes, 3, 0, s->a);
    }
    if (!ok) return 0;
    /* Every register stays within its bits along the whole span. */
    int64_t d[4] = {s->a[0], s->a[1], s->a[2], s->a[3]};
    for (int k = 0; k < n; k++) {
        if (kind == PERSP_HW_TW_PWQUAD && k == s->m + 1) d[0] = s->b[0], d[1] = s->b[1], d[2] = s->b[2], d[3] = 0;
        for (int j = 0; j < 4; j++)
            if (!tw_fits(d[j])) return 0;
        d[0] += d[1], d[1] += d[2], d[2] += d[3];
    }
    return 1;
}

void persp__hw_tw_run(persp_hw_tw_kind kind, const persp_hw_tw_span *s, int64_t *out)
{
    const int64_t one = (int64_t)1 << PERSP_HW_TW_FRAC;
    if (kind == PERSP_HW_TW_EXACT) {
        /* N = k·Q1 and D = (L − k)·Q0 + k·Q1 stepped by additions; one
         * restoring division per pixel, N ≤ D so t_w ≤ 1 (17 quotient bits). */
        const int64_t Q0 = s->a[0], Q1 = s->a[1];
        int64_t N = 0, D = (int64_t)(s->n - 1) * Q0;
        for (int k = 0; k < s->n; k++) {
            out[k] = D ? (N << PERSP_HW_TW_FRAC) / D : 0;
            N += Q1, D += Q1 - Q0;
        }
        return;
    }
    /* Forward differences: additions only (§4.3); the output is d0's top
     * bits, clamped to [0, 1] (the polynomial may overshoot by its error). */
    int64_t d[4] = {s->a[0], s->a[1], s->a[2], s->a[3]};
    for (int k = 0; k < s->n; k++) {
        if (kind == PERSP_HW_TW_PWQUAD && k == s->m + 1) d[0] = s->b[0], d[1] = s->b[1], d[2] = s->b[2], d[3] = 0;
        const int64_t t = tw_asr(d[0], PERSP_HW_TW_DFRAC - PERSP_HW_TW_FRAC);
        out[k] = t < 0 ? 0 : t > one ? one : t;
        d[0] += d[1], d[1] += d[2], d[2] += d[3];
    }
}

void persp__hw_tw_float(persp_hw_tw_kind kind, double q0, double q1, int n, float *out)
{
    const int L = n - 1;
    if (n < 1) return;
    if (L == 0) {
        out[0] = 0.0f;
        return;
    }
    const persp_rat1 f = {q1, 0.0, q1 - q0, (double)L * q0};
    if (kind == PERSP_HW_TW_EXACT) {
        for (int k = 0; k < n; k++) out[k] = (float)persp__rat1_eval(&f, (double)k);
        return;
    }
    const persp_approx_kind ak = kind == PERSP_HW_TW_CUBIC    ? PERSP_APPROX_CUBIC
                                 : kind == PERSP_HW_TW_PWQUAD ? PERSP_APPROX_PWQUAD
                                                              : PERSP_APPROX_QUAD;
    persp__approx_span(&f, ak, 0.5, n, out, NULL);
}
