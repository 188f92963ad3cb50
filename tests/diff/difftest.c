/*
 * Differential test of persp against Mesa llvmpipe (docs/RELIABILITY.md,
 * "Differential testing against Mesa"): scenes from diffgen.c drawn by
 * persp (method exact, shading none) and by the OpenGL peer of `persp
 * bench` (bench/peer_osmesa.c), compared pixel by pixel within bounds per
 * filter that follow from what OpenGL fixes and what it leaves to the
 * implementation (see bounds[] below).
 *
 *   persp_difftest [--seeds A:B] [--fail-dir DIR] [--verbose]
 *       random scenes of seeds A..B-1; a scene out of bounds is written to
 *       DIR/seed-N/ (scene.json, textures, persp.png, peer.png, diff.png)
 *   persp_difftest --seeds A:B --generate DIR
 *       only writes the scenes of seeds A..B-1 to DIR/seed-N/
 *   persp_difftest --replay DIR...
 *       the scenes of those folders (written by --fail-dir, or
 *       tests/diff/regress/NAME/)
 *   persp_difftest --golden DIR
 *       the golden images of DIR (tests/golden/data) whose scene and filter
 *       OpenGL defines, against the peer
 *
 * Prints one line per scene out of bounds (every scene with --verbose) and a
 * summary per filter; exits 1 when any scene is out of bounds, 2 on bad
 * usage or a setup failure.
 */
#include "diffgen.h"
#include "diffref.h"
#include "../../bench/peer.h"

#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* ------------------------------------------------------------- the bounds */

/* What passes (docs/RELIABILITY.md, "Differential testing against Mesa").
 *
 * llvmpipe is a conforming OpenGL implementation, not an exact one: it
 * takes derivatives by differences across 2×2 pixel quads and approximates
 * rho, both within the latitude of GL 4.6 §8.14.1, so on mip-mapped scenes
 * many of its pixels (up to 45 % of those checked) lie a level or a blend
 * weight away from the ideal value (the "peer off" column), and bounds on the share of pixels
 * that differ or on the PSNR between the two images would measure
 * llvmpipe's approximations as much as persp's errors. Instead every pixel
 * where the two disagree (and every 16th where they agree) is judged by
 * diffref.c, which gives the interval of values GL allows there, and
 * persp must be inside it everywhere: max_persp_off is 0 for every filter.
 *
 * Coverage has the same arbiter (a pixel drawn by one side only is judged
 * like any other); the share of such pixels is bounded as well, as an
 * alarm that names the problem directly. Both rasterizers snap vertices to
 * 1/256 pixel and use the top-left rule, so they disagree only where a
 * pixel centre lies within about 1/256 pixel of an edge of a snapped
 * vertex that rounds differently (after clipping, say): an object of
 * perimeter P pixels has ~P/128 such pixels, 0.1 % of a 20×20 square. A
 * fill-rule, half-pixel or clipping error moves whole edges (every pixel
 * along P), tens of times that: 1 % separates the two.
 *
 * `differ_tol` only chooses which pixels count as "differing" for the
 * report and the arbiter: any difference for the filters that return one
 * texel, more than 1 (rounding of a blend) for the others. */
typedef struct bound {
    persp_filter filter;
    int differ_tol;
    double max_coverage_share; /* covered by exactly one side / covered by either */
    size_t max_persp_off;      /* pixels where persp's value is not one GL allows */
} bound;

static const bound bounds[] = {
    {PERSP_FILTER_NEAREST, 0, 0.01, 0},
    {PERSP_FILTER_BILINEAR, 1, 0.01, 0},
    {PERSP_FILTER_NEAREST_MIP_NEAREST, 0, 0.01, 0},
    {PERSP_FILTER_BILINEAR_MIP_NEAREST, 1, 0.01, 0},
    {PERSP_FILTER_NEAREST_MIP_LINEAR, 1, 0.01, 0},
    {PERSP_FILTER_TRILINEAR, 1, 0.01, 0},
};

