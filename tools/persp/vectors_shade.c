/* persp vectors --module window_one | window_two | tw_exact | tw_quadratic |
 * tw_pwquad | tw_cubic: the vectors of the RTL of [Romanyuk-PCF] §4.8 (the
 * rotated footprint window) and §4.3 (t_w along a span) from their C models
 * (src/analysis/hw_models_shade.c; formats in docs/HARDWARE.md, "Vectors"),
 * with each model's error against the exact computation in double and
 * against persp's float method. The triangles and their spans are those of
 * the other modules (persp_midpoint_trace), so every module sees the same
 * pixels. */
#include "options.h"

#include "../../src/analysis/hw_models.h"

#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static const char *const shade_modules[] = {"window_one", "window_two", "tw_exact",
                                            "tw_quadratic", "tw_pwquad", "tw_cubic"};
enum { N_SHADE = (int)(sizeof shade_modules / sizeof shade_modules[0]) };

/* The max_aniso the windows are made for (persp's aniso-window:16). */
enum { WINDOW_ANISO = PERSP_MAX_ANISO };

int vectors_shade_module(const char *name)
{
    for (int k = 0; k < N_SHADE; k++)
        if (!strcmp(name, shade_modules[k])) return 1;
    return 0;
}

typedef struct shade_out {
    FILE *f;
    int window; /* 0: t_w */
    persp_hw_tw_kind kind;
    int two; /* window_two */
    long spans, pixels, hw_items, outside, texels, set_diffs;
    double err_model, err_float; /* max |Δt_w| or texel position error */
    int *xy, *ij, *xy2;          /* window scratch: PERSP_HW_WINDOW_MAX² texels */
} shade_out;

/* The window of one pixel: its texels in the module's order, each texel's
 * distance (max norm) from the exact rotated rectangle's point (i, r) of the
 * unquantised slope, and whether the set equals the other traversal's. */
static void put_window(shade_out *o, const double J[4], double u, double v)
{
    persp_hw_window w;
    int level;
    if (!persp__hw_window_setup(J, u, v, WINDOW_ANISO, &w, &level)) {
        o->outside++;
        return;
    }
    const size_t cap = (size_t)PERSP_HW_WINDOW_MAX * PERSP_HW_WINDOW_MAX;
    const size_t n = o->two ? persp__hw_window_two(&w, o->xy, o->ij, cap) : persp__hw_window_one(&w, o->xy, o->ij, cap);
    const size_t n2 = o->two ? persp__hw_window_one(&w, o->xy2, NULL, cap) : persp__hw_window_two(&w, o->xy2, NULL, cap);
    fprintf(o->f, "win %d %d %d %d %d %d %d %d %d\n", w.x0, w.y0, w.x_major, w.sx, w.sy, w.dy, w.len, w.rows, level);
    o->hw_items++;
    /* The exact corner and sides (window.c's centring, slope t unrounded). */
    const double sc = ldexp(1.0, -level), t = w.t;
    const double px = w.x_major ? w.sx : w.sx * t, py = w.x_major ? w.sy * t : w.sy;
    const double hl = 0.5 * (w.len - 1), hr = 0.5 * (w.rows - 1);
    const double ax = u * sc - hl * px + hr * py, ay = v * sc - hl * py - hr * px;
    const double fx = floor(ax), fy = floor(ay);
    int differs = n != n2;
    for (size_t k = 0; k < n; k++) {
        const int x = o->xy[2 * k], y = o->xy[2 * k + 1], i = o->ij[2 * k], r = o->ij[2 * k + 1];
        fprintf(o->f, "wt %d %d\n", x, y);
        /* The texel holding A is the corner; from there the exact sides. */
        const double ex = fx + 0.5 + i * px - r * py, ey = fy + 0.5 + i * py + r * px;
        const double e = fmax(fabs(x + 0.5 - ex), fabs(y + 0.5 - ey));
        if (e > o->err_model) o->err_model = e;
        int found = 0;
        for (size_t m = 0; m < n2 && !found; m++) found = o->xy2[2 * m] == x && o->xy2[2 * m + 1] == y;
        if (!found) differs = 1;
    }
    o->texels += (long)n;
    if (differs) o->set_diffs++;
}

static void put_tw_span(shade_out *o, double q0, double q1, int x0, int y, int n)
{
    persp_hw_tw_span s;
    int64_t t[PERSP_HW_TW_MAXN];
    float fl[PERSP_HW_TW_MAXN];
    const int hw = persp__hw_tw_setup(o->kind, q0, q1, n, &s);
    fprintf(o->f, "twspan %d %d %d %d %d %" PRId64 " %" PRId64 " %" PRId64 " %" PRId64 " %" PRId64 " %" PRId64
                  " %" PRId64 "\n",
            x0, y, n, hw, s.m, s.a[0], s.a[1], s.a[2], s.a[3], s.b[0], s.b[1], s.b[2]);
    o->spans++, o->pixels += n;
    if (!hw) {
        o->outside++;
        return;
    }
    persp__hw_tw_run(o->kind, &s, t);
    persp__hw_tw_float(o->kind, q0, q1, n, fl);
    const int L = n - 1;
    for (int k = 0; k < n; k++) {
        fprintf(o->f, "twpx %" PRId64 "\n", t[k]);
        const double ex = L ? (double)k * q1 / ((double)(L - k) * q0 + (double)k * q1) : 0.0;
        const double em = fabs(ldexp((double)t[k], -PERSP_HW_TW_FRAC) - ex), ef = fabs((double)fl[k] - ex);
        if (em > o->err_model) o->err_model = em;
        if (ef > o->err_float) o->err_float = ef;
    }
    o->hw_items += n;
}

