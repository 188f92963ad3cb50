/* persp vectors: test vectors of midpoint:int (the fixed-point model of
 * [Romanyuk-PCF] §4.5) for simulating a hardware design against persp,
 * register by register (persp_midpoint_trace; format in docs/METHODS.md,
 * "Test vectors"), and with --module those of the other RTL modules of
 * hw/rtl, from their C models (src/analysis/hw_models.c; formats in
 * docs/HARDWARE.md, "Vectors"). */
#include "options.h"

#include "../../src/analysis/hw_models.h"

#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static void usage(FILE *out, const cli_command *cmd)
{
    fprintf(out, "usage: persp vectors [options]\n\n"
                 "Writes test vectors of midpoint:int, the fixed-point model of the\n"
                 "division-free method ([Romanyuk-PCF] Section 4.5): for each triangle its\n"
                 "vertices, set-up's planes and the fixed-point planes, then for each span its\n"
                 "start values and for each pixel the accepted lattice indices, W after the\n"
                 "search, the lattice steps taken, re-seeds and the output u, v, exactly as\n"
                 "persp_render computes them. Triangles are seeded random ones, or read from\n"
                 "--input (one triangle per line: x y w u v of each vertex, window pixels,\n"
                 "y up). The format is in docs/METHODS.md, \"Test vectors\".\n\n"
                 "--module exact writes those of the RTL baseline instead (hw/rtl/exact.v,\n"
                 "docs/HARDWARE.md): its fixed-point planes, span start values and each\n"
                 "pixel's output, with the model's error against the exact rational form.\n\n"
                 "options:\n");
    cli_print_options(out, cmd);
}

static const char *const method_names[] = {"midpoint:int", "midpoint:int,edge", NULL};
static const cli_spec opt_method = {.name = "method",
                                    .kind = CLI_KIND_STRING,
                                    .metavar = "M",
                                    .names = method_names,
                                    .help = "midpoint:int (texel centres, default) or\n"
                                            "midpoint:int,edge (the chapter's lattice)"};
static const char *const module_names[] = {"midpoint_int", "exact",      "subdiv",       "subdiv:8",
                                            "incremental",  "quadratic",  "cubic",        "bezier",
                                            "window_one",   "window_two", "tw_exact",     "tw_quadratic",
                                            "tw_pwquad",    "tw_cubic",   NULL};
static const cli_spec opt_module = {.name = "module",
                                    .kind = CLI_KIND_STRING,
                                    .metavar = "NAME",
                                    .names = module_names,
                                    .help = "the RTL module of hw/rtl the vectors are for\n"
                                            "(default midpoint_int; exact, subdiv, subdiv:8,\n"
                                            "incremental, quadratic, cubic, bezier, window_one,\n"
                                            "window_two, tw_exact, tw_quadratic, tw_pwquad,\n"
                                            "tw_cubic: docs/HARDWARE.md)"};
static const cli_spec opt_triangles = {.name = "triangles",
                                       .kind = CLI_KIND_INT,
                                       .metavar = "N",
                                       .lo = 1,
                                       .hi = 100000,
                                       .help = "random triangles (default 8)"};
static const cli_spec opt_depth_ratio = {.name = "depth-ratio",
                                         .kind = CLI_KIND_REAL,
                                         .metavar = "R",
                                         .lo = 1.0,
                                         .hi = 1.0e6,
                                         .help = "random vertices' w lie in [1, R], log-uniform\n"
                                                 "(default 8)"};
static const cli_spec opt_uv_range = {.name = "uv-range",
                                      .kind = CLI_KIND_REAL,
                                      .metavar = "R",
                                      .lo = 1.0e-3,
                                      .hi = 1.0e4,
                                      .help = "random u, v lie in [0, R] (default 1; above 1 the texture\n"
                                              "repeats, and large R reaches the format's limits)"};
