/*
 * persp report: the study as one web page. Everything on the page is
 * measured in this call through the public analysis API (or read back from a
 * merged sweep), so the page cannot drift from the code: plots are SVG
 * written by svg.c and inlined, images are PNG files beside index.html, and
 * the only script is the before/after slider. Claims and their published
 * numbers mirror docs/REPRODUCTION.md; the verdicts are recomputed here.
 */
#include "analysis/analysis.h"
#include "analysis/claims.h"
#include "analysis/shading.h"
#include "analysis/svg.h"
#include "core/internal.h"
#include "io/outfile.h"
#include "io/text.h"

#include <dirent.h>
#include <errno.h>
#include <jansson.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#define MAX_METHODS 64

static const char *const scenes[] = {"corridor", "floor"};
#define SCENES 2

typedef struct rep {
    persp_context *ctx;
    const persp_report_html_desc *d;
    FILE *f, *log;
    const char *dir;
    int quick, w, h, triangles;
    const persp_accuracy_result *acc;
    const char *specs[MAX_METHODS];
    size_t nspecs;
    double ms[MAX_METHODS]; /* corridor render time per method; NaN: not timed */
    int svgs;               /* SVG documents put into the page so far */
} rep;

static void say(rep *r, const char *fmt, ...)
{
    if (!r->log) return;
    va_list ap;
    va_start(ap, fmt);
    fputs("report: ", r->log);
    vfprintf(r->log, fmt, ap);
    fputc('\n', r->log);
    fflush(r->log);
    va_end(ap);
}

static void esc(FILE *f, const char *s)
{
    for (; s && *s; s++)
        switch (*s) {
        case '<':
            fputs("&lt;", f);
            break;
        case '>':
            fputs("&gt;", f);
            break;
        case '&':
            fputs("&amp;", f);
            break;
        case '"':
            fputs("&quot;", f);
            break;
        default:
            fputc(*s, f);
        }
}

/* File names as the accuracy heat maps spell them (accuracy.c, sanitize). */
static void file_name(char *s)
{
    for (; *s; s++)
        if (!((*s >= 'a' && *s <= 'z') || (*s >= 'A' && *s <= 'Z') || (*s >= '0' && *s <= '9') ||
              *s == '.' || *s == '-' || *s == '_'))
            *s = '-';
}

static int file_exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && st.st_size > 0;
}

static void copy_file(const char *from, const char *to)
{
    FILE *in = fopen(from, "rb"), *out = in ? fopen(to, "wb") : NULL;
    char buf[65536];
    size_t n;
    int ok = in && out;
    while (ok && (n = fread(buf, 1, sizeof buf, in)) > 0)
        ok = fwrite(buf, 1, n, out) == n;
    if (in) fclose(in);
    if (out && fclose(out) != 0) ok = 0;
    if (out && !ok) remove(to);
}

static void num(FILE *f, double v)
{
    if (v != v)
        fputs("–", f);
    else if (v == 0.0)
        fputs("0", f);
    else
        fprintf(f, "%.3g", v);
}

/* --------------------------------------------------------- accuracy rows */

/* The row of method on case (a scene case matches "NAME@WxH"); hbar > 0
 * selects a random-triangles group. */
static const persp_accuracy_row *row_of(const rep *r, const char *method, const char *cname,
                                        double hbar)
{
    size_t cl = strlen(cname);
    for (size_t i = 0; i < persp_accuracy_row_count(r->acc); i++) {
        const persp_accuracy_row *x = persp_accuracy_row_at(r->acc, i);
        if (strcmp(x->method, method)) continue;
        if (strncmp(x->case_name, cname, cl) || (x->case_name[cl] && x->case_name[cl] != '@'))
            continue;
        if (hbar > 0.0 && fabs(x->hbar - hbar) > 1e-9) continue;
        return x;
    }
    return NULL;
}

static double rmax(const persp_accuracy_row *x)
{
    return x ? fmax(x->max_u, x->max_v) : NAN;
}
static double rp99(const persp_accuracy_row *x)
{
    return x ? fmax(x->p99_u, x->p99_v) : NAN;
}
static double rrel(const persp_accuracy_row *x)
{
    return x ? fmax(x->relpt_u, x->relpt_v) : NAN;
}

/* Methods present in the accuracy result, in its order. */
static void methods_of_result(rep *r)
{
    r->nspecs = 0;
    for (size_t i = 0; i < persp_accuracy_row_count(r->acc) && r->nspecs < MAX_METHODS; i++) {
        const char *m = persp_accuracy_row_at(r->acc, i)->method;
        size_t k = 0;
        while (k < r->nspecs && strcmp(r->specs[k], m))
            k++;
        if (k == r->nspecs) r->specs[r->nspecs++] = m;
    }
}

/* ------------------------------------------------------------------ SVG */

/* Puts an SVG document into the page, without its XML declaration. The
 * documents share the page's one id space (HTML Living Standard, "The id
 * attribute": ids are unique in the document), and every plot names its
 * clip path c0, so each document's ids and references to them get a prefix
 * of their own; otherwise browsers clip every plot to the first plot's box. */
static void put_svg(rep *r, const char *s)
{
    const char *at = strstr(s, "<svg");
    if (at) s = at;
    int n = ++r->svgs;
    static const char *const refs[] = {" id=\"", "url(#", "href=\"#"};
    while (*s) {
        size_t k = 0;
        while (k < 3 && strncmp(s, refs[k], strlen(refs[k]))) k++;
        if (k == 3) {
            fputc(*s++, r->f);
            continue;
        }
        fprintf(r->f, "%ss%d-", refs[k], n);
        s += strlen(refs[k]);
    }
}

/* Writes an SVG document into the page. */
static int inline_svg(rep *r, const persp_svg_panel *panels, int count, int pw, int ph)
{
    char *buf = NULL;
    size_t len = 0;
    FILE *m = open_memstream(&buf, &len);
    if (!m) return -1;
    int rc = persp__svg_write(m, panels, count, pw, ph);
    fclose(m);
    if (rc == 0) put_svg(r, buf);
    free(buf);
    return rc;
}

/* Copies an SVG file written by the library into the page. */
static void inline_svg_file(rep *r, const char *path)
{
    FILE *in = fopen(path, "rb");
    if (!in) return;
    char *buf = NULL;
    size_t len = 0;
    FILE *m = open_memstream(&buf, &len);
    if (m) {
        char chunk[4096];
        size_t got;
        while ((got = fread(chunk, 1, sizeof chunk, in)) > 0) fwrite(chunk, 1, got, m);
        fclose(m);
        put_svg(r, buf);
        free(buf);
    }
    fclose(in);
}

