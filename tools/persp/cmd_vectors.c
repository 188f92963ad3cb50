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
            errno = 0;
            x[count] = strtod(s, &end);
            if (end == s || (*end && *end != ' ' && *end != '\t' && *end != '\r' && *end != '\n'))
                return read_error("vectors: %s:%ld: number %d is not a number", path, *line, count + 1);
            if (!isfinite(x[count]))
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
    if (ferror(in)) return read_error("vectors: %s: read error", path);
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

int cmd_vectors(int argc, char **argv)
{
    const char *method = "midpoint:int", *output = NULL, *input = NULL, *module = "midpoint_int";
    uint64_t seed = 1;
    int triangles = 8;
    double depth_ratio = 8.0, uv_range = 1.0;
    cli_size size = {1024, 768}, tex = {256, 256};
    cli_option opts[] = {
        CLI_OPT(opt_module, &module),
        CLI_OPT(opt_method, &method),
        CLI_OPT(opt_triangles, &triangles),
        CLI_OPT(cli_opt_seed, &seed),
        CLI_OPT(opt_depth_ratio, &depth_ratio),
        CLI_OPT(opt_uv_range, &uv_range),
        CLI_OPT_HELP(cli_opt_size, &size, "window in pixels (default 1024x768)"),
        CLI_OPT(opt_texture_size, &tex),
        CLI_OPT(opt_input, &input),
        CLI_OPT_HELP(cli_opt_output, &output, "write the vectors to FILE (default, and -: standard output)"),
        CLI_OPT_NO_DEST(cli_opt_help),
    };
    cli_command cmd = {"vectors", "persp vectors --help", NULL, opts, sizeof opts / sizeof opts[0], NULL, 0, 0, NULL};
    int rc = cli_parse_or_usage(&cmd, argc, argv, usage);
    if (rc != CLI_OK) return rc == CLI_HELP ? CLI_OK : rc;
    if (input && (cli_given(&cmd, &opt_triangles) || cli_given(&cmd, &cli_opt_seed) ||
                  cli_given(&cmd, &opt_depth_ratio) || cli_given(&cmd, &opt_uv_range)))
        return cli_error(CLI_USAGE, "vectors: --input takes the triangles from its file: --triangles, --seed, "
                                    "--depth-ratio and --uv-range shape random ones");
    if (vectors_shade_module(module)) {
        if (cli_given(&cmd, &opt_method))
            return cli_error(CLI_USAGE, "vectors: --method chooses midpoint:int's lattice; --module %s has none", module);
        return vectors_shade(module, input, output, triangles, (unsigned long long)seed, depth_ratio, uv_range,
                             size.width, size.height, tex.width, tex.height);
    }
    if (vectors_span_module(module)) {
        if (cli_given(&cmd, &opt_method))
            return cli_error(CLI_USAGE, "vectors: --method chooses midpoint:int's lattice; --module %s has none", module);
        return vectors_span(module, input, output, triangles, (unsigned long long)seed, depth_ratio, uv_range,
                            size.width, size.height, tex.width, tex.height);
    }
    const int exact = strcmp(module, "exact") == 0;
    if (exact && cli_given(&cmd, &opt_method))
        return cli_error(CLI_USAGE, "vectors: --method chooses midpoint:int's lattice; --module exact has none");
    FILE *in = NULL;
    if (input && !(in = fopen(input, "r")))
        return cli_error(CLI_FAIL, "vectors: %s: cannot open: %s", input, strerror(errno));
    persp_context *ctx = NULL;
    persp_status st = persp_context_create(NULL, &ctx);
    if (st != PERSP_OK) {
        if (in) fclose(in);
        return cli_status(NULL, st, "vectors: context");
    }
    persp_context_set_temp_file_handler(ctx, cli_temp_file, NULL);
    cli_output out;
    if ((rc = cli_output_open("vectors", output, &out)) != CLI_OK) {
        if (in) fclose(in);
        persp_context_destroy(ctx);
        return rc;
    }
    vec_out o = {out.f, 0, 0, 0, 0, 0, NULL, 0};
    exact_out xo = {out.f, 0, 0, 0, 0, {0.0, 0.0}};
    if (exact)
        fprintf(out.f, "# persp test vectors of the RTL module exact, format 1 (docs/HARDWARE.md, \"Vectors\")\n");
    else
        fprintf(out.f, "# persp test vectors of %s, format 1 (docs/METHODS.md, \"Test vectors\")\n", method);
    fprintf(out.f, "# window %dx%d, texture %dx%d, ", size.width, size.height, tex.width, tex.height);
    if (in)
        fprintf(out.f, "triangles from %s\n", input);
    else
        fprintf(out.f, "%d random triangle%s, seed %" PRIu64 ", depth ratio %g, u and v in [0, %g]\n", triangles,
                triangles == 1 ? "" : "s", seed, depth_ratio, uv_range);
    uint64_t state = seed;
    long line = 0, index = 0;
    for (;;) {
        persp_method_vertex v[3];
        if (in) {
            int got = vectors_read_triangle(in, input, &line, v);
            if (got != 1) {
                rc = got < 0 ? CLI_FAIL : CLI_OK;
                break;
            }
        } else {
            if (index == triangles) break;
            vectors_random_triangle(&state, size.width, size.height, depth_ratio, uv_range, v);
        }
        rc = exact ? put_exact_triangle(ctx, v, size.width, size.height, tex.width, tex.height, index, &xo)
                   : put_triangle(ctx, method, v, size.width, size.height, tex.width, tex.height, index, &o);
        if (rc != CLI_OK) break;
        index++;
    }
    if (in) fclose(in);
    if (rc == CLI_OK && exact)
        fprintf(out.f, "# %ld triangles, %ld spans, %ld pixels (%ld in the hardware, %ld of them out of range), "
                       "max |du| %.9f texels, max |dv| %.9f texels\n",
                index, xo.spans, xo.pixels, xo.hw_pixels, xo.ovf_pixels, xo.max_err[0], xo.max_err[1]);
    else if (rc == CLI_OK)
        fprintf(out.f, "# %ld triangles, %ld spans, %ld pixels (%ld on the integer path), %ld lattice steps, %ld re-seeds\n",
                index, o.spans, o.pixels, o.int_pixels, o.steps, o.reseeds);
    int out_rc = cli_output_close("vectors", &out, rc == CLI_OK);
    if (rc == CLI_OK) rc = out_rc;
    if (rc == CLI_OK && output && strcmp(output, "-") && exact)
        fprintf(stderr, "persp: vectors: %ld triangles, %ld spans, %ld pixels (%ld in the hardware) to %s\n", index,
                xo.spans, xo.pixels, xo.hw_pixels, output);
    else if (rc == CLI_OK && output && strcmp(output, "-"))
        fprintf(stderr, "persp: vectors: %ld triangles, %ld spans, %ld pixels (%ld integer) to %s\n", index, o.spans,
                o.pixels, o.int_pixels, output);
    persp_context_destroy(ctx);
    return rc;
}