static int put_triangle(persp_context *ctx, const persp_method_vertex v[3], int width, int height, int tex_w,
                        int tex_h, long index, shade_out *o)
{
    persp_midpoint_format mf;
    vectors_spans l = {NULL, 0, 0, 0};
    fprintf(o->f, "tri %ld", index);
    for (int k = 0; k < 3; k++)
        fprintf(o->f, " %a %a %a %a %a", v[k].x, v[k].y, v[k].w, (double)v[k].u, (double)v[k].v);
    fputc('\n', o->f);
    persp_status st = persp_midpoint_trace(ctx, "midpoint:int", v, width, height, tex_w, tex_h, &mf, vectors_keep_span, &l);
    if (st != PERSP_OK || l.failed) {
        free(l.s);
        return st != PERSP_OK ? cli_status(ctx, st, "vectors") : cli_error(CLI_FAIL, "vectors: out of memory");
    }
    const double *pl = mf.plane;
    for (size_t k = 0; k < l.n; k++) {
        const int x0 = l.s[k][0], y = l.s[k][1], n = l.s[k][2];
        const double py = y + 0.5;
        if (!o->window) {
            /* 1/w at the span's end pixels (the plane's scale cancels in t_w). */
            double q0 = pl[6] * (x0 + 0.5) + pl[7] * py + pl[8], q1 = pl[6] * (x0 + n - 0.5) + pl[7] * py + pl[8];
            if (q0 < 0.0 && q1 < 0.0) q0 = -q0, q1 = -q1;
            put_tw_span(o, q0, q1, x0, y, n);
            continue;
        }
        o->spans++, o->pixels += n;
        for (int i = 0; i < n; i++) {
            /* The footprint's Jacobian at the pixel centre, texels of level 0:
             * d(P·N/E)/dx = P·(a·E − g·N)/E². */
            const double px = x0 + i + 0.5, E = pl[6] * px + pl[7] * py + pl[8];
            double J[4], uv[2];
            for (int j = 0; j < 2; j++) {
                const double N = pl[3 * j] * px + pl[3 * j + 1] * py + pl[3 * j + 2];
                uv[j] = mf.P[j] * N / E;
                J[j] = mf.P[j] * (pl[3 * j] * E - pl[6] * N) / (E * E);
                J[2 + j] = mf.P[j] * (pl[3 * j + 1] * E - pl[7] * N) / (E * E);
            }
            put_window(o, J, uv[0], uv[1]);
        }
    }
    free(l.s);
    return CLI_OK;
}

static int shade_triangle(persp_context *ctx, const vectors_job *job, const persp_method_vertex v[3], long index,
                          FILE *f, void *state)
{
    shade_out *o = state;
    o->f = f;
    return put_triangle(ctx, v, job->width, job->height, job->tex_w, job->tex_h, index, o);
}

static void shade_footer(FILE *f, long index, void *state)
{
    const shade_out *o = state;
    if (o->window)
        fprintf(f, "# %ld triangles, %ld spans, %ld pixels, %ld windows (%ld pixels magnify or leave the format), "
                   "%ld texels, max texel position error %.9f texels, %ld windows whose texel set differs from "
                   "the other traversal's\n",
                index, o->spans, o->pixels, o->hw_items, o->outside, o->texels, o->err_model, o->set_diffs);
    else
        fprintf(f, "# %ld triangles, %ld spans, %ld pixels (%ld in the hardware, %ld spans outside the format), "
                   "max |dtw| model %.9f, max |dtw| float method %.9f\n",
                index, o->spans, o->pixels, o->hw_items, o->outside, o->err_model, o->err_float);
}

static void shade_summary(long index, const char *output, void *state)
{
    const shade_out *o = state;
    fprintf(stderr, "persp: vectors: %ld triangles, %ld spans, %ld %s to %s\n", index, o->spans,
            o->window ? o->texels : o->hw_items, o->window ? "texels" : "pixels", output);
}

int vectors_shade(const vectors_job *job)
{
    const char *module = job->module;
    shade_out o;
    memset(&o, 0, sizeof o);
    o.window = !strncmp(module, "window_", 7);
    o.two = !strcmp(module, "window_two");
    o.kind = !strcmp(module, "tw_quadratic") ? PERSP_HW_TW_QUAD
             : !strcmp(module, "tw_pwquad")  ? PERSP_HW_TW_PWQUAD
             : !strcmp(module, "tw_cubic")   ? PERSP_HW_TW_CUBIC
                                             : PERSP_HW_TW_EXACT;
    if (o.window) {
        const size_t cap = (size_t)PERSP_HW_WINDOW_MAX * PERSP_HW_WINDOW_MAX * 2;
        o.xy = malloc(cap * sizeof *o.xy), o.ij = malloc(cap * sizeof *o.ij), o.xy2 = malloc(cap * sizeof *o.xy2);
        if (!o.xy || !o.ij || !o.xy2) {
            free(o.xy), free(o.ij), free(o.xy2);
            return cli_error(CLI_FAIL, "vectors: out of memory");
        }
    }
    vectors_writer w = {"", shade_triangle, shade_footer, shade_summary, &o};
    snprintf(w.title, sizeof w.title, "# persp test vectors of the RTL module %s, format 1 (docs/HARDWARE.md, \"Vectors\")",
             module);
    int rc = vectors_run(job, &w);
    free(o.xy), free(o.ij), free(o.xy2);
    return rc;
}
