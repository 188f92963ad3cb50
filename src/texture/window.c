/*
 * Anisotropic filtering over a rotated rectangular window ([Romanyuk-PCF] §4.8).
 *
 * The pixel's footprint in the texture is the parallelogram spanned by the
 * Jacobian's columns P1 = d(u,v)/dx and P2 = d(u,v)/dy (§4.8, Fig. 4.15). It
 * is replaced by the rectangle aligned with the longer column: length
 * |Pmax|, width |det J| / |Pmax| (the parallelogram's height over that side,
 * so the area is kept). The mip level is the nearest to lambda' - 1, with
 * lambda' = log2(|Pmax| / min(ceil(|Pmax| / width), N)) the level of
 * EXT_texture_filter_anisotropic for N = max_aniso, so the window is at
 * most about 2·N texels long and two to four texels wide there.
 *
 * The window is a digital rectangle: each row is the digital line of the
 * major axis (a sequence of axial and diagonal unit steps, produced by one
 * Bresenham interpolator), and the rows are offset from one another by the
 * same step sequence rotated by 90 degrees — the sides AB and AC of
 * Fig. 4.16 have the same inclination, so their step increments coincide up
 * to the swap of components and a sign. The traversal is the §4.8
 * "daisy-chain" (Fig. 4.17, 4.18): row 1 is walked from A to B while the
 * step pattern is memorised; at the end of row i the i-th memorised step,
 * rotated, moves to the next row, which is walked back in the opposite
 * direction; and so on. Only one interpolator is ever running.
 *
 * persp__window_visit() lists the texels of that traversal and of a direct
 * traversal (every texel computed as A + P(i) + Q(r) in closed form), so the
 * tests can show that both visit the same texels. The colour is the box
 * average of the visited texels.
 */
#include "texture/sample.h"

#include <math.h>

/* Slope resolution of the digital line: dy/dx with dx = WINDOW_DX. */
#define WINDOW_DX 4096

/* Direction of memorised step k (1-based) of the pattern. */
static inline void window_step(const persp_tex_window *w, int diagonal, int *x, int *y)
{
    if (w->x_major) {
        *x = w->sx;
        *y = diagonal ? w->sy : 0;
    } else {
        *x = diagonal ? w->sx : 0;
        *y = w->sy;
    }
}

/* Bresenham in integers: after step k the minor coordinate is
 * floor((2·k·dy + dx) / (2·dx)), so the step is diagonal exactly when the
 * running numerator passes a multiple of 2·dx. */
static inline uint64_t window_pattern(const persp_tex_window *w, int steps)
{
    uint64_t bits = 0;
    int num = w->dx, two_dx = 2 * w->dx, two_dy = 2 * w->dy;
    for (int k = 1; k <= steps; k++) {
        num += two_dy;
        if (num >= two_dx) {
            num -= two_dx;
            bits |= (uint64_t)1 << k;
        }
    }
    return bits;
}