static const bound *bound_of(persp_filter f)
{
    for (size_t i = 0; i < sizeof bounds / sizeof bounds[0]; i++)
        if (bounds[i].filter == f) return &bounds[i];
    return NULL;
}

/* ------------------------------------------------------------- comparison */

typedef struct diff_result {
    size_t either, both, one_only, differ;
    int max_abs;
    double psnr;
    double coverage_share, differ_share;
    /* From the arbiter (diffref.c): pixels checked, and those where
     * persp's / the peer's value is not one GL allows. */
    size_t checked, persp_off, peer_off;
    int off_x, off_y;
} diff_result;

/* a and b: RGBA8, w*h, the same row order. A pixel is covered where its
 * alpha is not the clear colour's 0 (diffgen.c gives every texel alpha 1).
 * With cover_by_alpha 0 every pixel counts as covered by both (golden
 * images, whose scenes clear to an opaque colour). */
static diff_result compare(const uint8_t *a, size_t a_stride, const uint8_t *b, size_t b_stride, int w, int h,
                           int cover_by_alpha, int tol, uint8_t *diff_rgba)
{
    diff_result r;
    memset(&r, 0, sizeof r);
    double sq = 0.0;
    for (int y = 0; y < h; y++) {
        const uint8_t *pa = a + (size_t)y * a_stride, *pb = b + (size_t)y * b_stride;
        for (int x = 0; x < w; x++, pa += 4, pb += 4) {
            uint8_t *pd = diff_rgba ? diff_rgba + 4 * ((size_t)y * (size_t)w + (size_t)x) : NULL;
            int ca = !cover_by_alpha || pa[3] != 0, cb = !cover_by_alpha || pb[3] != 0;
            if (pd) pd[0] = pd[1] = pd[2] = 0, pd[3] = 255;
            if (!ca && !cb) continue;
            r.either++;
            if (ca != cb) {
                r.one_only++;
                if (pd) pd[2] = 255; /* blue: covered by one side only */
                continue;
            }
            r.both++;
            int worst = 0;
            for (int c = 0; c < 3; c++) {
                int d = abs((int)pa[c] - (int)pb[c]);
                if (d > worst) worst = d;
                sq += (double)d * d;
            }
            if (worst > r.max_abs) r.max_abs = worst;
            if (worst > tol) r.differ++;
            if (pd) pd[0] = (uint8_t)(worst * 8 > 255 ? 255 : worst * 8), pd[1] = worst > tol ? 255 : 0;
        }
    }
    double mse = r.both ? sq / (3.0 * (double)r.both) : 0.0;
    r.psnr = mse > 0.0 ? 10.0 * log10(255.0 * 255.0 / mse) : INFINITY;
    r.coverage_share = r.either ? (double)r.one_only / (double)r.either : 0.0;
    r.differ_share = r.both ? (double)r.differ / (double)r.both : 0.0;
    return r;
}

static int within(const diff_result *r, const bound *b)
{
    return r->persp_off <= b->max_persp_off && r->coverage_share <= b->max_coverage_share;
}

/* ---------------------------------------------------------------- summary */

typedef struct summary {
    int scenes, failed;
    double worst_psnr, worst_differ, worst_coverage;
    int worst_max_abs;
    size_t checked, persp_off, peer_off;
    uint64_t worst_psnr_seed, worst_differ_seed, worst_coverage_seed;
} summary;

static summary sums[DIFF_FILTER_COUNT];