static void plot_by_depth(rep *r)
{
    /* Two panels' worth of methods, so that each legend stays readable. */
    const size_t per = r->nspecs > 10 ? (r->nspecs + 1) / 2 : 10;
    /* On the stack (about 11 kB), not static: the report is reentrant. */
    double xs[PERSP_HBAR_COUNT];
    for (int g = 0; g < PERSP_HBAR_COUNT; g++)
        xs[g] = persp__hbar_groups[g];
    double ys[3][MAX_METHODS][PERSP_HBAR_COUNT];
    for (size_t c = 0; c * per < r->nspecs; c++) {
        persp_svg_panel p[3];
        memset(p, 0, sizeof p);
        const char *titles[3] = {"max error", "p99 error", "texel miss"};
        const char *ylab[3] = {"log10 max |Δ| (texels)", "log10 p99 |Δ| (texels)",
                               "texel miss (%)"};
        for (int k = 0; k < 3; k++) {
            p[k].title = titles[k];
            p[k].xlabel = "depth ratio ħ = z_far / z_near";
            p[k].ylabel = ylab[k];
            p[k].xmin = 1.0;
            p[k].xmax = 8.0;
        }
        /* The same ranges in every row of panels, so that rows compare. */
        p[0].ymin = p[1].ymin = -6.0, p[0].ymax = p[1].ymax = 5.0;
        p[2].ymin = 0.0, p[2].ymax = 100.0;
        for (size_t i = c * per; i < r->nspecs && i < (c + 1) * per; i++) {
            int used = 0;
            for (int g = 0; g < PERSP_HBAR_COUNT; g++) {
                const persp_accuracy_row *x = row_of(r, r->specs[i], "random-triangles", xs[g]);
                used |= x != NULL;
                ys[0][i][g] = x ? log10(fmax(rmax(x), 1e-6)) : NAN;
                ys[1][i][g] = x ? log10(fmax(rp99(x), 1e-6)) : NAN;
                ys[2][i][g] = x ? 100.0 * x->texel_miss : NAN;
            }
            if (!used) continue;
            for (int k = 0; k < 3; k++) {
                persp_svg_series *s = &p[k].series[p[k].series_count++];
                s->x = xs, s->y = ys[k][i], s->n = PERSP_HBAR_COUNT, s->label = r->specs[i];
            }
        }
        if (!p[0].series_count) continue;
        fputs("<figure class=plot>", r->f);
        inline_svg(r, p, 3, 400, 340);
        fputs("</figure>\n", r->f);
    }
}

/* -------------------------------------------------------------- rendering */

static persp_status write_png(rep *r, const char *name, const uint8_t *rgba, int w, int h)
{
    char path[1200];
    snprintf(path, sizeof path, "%s/img/%s", r->dir, name);
    persp_image img = {w, h, (size_t)w * 4, (uint8_t *)rgba};
    return persp_image_write_png(r->ctx, path, &img);
}

/* The middle fifth of the image around its centre, enlarged 4× (nearest) so
 * that texel-level differences show. */
static persp_status write_crop(rep *r, const char *name, const uint8_t *rgba, int w, int h)
{
    int cw = w / 5, ch = h / 5, x0 = (w - cw) / 2, y0 = (h - ch) / 2, z = 4;
    /* From the context, so that its memory budget (--max-memory) counts it. */
    uint8_t *out = persp__alloc(r->ctx, (size_t)cw * (size_t)ch * (size_t)(z * z) * 4);
    if (!out) return persp__fail(r->ctx, PERSP_ERR_OUT_OF_MEMORY, "%s: out of memory", name);
    for (int y = 0; y < ch * z; y++)
        for (int x = 0; x < cw * z; x++)
            memcpy(&out[((size_t)y * (size_t)(cw * z) + (size_t)x) * 4],
                   &rgba[((size_t)(y0 + y / z) * (size_t)w + (size_t)(x0 + x / z)) * 4], 4);
    persp_status st = write_png(r, name, out, cw * z, ch * z);
    persp__free(r->ctx, out);
    return st;
}

static persp_status render_all(rep *r)
{
    size_t px = (size_t)r->w * (size_t)r->h;
    /* From the context, so that its memory budget (--max-memory) counts them. */
    uint8_t *color = persp__alloc(r->ctx, px * 4);
    float *depth = color ? persp__alloc(r->ctx, px * sizeof(float)) : NULL;
    persp_status st = color && depth ? PERSP_OK
                                     : persp__fail(r->ctx, PERSP_ERR_OUT_OF_MEMORY,
                                                   "framebuffer of %dx%d: out of memory", r->w,
                                                   r->h);
    for (size_t i = 0; i < MAX_METHODS; i++)
        r->ms[i] = NAN;
    for (int s = 0; s < SCENES && st == PERSP_OK; s++) {
        persp_scene *scene = NULL;
        st = persp_scene_builtin(r->ctx, scenes[s], &scene);
        say(r, "rendering %s with %zu methods at %dx%d", scenes[s], r->nspecs, r->w, r->h);
        for (size_t i = 0; i < r->nspecs && st == PERSP_OK; i++) {
            persp_render_desc rd;
            memset(&rd, 0, sizeof rd);
            rd.method = r->specs[i];
            persp_framebuffer fb = {r->w, r->h, color, depth};
            int reps = r->quick ? 2 : 5;
            double best = INFINITY;
            for (int k = 0; k < reps && st == PERSP_OK; k++) {
                struct timespec t0, t1;
                clock_gettime(CLOCK_MONOTONIC, &t0);
                st = persp_render(r->ctx, scene, &rd, &fb, NULL);
                clock_gettime(CLOCK_MONOTONIC, &t1);
                double ms = (double)(t1.tv_sec - t0.tv_sec) * 1e3 +
                            (double)(t1.tv_nsec - t0.tv_nsec) * 1e-6;
                if (ms < best) best = ms;
            }
            if (s == 0) r->ms[i] = best;
            char name[256];
            snprintf(name, sizeof name, "%s_%s", scenes[s], r->specs[i]);
            file_name(name);
            char file[300];
            snprintf(file, sizeof file, "%s.png", name);
            if (st == PERSP_OK) st = write_png(r, file, color, r->w, r->h);
            snprintf(file, sizeof file, "%s_crop.png", name);
            if (st == PERSP_OK) st = write_crop(r, file, color, r->w, r->h);
        }
        persp_scene_destroy(scene);
    }
    persp__free(r->ctx, color);
    persp__free(r->ctx, depth);
    return st;
}

/* ------------------------------------------------------------- sections */

static void head(rep *r)
{
    fputs(
        "<!DOCTYPE html>\n<html lang=en><head><meta charset=utf-8>\n"
        "<title>persp: perspective-correct texture mapping, the study</title>\n<style>\n"
        "body{font-family:sans-serif;max-width:1400px;margin:1em auto;padding:0 1em;color:#222}\n"
        "table{border-collapse:collapse;font-size:13px;margin:.5em 0}\n"
        "td,th{border:1px solid #bbb;padding:2px 6px;text-align:right}\n"
        "td:first-child,th:first-child{text-align:left}\n"
        "th{background:#eee}\n.claims td,.claims "
        "th{text-align:left}\n.holds{background:#dfd}.fails{background:#fdd}.partly{background:#"
        "ffd}\n"
        "code{background:#f4f4f4;padding:1px "
        "3px}\npre{background:#f7f7f7;padding:.5em;overflow:auto;font-size:12px}\n"
        "figure{display:inline-block;margin:4px;vertical-align:top;font-size:12px}\n"
        "figure img{display:block;image-rendering:pixelated}\n"
        ".plot svg{max-width:100%;height:auto}\n"
        ".slider{position:relative;display:inline-block}\n"
        ".slider img{display:block;image-rendering:pixelated}\n"
        ".slider .top{position:absolute;left:0;top:0;overflow:hidden;border-right:2px solid #f00}\n"
        "</style></head><body>\n"
        "<h1>persp: perspective-correct texture mapping — the study</h1>\n",
        r->f);
    fprintf(r->f,
            "<p>Every number, plot and image below was produced by <code>persp report</code> "
            "in one run (%s mode)%s. Sources are cited by the keys of docs/SOURCES.md.</p>\n",
            r->quick ? "quick" : "full",
            r->d->from_dir ? "; the method accuracy was read from a merged sweep" : "");
}