int persp__window_setup(const persp_sampler_state *st, float u, float v, float dudx, float dvdx,
                        float dudy, float dvdy, persp_tex_window *w)
{
    const persp_texture *tex = st->tex;
    int top = tex->levels - 1;
    double ux = (double)dudx * tex->width, vx = (double)dvdx * tex->height;
    double uy = (double)dudy * tex->width, vy = (double)dvdy * tex->height;
    double px2 = ux * ux + vx * vx, py2 = uy * uy + vy * vy;
    int major_x = px2 >= py2;
    double mu = major_x ? ux : uy, mv = major_x ? vx : vy;
    double len = sqrt(major_x ? px2 : py2);
    if (!(len > 1.0) || !(len < 1e30)) {
        /* Magnified along both axes (or a degenerate footprint): the
         * in-level filter alone, like every linear filter's magnification. */
        w->level = !(len < 1e30) ? top : 0;
        return 0;
    }
    double det = fabs(ux * vy - uy * vx);
    double width = det / len;
    double n = (double)st->max_aniso;
    if (width * n > len) n = ceil(len / width);
    /* One level below EXT's lambda': there the window is at least two
     * texels wide, so the box over it integrates the footprint instead of
     * point-sampling across its width (the chapter leaves the level open;
     * measured with persp accuracy --filter, docs/TEXTURES.md). */
    float lam = persp__clamp_lod(st, (float)log2(len / n) - 1.0f + st->lod_bias);
    int level = 0;
    if (lam > 0.5f) {
        float d = ceilf(lam + 0.5f) - 1.0f;
        level = d >= (float)top ? top : (int)d;
    }
    const persp_tex_level *lv = &tex->level[level];
    double sx = (double)lv->w / tex->width, sy = (double)lv->h / tex->height;
    mu *= sx;
    mv *= sy;
    double llen = sqrt(mu * mu + mv * mv);
    double lwidth = llen > 0.0 ? det * sx * sy / llen : 0.0;
    double amu = fabs(mu), amv = fabs(mv);
    w->x_major = amu >= amv;
    w->sx = mu < 0.0 ? -1 : 1;
    w->sy = mv < 0.0 ? -1 : 1;
    double t = w->x_major ? (amu > 0.0 ? amv / amu : 0.0) : (amv > 0.0 ? amu / amv : 0.0);
    w->dx = WINDOW_DX;
    w->dy = (int)lround(t * WINDOW_DX);
    if (w->dy > WINDOW_DX) w->dy = WINDOW_DX;
    /* Each unit step of the digital line advances sqrt(1 + t²) texels. */
    double step = sqrt(1.0 + t * t);
    double cap = 2.0 * st->max_aniso + 1.0;
    double nl = floor(llen / step + 0.5), nr = floor(lwidth / step + 0.5);
    w->len = nl < 1.0 ? 1 : nl > cap ? (int)cap : (int)nl;
    w->rows = nr < 1.0 ? 1 : nr > cap ? (int)cap : (int)nr;
    w->level = level;
    /* Start corner A: the texel holding the point that lies half the window
     * back from (u, v) along both of its sides (the sides' mean directions,
     * P = (sx, sy·t) for an x-major line and Q = P rotated by +90 degrees),
     * so the window is centred on the footprint to within the digital
     * lines' rounding. */
    double ex = (double)persp__tex_safe(u * (float)lv->w), ey = (double)persp__tex_safe(v * (float)lv->h);
    double px = w->x_major ? w->sx : w->sx * t, py = w->x_major ? w->sy * t : w->sy;
    double hl = 0.5 * (w->len - 1), hr = 0.5 * (w->rows - 1);
    w->x0 = (int)floor(ex - hl * px + hr * py);
    w->y0 = (int)floor(ey - hl * py - hr * px);
    return 1;
}

/* The daisy-chain traversal. With xy == NULL it accumulates the texels of
 * the level into acc (the sampler); otherwise it records their indices
 * (tests). The pattern is produced once by the interpolator and replayed
 * forwards and backwards; row transitions use its r-th step rotated. */
static inline size_t daisy_walk(const persp_sampler_state *st, const persp_tex_window *w, int ws,
                                int wt, float acc[4], int *xy, size_t cap)
{
    const persp_tex_level *lv = &st->tex->level[w->level];
    int steps = (w->len > w->rows ? w->len : w->rows) - 1;
    uint64_t pattern = window_pattern(w, steps);
    int x = w->x0, y = w->y0;
    size_t count = 0;
    for (int r = 0; r < w->rows; r++) {
        int forward = (r & 1) == 0;
        for (int i = 0; i < w->len; i++) {
            if (i > 0) {
                int k = forward ? i : w->len - i;
                int ddx, ddy;
                window_step(w, (int)(pattern >> k & 1u), &ddx, &ddy);
                x += forward ? ddx : -ddx;
                y += forward ? ddy : -ddy;
            }
            if (xy) {
                if (count < cap) {
                    xy[2 * count] = x;
                    xy[2 * count + 1] = y;
                }
            } else {
                persp__acc(acc, persp__texel(st, lv, ws, wt, x, y), 1.0f);
            }
            count++;
        }
        if (r + 1 < w->rows) {
            int ddx, ddy;
            window_step(w, (int)(pattern >> (r + 1) & 1u), &ddx, &ddy);
            x += -ddy;
            y += ddx;
        }
    }
    return count;
}