static void add_summary(int fi, uint64_t seed, const diff_result *r, int ok)
{
    summary *s = &sums[fi];
    if (s->scenes == 0) s->worst_psnr = INFINITY;
    s->scenes++;
    s->failed += !ok;
    if (r->psnr < s->worst_psnr) s->worst_psnr = r->psnr, s->worst_psnr_seed = seed;
    if (r->differ_share >= s->worst_differ) s->worst_differ = r->differ_share, s->worst_differ_seed = seed;
    if (r->coverage_share >= s->worst_coverage) s->worst_coverage = r->coverage_share, s->worst_coverage_seed = seed;
    if (r->max_abs > s->worst_max_abs) s->worst_max_abs = r->max_abs;
    s->checked += r->checked, s->persp_off += r->persp_off, s->peer_off += r->peer_off;
}

/* The peer's GL_RENDERER and GL_VERSION, for the summary. */
static char peer_name[256];

static void print_summary(void)
{
    printf("peer: %s\n", peer_name[0] ? peer_name : "(not run)");
    printf("%-20s %6s %6s %20s %24s %24s %6s %8s %6s %6s\n", "filter", "scenes", "failed", "worst PSNR dB (seed)",
           "worst differing % (seed)", "worst coverage % (seed)", "max|d|", "checked", "persp!", "peer!");
    for (int i = 0; i < DIFF_FILTER_COUNT; i++) {
        const summary *s = &sums[i];
        if (!s->scenes) continue;
        char psnr[32];
        if (isinf(s->worst_psnr))
            snprintf(psnr, sizeof psnr, "inf");
        else
            snprintf(psnr, sizeof psnr, "%.1f (%llu)", s->worst_psnr, (unsigned long long)s->worst_psnr_seed);
        printf("%-20s %6d %6d %20s %15.3f (%6llu) %15.3f (%6llu) %6d %8zu %6zu %6zu\n",
               persp_filter_name(diff_filters[i]), s->scenes, s->failed, psnr, 100.0 * s->worst_differ,
               (unsigned long long)s->worst_differ_seed, 100.0 * s->worst_coverage,
               (unsigned long long)s->worst_coverage_seed, s->worst_max_abs, s->checked, s->persp_off, s->peer_off);
    }
}

/* ------------------------------------------------------------- rendering */

typedef struct frames {
    persp_image mine;
    uint8_t *peer; /* w*h RGBA8, row 0 = bottom */
    int w, h;
} frames;

static void frames_free(persp_context *ctx, frames *f)
{
    persp_image_free(ctx, &f->mine);
    free(f->peer);
    memset(f, 0, sizeof *f);
}

/* Draws the scene with persp (unless skip_persp) and with llvmpipe. */
static int render_both(persp_context *ctx, const persp_scene *scene, int w, int h, persp_filter filter,
                       persp_depth_mode depth, int skip_persp, frames *out, char *err, size_t err_size)
{
    memset(out, 0, sizeof *out);
    out->w = w, out->h = h;
    if (!skip_persp) {
        if (persp_image_alloc(ctx, w, h, &out->mine) != PERSP_OK) {
            snprintf(err, err_size, "%s", persp_context_error(ctx));
            return -1;
        }
        float *zbuf = malloc((size_t)w * (size_t)h * sizeof *zbuf);
        if (!zbuf) {
            snprintf(err, err_size, "out of memory");
            frames_free(ctx, out);
            return -1;
        }
        persp_framebuffer fb = {w, h, out->mine.pixels, zbuf};
        persp_render_desc desc;
        memset(&desc, 0, sizeof desc);
        desc.method = "exact";
        desc.filter = filter;
        desc.shading = PERSP_SHADING_NONE;
        desc.depth_mode = depth;
        persp_status st = persp_render(ctx, scene, &desc, &fb, NULL);
        free(zbuf);
        if (st != PERSP_OK) {
            snprintf(err, err_size, "persp_render: %s", persp_context_error(ctx));
            frames_free(ctx, out);
            return -1;
        }
    }
    bench_peer_desc pd;
    memset(&pd, 0, sizeof pd);
    pd.width = w, pd.height = h, pd.scene = scene, pd.shading = PERSP_SHADING_NONE, pd.filter = filter;
    bench_peer *p = bench_peer_create(&pd, err, err_size);
    if (!p) {
        frames_free(ctx, out);
        return -1;
    }
    bench_peer_render(p, 1);
    if (!peer_name[0])
        snprintf(peer_name, sizeof peer_name, "%s, OpenGL %s", bench_peer_renderer(p), bench_peer_version(p));
    out->peer = malloc((size_t)w * (size_t)h * 4);
    if (out->peer) memcpy(out->peer, bench_peer_pixels(p), (size_t)w * (size_t)h * 4);
    bench_peer_destroy(p);
    if (!out->peer) {
        snprintf(err, err_size, "out of memory");
        frames_free(ctx, out);
        return -1;
    }
    return 0;
}

