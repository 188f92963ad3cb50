/* persp vectors --module subdiv, subdiv:8, incremental, quadratic, cubic,
 * bezier: the inputs and outputs of the span datapaths of hw/rtl from their
 * C models (src/analysis/hw_models_span.c; formats in docs/HARDWARE.md,
 * "Vectors"), on the spans of persp_midpoint_trace (the renderer's), so
 * every module's vectors cover the same pixels as exact's. Each file ends
 * with the model's max error against the rational form and the float
 * method's on the same pixels. */
#include "options.h"

#include "../../src/analysis/hw_models.h"

#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { SPAN_MAX = 64 }; /* the renderer's spans: one row of a 64-pixel tile */
enum { SP_SUBDIV, SP_INCREMENTAL, SP_QUADRATIC, SP_CUBIC, SP_BEZIER };

static const struct {
    const char *name, *method; /* the module, the float method it implements */
    int kind, step;
} span_modules[] = {
    {"subdiv", "subdiv:16", SP_SUBDIV, 16},           {"subdiv:8", "subdiv:8", SP_SUBDIV, 8},
    {"incremental", "incremental:bidir", SP_INCREMENTAL, 0}, {"quadratic", "quadratic", SP_QUADRATIC, 0},
    {"cubic", "cubic", SP_CUBIC, 0},                  {"bezier", "bezier:quadt", SP_BEZIER, 0},
};
enum { N_SPAN = (int)(sizeof span_modules / sizeof span_modules[0]) };

static int span_index(const char *name)
{
    for (int k = 0; k < N_SPAN; k++)
        if (!strcmp(name, span_modules[k].name)) return k;
    return -1;
}

int vectors_span_module(const char *name) { return span_index(name) >= 0; }

typedef struct span_out {
    FILE *f;
    int mod;
    long spans, outside, pixels, hw_pixels, ovf_pixels;
    double err_model[2], err_float[2]; /* texels, against the rational form in double */
    float *fu, *fv;                    /* the float method's outputs, width × height */
} span_out;

/* The error of the model's t (texels·2^8) and of the float method's output
 * at pixel (x, y), both against the rational form of set-up's planes. */
static void measure(span_out *o, const double *pl, const double P[2], int width, int x, int y, const int64_t t[2])
{
    const double px = x + 0.5, py = y + 0.5, q = pl[6] * px + pl[7] * py + pl[8];
    const float fl[2] = {o->fu[(size_t)y * (size_t)width + (size_t)x], o->fv[(size_t)y * (size_t)width + (size_t)x]};
    for (int j = 0; j < 2; j++) {
        const double exact = P[j] * (pl[3 * j] * px + pl[3 * j + 1] * py + pl[3 * j + 2]) / q;
        const double e = fabs(ldexp((double)t[j], -PERSP_HW_EXACT_FRAC) - exact);
        const double ef = fabs((double)fl[j] * P[j] - exact);
        if (e > o->err_model[j]) o->err_model[j] = e;
        if (ef > o->err_float[j]) o->err_float[j] = ef;
    }
}