/* Direct traversal: texel (i, r) = A + P(i) + Q(r) with P from the closed
 * form of the digital line, no interpolator state carried between texels. */
static size_t direct_walk(const persp_tex_window *w, int *xy, size_t cap)
{
    size_t count = 0;
    for (int r = 0; r < w->rows; r++) {
        int pr = (int)(((int64_t)2 * r * w->dy + w->dx) / ((int64_t)2 * w->dx));
        int qx = w->x_major ? -w->sy * pr : -w->sy * r;
        int qy = w->x_major ? w->sx * r : w->sx * pr;
        for (int i = 0; i < w->len; i++) {
            int pi = (int)(((int64_t)2 * i * w->dy + w->dx) / ((int64_t)2 * w->dx));
            int px = w->x_major ? w->sx * i : w->sx * pi;
            int py = w->x_major ? w->sy * pi : w->sy * i;
            if (count < cap) {
                xy[2 * count] = w->x0 + px + qx;
                xy[2 * count + 1] = w->y0 + py + qy;
            }
            count++;
        }
    }
    return count;
}

size_t persp__window_visit(const persp_sampler_state *st, const persp_tex_window *w, int daisy,
                           int *xy, size_t cap)
{
    if (!xy) return (size_t)w->len * (size_t)w->rows;
    if (!daisy) return direct_walk(w, xy, cap);
    return daisy_walk(st, w, PERSP_WRAP_REPEAT, PERSP_WRAP_REPEAT, NULL, xy, cap);
}

static inline void span_window(const persp_sampler_state *st, const persp_tex_span_in *in,
                               uint32_t *out, int ws, int wt)
{
    float W = (float)st->tex->width, H = (float)st->tex->height;
    for (int k = 0; k < in->n; k++) {
        persp_tex_jac j = persp__span_jacobian(st, in, k);
        persp_tex_window w;
        float c[4] = {0.0f, 0.0f, 0.0f, 0.0f};
        if (persp__window_setup(st, in->u[k], in->v[k], j.ux / W, j.vx / H, j.uy / W, j.vy / H,
                                &w)) {
            size_t n = daisy_walk(st, &w, ws, wt, c, NULL, 0);
            float inv = 1.0f / (float)n;
            for (int m = 0; m < 4; m++) c[m] *= inv;
        } else {
            persp__bilinear(st, w.level, ws, wt, in->u[k], in->v[k], c);
        }
        out[k] = persp__pack(c);
    }
}

#define SPAN_WINDOW(NAME, WS, WT)                                                               \
    static void NAME(const persp_sampler_state *st, const persp_tex_span_in *in, uint32_t *out) \
    {                                                                                           \
        span_window(st, in, out, WS, WT);                                                       \
    }
#define R PERSP_WRAP_REPEAT
#define E PERSP_WRAP_CLAMP_TO_EDGE
#define M PERSP_WRAP_MIRRORED_REPEAT
#define B PERSP_WRAP_CLAMP_TO_BORDER
SPAN_WINDOW(win_RR, R, R) SPAN_WINDOW(win_RE, R, E) SPAN_WINDOW(win_RM, R, M)
SPAN_WINDOW(win_RB, R, B) SPAN_WINDOW(win_ER, E, R) SPAN_WINDOW(win_EE, E, E)
SPAN_WINDOW(win_EM, E, M) SPAN_WINDOW(win_EB, E, B) SPAN_WINDOW(win_MR, M, R)
SPAN_WINDOW(win_ME, M, E) SPAN_WINDOW(win_MM, M, M) SPAN_WINDOW(win_MB, M, B)
SPAN_WINDOW(win_BR, B, R) SPAN_WINDOW(win_BE, B, E) SPAN_WINDOW(win_BM, B, M)
SPAN_WINDOW(win_BB, B, B)
#undef R
#undef E
#undef M
#undef B

const persp_tex_span_fn persp__window_spans[16] = {
    win_RR, win_RE, win_RM, win_RB, win_ER, win_EE, win_EM, win_EB,
    win_MR, win_ME, win_MM, win_MB, win_BR, win_BE, win_BM, win_BB};