static void write_rgba(persp_context *ctx, const char *path, uint8_t *pixels, int w, int h)
{
    persp_image img = {w, h, (size_t)w * 4, pixels};
    if (persp_image_write_png(ctx, path, &img) != PERSP_OK)
        fprintf(stderr, "persp_difftest: %s\n", persp_context_error(ctx));
}

/* --------------------------------------------------------------- folders */

static int remove_tree(const char *dir)
{
    DIR *d = opendir(dir);
    if (!d) return -1;
    struct dirent *e;
    char path[4096];
    while ((e = readdir(d))) {
        if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, "..")) continue;
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        remove(path);
    }
    closedir(d);
    return rmdir(dir);
}

/* mkdir -p: every missing folder of the path. */
static int make_dir(const char *dir)
{
    char part[4096];
    snprintf(part, sizeof part, "%s", dir);
    for (char *p = part + 1; *p; p++) {
        if (*p != '/') continue;
        *p = 0;
        if (mkdir(part, 0777) != 0 && errno != EEXIST) break;
        *p = '/';
    }
    if (mkdir(dir, 0777) == 0 || errno == EEXIST) return 0;
    fprintf(stderr, "persp_difftest: cannot create %s: %s\n", dir, strerror(errno));
    return -1;
}

/* ---------------------------------------------------------- arbitration */

typedef struct arbiter_result {
    size_t checked, persp_off, peer_off;
    int first_x, first_y; /* first pixel persp is off at, -1 if none */
    uint8_t first_persp[4], first_peer[4];
    diff_ref_pixel first_ref;
    int peer_x, peer_y; /* first pixel the peer is off at */
    uint8_t peer_persp[4], peer_peer[4];
    diff_ref_pixel peer_ref;
} arbiter_result;

/* Whether value (RGBA8, alpha 0 = not covered) is one GL allows at the
 * pixel. tol: rounding to 8 bits (0.5) for the filters that return one
 * texel, plus the float evaluation of the blend (0.5 more) for the others. */
static int allowed(const diff_ref_pixel *p, const uint8_t *value, double tol, const uint8_t *clear)
{
    int inside = p->covered;
    for (int c = 0; c < 3 && inside; c++) inside = value[c] >= p->lo[c] - tol && value[c] <= p->hi[c] + tol;
    if (clear) /* opaque clear colour: the background is told by its colour */
        return inside || (p->background_ok && !memcmp(value, clear, 3));
    return value[3] == 0 ? p->background_ok : inside;
}

/* Every pixel where persp and the peer disagree (beyond tol, or on
 * coverage) and every SAMPLE_STEP-th pixel where they agree (a check of
 * the arbiter and of a fault both might share) against diffref.c. */