static const cli_spec opt_texture_size = {.name = "texture-size",
                                          .kind = CLI_KIND_SIZE,
                                          .metavar = "WxH",
                                          .help = "texture level 0 in texels: P of u and v (default 256x256)"};
static const cli_spec opt_input = {.name = "input",
                                   .kind = CLI_KIND_STRING,
                                   .metavar = "FILE",
                                   .help = "triangles from FILE instead of random ones: 15 numbers a\n"
                                           "line (x y w u v per vertex), '#' starts a comment"};

typedef struct vec_out {
    FILE *f;
    long spans, pixels, int_pixels, reseeds, steps;
    const persp_midpoint_format *format; /* the triangle's, filled before its first span */
    int head;                            /* its plane and fmt lines are written */
} vec_out;

static void put_head(vec_out *o)
{
    const persp_midpoint_format *f = o->format;
    o->head = 1;
    fputs("plane", o->f);
    for (int k = 0; k < 9; k++) fprintf(o->f, " %a", f->plane[k]);
    fprintf(o->f, "\nfmt %d %d %d %" PRId64 " %" PRId64 " %" PRId64, f->in_format, f->shift, f->lattice2, f->G,
            f->H, f->I);
    for (int j = 0; j < 2; j++) fprintf(o->f, " %" PRId64 " %" PRId64 " %" PRId64, f->A[j], f->B[j], f->C[j]);
    fprintf(o->f, " %" PRId64 " %" PRId64 " %.17g %.17g\n", f->X2max, f->Y2max, f->P[0], f->P[1]);
}

static void put_span(void *user, const persp_midpoint_span *s, const persp_midpoint_pixel *px)
{
    vec_out *o = user;
    if (!o->head) put_head(o);
    o->spans++;
    fprintf(o->f, "span %d %d %d %d %" PRId64, s->x0, s->y, s->n, s->int_pixels, s->E0);
    for (int j = 0; j < 2; j++)
        fprintf(o->f, " %" PRId64 " %" PRId64 " %" PRId64 " %" PRId64 " %" PRId64, s->N2[j], s->n0[j],
                s->W0[j], s->T0[j], s->K[j]);
    fputc('\n', o->f);
    for (int k = 0; k < s->n; k++) {
        uint32_t ub, vb;
        memcpy(&ub, &px[k].u, sizeof ub);
        memcpy(&vb, &px[k].v, sizeof vb);
        o->pixels++;
        if (k >= s->int_pixels) {
            fprintf(o->f, "dpx %08" PRIx32 " %08" PRIx32 "\n", ub, vb);
            continue;
        }
        o->int_pixels++;
        fputs("px", o->f);
        for (int j = 0; j < 2; j++) {
            fprintf(o->f, " %" PRId64 " %" PRId64 " %d %d", px[k].n[j], px[k].W[j], px[k].steps[j],
                    px[k].reseed[j]);
            o->reseeds += px[k].reseed[j];
            o->steps += abs(px[k].steps[j]);
        }
        fprintf(o->f, " %08" PRIx32 " %08" PRIx32 "\n", ub, vb);
    }
}

static int put_triangle(persp_context *ctx, const char *method, const persp_method_vertex v[3], int width,
                        int height, int tex_w, int tex_h, long index, vec_out *o)
{
    persp_midpoint_format f;
    fprintf(o->f, "tri %ld", index);
    for (int k = 0; k < 3; k++)
        fprintf(o->f, " %a %a %a %a %a", v[k].x, v[k].y, v[k].w, (double)v[k].u, (double)v[k].v);
    fputc('\n', o->f);
    /* The planes come before the spans: written at the first span, or
     * after the trace for a triangle that has none. */
    o->format = &f, o->head = 0;
    persp_status st = persp_midpoint_trace(ctx, method, v, width, height, tex_w, tex_h, &f, put_span, o);
    if (st != PERSP_OK) return cli_status(ctx, st, "vectors");
    if (!o->head) put_head(o);
    return CLI_OK;
}