static void environment(rep *r)
{
    char cpu[256] = "unknown";
    FILE *c = fopen("/proc/cpuinfo", "r");
    if (c) {
        char line[512];
        while (fgets(line, sizeof line, c))
            if (!strncmp(line, "model name", 10) && strchr(line, ':')) {
                snprintf(cpu, sizeof cpu, "%s", strchr(line, ':') + 2);
                cpu[strcspn(cpu, "\n")] = '\0';
                break;
            }
        fclose(c);
    }
    char date[64];
    time_t now = time(NULL);
    struct tm tm;
    gmtime_r(&now, &tm);
    strftime(date, sizeof date, "%Y-%m-%d %H:%M:%S UTC", &tm);
    fputs("<h2 id=env>Environment</h2>\n<table>\n<tr><td>CPU<td>", r->f);
    esc(r->f, cpu);
    fprintf(r->f, " (%ld online)\n<tr><td>compiler<td>", sysconf(_SC_NPROCESSORS_ONLN));
#ifdef __VERSION__
    fputs("cc ", r->f);
    esc(r->f, __VERSION__);
#else
    fputs("unknown", r->f);
#endif
    fputs("\n<tr><td>persp<td>", r->f);
    esc(r->f, persp_version());
    fputs("\n<tr><td>git commit<td>", r->f);
    /* NULL: built from a downloaded archive or without git; the version
     * in the row above identifies the sources then. */
    esc(r->f, r->d->git_commit ? r->d->git_commit : "none: not a git checkout");
    fprintf(r->f, "\n<tr><td>date<td>%s\n<tr><td>command<td><code>", date);
    esc(r->f, r->d->command ? r->d->command : "persp report");
    fputs("</code>\n</table>\n", r->f);
}