static int put_triangle(persp_context *ctx, const persp_method_vertex v[3], int width, int height, int tex_w,
                        int tex_h, long index, span_out *o)
{
    persp_midpoint_format mf;
    vectors_spans l = {NULL, 0, 0, 0};
    fprintf(o->f, "tri %ld", index);
    for (int k = 0; k < 3; k++)
        fprintf(o->f, " %a %a %a %a %a", v[k].x, v[k].y, v[k].w, (double)v[k].u, (double)v[k].v);
    fputc('\n', o->f);
    persp_status st = persp_midpoint_trace(ctx, "midpoint:int", v, width, height, tex_w, tex_h, &mf, vectors_keep_span, &l);
    if (st == PERSP_OK && !l.failed)
        st = persp_method_triangle(ctx, span_modules[o->mod].method, v, width, height, tex_w, tex_h, o->fu, o->fv,
                                   NULL, NULL);
    if (st != PERSP_OK || l.failed) {
        free(l.s);
        return st != PERSP_OK ? cli_status(ctx, st, "vectors") : cli_error(CLI_FAIL, "vectors: out of memory");
    }
    const int kind = span_modules[o->mod].kind;
    const double *pl = mf.plane;
    persp_hw_exact_format f;
    memset(&f, 0, sizeof f);
    if (kind == SP_SUBDIV || kind == SP_INCREMENTAL) {
        int xmax = -1, ymax = -1;
        for (size_t k = 0; k < l.n; k++) {
            if (l.s[k][0] + l.s[k][2] - 1 > xmax) xmax = l.s[k][0] + l.s[k][2] - 1;
            if (l.s[k][1] > ymax) ymax = l.s[k][1];
        }
        persp__hw_exact_format(pl, mf.P, xmax, ymax, &f);
        fprintf(o->f, "xfmt %d %d %" PRId64 " %" PRId64 " %" PRId64, f.in_format, f.shift, f.G, f.H, f.I);
        for (int j = 0; j < 2; j++) fprintf(o->f, " %" PRId64 " %" PRId64 " %" PRId64, f.A[j], f.B[j], f.C[j]);
        fprintf(o->f, " %" PRId64 " %" PRId64 " %.17g %.17g\n", f.X2max, f.Y2max, mf.P[0], mf.P[1]);
    }
    for (size_t s = 0; s < l.n; s++) {
        const int x0 = l.s[s][0], y = l.s[s][1], n = l.s[s][2];
        int64_t t[SPAN_MAX][2];
        int ovf[SPAN_MAX];
        o->spans++, o->pixels += n;
        if (n > SPAN_MAX) {
            free(l.s);
            return cli_error(CLI_FAIL, "vectors: a span of %d pixels", n);
        }
        if (kind == SP_SUBDIV || kind == SP_INCREMENTAL) {
            int64_t E = 0, N2[2] = {0, 0};
            const int hw = persp__hw_exact_span(&f, x0, y, n, &E, N2);
            const int64_t G2 = 2 * f.G, A2[2] = {2 * f.A[0], 2 * f.A[1]}, L = n - 1;
            /* The end values: the right chain's start (incremental) and the
             * last node (subdiv), exact integers E0 + L·2G. */
            fprintf(o->f, "sspan %d %d %d %d %" PRId64 " %" PRId64 " %" PRId64 " %" PRId64 " %" PRId64 " %" PRId64 "\n",
                    x0, y, n, hw, hw ? E : 0, hw ? N2[0] : 0, hw ? N2[1] : 0, hw ? E + G2 * L : 0,
                    hw ? N2[0] + A2[0] * L : 0, hw ? N2[1] + A2[1] * L : 0);
            if (!hw) {
                o->outside++;
                continue;
            }
            if (kind == SP_SUBDIV)
                persp__hw_subdiv_span(span_modules[o->mod].step, E, N2, G2, A2, n, ovf, t);
            else
                persp__hw_incremental_span(E, N2, G2, A2, n, ovf, t);
        } else {
            persp_hw_fd fd;
            const persp_hw_fd_kind fk = kind == SP_QUADRATIC ? PERSP_HW_FD_QUADRATIC
                                        : kind == SP_CUBIC   ? PERSP_HW_FD_CUBIC
                                                             : PERSP_HW_FD_BEZIER;
            const int hw = persp__hw_fd_setup(fk, pl, mf.P, x0, y, n, &fd);
            fprintf(o->f, "sspan %d %d %d %d", x0, y, n, hw);
            for (int j = 0; j < 2; j++)
                for (int i = 0; i <= (int)fk; i++) fprintf(o->f, " %" PRId64, hw ? fd.d[j][i] : 0);
            fputc('\n', o->f);
            if (!hw) {
                o->outside++;
                continue;
            }
            for (int k = 0; k < n; k++) {
                ovf[k] = 0;
                persp__hw_fd_pixel(&fd, t[k]);
            }
        }
        for (int k = 0; k < n; k++) {
            fprintf(o->f, "spx %d %" PRId64 " %" PRId64 "\n", ovf[k], ovf[k] ? 0 : t[k][0], ovf[k] ? 0 : t[k][1]);
            o->hw_pixels++;
            if (ovf[k])
                o->ovf_pixels++;
            else
                measure(o, pl, mf.P, width, x0 + k, y, t[k]);
        }
    }
    free(l.s);
    return CLI_OK;
}

static int span_triangle(persp_context *ctx, const vectors_job *job, const persp_method_vertex v[3], long index,
                         FILE *f, void *state)
{
    span_out *o = state;
    o->f = f;
    return put_triangle(ctx, v, job->width, job->height, job->tex_w, job->tex_h, index, o);
}

static void span_footer(FILE *f, long index, void *state)
{
    const span_out *o = state;
    fprintf(f, "# %ld triangles, %ld spans, %ld pixels (%ld in the hardware, %ld of them out of range, "
               "%ld spans outside the format), max |du| %.9f texels, max |dv| %.9f texels; float method %s on "
               "the same pixels: u %.9f, v %.9f texels\n",
            index, o->spans, o->pixels, o->hw_pixels, o->ovf_pixels, o->outside, o->err_model[0], o->err_model[1],
            span_modules[o->mod].method, o->err_float[0], o->err_float[1]);
}

static void span_summary(long index, const char *output, void *state)
{
    const span_out *o = state;
    fprintf(stderr, "persp: vectors: %ld triangles, %ld spans, %ld pixels (%ld in the hardware) to %s\n", index,
            o->spans, o->pixels, o->hw_pixels, output);
}

int vectors_span(const vectors_job *job)
{
    span_out o;
    memset(&o, 0, sizeof o);
    o.mod = span_index(job->module);
    if (o.mod < 0) return cli_error(CLI_USAGE, "vectors: %s: not a span module", job->module);
    const size_t npx = (size_t)job->width * (size_t)job->height;
    o.fu = malloc(npx * sizeof *o.fu), o.fv = malloc(npx * sizeof *o.fv);
    if (!o.fu || !o.fv) {
        free(o.fu), free(o.fv);
        return cli_error(CLI_FAIL, "vectors: out of memory");
    }
    vectors_writer w = {"", span_triangle, span_footer, span_summary, &o};
    snprintf(w.title, sizeof w.title, "# persp test vectors of the RTL module %s, format 1 (docs/HARDWARE.md, \"Vectors\")",
             job->module);
    int rc = vectors_run(job, &w);
    free(o.fu), free(o.fv);
    return rc;
}