/* ------------------------------------------------------- --module exact */

/* The covered pixels of one triangle as spans, in the renderer's order
 * (persp_midpoint_trace's, so that every module's vectors share them). */
typedef struct span_list {
    int (*s)[3]; /* x0, y, n */
    size_t n, cap;
    int failed;
} span_list;

static void keep_span(void *user, const persp_midpoint_span *s, const persp_midpoint_pixel *px)
{
    (void)px;
    span_list *l = user;
    if (l->failed) return;
    if (l->n == l->cap) {
        size_t cap = l->cap ? 2 * l->cap : 256;
        int(*p)[3] = realloc(l->s, cap * sizeof *p);
        if (!p) {
            l->failed = 1;
            return;
        }
        l->s = p, l->cap = cap;
    }
    l->s[l->n][0] = s->x0, l->s[l->n][1] = s->y, l->s[l->n][2] = s->n;
    l->n++;
}

typedef struct exact_out {
    FILE *f;
    long spans, pixels, hw_pixels, ovf_pixels;
    double max_err[2]; /* texels, against the rational form in double */
} exact_out;

static int put_exact_triangle(persp_context *ctx, const persp_method_vertex v[3], int width, int height,
                              int tex_w, int tex_h, long index, exact_out *o)
{
    persp_midpoint_format mf;
    span_list l = {NULL, 0, 0, 0};
    fprintf(o->f, "tri %ld", index);
    for (int k = 0; k < 3; k++)
        fprintf(o->f, " %a %a %a %a %a", v[k].x, v[k].y, v[k].w, (double)v[k].u, (double)v[k].v);
    fputc('\n', o->f);
    persp_status st = persp_midpoint_trace(ctx, "midpoint:int", v, width, height, tex_w, tex_h, &mf, keep_span, &l);
    if (st != PERSP_OK || l.failed) {
        free(l.s);
        return st != PERSP_OK ? cli_status(ctx, st, "vectors") : cli_error(CLI_FAIL, "vectors: out of memory");
    }
    int xmax = -1, ymax = -1;
    for (size_t k = 0; k < l.n; k++) {
        if (l.s[k][0] + l.s[k][2] - 1 > xmax) xmax = l.s[k][0] + l.s[k][2] - 1;
        if (l.s[k][1] > ymax) ymax = l.s[k][1];
    }
    persp_hw_exact_format f;
    persp__hw_exact_format(mf.plane, mf.P, xmax, ymax, &f);
    fprintf(o->f, "xfmt %d %d %" PRId64 " %" PRId64 " %" PRId64, f.in_format, f.shift, f.G, f.H, f.I);
    for (int j = 0; j < 2; j++) fprintf(o->f, " %" PRId64 " %" PRId64 " %" PRId64, f.A[j], f.B[j], f.C[j]);
    fprintf(o->f, " %" PRId64 " %" PRId64 " %.17g %.17g\n", f.X2max, f.Y2max, mf.P[0], mf.P[1]);
    const double *pl = mf.plane;
    for (size_t k = 0; k < l.n; k++) {
        const int x0 = l.s[k][0], y = l.s[k][1], n = l.s[k][2];
        int64_t E = 0, N2[2] = {0, 0};
        const int hw = persp__hw_exact_span(&f, x0, y, n, &E, N2);
        o->spans++, o->pixels += n;
        fprintf(o->f, "xspan %d %d %d %d %" PRId64 " %" PRId64 " %" PRId64 "\n", x0, y, n, hw, hw ? E : 0,
                hw ? N2[0] : 0, hw ? N2[1] : 0);
        if (!hw) continue;
        for (int i = 0; i < n; i++) {
            int64_t t[2] = {0, 0};
            /* Stepped exactly: E and N2 are linear in x (docs/HARDWARE.md). */
            const int ovf = persp__hw_exact_pixel(E, N2, t);
            fprintf(o->f, "xpx %d %" PRId64 " %" PRId64 "\n", ovf, t[0], t[1]);
            o->hw_pixels++;
            if (ovf) o->ovf_pixels++;
            else {
                const double px = x0 + i + 0.5, py = y + 0.5, q = pl[6] * px + pl[7] * py + pl[8];
                for (int j = 0; j < 2; j++) {
                    const double exact = mf.P[j] * (pl[3 * j] * px + pl[3 * j + 1] * py + pl[3 * j + 2]) / q;
                    const double err = fabs(ldexp((double)t[j], -PERSP_HW_EXACT_FRAC) - exact);
                    if (err > o->max_err[j]) o->max_err[j] = err;
                }
            }
            E += 2 * f.G, N2[0] += 2 * f.A[0], N2[1] += 2 * f.A[1];
        }
    }
    free(l.s);
    return CLI_OK;
}