static void cmd(rep *r, const char *fmt, ...)
{
    char buf[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    fputs("<p class=cmd>Reproduce: <code>", r->f);
    esc(r->f, buf);
    fputs("</code></p>\n", r->f);
}

static void method_table(rep *r)
{
    fputs(
        "<h2 id=methods>Texture-coordinate methods</h2>\n"
        "<p>Absolute errors in texels against the exact rational form (Heckbert 1989 §2.3.2) in "
        "double "
        "precision at each pixel centre; relpt = point-wise relative error; ops per pixel as "
        "counted by "
        "each method on the corridor; render time of the corridor image below, relative to "
        "<code>exact</code>.</p>\n<table>\n<tr><th>method<th>paper-quad max u / v<th>relpt u / v %"
        "<th>ħ=2 max<th>ħ=8 max<th>corridor max / p99 / miss %<th>floor max / p99 / miss %"
        "<th>div / mul / add / cmp per px<th>time vs exact\n",
        r->f);
    double exact_ms = NAN;
    for (size_t i = 0; i < r->nspecs; i++)
        if (!strcmp(r->specs[i], "exact")) exact_ms = r->ms[i];
    for (size_t i = 0; i < r->nspecs; i++) {
        const char *m = r->specs[i];
        const persp_accuracy_row *pq = row_of(r, m, "paper-quad", 0),
                                 *h2 = row_of(r, m, "random-triangles", 2.0),
                                 *h8 = row_of(r, m, "random-triangles", 8.0);
        fputs("<tr><td>", r->f);
        esc(r->f, m);
        fputs("<td>", r->f);
        num(r->f, pq ? pq->max_u : NAN), fputs(" / ", r->f), num(r->f, pq ? pq->max_v : NAN);
        fputs("<td>", r->f);
        num(r->f, pq ? 100 * pq->relpt_u : NAN), fputs(" / ", r->f),
            num(r->f, pq ? 100 * pq->relpt_v : NAN);
        fputs("<td>", r->f), num(r->f, rmax(h2));
        fputs("<td>", r->f), num(r->f, rmax(h8));
        const persp_accuracy_row *ops = NULL;
        for (int s = 0; s < SCENES; s++) {
            const persp_accuracy_row *x = row_of(r, m, scenes[s], 0);
            if (s == 0) ops = x;
            fputs("<td>", r->f);
            num(r->f, rmax(x)), fputs(" / ", r->f), num(r->f, rp99(x)), fputs(" / ", r->f);
            num(r->f, x ? 100 * x->texel_miss : NAN);
        }
        if (!ops || !ops->ops_measured) ops = h2;
        fputs("<td>", r->f);
        if (ops && ops->ops_measured) {
            num(r->f, ops->div_px), fputs(" / ", r->f), num(r->f, ops->mul_px), fputs(" / ", r->f);
            num(r->f, ops->add_px), fputs(" / ", r->f), num(r->f, ops->cmp_px);
        } else
            fputs("–", r->f);
        fputs("<td>", r->f);
        num(r->f, r->ms[i] / exact_ms);
        fputc('\n', r->f);
    }
    fputs("</table>\n", r->f);
    fputs("<h3>Error by depth ratio (random triangles)</h3>\n", r->f);
    plot_by_depth(r);
}

/* ---------------------------------------------------------------- claims */

typedef enum { V_NA, V_HOLDS, V_PARTLY, V_FAILS, V_SEE } verdict;

static void claim(rep *r, const persp_claim *c, const char *measured, verdict v)
{
    const char *source = c->source, *text = c->text, *published = c->published;
    static const char *const cls[] = {"", "holds", "partly", "fails", ""};
    static const char *const word[] = {"not measured", "holds", "partly", "does not hold",
                                       "see <a href=#shading>Shading</a>"};
    fprintf(r->f, "<tr class=%s><td>", cls[v]);
    esc(r->f, source);
    fputs("<td style=text-align:left>", r->f);
    esc(r->f, text);
    fputs("<td>", r->f);
    esc(r->f, published);
    fputs("<td>", r->f);
    esc(r->f, measured);
    fprintf(r->f, "<td>%s\n", word[v]);
}

/* The analytic claims of [Romanyuk-PCF] §4.2-4.3, recomputed from the
 * shading analysis (src/analysis/shading.c): they need no measurement run,
 * so every page has them, --from included. */
static void shading_claims(rep *r)
{
    char buf[512];
    static const double ratios[] = {1.25, 1.5, 2, 3, 5, 10};
    double worst = 0.0, worst_sym = 0.0;
    size_t len = 0;
    buf[0] = '\0';
    for (size_t k = 0; k < sizeof ratios / sizeof ratios[0]; k++) {
        double rr = ratios[k], ustar, ustar_inv, best = 0.0;
        double dstar = persp__delta_extremum(rr, &ustar);
        for (int i = 0; i <= 100000; i++)
            best = fmax(best, persp__delta_factor(i / 100000.0, rr));
        worst = fmax(worst, fabs(best - dstar));
        double dinv = persp__delta_extremum(1.0 / rr, &ustar_inv);
        worst_sym = fmax(worst_sym, fmax(fabs(dinv + dstar), fabs(ustar_inv - (1.0 - ustar))));
        int n = snprintf(buf + len, sizeof buf - len, "%s%.3g", k ? ", " : "Δ* = ", dstar);
        if (n > 0 && (size_t)n < sizeof buf - len) len += (size_t)n;
    }
    snprintf(buf + len, sizeof buf - len,
             " for r = 1.25 … 10; a search over 100 001 u agrees to %.1g", worst);
    /* Analytic: recomputed, not thresholds of a measurement. */
    const persp_claim s1 = {.source = "[Romanyuk-PCF] §4.2 (4.1), Fig. 4.3",
                            .text = "screen-linear Gouraud misses the perspective-correct "
                                    "intensity by ΔI = (I_B − I_A)·Δ(u)",
                            .published = "Fig. 4.3 (extremum derived: (√r − 1)/(√r + 1))"};
    claim(r, &s1, buf, worst < 1e-6 ? V_HOLDS : V_FAILS);
    snprintf(buf, sizeof buf, "|Δ*(1/r) + Δ*(r)|, |u*(1/r) − (1 − u*(r))| ≤ %.1g", worst_sym);
    const persp_claim s2 = {.source = "[Romanyuk-PCF] §4.2 Fig. 4.4",
                            .text = "for z1 > z2 Δ < 0, the extremum lies at 1 − u and the maxima "
                                    "coincide",
                            .published = "mirror image"};
    claim(r, &s2, buf, worst_sym < 1e-9 ? V_HOLDS : V_FAILS);

    const persp_claim *tw = persp__claim(PERSP_CLAIM_TW_BOUNDS);
    persp_tw_error pw[PERSP_CLAIM_TW_HBARS], cu[PERSP_CLAIM_TW_HBARS], qu[PERSP_CLAIM_TW_HBARS];
    int within = 1, below = 1, cubic_better = 1;
    for (int k = 0; k < PERSP_CLAIM_TW_HBARS; k++) {
        const double hb = 2.0 + k;
        persp__tw_error(PERSP_APPROX_PWQUAD, hb, &pw[k]);
        persp__tw_error(PERSP_APPROX_CUBIC, hb, &cu[k]);
        persp__tw_error(PERSP_APPROX_QUAD, hb, &qu[k]);
        const double off_pw = 100 * pw[k].rel_third - tw->series[k],
                     off_cu = 100 * cu[k].rel_third - tw->series[PERSP_CLAIM_TW_HBARS + k];
        below &= off_pw <= 0.0 && off_cu <= 0.0;
        within &= off_pw < tw->tol[0] && off_cu < tw->tol[1];
        cubic_better &= cu[k].rel_third < pw[k].rel_third;
    }
    snprintf(
        buf, sizeof buf,
        "relative error over t_v ∈ [1/3, 1]: piecewise quadratic %.2f / %.2f / %.2f / %.2f %%, "
        "cubic %.2f / %.2f / %.2f / %.2f %% (max absolute error %.2f / %.2f / %.2f / %.2f %% "
        "and %.2f / %.2f / %.2f / %.2f %%)",
        100 * pw[0].rel_third, 100 * pw[1].rel_third, 100 * pw[2].rel_third, 100 * pw[3].rel_third,
        100 * cu[0].rel_third, 100 * cu[1].rel_third, 100 * cu[2].rel_third, 100 * cu[3].rel_third,
        100 * pw[0].abs_max, 100 * pw[1].abs_max, 100 * pw[2].abs_max, 100 * pw[3].abs_max,
        100 * cu[0].abs_max, 100 * cu[1].abs_max, 100 * cu[2].abs_max, 100 * cu[3].abs_max);
    /* "Does not exceed" is exceeded by a few tenths of a point under the one
     * metric that comes close (docs/REPRODUCTION.md, S3): partly. */
    claim(r, tw, buf,
          below    ? V_HOLDS
          : within ? V_PARTLY
                   : V_FAILS);
    snprintf(buf, sizeof buf,
             "cubic below the piecewise quadratic at %s ħ = 2 … 5 (relative error over [1/3, 1])",
             cubic_better ? "every" : "not every");
    const persp_claim s4 = {.source = "[Romanyuk-PCF] §4.3",
                            .text = "the cubic results in higher accuracy than the piecewise "
                                    "quadratic",
                            .published = "more accurate"};
    claim(r, &s4, buf, cubic_better ? V_HOLDS : V_FAILS);
    snprintf(buf, sizeof buf,
             "max absolute t_w error %.1f / %.1f / %.1f / %.1f %% at ħ = 2 / 3 / 4 / 5",
             100 * qu[0].abs_max, 100 * qu[1].abs_max, 100 * qu[2].abs_max, 100 * qu[3].abs_max);
    const persp_claim *s5 = persp__claim(PERSP_CLAIM_QUADRATIC_HBAR3);
    claim(r, s5, buf,
          100 * qu[1].abs_max < s5->bound && 100 * qu[2].abs_max > s5->above ? V_HOLDS : V_PARTLY);
}

/* Each claim of the sources, measured in this run: *buf says what was
 * measured ("" where the run has not the rows it needs), the verdict
 * follows the thresholds of the claims table (src/analysis/claims.c). */
typedef verdict (*claim_check)(rep *r, char *buf, size_t size);

static const persp_accuracy_row *paper_quad(rep *r, const char *method)
{
    return row_of(r, method, "paper-quad", 0);
}

static verdict check_shifted_anchor(rep *r, char *buf, size_t size)
{
    const persp_accuracy_row *q = paper_quad(r, "quadratic"), *qs = paper_quad(r, "quadratic-shifted");
    if (!q || !qs) return V_NA;
    double ratio = qs->relpt_v / q->relpt_v;
    snprintf(buf, size, "relpt v %.3f %% → %.3f %%, ratio %.3f", 100 * q->relpt_v, 100 * qs->relpt_v, ratio);
    const persp_claim *c = persp__claim(PERSP_CLAIM_SHIFTED_ANCHOR);
    return ratio >= c->lo && ratio <= c->hi ? V_HOLDS : V_FAILS;
}

/* A Bézier approach against the quadratic: both halves, the bound and "almost
 * 3 times" (2.5); beating the quadratic by less is neither
 * (docs/REPRODUCTION.md, claim 3). */
static verdict bezier_against_quadratic(rep *r, const char *method, persp_claim_id id, const char *fmt, char *buf,
                                        size_t size)
{
    const persp_accuracy_row *q = paper_quad(r, "quadratic"), *bz = paper_quad(r, method);
    if (!q || !bz) return V_NA;
    double e = rrel(bz), k = fmin(q->relpt_u / bz->relpt_u, q->relpt_v / bz->relpt_v);
    snprintf(buf, size, fmt, 100 * e, k);
    const persp_claim *c = persp__claim(id);
    const int bounded = 100 * e <= c->bound, less = k >= c->factor;
    return bounded && less ? V_HOLDS : bounded || less ? V_PARTLY : V_FAILS;
}

static verdict check_bezier(rep *r, char *buf, size_t size)
{
    return bezier_against_quadratic(r, "bezier", PERSP_CLAIM_BEZIER, "%.3f %%, %.1f× below the quadratic", buf,
                                    size);
}

static verdict check_bezier_quadt(rep *r, char *buf, size_t size)
{
    return bezier_against_quadratic(r, "bezier:quadt", PERSP_CLAIM_BEZIER_QUADT,
                                    "%.2f %%, %.1f× below the quadratic", buf, size);
}

static verdict check_quadratic_unnorm(rep *r, char *buf, size_t size)
{
    const persp_accuracy_row *q = paper_quad(r, "quadratic"), *qu = paper_quad(r, "quadratic-unnorm");
    if (!q || !qu) return V_NA;
    int same = q->max_u == qu->max_u && q->max_v == qu->max_v && q->relpt_u == qu->relpt_u;
    double d = fmax(fabs(q->max_u - qu->max_u), fabs(q->max_v - qu->max_v));
    snprintf(buf, size, "max errors %.4g / %.4g vs %.4g / %.4g (difference %.2g)", q->max_u, q->max_v,
             qu->max_u, qu->max_v, d);
    return same || d < persp__claim(PERSP_CLAIM_QUADRATIC_UNNORM)->bound ? V_HOLDS : V_FAILS;
}

static verdict check_cubic(rep *r, char *buf, size_t size)
{
    const persp_accuracy_row *q = paper_quad(r, "quadratic"), *cu = paper_quad(r, "cubic");
    if (!q || !cu) return V_NA;
    int groups = 0, wins = 0;
    for (int g = 0; g < PERSP_HBAR_COUNT; g++) {
        const persp_accuracy_row *a = row_of(r, "cubic", "random-triangles", persp__hbar_groups[g]),
                                 *b = row_of(r, "quadratic", "random-triangles", persp__hbar_groups[g]);
        if (a && b) groups++, wins += rmax(a) <= rmax(b);
    }
    snprintf(buf, size, "paper-quad max %.3g vs %.3g texels; better in %d of %d depth groups", rmax(cu),
             rmax(q), wins, groups);
    return rmax(cu) < rmax(q) && wins == groups ? V_HOLDS : rmax(cu) < rmax(q) ? V_PARTLY : V_FAILS;
}

static verdict check_incremental(rep *r, char *buf, size_t size)
{
    double worst = -1;
    for (size_t i = 0; i < persp_accuracy_row_count(r->acc); i++) {
        const persp_accuracy_row *x = persp_accuracy_row_at(r->acc, i);
        if (!strcmp(x->method, "incremental") && !strchr(x->case_name, '@')) worst = fmax(worst, rmax(x));
    }
    if (worst < 0) return V_NA;
    snprintf(buf, size, "max %.2g texels over paper-quad and random triangles", worst);
    return worst < persp__claim(PERSP_CLAIM_INCREMENTAL)->bound ? V_HOLDS : V_FAILS;
}

static verdict check_affine_grows(rep *r, char *buf, size_t size)
{
    /* With few triangles per group one step may dip; the trend is the claim. */
    int n = 0, rising = 0;
    double prev = -1, first = NAN, last = NAN;
    for (int g = 0; g < PERSP_HBAR_COUNT; g++) {
        const persp_accuracy_row *x = row_of(r, "affine", "random-triangles", persp__hbar_groups[g]);
        if (!x) continue;
        if (n++ == 0) first = x->max_u;
        rising += x->max_u > prev;
        prev = last = x->max_u;
    }
    if (n <= 1) return V_NA;
    snprintf(buf, size, "max u %.3g → %.3g texels from ħ = 1.25 to 8", first, last);
    return last > first && rising >= n - 1 ? V_HOLDS : last > first ? V_PARTLY : V_FAILS;
}

static verdict check_incremental_speed(rep *r, char *buf, size_t size)
{
    double e = NAN, inc = NAN;
    for (size_t i = 0; i < r->nspecs; i++) {
        if (!strcmp(r->specs[i], "exact")) e = r->ms[i];
        if (!strcmp(r->specs[i], "incremental")) inc = r->ms[i];
    }
    if (!(e == e && inc == inc)) return V_NA;
    double gain = e / inc - 1.0;
    snprintf(buf, size, "%+.0f %% (corridor %dx%d, %.3g vs %.3g ms; timing noise included)", 100 * gain, r->w,
             r->h, inc, e);
    return 100 * gain >= persp__claim(PERSP_CLAIM_INCREMENTAL_SPEED)->above ? V_HOLDS
           : gain > 0                                                      ? V_PARTLY
                                                                           : V_FAILS;
}

static void claims(rep *r)
{
    fputs(
        "<h2 id=claims>Claims of the sources</h2>\n<p>As listed in docs/REPRODUCTION.md, "
        "measured again "
        "in this run (paper-quad: the line y = 32 of [Romanyuk-PCF] Fig. 4.10; relpt in %).</p>\n"
        "<table class=claims>\n<tr><th>source<th>claim<th>published<th>measured here<th>verdict\n",
        r->f);
    static const struct {
        persp_claim_id id;
        claim_check check;
    } checks[] = {
        {PERSP_CLAIM_SHIFTED_ANCHOR, check_shifted_anchor},
        {PERSP_CLAIM_BEZIER, check_bezier},
        {PERSP_CLAIM_BEZIER_QUADT, check_bezier_quadt},
        {PERSP_CLAIM_QUADRATIC_UNNORM, check_quadratic_unnorm},
        {PERSP_CLAIM_CUBIC, check_cubic},
        {PERSP_CLAIM_INCREMENTAL, check_incremental},
        {PERSP_CLAIM_AFFINE_GROWS, check_affine_grows},
        {PERSP_CLAIM_INCREMENTAL_SPEED, check_incremental_speed},
    };
    for (size_t i = 0; i < sizeof checks / sizeof checks[0]; i++) {
        char buf[256] = "";
        const verdict v = checks[i].check(r, buf, sizeof buf);
        claim(r, persp__claim(checks[i].id), buf, v);
    }
    shading_claims(r);
    fputs("</table>\n", r->f);
}

/* ---------------------------------------------------------------- images */

static void images(rep *r)
{
    fprintf(
        r->f,
        "<h2 id=images>Images</h2>\n<p>Every method on the built-in scenes at %dx%d, the middle "
        "fifth enlarged 4×, and the per-pixel error against the exact form (max of |Δu|, |Δv| in "
        "texels, logarithmic scale with its legend).</p>\n",
        r->w, r->h);
    /* The slider: a method over exact, the split dragged with a range input. */
    fputs("<h3>Before / after</h3>\n<p><select id=sm>", r->f);
    for (size_t i = 0; i < r->nspecs; i++) {
        char name[256];
        snprintf(name, sizeof name, "corridor_%s", r->specs[i]);
        file_name(name);
        fprintf(r->f, "<option value=\"img/%s.png\"%s>", name,
                !strcmp(r->specs[i], "affine") ? " selected" : "");
        esc(r->f, r->specs[i]);
        fputs("</option>", r->f);
    }
    fprintf(r->f,
            "</select> (left) against exact (right)</p>\n<div class=slider id=sl>"
            "<img src=\"img/corridor_exact.png\" width=%d height=%d alt=exact>"
            "<div class=top id=st style=\"width:50%%\"><img id=si src=\"img/corridor_affine.png\" "
            "width=%d "
            "height=%d alt=method></div></div><br><input type=range id=sr min=0 max=100 value=50 "
            "style=\"width:%dpx\">\n",
            2 * r->w, 2 * r->h, 2 * r->w, 2 * r->h, 2 * r->w);
    fputs(
        "<script>\n(function(){var s=document.getElementById('sr'),t=document.getElementById('st'),"
        "m=document.getElementById('sm'),i=document.getElementById('si');\n"
        "s.oninput=function(){t.style.width=s.value+'%';};\n"
        "m.onchange=function(){i.src=m.value;};\n"
        "document.getElementById('sl').setAttribute('data-slider','ready');})();\n</script>\n",
        r->f);
    cmd(r, "persp render corridor --method affine --size %dx%d -o affine.png", r->w, r->h);
    for (int s = 0; s < SCENES; s++) {
        fprintf(r->f, "<h3>%s</h3>\n", scenes[s]);
        for (size_t i = 0; i < r->nspecs; i++) {
            char name[256], heat[256], path[1400];
            snprintf(name, sizeof name, "%s_%s", scenes[s], r->specs[i]);
            file_name(name);
            snprintf(heat, sizeof heat, "%s@%dx%d_%s", scenes[s], r->w, r->h, r->specs[i]);
            file_name(heat);
            fputs("<figure>", r->f);
            fprintf(r->f, "<img src=\"img/%s.png\" width=%d height=%d alt=\"%s\">", name, r->w,
                    r->h, name);
            fprintf(r->f, "<img src=\"img/%s_crop.png\" width=%d height=%d alt=\"%s crop\">", name,
                    r->w / 5 * 4, r->h / 5 * 4, name);
            snprintf(path, sizeof path, "%s/heat/%s.png", r->dir, heat);
            if (r->d->from_dir && !file_exists(path)) {
                /* A sweep run with --heatmap FROM/heat: its maps join the page. */
                char src[1400];
                snprintf(src, sizeof src, "%s/heat/%s.png", r->d->from_dir, heat);
                if (file_exists(src)) copy_file(src, path);
            }
            if (file_exists(path))
                /* At its own size: scaled down, its legend's text would shrink
                 * below legibility. */
                fprintf(r->f, "<img src=\"heat/%s.png\" alt=\"%s error\">", heat, heat);
            fputs("<figcaption>", r->f);
            esc(r->f, r->specs[i]);
            fputs("</figcaption></figure>\n", r->f);
        }
        cmd(r,
            "persp render %s --method M --size %dx%d -o M.png; persp accuracy --case %s --size "
            "%dx%d --heatmap heat/",
            scenes[s], r->w, r->h, scenes[s], r->w, r->h);
    }
}

/* --------------------------------------------------------------- shading */

static persp_status shading(rep *r)
{
    fputs("<h2 id=shading>Shading ([Romanyuk-PCF] §4.2–4.3)</h2>\n", r->f);
    if (r->d->from_dir) {
        fputs("<p>Not part of the sweep read from the merged results.</p>\n", r->f);
        return PERSP_OK;
    }
    char svg[1200], txt[1200];
    snprintf(svg, sizeof svg, "%s/shading.svg", r->dir);
    snprintf(txt, sizeof txt, "%s/shading.txt", r->dir);
    say(r, "shading accuracy (%d triangles per depth ratio)", r->quick ? 4 : 20);
    FILE *t = fopen(txt, "w");
    if (!t) return persp__fail(r->ctx, PERSP_ERR_IO, "%s: cannot create", txt);
    persp_shading_accuracy_desc sd;
    memset(&sd, 0, sizeof sd);
    sd.triangles = r->quick ? 4 : 20;
    sd.width = r->quick ? 160 : 640, sd.height = r->quick ? 120 : 480;
    sd.svg_path = svg;
    persp_status st = persp_shading_accuracy_report(r->ctx, &sd, t);
    if (fclose(t) != 0 && st == PERSP_OK)
        st = persp__fail(r->ctx, PERSP_ERR_IO, "%s: write failed", txt);
    if (st != PERSP_OK) return st;
    fputs("<p>Fig. 4.3–4.4 (Gouraud's error factor Δ(u) and its maximum by depth ratio) and the "
          "errors of the t_w "
          "approximations of §4.3, measured in this run:</p>\n<figure class=plot>",
          r->f);
    inline_svg_file(r, svg);
    fputs("</figure>\n<details><summary>The full shading report (colour and normal errors of every "
          "mode by depth "
          "ratio, t_w table, lit scene)</summary><pre>",
          r->f);
    FILE *in = fopen(txt, "r");
    if (in) {
        char line[1024];
        while (fgets(line, sizeof line, in))
            esc(r->f, line);
        fclose(in);
    }
    fputs("</pre></details>\n", r->f);
    cmd(r, "persp accuracy --shading --triangles %d --size %dx%d --svg shading.svg", sd.triangles,
        sd.width, sd.height);
    return PERSP_OK;
}

/* --------------------------------------------------------------- filters */

/* The rows of `persp accuracy --filter --json` read back, for --from. */
static persp_filter_accuracy_row *filter_rows_read(const char *path, size_t *count)
{
    json_t *root = json_load_file(path, 0, NULL);
    *count = 0;
    if (!json_is_array(root)) {
        json_decref(root);
        return NULL;
    }
    size_t n = json_array_size(root);
    persp_filter_accuracy_row *rows = calloc(n ? n : 1, sizeof *rows);
    for (size_t i = 0; rows && i < n; i++) {
        json_t *o = json_array_get(root, i);
        persp_filter_accuracy_row *x = &rows[*count];
        const char *c = json_string_value(json_object_get(o, "case")),
                   *p = json_string_value(json_object_get(o, "pipeline")),
                   *f = json_string_value(json_object_get(o, "filter"));
        if (!c || !p || !f) continue;
        snprintf(x->case_name, sizeof x->case_name, "%s", c);
        snprintf(x->pipeline, sizeof x->pipeline, "%s", p);
        snprintf(x->filter, sizeof x->filter, "%s", f);
        json_t *ps = json_object_get(o, "psnr_db");
        x->psnr = json_is_number(ps) ? json_number_value(ps) : INFINITY;
        x->ssim = json_number_value(json_object_get(o, "ssim"));
        x->max_err = json_number_value(json_object_get(o, "max_err"));
        x->mean_err = json_number_value(json_object_get(o, "mean_err"));
        x->fetches_px = json_number_value(json_object_get(o, "fetches_px"));
        x->ns_px = json_number_value(json_object_get(o, "ns_px"));
        (*count)++;
    }
    json_decref(root);
    return rows;
}

/* PSNR against the tilt of the plane, one line per filter: how each filter
 * holds up as the footprint grows anisotropic. */
static void filter_plot(rep *r, const persp_filter_accuracy_row *rows, size_t n)
{
    enum { MAXP = 16 };
    double xs[PERSP_SVG_MAX_SERIES][MAXP], ys[PERSP_SVG_MAX_SERIES][MAXP];
    persp_svg_panel p;
    memset(&p, 0, sizeof p);
    p.title = "filter quality against tilt";
    p.xlabel = "tilt of the plane (degrees)";
    p.ylabel = "PSNR (dB)";
    p.xmin = 0, p.xmax = 90;
    const char *names[PERSP_SVG_MAX_SERIES];
    int points = 0;
    for (size_t i = 0; i < n; i++) {
        int deg;
        if (sscanf(rows[i].case_name, "tilt-%d", &deg) != 1 || !isfinite(rows[i].psnr)) continue;
        int k = 0;
        while (k < p.series_count && strcmp(names[k], rows[i].filter))
            k++;
        if (k == p.series_count) {
            if (k == PERSP_SVG_MAX_SERIES) continue;
            names[k] = rows[i].filter;
            p.series[k].label = names[k];
            p.series[k].x = xs[k], p.series[k].y = ys[k];
            p.series_count++;
        }
        if (p.series[k].n < MAXP) {
            xs[k][p.series[k].n] = deg, ys[k][p.series[k].n] = rows[i].psnr;
            p.series[k].n++, points++;
        }
    }
    if (points < 2 * p.series_count || !p.series_count) return;
    fputs("<figure class=plot>", r->f);
    inline_svg(r, &p, 1, 620, 360);
    fputs("</figure>\n", r->f);
}

static const persp_filter_accuracy_row *filter_row(const persp_filter_accuracy_row *rows, size_t n,
                                                   const char *filter, const char *cname)
{
    for (size_t i = 0; i < n; i++)
        if (!strcmp(rows[i].filter, filter) && !strcmp(rows[i].case_name, cname)) return &rows[i];
    return NULL;
}

/* The conclusions of [Romaniuk-ObjSpace] that the filter rows decide
 * (docs/REPRODUCTION.md, claims 3 and 4 of that section). */
static void objspace_claims(rep *r, const persp_filter_accuracy_row *rows, size_t n)
{
    int cases = 0, over_iso = 0, over_aniso = 0, faster = 0;
    double log_ratio = 0.0;
    for (size_t i = 0; i < n; i++) {
        if (strcmp(rows[i].filter, "object")) continue;
        const persp_filter_accuracy_row *o = &rows[i],
                                        *t = filter_row(rows, n, "trilinear", o->case_name),
                                        *e = filter_row(rows, n, "ewa", o->case_name),
                                        *a = filter_row(rows, n, "aniso:16", o->case_name);
        if (!t || !e || !a) continue;
        cases++;
        over_iso += o->psnr > t->psnr && o->psnr > e->psnr;
        over_aniso += o->psnr > a->psnr;
        faster += o->ns_px < a->ns_px;
        log_ratio += log(o->ns_px / a->ns_px);
    }
    if (!cases) return;
    fputs("<h3>Claims of [Romaniuk-ObjSpace]</h3>\n<table "
          "class=claims>\n<tr><th>source<th>claim<th>published"
          "<th>measured here<th>verdict\n",
          r->f);
    char buf[256];
    snprintf(buf, sizeof buf,
             "PSNR of object above trilinear and EWA in %d of %d cases, above aniso:16 in %d of %d",
             over_iso, cases, over_aniso, cases);
    /* Comparisons without figures: nothing for the claims table to hold. */
    const persp_claim accuracy = {.source = "[Romaniuk-ObjSpace]",
                                  .text = "texturing in object space gives higher accuracy than "
                                          "screen-space texturing",
                                  .published = "higher accuracy"},
                      speed = {.source = "[Romaniuk-ObjSpace]",
                               .text = "filtering in screen space is substantially more "
                                       "productive than anisotropic filtering",
                               .published = "more productive"};
    claim(r, &accuracy, buf,
          over_iso == cases && over_aniso == cases ? V_HOLDS
          : over_iso == cases                      ? V_PARTLY
                                                   : V_FAILS);
    snprintf(buf, sizeof buf,
             "object faster than aniso:16 in %d of %d cases (time ratio %.2g, geometric mean)",
             faster, cases, exp(log_ratio / cases));
    claim(r, &speed, buf,
          faster == cases ? V_HOLDS
          : faster        ? V_PARTLY
                          : V_FAILS);
    fputs("</table>\n", r->f);
}

static void filter_table(rep *r, const persp_filter_accuracy_row *rows, size_t n)
{
    fputs("<p>PSNR over R, G, B of covered pixels and mean SSIM of luma against N×N samples per "
          "pixel of the exact "
          "mapping (bilinear on level 0, box-filtered); texels read and render time per pixel. "
          "<a href=\"filter.json\">filter.json</a></p>\n<table>\n<tr><th>filter<th>pipeline<th>case"
          "<th>PSNR dB<th>SSIM<th>max err<th>mean err<th>fetches/px<th>ns/px\n",
          r->f);
    for (size_t i = 0; i < n; i++) {
        const persp_filter_accuracy_row *x = &rows[i];
        fputs("<tr><td>", r->f);
        esc(r->f, x->filter);
        fputs("<td>", r->f);
        esc(r->f, x->pipeline);
        fputs("<td>", r->f);
        esc(r->f, x->case_name);
        if (isfinite(x->psnr))
            fprintf(r->f, "<td>%.2f", x->psnr);
        else
            fputs("<td>∞", r->f);
        fprintf(r->f, "<td>%.4f<td>%.3g<td>%.3g<td>%.3g<td>%.3g\n", x->ssim, x->max_err,
                x->mean_err, x->fetches_px, x->ns_px);
    }
    fputs("</table>\n", r->f);
    filter_plot(r, rows, n);
    objspace_claims(r, rows, n);
}

static persp_status filters(rep *r)
{
    fputs("<h2 id=filters>Texture filters against the supersampled reference</h2>\n", r->f);
    char path[1200];
    snprintf(path, sizeof path, "%s/filter.json", r->dir);
    if (r->d->from_dir) {
        char src[1200];
        size_t n = 0;
        snprintf(src, sizeof src, "%s/filter.json", r->d->from_dir);
        persp_filter_accuracy_row *rows = file_exists(src) ? filter_rows_read(src, &n) : NULL;
        if (!rows || !n) {
            fputs("<p>Not in the folder the page was built from (put the output of <code>persp "
                  "accuracy "
                  "--filter --json</code> there as filter.json).</p>\n",
                  r->f);
        } else {
            copy_file(src, path);
            filter_table(r, rows, n);
            cmd(r, "persp accuracy --filter --json -o filter.json");
        }
        free(rows);
        return PERSP_OK;
    }
    static const char *const quick_cases[] = {"corridor", "floor", "tilt-45", "tilt-70", "tilt-85"};
    persp_filter_accuracy_desc fd;
    memset(&fd, 0, sizeof fd);
    if (r->quick) {
        fd.cases = quick_cases, fd.case_count = 5;
        fd.width = 96, fd.height = 72, fd.samples = 4, fd.repeats = 1;
    }
    say(r, "filter accuracy (%s)",
        r->quick ? "5 cases at 96x72, 4x4 reference samples" : "all cases, defaults");
    persp_filter_accuracy_result *fr = NULL;
    persp_status st = persp_filter_accuracy_run(r->ctx, &fd, &fr);
    if (st != PERSP_OK) return st;
    persp_outfile j;
    if ((st = persp__outfile_open(r->ctx, path, &j)) == PERSP_OK)
        st = persp__outfile_close(r->ctx, &j,
                                  persp_filter_accuracy_write(r->ctx, fr, PERSP_REPORT_JSON, j.f));
    if (st != PERSP_OK) {
        persp_filter_accuracy_destroy(fr);
        return st;
    }
    size_t n = persp_filter_accuracy_row_count(fr);
    filter_table(r, n ? persp_filter_accuracy_row_at(fr, 0) : NULL, n);
    if (r->quick)
        cmd(r, "persp accuracy --filter --case corridor,floor,tilt-45,tilt-70,tilt-85 --size 96x72 "
               "--samples 4 "
               "--repeats 1");
    else
        cmd(r, "persp accuracy --filter");
    persp_filter_accuracy_destroy(fr);
    return PERSP_OK;
}

/* --------------------------------------------------------------- hardware */

/* The RTL modules' area and error (docs/HARDWARE.md) from the summary
 * scripts/hw.sh wrote (persp_report_html_desc.hardware_summary): its table
 * and the area/error plot beside it (hw/plot_pareto.py). Read, not
 * measured here: the flow needs Verilator, Yosys and nextpnr, and minutes. */
static void hardware(rep *r, const char *summary)
{
    if (!summary) return;
    char plot[PERSP_PATH_MAX];
    const char *slash = strrchr(summary, '/');
    snprintf(plot, sizeof plot, "%.*spareto.svg", slash ? (int)(slash - summary + 1) : 0, summary);
    json_error_t err;
    json_t *root = file_exists(summary) ? json_load_file(summary, JSON_REJECT_DUPLICATES, &err) : NULL;
    json_t *mods = root ? json_object_get(root, "modules") : NULL;
    if (!json_is_array(mods)) {
        json_decref(root);
        return;
    }
    fputs("<h2 id=hardware>Hardware ([Romanyuk-PCF] §4.3, §4.5, §4.8)</h2>\n<p>Read from out/hw/summary.json "
          "(scripts/hw.sh; docs/HARDWARE.md): every module verified bit for bit against its C model, then "
          "synthesized. ice40_lc includes the out-of-context wrapper's flip-flops.</p>\n<table>\n<tr><th>module"
          "<th>CMOS transistors<th>iCE40 LC<th>SB_MAC16<th>Fmax MHz<th>pixels/clock<th>max error<th>unit"
          "<th>checked<th>mismatches\n",
          r->f);
    static const char *const keys[] = {"cmos_transistors", "ice40_lc", "ice40_dsp", "fmax_mhz", "pixels_per_clock"};
    size_t i;
    json_t *m;
    json_array_foreach(mods, i, m)
    {
        const char *unit = json_string_value(json_object_get(m, "error_unit"));
        json_t *e = json_object_get(m, unit ? "max_error" : "max_error_texels");
        fputs("<tr><td>", r->f);
        esc(r->f, json_string_value(json_object_get(m, "module")));
        for (size_t k = 0; k < sizeof keys / sizeof keys[0]; k++) {
            json_t *v = json_object_get(m, keys[k]);
            fputs("<td>", r->f);
            if (json_is_integer(v))
                fprintf(r->f, "%lld", (long long)json_integer_value(v));
            else
                num(r->f, json_is_number(v) ? json_number_value(v) : NAN);
        }
        fputs("<td>", r->f);
        num(r->f, json_is_number(e) ? json_number_value(e) : NAN);
        fputs("<td>", r->f);
        esc(r->f, unit ? unit : "texels");
        for (int k = 0; k < 2; k++) {
            json_t *v = json_object_get(m, k ? "mismatches" : "vectors_checked");
            fputs("<td>", r->f);
            if (json_is_integer(v)) fprintf(r->f, "%lld", (long long)json_integer_value(v));
            else fputs("–", r->f);
        }
        fputc('\n', r->f);
    }
    fputs("</table>\n", r->f);
    if (file_exists(plot)) inline_svg_file(r, plot);
    cmd(r, "bash scripts/hw.sh BUILD");
    json_decref(root);
}

/* ------------------------------------------------------------------ entry */

/* Every method that runs without parameters, and the second approach of
 * [Romanyuk-PCF] §4.7, which the claims need. */
static void default_methods(rep *r)
{
    persp_method_info info;
    r->nspecs = 0;
    for (size_t i = 0; persp_method_get(i, &info) == PERSP_OK && r->nspecs < MAX_METHODS - 1; i++)
        if (persp_method_check(info.name) == PERSP_OK) r->specs[r->nspecs++] = info.name;
    if (persp_method_check("bezier:quadt") == PERSP_OK) r->specs[r->nspecs++] = "bezier:quadt";
}

/* Removes the files in folder (not in folders below it) and then folder
 * itself if that leaves it empty: a folder persp_report_html made, whose
 * every file is the failed call's. */
static void remove_made(const char *folder)
{
    DIR *d = opendir(folder);
    if (d) {
        struct dirent *e;
        char file[1400];
        while ((e = readdir(d)) != NULL) {
            struct stat sb;
            snprintf(file, sizeof file, "%s/%s", folder, e->d_name);
            if (lstat(file, &sb) == 0 && S_ISREG(sb.st_mode)) (void)unlink(file);
        }
        closedir(d);
    }
    (void)rmdir(folder);
}

/* The page and its files into the folders persp_report_html made: dir,
 * with img/ and heatdir (its heat/). */
static persp_status report_files(rep *r, const persp_report_html_desc *desc, const char *dir,
                                 const char *heatdir)
{
    char path[1200];
    persp_accuracy_result *acc = NULL;
    persp_status st;
    if (desc->from_dir) {
        snprintf(path, sizeof path, "%s/accuracy.json", desc->from_dir);
        say(r, "reading %s", path);
        st = persp_accuracy_read(r->ctx, path, &acc);
        if (st != PERSP_OK) return st;
        r->acc = acc;
        methods_of_result(r);
        /* The images are rendered at the size the sweep measured its scenes at. */
        for (size_t i = 0; i < persp_accuracy_row_count(acc); i++) {
            const char *at = strchr(persp_accuracy_row_at(acc, i)->case_name, '@');
            int w, h;
            if (at && sscanf(at + 1, "%dx%d", &w, &h) == 2 && w > 0 && h > 0 && w <= 4096 &&
                h <= 4096) {
                r->w = w, r->h = h;
                break;
            }
        }
    } else {
        default_methods(r);
        static const char *const cases[] = {"paper-quad", "random-triangles", "corridor", "floor"};
        persp_accuracy_desc ad;
        memset(&ad, 0, sizeof ad);
        ad.methods = r->specs, ad.method_count = r->nspecs;
        ad.cases = cases, ad.case_count = 4;
        ad.width = r->w, ad.height = r->h;
        ad.triangles = r->triangles;
        ad.heatmap_dir = heatdir;
        say(r, "method accuracy: %zu methods, %d triangles per depth ratio, scenes at %dx%d",
            r->nspecs, r->triangles, r->w, r->h);
        st = persp_accuracy_run(r->ctx, &ad, &acc);
        if (st != PERSP_OK) return st;
        r->acc = acc;
        snprintf(path, sizeof path, "%s/accuracy.json", dir);
        persp_outfile j;
        if ((st = persp__outfile_open(r->ctx, path, &j)) == PERSP_OK)
            st = persp__outfile_close(r->ctx, &j,
                                      persp_accuracy_write(r->ctx, acc, PERSP_REPORT_JSON, j.f));
    }
    if (st == PERSP_OK) st = render_all(r);
    /* Written last, through a temporary file: the page appears only whole. */
    snprintf(path, sizeof path, "%s/index.html", dir);
    persp_outfile page;
    if (st == PERSP_OK && (st = persp__outfile_open(r->ctx, path, &page)) == PERSP_OK) r->f = page.f;
    if (st == PERSP_OK) {
        head(r);
        fputs("<p><a href=#methods>methods</a> · <a href=#claims>claims</a> · <a "
              "href=#images>images</a> · "
              "<a href=#shading>shading</a> · <a href=#filters>filters</a> · <a "
              "href=#env>environment</a> · "
              "<a href=\"accuracy.json\">accuracy.json</a></p>\n",
              r->f);
        method_table(r);
        if (desc->from_dir)
            cmd(r, "persp accuracy --case paper-quad,random-triangles,corridor,floor --json "
                    "--shard K/N; persp merge; "
                    "persp report --from DIR");
        else {
            char ml[700] = "";
            for (size_t i = 0; i < r->nspecs; i++)
                if (strlen(ml) + strlen(r->specs[i]) + 2 < sizeof ml)
                    strcat(ml, i ? "," : ""), strcat(ml, r->specs[i]);
            cmd(r,
                "persp accuracy --method %s --case paper-quad,random-triangles,corridor,floor "
                "--size %dx%d "
                "--triangles %d --json",
                ml, r->w, r->h, r->triangles);
        }
        claims(r);
        images(r);
        st = shading(r);
        if (st == PERSP_OK) st = filters(r);
        if (st == PERSP_OK) {
            hardware(r, desc->hardware_summary);
            environment(r);
            fputs("</body></html>\n", r->f);
        }
        st = persp__outfile_close(r->ctx, &page, st);
        if (st == PERSP_OK) say(r, "wrote %s", path);
    }
    persp_accuracy_destroy(acc);
    return st;
}

persp_status persp_report_html(persp_context *ctx, const persp_report_html_desc *desc)
{
    if (!ctx) return PERSP_ERR_INVALID_ARGUMENT;
    persp__clear_error(ctx);
    if (!desc || !desc->dir)
        return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "report: no folder");
    if (strlen(desc->dir) > 1000)
        return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "report: folder name too long");
    /* "out/" names the folder "out": its files are "out/index.html", not
     * "out//index.html" (the root "/" stays). */
    char dir[1001];
    snprintf(dir, sizeof dir, "%s", desc->dir);
    for (size_t n = strlen(dir); n > 1 && dir[n - 1] == '/'; n--) dir[n - 1] = '\0';
    rep r;
    memset(&r, 0, sizeof r);
    r.ctx = ctx, r.d = desc, r.log = desc->log, r.dir = dir, r.quick = desc->quick;
    r.w = r.quick ? 192 : 512, r.h = r.quick ? 144 : 384;
    r.triangles = r.quick ? 4 : 40;
    char path[1200];
    snprintf(path, sizeof path, "%s/img", dir);
    char heatdir[1200];
    snprintf(heatdir, sizeof heatdir, "%s/heat", dir);
    /* The folder that could not be made is named, the report's own first.
     * Those this call made are removed again, with the files it wrote into
     * them, if it fails: a refused report leaves nothing half-written. (In
     * folders that were there before, the files written up to the failure
     * stay; the page itself appears only whole.) */
    const char *dirs[3] = {dir, path, heatdir};
    int made[3] = {0, 0, 0};
    persp_status st = PERSP_OK;
    for (int k = 0; k < 3 && st == PERSP_OK; k++) {
        made[k] = mkdir(dirs[k], 0777) == 0;
        if (!made[k] && errno != EEXIST)
            st = persp__fail(ctx, PERSP_ERR_IO, "%s: cannot create the folder: %s", dirs[k], strerror(errno));
    }
    if (st == PERSP_OK) st = report_files(&r, desc, dir, heatdir);
    for (int k = 2; k >= 0 && st != PERSP_OK; k--)
        if (made[k]) remove_made(dirs[k]);
    return st;
}