#define SAMPLE_STEP 16
static arbiter_result arbitrate(const diff_ref *ref, const persp_image *mine, const uint8_t *peer, int w, int h,
                                persp_filter filter, int tol, const uint8_t *clear)
{
    arbiter_result a;
    memset(&a, 0, sizeof a);
    a.first_x = a.first_y = -1;
    double rtol = filter == PERSP_FILTER_NEAREST || filter == PERSP_FILTER_NEAREST_MIP_NEAREST ? 0.5 : 1.0;
    size_t k = 0;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++, k++) {
            const uint8_t *pa = mine->pixels + (size_t)y * mine->stride + 4 * (size_t)x;
            const uint8_t *pb = peer + 4 * ((size_t)y * (size_t)w + (size_t)x);
            int differ = (pa[3] != 0) != (pb[3] != 0);
            for (int c = 0; c < 3 && !differ && pa[3]; c++) differ = abs((int)pa[c] - (int)pb[c]) > tol;
            int background = clear ? !memcmp(pa, clear, 3) && !memcmp(pb, clear, 3) : !pa[3] && !pb[3];
            if (!differ && (k % SAMPLE_STEP || background)) continue;
            diff_ref_pixel p = diff_ref_eval(ref, x, y);
            a.checked++;
            if (!allowed(&p, pa, rtol, clear)) {
                if (!a.persp_off) {
                    a.first_x = x, a.first_y = y, a.first_ref = p;
                    memcpy(a.first_persp, pa, 4);
                    memcpy(a.first_peer, pb, 4);
                }
                a.persp_off++;
            }
            if (!allowed(&p, pb, rtol, clear)) {
                if (!a.peer_off) {
                    a.peer_x = x, a.peer_y = y, a.peer_ref = p;
                    memcpy(a.peer_persp, pa, 4);
                    memcpy(a.peer_peer, pb, 4);
                }
                a.peer_off++;
            }
        }
    return a;
}

/* ------------------------------------------------------------------ cases */

static int verbose;

static void report(const char *what, persp_filter filter, persp_depth_mode depth, const diff_result *r,
                   const bound *b, int ok)
{
    if (ok && !verbose) return;
    printf("%s %s: %s depth=%s: %zu pixels covered, by one side only %.3f%% (<= %.1f%%); differing by > %d "
           "%.3f%%, PSNR %.1f dB, max |d| %d; checked against GL %zu, persp off %zu (<= %zu), peer off %zu\n",
           ok ? "ok  " : "FAIL", what, persp_filter_name(filter), depth == PERSP_DEPTH_INVW ? "invw" : "z",
           r->either, 100.0 * r->coverage_share, 100.0 * b->max_coverage_share, b->differ_tol,
           100.0 * r->differ_share, r->psnr, r->max_abs, r->checked, r->persp_off, b->max_persp_off, r->peer_off);
}

static int filter_index(persp_filter f)
{
    for (int i = 0; i < DIFF_FILTER_COUNT; i++)
        if (diff_filters[i] == f) return i;
    return -1;
}

static void print_pixel(const char *who, int x, int y, const uint8_t *mine, const uint8_t *peer,
                        const diff_ref_pixel *p)
{
    printf("  first pixel %s is off at: (%d, %d) from the bottom left: persp %d %d %d a=%d, peer %d %d %d a=%d; "
           "GL allows %s[%.2f, %.2f] [%.2f, %.2f] [%.2f, %.2f]%s\n",
           who, x, y, mine[0], mine[1], mine[2], mine[3], peer[0], peer[1], peer[2], peer[3],
           p->covered ? "" : "(no triangle) ", p->lo[0], p->hi[0], p->lo[1], p->hi[1], p->lo[2], p->hi[2],
           p->background_ok ? " or background" : "");
}

/* Loads DIR/scene.json, draws it both ways and compares; writes persp.png,
 * peer.png and diff.png into keep_dir when it is out of bounds and
 * keep_dir is set. 1: within bounds, 0: out of bounds, -1: error. */