/* cli_error's message, then -1 (vectors_read_triangle's failure, which must not
 * read as a triangle). */
#define read_error(...) (cli_error(CLI_FAIL, __VA_ARGS__), -1)

/* "inf", "infinity" or "nan" in any case, signed or not: named as what
 * they are rather than as words. */
static int non_finite_word(const char *s)
{
    if (*s == '-' || *s == '+') s++;
    char low[10];
    size_t n = 0;
    for (; s[n] && n < sizeof low - 1; n++) low[n] = (char)(s[n] >= 'A' && s[n] <= 'Z' ? s[n] - 'A' + 'a' : s[n]);
    if (s[n]) return 0;
    low[n] = '\0';
    return !strcmp(low, "inf") || !strcmp(low, "infinity") || !strcmp(low, "nan");
}

/* One vertex set per line (declared in cli.h for tests/fuzz/fuzz_vectors.c). */
int vectors_read_triangle(FILE *in, const char *path, long *line, persp_method_vertex v[3])
{
    char text[4096];
    for (;;) {
        /* A NUL byte would end the line for strlen unseen, and the rest of
         * an overlong line would count as the next: with the buffer filled
         * with non-zero bytes first, the last NUL is the one fgets wrote. */
        memset(text, 1, sizeof text);
        if (!fgets(text, sizeof text, in)) break;
        ++*line;
        size_t n = strlen(text), got = sizeof text - 1;
        while (text[got])
            got--;
        if (got != n) return read_error("vectors: %s:%ld: a NUL byte in the line", path, *line);
        if (n == sizeof text - 1 && text[n - 1] != '\n')
            return read_error("vectors: %s:%ld: line longer than %zu characters", path, *line,
                             sizeof text - 2);
        char *hash = strchr(text, '#');
        if (hash) *hash = '\0';
        double x[15];
        int count = 0;
        char *s = text, *end;
        for (;;) {
            while (*s == ' ' || *s == '\t' || *s == '\r' || *s == '\n') s++;
            if (!*s) break;
            if (count == 15)
                return read_error("vectors: %s:%ld: more than 15 numbers (x y w u v per vertex)",
                                 path, *line);
            end = s + strcspn(s, " \t\r\n");
            const char saved = *end;
            *end = '\0';
            /* Decimal only: strtod would also read "0x10" as 16 and
             * "inf", "nan" (C11 7.22.1.3), which no coordinate means. */
            const int decimal = cli_decimal_syntax(s, 1);
            const int nonfinite = !decimal && non_finite_word(s);
            x[count] = decimal ? strtod(s, NULL) : 0.0;
            *end = saved;
            if (!decimal && !nonfinite)
                return read_error("vectors: %s:%ld: number %d is not a number", path, *line, count + 1);
            if (nonfinite || !isfinite(x[count]))
                return read_error("vectors: %s:%ld: number %d is not finite", path, *line, count + 1);
            count++, s = end;
        }
        if (count == 0) continue;
        if (count != 15)
            return read_error("vectors: %s:%ld: %d numbers, expected 15 (x y w u v per vertex)", path,
                             *line, count);
        for (int k = 0; k < 3; k++) {
            const double *p = x + 5 * k;
            if (!(p[2] > 0.0))
                return read_error("vectors: %s:%ld: vertex %d has w = %g (must be > 0)", path, *line, k + 1,
                                 p[2]);
            if (fabs(p[3]) > 3.0e38 || fabs(p[4]) > 3.0e38)
                return read_error("vectors: %s:%ld: vertex %d: u or v beyond a float's range", path, *line,
                                 k + 1);
            v[k] = (persp_method_vertex){p[0], p[1], p[2], (float)p[3], (float)p[4]};
        }
        return 1;
    }
    if (ferror(in)) return read_error("vectors: %s: read error: %s", path, strerror(errno ? errno : EIO));
    return 0;
}