static int run_case(persp_context *ctx, const char *dir, const char *label, const char *keep_dir, int count)
{
    char path[4096], err[512];
    snprintf(path, sizeof path, "%s/scene.json", dir);
    diff_case c;
    if (diff_case_read(path, &c, err, sizeof err)) {
        fprintf(stderr, "persp_difftest: %s\n", err);
        return -1;
    }
    persp_scene *scene = NULL;
    if (persp_scene_load(ctx, path, &scene) != PERSP_OK) {
        fprintf(stderr, "persp_difftest: %s\n", persp_context_error(ctx));
        return -1;
    }
    frames fr;
    if (render_both(ctx, scene, c.width, c.height, c.filter, c.depth, 0, &fr, err, sizeof err)) {
        fprintf(stderr, "persp_difftest: %s: %s\n", path, err);
        persp_scene_destroy(scene);
        return -1;
    }
    const bound *b = bound_of(c.filter);
    uint8_t *d = malloc((size_t)c.width * (size_t)c.height * 4);
    diff_result r = compare(fr.mine.pixels, fr.mine.stride, fr.peer, (size_t)c.width * 4, c.width, c.height, 1,
                            b->differ_tol, d);
    diff_ref *ref = diff_ref_create(scene, c.width, c.height, c.filter);
    if (!ref) {
        fprintf(stderr, "persp_difftest: %s: out of memory\n", path);
        persp_scene_destroy(scene);
        frames_free(ctx, &fr);
        free(d);
        return -1;
    }
    arbiter_result a = arbitrate(ref, &fr.mine, fr.peer, c.width, c.height, c.filter, b->differ_tol, NULL);
    diff_ref_destroy(ref);
    persp_scene_destroy(scene);
    r.checked = a.checked, r.persp_off = a.persp_off, r.peer_off = a.peer_off;
    r.off_x = a.first_x, r.off_y = a.first_y;
    int ok = within(&r, b);
    if (count) add_summary(filter_index(c.filter), c.seed, &r, ok);
    report(label, c.filter, c.depth, &r, b, ok);
    if (a.persp_off) print_pixel("persp", a.first_x, a.first_y, a.first_persp, a.first_peer, &a.first_ref);
    if (a.peer_off && verbose) print_pixel("peer", a.peer_x, a.peer_y, a.peer_persp, a.peer_peer, &a.peer_ref);
    if (!ok && keep_dir) {
        snprintf(path, sizeof path, "%s/persp.png", keep_dir);
        write_rgba(ctx, path, fr.mine.pixels, c.width, c.height);
        snprintf(path, sizeof path, "%s/peer.png", keep_dir);
        write_rgba(ctx, path, fr.peer, c.width, c.height);
        if (d) {
            snprintf(path, sizeof path, "%s/diff.png", keep_dir);
            write_rgba(ctx, path, d, c.width, c.height);
        }
    }
    free(d);
    frames_free(ctx, &fr);
    return ok;
}

static int run_seeds(persp_context *ctx, uint64_t first, uint64_t end, const char *fail_dir)
{
    char tmp[] = "/tmp/persp-difftest-XXXXXX";
    if (!mkdtemp(tmp)) {
        fprintf(stderr, "persp_difftest: cannot create a temporary folder: %s\n", strerror(errno));
        return 2;
    }
    int failed = 0, errors = 0;
    for (uint64_t seed = first; seed < end; seed++) {
        char dir[4096], label[64], err[512];
        snprintf(dir, sizeof dir, "%s/seed-%llu", tmp, (unsigned long long)seed);
        snprintf(label, sizeof label, "seed %llu", (unsigned long long)seed);
        if (make_dir(dir) || diff_generate(ctx, seed, dir, NULL, err, sizeof err)) {
            fprintf(stderr, "persp_difftest: seed %llu: %s\n", (unsigned long long)seed, err);
            errors++;
            continue;
        }
        int ok = run_case(ctx, dir, label, NULL, 1);
        remove_tree(dir);
        if (ok < 0) {
            errors++;
        } else if (!ok) {
            failed++;
            if (fail_dir) {
                /* The same seed writes the same files: the case again, kept. */
                snprintf(dir, sizeof dir, "%s/seed-%llu", fail_dir, (unsigned long long)seed);
                if (!make_dir(fail_dir) && !make_dir(dir) && !diff_generate(ctx, seed, dir, NULL, err, sizeof err)) {
                    int again = run_case(ctx, dir, "  kept", dir, 0);
                    (void)again;
                    printf("  written to %s (replay: persp_difftest --replay %s)\n", dir, dir);
                }
            }
        }
    }
    remove_tree(tmp);
    print_summary();
    printf("%llu scenes, %d out of bounds, %d errors\n", (unsigned long long)(end - first), failed, errors);
    return errors ? 2 : failed ? 1 : 0;
}

static int run_generate(persp_context *ctx, uint64_t first, uint64_t end, const char *out)
{
    if (make_dir(out)) return 2;
    for (uint64_t seed = first; seed < end; seed++) {
        char dir[4096], err[512];
        snprintf(dir, sizeof dir, "%s/seed-%llu", out, (unsigned long long)seed);
        if (make_dir(dir) || diff_generate(ctx, seed, dir, NULL, err, sizeof err)) {
            fprintf(stderr, "persp_difftest: seed %llu: %s\n", (unsigned long long)seed, err);
            return 2;
        }
    }
    return 0;
}

static int run_replay(persp_context *ctx, int n, char **dirs)
{
    int failed = 0, errors = 0;
    for (int i = 0; i < n; i++) {
        int ok = run_case(ctx, dirs[i], dirs[i], NULL, 1);
        if (ok < 0)
            errors++;
        else if (!ok)
            failed++;
    }
    print_summary();
    printf("%d scenes replayed, %d out of bounds, %d errors\n", n, failed, errors);
    return errors ? 2 : failed ? 1 : 0;
}

/* ----------------------------------------------------------------- golden */

/* The golden images whose scene OpenGL draws the same way: built-in
 * scenes, unlit, with the filters GL defines (aniso, aniso-window, ewa and
 * the object-space pipeline have no GL counterpart). */
static const struct {
    const char *scene, *filter;
    int w, h;
} goldens[] = {
    {"corridor", "nearest", 512, 384},
    {"corridor", "bilinear", 512, 384},
    {"corridor", "trilinear", 512, 384},
    {"floor", "bilinear", 320, 240},
    {"cube", "bilinear", 320, 240},
};