/* splitmix64 (Steele, Lea, Flood 2014): the stream depends on the seed only. */
static double rnd(uint64_t *state, double lo, double hi)
{
    uint64_t z = (*state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    z ^= z >> 31;
    return lo + (hi - lo) * ((double)(z >> 11) * (1.0 / 9007199254740992.0));
}

void vectors_random_triangle(uint64_t *state, int width, int height, double depth_ratio, double uv_range,
                             persp_method_vertex v[3])
{
    const double radius = exp(rnd(state, log(3.0), log(0.4 * (width < height ? width : height) + 3.0)));
    const double cx = rnd(state, 0.0, width), cy = rnd(state, 0.0, height);
    for (int k = 0; k < 3; k++) {
        const double th = rnd(state, 0.0, 6.283185307179586), r = radius * rnd(state, 0.3, 1.0);
        v[k].x = cx + r * cos(th), v[k].y = cy + r * sin(th);
        v[k].w = exp(rnd(state, 0.0, log(depth_ratio)));
        v[k].u = (float)rnd(state, 0.0, uv_range), v[k].v = (float)rnd(state, 0.0, uv_range);
    }
}

void vectors_keep_span(void *user, const persp_midpoint_span *s, const persp_midpoint_pixel *px)
{
    (void)px;
    vectors_spans *l = user;
    if (l->failed) return;
    if (l->n == l->cap) {
        size_t cap = l->cap ? 2 * l->cap : 256;
        int(*p)[3] = realloc(l->s, cap * sizeof *p);
        if (!p) {
            l->failed = 1;
            return;
        }
        l->s = p, l->cap = cap;
    }
    l->s[l->n][0] = s->x0, l->s[l->n][1] = s->y, l->s[l->n][2] = s->n;
    l->n++;
}

/* ------------------------------------------------------------ the driver */

typedef struct vectors_state {
    const vectors_job *job;
    const vectors_writer *w;
    FILE *in;
    long count;
} vectors_state;

static int vectors_body(persp_context *ctx, cli_output *out, void *user)
{
    vectors_state *vs = user;
    const vectors_job *job = vs->job;
    const vectors_writer *w = vs->w;
    fprintf(out->f, "%s\n# window %dx%d, texture %dx%d, ", w->title, job->width, job->height, job->tex_w, job->tex_h);
    if (vs->in)
        fprintf(out->f, "triangles from %s\n", job->input);
    else
        fprintf(out->f, "%d random triangle%s, seed %" PRIu64 ", depth ratio %g, u and v in [0, %g]\n",
                job->triangles, job->triangles == 1 ? "" : "s", job->seed, job->depth_ratio, job->uv_range);
    uint64_t state = job->seed;
    long line = 0;
    int rc = CLI_OK;
    /* A full output ends the loop: cli_output_close names the limit. */
    while (!cli_output_full(out)) {
        persp_method_vertex v[3];
        if (vs->in) {
            int got = vectors_read_triangle(vs->in, job->input, &line, v);
            if (got != 1) {
                rc = got < 0 ? CLI_FAIL : CLI_OK;
                break;
            }
        } else {
            if (vs->count == job->triangles) break;
            vectors_random_triangle(&state, job->width, job->height, job->depth_ratio, job->uv_range, v);
        }
        if ((rc = w->triangle(ctx, job, v, vs->count, out->f, w->state)) != CLI_OK) break;
        vs->count++;
    }
    if (rc == CLI_OK) w->footer(out->f, vs->count, w->state);
    return rc;
}

int vectors_run(const vectors_job *job, const vectors_writer *w)
{
    vectors_state vs = {job, w, NULL, 0};
    if (job->input) {
        /* fopen opens a folder for reading; only reading it fails, as a
         * "read error" that does not say why. */
        struct stat sb;
        if (stat(job->input, &sb) == 0 && S_ISDIR(sb.st_mode))
            return cli_error(CLI_FAIL, "vectors: %s: is a directory (--input takes a file of triangles)", job->input);
        if (!(vs.in = fopen(job->input, "r")))
            return cli_error(CLI_FAIL, "vectors: %s: cannot open: %s", job->input, strerror(errno));
    }
    cli_run_desc run = {.command = "vectors",
                        .report = 1,
                        .output = job->output,
                        .output_limit = job->max_output,
                        .limit_option = "--max-output"};
    int rc = cli_run(&run, vectors_body, &vs);
    if (vs.in) fclose(vs.in);
    if (rc == CLI_OK && job->output && strcmp(job->output, "-")) w->summary(vs.count, job->output, w->state);
    return rc;
}

/* ---------------------------------------------- midpoint_int and exact */

static int midpoint_triangle(persp_context *ctx, const vectors_job *job, const persp_method_vertex v[3], long index,
                             FILE *f, void *state)
{
    vec_out *o = state;
    o->f = f;
    return put_triangle(ctx, job->method, v, job->width, job->height, job->tex_w, job->tex_h, index, o);
}

static void midpoint_footer(FILE *f, long index, void *state)
{
    const vec_out *o = state;
    fprintf(f, "# %ld triangles, %ld spans, %ld pixels (%ld on the integer path), %ld lattice steps, %ld re-seeds\n",
            index, o->spans, o->pixels, o->int_pixels, o->steps, o->reseeds);
}

static void midpoint_summary(long index, const char *output, void *state)
{
    const vec_out *o = state;
    fprintf(stderr, "persp: vectors: %ld triangles, %ld spans, %ld pixels (%ld integer) to %s\n", index, o->spans,
            o->pixels, o->int_pixels, output);
}

static int exact_triangle(persp_context *ctx, const vectors_job *job, const persp_method_vertex v[3], long index,
                          FILE *f, void *state)
{
    exact_out *o = state;
    o->f = f;
    return put_exact_triangle(ctx, v, job->width, job->height, job->tex_w, job->tex_h, index, o);
}

static void exact_footer(FILE *f, long index, void *state)
{
    const exact_out *o = state;
    fprintf(f, "# %ld triangles, %ld spans, %ld pixels (%ld in the hardware, %ld of them out of range), "
               "max |du| %.9f texels, max |dv| %.9f texels\n",
            index, o->spans, o->pixels, o->hw_pixels, o->ovf_pixels, o->max_err[0], o->max_err[1]);
}

static void exact_summary(long index, const char *output, void *state)
{
    const exact_out *o = state;
    fprintf(stderr, "persp: vectors: %ld triangles, %ld spans, %ld pixels (%ld in the hardware) to %s\n", index,
            o->spans, o->pixels, o->hw_pixels, output);
}

/* ------------------------------------------------------------- options */

/* The default cap of --max-output: the largest set scripts/hw.sh writes is
 * a few MiB; one triangle over a 1024x768 window writes about 25 MB. */
#define VECTORS_MAX_OUTPUT ((size_t)64 << 20)

static const cli_spec opt_max_output = {.name = "max-output",
                                        .kind = CLI_KIND_CUSTOM,
                                        .metavar = "SIZE",
                                        .accepts = "a byte count, optionally with K, M, G or T (binary), e.g. 256M",
                                        .help = "refuse to write more than SIZE bytes of vectors (default 64M;\n"
                                                "K, M, G, T binary)"};

int cmd_vectors(int argc, char **argv)
{
    vectors_job job = {.module = "midpoint_int",
                       .method = "midpoint:int",
                       .triangles = 8,
                       .seed = 1,
                       .depth_ratio = 8.0,
                       .uv_range = 1.0,
                       .max_output = VECTORS_MAX_OUTPUT};
    cli_size size = {1024, 768}, tex = {256, 256};
    cli_spec max_output_spec = opt_max_output;
    max_output_spec.parse = cli_opt_max_memory.parse;
    cli_option opts[] = {
        CLI_OPT(opt_module, &job.module),
        CLI_OPT(opt_method, &job.method),
        CLI_OPT(opt_triangles, &job.triangles),
        CLI_OPT(cli_opt_seed, &job.seed),
        CLI_OPT(opt_depth_ratio, &job.depth_ratio),
        CLI_OPT(opt_uv_range, &job.uv_range),
        CLI_OPT_HELP(cli_opt_size, &size, "window in pixels (default 1024x768)"),
        CLI_OPT(opt_texture_size, &tex),
        CLI_OPT(opt_input, &job.input),
        CLI_OPT_HELP(cli_opt_output, &job.output, "write the vectors to FILE (default, and -: standard output)"),
        CLI_OPT(max_output_spec, &job.max_output),
        CLI_OPT_NO_DEST(cli_opt_help),
    };
    cli_command cmd = {"vectors", "persp vectors --help", NULL, opts, sizeof opts / sizeof opts[0], NULL, 0, 0, NULL};
    int rc = cli_parse_or_usage(&cmd, argc, argv, usage);
    if (rc != CLI_OK) return rc == CLI_HELP ? CLI_OK : rc;
    job.width = size.width, job.height = size.height, job.tex_w = tex.width, job.tex_h = tex.height;
    if (job.input && (cli_given(&cmd, &opt_triangles) || cli_given(&cmd, &cli_opt_seed) ||
                      cli_given(&cmd, &opt_depth_ratio) || cli_given(&cmd, &opt_uv_range)))
        return cli_error(CLI_USAGE, "vectors: --input takes the triangles from its file: --triangles, --seed, "
                                    "--depth-ratio and --uv-range shape random ones");
    const int exact = strcmp(job.module, "exact") == 0;
    if ((exact || vectors_shade_module(job.module) || vectors_span_module(job.module)) && cli_given(&cmd, &opt_method))
        return cli_error(CLI_USAGE, "vectors: --method chooses midpoint:int's lattice; --module %s has none",
                         job.module);
    if ((rc = cli_check_not_input("vectors", "-o", job.output, job.input)) != CLI_OK) return rc;
    if (vectors_shade_module(job.module)) return vectors_shade(&job);
    if (vectors_span_module(job.module)) return vectors_span(&job);
    vec_out o = {NULL, 0, 0, 0, 0, 0, NULL, 0};
    exact_out xo = {NULL, 0, 0, 0, 0, {0.0, 0.0}};
    vectors_writer w = {"", exact ? exact_triangle : midpoint_triangle, exact ? exact_footer : midpoint_footer,
                        exact ? exact_summary : midpoint_summary, exact ? (void *)&xo : (void *)&o};
    if (exact)
        snprintf(w.title, sizeof w.title,
                 "# persp test vectors of the RTL module exact, format 1 (docs/HARDWARE.md, \"Vectors\")");
    else
        snprintf(w.title, sizeof w.title, "# persp test vectors of %s, format 1 (docs/METHODS.md, \"Test vectors\")",
                 job.method);
    return vectors_run(&job, &w);
}