static int run_golden(persp_context *ctx, const char *data_dir)
{
    int failed = 0;
    for (size_t i = 0; i < sizeof goldens / sizeof goldens[0]; i++) {
        char path[4096], err[512], label[256];
        snprintf(path, sizeof path, "%s/%s_exact_%s_%dx%d.png", data_dir, goldens[i].scene, goldens[i].filter,
                 goldens[i].w, goldens[i].h);
        snprintf(label, sizeof label, "golden %s_exact_%s_%dx%d.png", goldens[i].scene, goldens[i].filter,
                 goldens[i].w, goldens[i].h);
        persp_image golden;
        persp_scene *scene = NULL;
        persp_filter filter;
        int aniso = 0;
        if (persp_image_load(ctx, path, &golden) != PERSP_OK ||
            persp_scene_builtin(ctx, goldens[i].scene, &scene) != PERSP_OK ||
            persp_filter_parse(goldens[i].filter, &filter, &aniso) != PERSP_OK) {
            fprintf(stderr, "persp_difftest: %s\n", persp_context_error(ctx));
            return 2;
        }
        if (golden.width != goldens[i].w || golden.height != goldens[i].h) {
            fprintf(stderr, "persp_difftest: %s: %dx%d, expected %dx%d\n", path, golden.width, golden.height,
                    goldens[i].w, goldens[i].h);
            return 2;
        }
        frames fr;
        int rc = render_both(ctx, scene, golden.width, golden.height, filter, PERSP_DEPTH_Z, 1, &fr, err,
                             sizeof err);
        diff_ref *ref = rc ? NULL : diff_ref_create(scene, golden.width, golden.height, filter);
        persp_scene_info info;
        persp_scene_get_info(scene, &info);
        if (rc || !ref) {
            persp_scene_destroy(scene);
            fprintf(stderr, "persp_difftest: %s: %s\n", label, rc ? err : "out of memory");
            if (!rc) frames_free(ctx, &fr);
            persp_image_free(ctx, &golden);
            return 2;
        }
        const bound *b = bound_of(filter);
        /* These scenes clear to an opaque colour: every pixel counts as
         * covered by both for the statistics, and the arbiter tells the
         * background by the clear colour. */
        diff_result r = compare(golden.pixels, golden.stride, fr.peer, (size_t)golden.width * 4, golden.width,
                                golden.height, 0, b->differ_tol, NULL);
        arbiter_result a =
            arbitrate(ref, &golden, fr.peer, golden.width, golden.height, filter, b->differ_tol, info.clear);
        diff_ref_destroy(ref); /* it reads the scene's textures */
        persp_scene_destroy(scene);
        r.checked = a.checked, r.persp_off = a.persp_off, r.peer_off = a.peer_off;
        int ok = within(&r, b);
        add_summary(filter_index(filter), 0, &r, ok);
        failed += !ok;
        int keep = verbose;
        verbose = 1;
        report(label, filter, PERSP_DEPTH_Z, &r, b, ok);
        verbose = keep;
        frames_free(ctx, &fr);
        persp_image_free(ctx, &golden);
    }
    printf("peer: %s\n%zu golden images, %d out of bounds\n", peer_name, sizeof goldens / sizeof goldens[0], failed);
    return failed ? 1 : 0;
}

/* ------------------------------------------------------------------- main */

static int usage(void)
{
    fprintf(stderr, "usage: persp_difftest [--seeds A:B] [--fail-dir DIR] [--verbose]\n"
                    "       persp_difftest --seeds A:B --generate DIR\n"
                    "       persp_difftest --replay DIR...\n"
                    "       persp_difftest --golden DATA_DIR\n");
    return 2;
}

int main(int argc, char **argv)
{
    /* Mesa reads the driver's name once, when the first context is made. */
    setenv("GALLIUM_DRIVER", "llvmpipe", 1);
    unsigned long long first = 1, end = 101;
    const char *fail_dir = NULL, *golden = NULL, *generate = NULL;
    int replay_at = 0;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--seeds") && i + 1 < argc) {
            char extra;
            if (sscanf(argv[++i], "%llu:%llu%c", &first, &end, &extra) != 2 || end <= first) {
                fprintf(stderr, "persp_difftest: --seeds '%s': expected A:B with A < B\n", argv[i]);
                return 2;
            }
        } else if (!strcmp(argv[i], "--fail-dir") && i + 1 < argc) {
            fail_dir = argv[++i];
        } else if (!strcmp(argv[i], "--generate") && i + 1 < argc) {
            generate = argv[++i];
        } else if (!strcmp(argv[i], "--golden") && i + 1 < argc) {
            golden = argv[++i];
        } else if (!strcmp(argv[i], "--verbose")) {
            verbose = 1;
        } else if (!strcmp(argv[i], "--replay") && i + 1 < argc) {
            replay_at = i + 1;
            break;
        } else {
            return usage();
        }
    }
    persp_context *ctx = NULL;
    if (persp_context_create(NULL, &ctx) != PERSP_OK) {
        fprintf(stderr, "persp_difftest: cannot create a context\n");
        return 2;
    }
    int rc;
    if (generate)
        rc = run_generate(ctx, first, end, generate);
    else if (golden)
        rc = run_golden(ctx, golden);
    else if (replay_at)
        rc = run_replay(ctx, argc - replay_at, argv + replay_at);
    else
        rc = run_seeds(ctx, first, end, fail_dir);
    persp_context_destroy(ctx);
    return rc;
}
