/*
 * `persp bench`: fill rate of persp_render on a scene (docs/WORKLOADS.md), per
 * texture-coordinate method, optionally against Mesa llvmpipe / softpipe
 * rendering the same scene through OSMesa (bench/peer_osmesa.c): the same
 * meshes, textures, camera, lights and materials, with the GL state of the
 * shading mode. The two images are compared over the pixels either covers,
 * so that the ratio is known to be between equal work.
 *
 * Fill rate = width·height·frames / seconds. One untimed warm-up frame, one
 * timed calibration frame that sets the frame count when --frames is not
 * given, then --reps runs of that many frames; the median and the spread
 * (min / max) of the runs are reported.
 *
 * Mesa reads GALLIUM_DRIVER and LP_NUM_THREADS once per process, so the peer
 * runs in a child: this same executable started with the hidden option
 * --peer-child, its environment set for the driver and thread count asked
 * for. The child loads the scene itself, reports its timings and its image
 * through a pipe; its memory stays out of persp's peak resident size.
 */
#include "options.h"

#ifdef PERSP_HAVE_OSMESA
#include "../../bench/peer.h"
#endif

#include <jansson.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#define BENCH_MAX_REPS 100
#define BENCH_MAX_FRAMES 1000000L
#define BENCH_MAX_METHODS 64

typedef struct run_stats {
    int frames, reps;
    double mpix[BENCH_MAX_REPS];
    int sort_first[BENCH_MAX_REPS]; /* frames of each run drawn sort first (persp_render_desc.sort_first) */
    double median, min, max;
} run_stats;

typedef struct method_result {
    char spec[64];
    int ok;
    char error[256];
    run_stats stats;
} method_result;

typedef struct peer_result {
    int ok;
    char renderer[128], version[128], pipeline[160];
    double aniso;
    run_stats stats;
    double maxrss_mib;
    int width, height;
    uint8_t *pixels; /* when the image was asked for */
} peer_result;

typedef struct image_diff {
    int max_abs[4];
    double pct_gt1, pct_gt2, pct_gt8; /* of the covered pixels */
    double psnr;                      /* over the covered pixels; INFINITY when identical */
    double covered_pct;               /* pixels either renderer drew, of all */
} image_diff;

typedef struct bench_opts {
    persp_scene_load_desc load;
    const char *scene, *method, *filter_name, *peer, *peer_image;
    int filter_given, shading_given;
    persp_shading shading; /* DEFAULT: the scene's */
    const char *shading_name;
    persp_filter filter;
    int max_aniso;
    int threads, peer_threads, width, height, reps, json;
    persp_toggle sort_first;
    persp_simd simd, simd_asked; /* the context's choice, and what --simd asked for */
    persp_simd simd_lighting;    /* the lighting loops' (persp_context_lighting_simd) */
    long frames; /* 0: calibrate */
    double run_seconds;
} bench_opts;

static void bench_usage(FILE *out, const cli_command *cmd)
{
    fprintf(out, "usage: persp bench [SCENE] [options]\n\n"
                 "Measures fill rate (Mpixels/s = width*height*frames/seconds) of persp_render.\n"
                 "SCENE is a built-in scene or a JSON scene file (default: corridor),\n"
                 "or a model file (OBJ, glTF/GLB, PLY, STL, FBX, COLLADA, 3DS, ...) shown with a\n"
                 "default camera and lights (docs/SCENES.md).\n\n"
                 "options:\n");
    cli_print_options(out, cmd);
#ifndef PERSP_HAVE_OSMESA
    fprintf(out, "\nthis persp was not built with OSMesa: --peer is unavailable\n");
#endif
}

static double peak_rss_mib(int who)
{
    struct rusage ru;
    if (getrusage(who, &ru) != 0) return 0.0;
    return (double)ru.ru_maxrss / 1024.0; /* Linux reports KiB */
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static void finish_stats(run_stats *s)
{
    double sorted[BENCH_MAX_REPS];
    memcpy(sorted, s->mpix, (size_t)s->reps * sizeof(double));
    qsort(sorted, (size_t)s->reps, sizeof(double), cmp_double);
    s->min = sorted[0];
    s->max = sorted[s->reps - 1];
    s->median = s->reps % 2 ? sorted[s->reps / 2]
                            : 0.5 * (sorted[s->reps / 2 - 1] + sorted[s->reps / 2]);
}

/* Frames per run so that one run lasts about `target` seconds, from the time
 * of one frame. */
static int calibrate_frames(double frame_seconds, double target)
{
    if (!(frame_seconds > 0.0)) return (int)BENCH_MAX_FRAMES;
    double n = ceil(target / frame_seconds);
    if (n < 1.0) n = 1.0;
    if (n > (double)BENCH_MAX_FRAMES) n = (double)BENCH_MAX_FRAMES;
    return (int)n;
}

static double mpix(int w, int h, int frames, double seconds)
{
    if (!(seconds > 0.0)) seconds = 1e-9;
    return (double)w * (double)h * (double)frames / seconds / 1e6;
}

/* ---------------------------------------------------------------- persp side */

typedef struct persp_bench {
    persp_context *ctx;
    persp_scene *scene;
    persp_framebuffer fb;
} persp_bench;

/* sorted_first (when not NULL): how many of the frames were drawn sort first. */
static persp_status render_frames(persp_bench *b, const persp_render_desc *desc, int frames, int *sorted_first)
{
    for (int f = 0; f < frames; f++) {
        persp_render_stats st;
        persp_status s = persp_render(b->ctx, b->scene, desc, &b->fb, &st);
        if (s != PERSP_OK) return s;
        if (sorted_first) *sorted_first += st.sort_first_regions > 0;
    }
    return PERSP_OK;
}

static void render_error(persp_bench *b, persp_status st, method_result *r)
{
    const char *detail = persp_context_error(b->ctx);
    snprintf(r->error, sizeof r->error, "%s%s(%s)", detail ? detail : "",
             detail && detail[0] ? " " : "", persp_status_string(st));
    r->ok = 0;
}

static void method_desc(const bench_opts *o, const method_result *r, persp_render_desc *desc)
{
    memset(desc, 0, sizeof *desc);
    desc->method = r->spec;
    desc->filter = o->filter;
    desc->max_aniso = o->max_aniso;
    desc->shading = o->shading;
    desc->sort_first = o->sort_first;
}

/* One untimed warm-up frame and one timed frame that sets the frame count
 * of each run when --frames is not given. */
static void prepare_method(persp_bench *b, const bench_opts *o, method_result *r)
{
    persp_render_desc desc;
    method_desc(o, r, &desc);
    r->ok = 0;
    persp_status st = render_frames(b, &desc, 1, NULL);
    double t0 = cli_now();
    if (st == PERSP_OK) st = render_frames(b, &desc, 1, NULL);
    double t1 = cli_now();
    if (st != PERSP_OK) {
        render_error(b, st, r);
        return;
    }
    r->stats.frames = o->frames ? (int)o->frames : calibrate_frames(t1 - t0, o->run_seconds);
    r->stats.reps = 0;
    r->ok = 1;
}

static void run_method(persp_bench *b, const bench_opts *o, method_result *r)
{
    persp_render_desc desc;
    method_desc(o, r, &desc);
    int sorted_first = 0;
    double a = cli_now();
    persp_status st = render_frames(b, &desc, r->stats.frames, &sorted_first);
    double z = cli_now();
    r->stats.sort_first[r->stats.reps] = sorted_first;
    if (st != PERSP_OK) {
        render_error(b, st, r);
        return;
    }
    r->stats.mpix[r->stats.reps++] = mpix(b->fb.width, b->fb.height, r->stats.frames, z - a);
}

/* ----------------------------------------------------------------- peer side */

#ifdef PERSP_HAVE_OSMESA
extern char **environ;

/* The child: loads the scene, builds the GL objects, draws a warm-up and a
 * calibration frame and prints "key value" lines ending with "frames N".
 * Then it obeys its standard input, one command a line, so that the parent
 * can interleave its runs with persp's on a shared machine: "run" draws one
 * run and prints "seconds S"; "end" prints "maxrss_mib M", then
 * "pixels W H" and the raw last frame, and exits. */
static int peer_child(const bench_opts *o)
{
    char err[512] = "";
    persp_context *ctx = NULL;
    persp_scene *scene = NULL;
    persp_status st = persp_context_create(NULL, &ctx);
    if (st == PERSP_OK)
        st = cli_is_builtin(o->scene) ? persp_scene_builtin(ctx, o->scene, &scene)
                                  : persp_scene_load_ex(ctx, o->scene, &o->load, &scene);
    if (st != PERSP_OK) {
        int rc = cli_status(ctx, st, o->scene);
        persp_context_destroy(ctx);
        return rc;
    }
    bench_peer_desc pd = {o->width, o->height, scene, o->shading, o->filter, o->max_aniso};
    bench_peer *p = bench_peer_create(&pd, err, sizeof err);
    /* The GL objects hold copies: the scene is not needed while drawing. */
    persp_scene_destroy(scene);
    persp_context_destroy(ctx);
    if (!p) return cli_error(CLI_FAIL, "%s", err);
    bench_peer_render(p, 1); /* warm-up */
    double t0 = cli_now();
    bench_peer_render(p, 1);
    double t1 = cli_now();
    int frames = o->frames ? (int)o->frames : calibrate_frames(t1 - t0, o->run_seconds);
    printf("renderer %s\nversion %s\npipeline %s\naniso %g\nframes %d\n", bench_peer_renderer(p),
           bench_peer_version(p), bench_peer_pipeline(p), (double)bench_peer_aniso(p), frames);
    fflush(stdout);
    char line[64];
    while (fgets(line, sizeof line, stdin)) {
        if (!strncmp(line, "run", 3)) {
            double a = cli_now();
            bench_peer_render(p, frames);
            printf("seconds %.9f\n", cli_now() - a);
            fflush(stdout);
        } else if (!strncmp(line, "end", 3)) {
            printf("maxrss_mib %.3f\npixels %d %d\n", peak_rss_mib(RUSAGE_SELF), o->width, o->height);
            fwrite(bench_peer_pixels(p), 4, (size_t)o->width * (size_t)o->height, stdout);
            fflush(stdout);
            break;
        }
    }
    bench_peer_destroy(p);
    return CLI_OK;
}

/* The running child, seen from the parent. */
typedef struct peer_proc {
    pid_t pid;
    FILE *to, *from;
} peer_proc;

/* Reads one "key value" line from the child into value; 0 on EOF or
 * another key. */
static int peer_read(peer_proc *pp, const char *key, char *value, size_t size)
{
    char line[512];
    if (!fgets(line, sizeof line, pp->from)) return 0;
    size_t k = strlen(key);
    if (strncmp(line, key, k) != 0 || line[k] != ' ') return 0;
    size_t n = strcspn(line + k + 1, "\n");
    if (n >= size) n = size - 1;
    memcpy(value, line + k + 1, n);
    value[n] = '\0';
    return 1;
}

/* Ends the child and reports how it ended when it failed. */
static int peer_reap(peer_proc *pp, const bench_opts *o, int rc)
{
    if (pp->to) fclose(pp->to);
    if (pp->from) fclose(pp->from);
    pp->to = pp->from = NULL;
    if (pp->pid <= 0) return rc;
    int status = 0;
    waitpid(pp->pid, &status, 0);
    pp->pid = 0;
    if (rc == CLI_OK && (!WIFEXITED(status) || WEXITSTATUS(status) != 0))
        rc = cli_error(CLI_FAIL, "bench: the %s peer failed (%s %d)", o->peer,
                       WIFEXITED(status) ? "exit status" : "signal",
                       WIFEXITED(status) ? WEXITSTATUS(status) : WTERMSIG(status));
    return rc;
}

static int peer_start(const bench_opts *o, peer_proc *pp, peer_result *r)
{
    memset(pp, 0, sizeof *pp);
    char size[40], threads[32], frames[32], seconds[32], driver[64];
    snprintf(size, sizeof size, "%dx%d", o->width, o->height);
    snprintf(frames, sizeof frames, "%ld", o->frames);
    snprintf(seconds, sizeof seconds, "%.6f", o->run_seconds);
    snprintf(driver, sizeof driver, "GALLIUM_DRIVER=%s", o->peer);
    snprintf(threads, sizeof threads, "LP_NUM_THREADS=%d", o->peer_threads);
    char *argv[32] = {"persp", "bench", (char *)o->scene, "--peer-child", (char *)o->peer, "--size", size,
                      "--time", seconds};
    int argc = 9;
    if (o->filter_given) argv[argc++] = "--filter", argv[argc++] = (char *)o->filter_name;
    if (o->shading_given) argv[argc++] = "--shading", argv[argc++] = (char *)o->shading_name;
    if (o->frames) argv[argc++] = "--frames", argv[argc++] = frames;
    if (o->load.any_folder == PERSP_TOGGLE_ON) argv[argc++] = "--any-folder";
    static const char *const up_args[] = {NULL, "y", "z", "x", "-x", "-y", "-z"};
    if ((unsigned)o->load.model_up < sizeof up_args / sizeof up_args[0] && up_args[o->load.model_up])
        argv[argc++] = "--up", argv[argc++] = (char *)up_args[o->load.model_up];
    if (o->load.formats == PERSP_MODEL_FORMATS_ALL) argv[argc++] = "--formats", argv[argc++] = "all";
    if (o->load.import == PERSP_MODEL_IMPORT_IN_PROCESS) argv[argc++] = "--import", argv[argc++] = "in-process";
    char timeout[32], crease[32];
    if (o->load.crease_deg > 0.0f) {
        snprintf(crease, sizeof crease, "%.9g", (double)o->load.crease_deg);
        argv[argc++] = "--crease", argv[argc++] = crease;
    }
    if (o->load.import_time_limit_ms) {
        snprintf(timeout, sizeof timeout, "%.3f", o->load.import_time_limit_ms / 1000.0);
        argv[argc++] = "--import-timeout", argv[argc++] = timeout;
    }
    argv[argc] = NULL;

    size_t nenv = 0;
    while (environ && environ[nenv]) nenv++;
    char **envp = calloc(nenv + 3, sizeof *envp);
    if (!envp) return cli_error(CLI_FAIL, "bench: out of memory");
    size_t e = 0;
    for (size_t i = 0; i < nenv; i++)
        if (strncmp(environ[i], "GALLIUM_DRIVER=", 15) && strncmp(environ[i], "LP_NUM_THREADS=", 15))
            envp[e++] = environ[i];
    envp[e++] = driver;
    envp[e++] = threads;
    envp[e] = NULL;

    int down[2], up[2];
    if (pipe(down) != 0) {
        free(envp);
        return cli_error(CLI_FAIL, "bench: cannot create a pipe for the peer");
    }
    if (pipe(up) != 0) {
        close(down[0]), close(down[1]);
        free(envp);
        return cli_error(CLI_FAIL, "bench: cannot create a pipe for the peer");
    }
    fflush(NULL);
    pid_t pid = fork();
    if (pid < 0) {
        close(down[0]), close(down[1]), close(up[0]), close(up[1]);
        free(envp);
        return cli_error(CLI_FAIL, "bench: cannot start the peer process");
    }
    if (pid == 0) {
        dup2(down[0], STDIN_FILENO);
        dup2(up[1], STDOUT_FILENO);
        close(down[0]), close(down[1]), close(up[0]), close(up[1]);
        execve("/proc/self/exe", argv, envp);
        _exit(127);
    }
    free(envp);
    close(down[0]);
    close(up[1]);
    pp->pid = pid;
    pp->to = fdopen(down[1], "w");
    pp->from = fdopen(up[0], "r");
    if (!pp->to || !pp->from) {
        if (!pp->to) close(down[1]);
        if (!pp->from) close(up[0]);
        return peer_reap(pp, o, cli_error(CLI_FAIL, "bench: cannot talk to the peer process"));
    }
    char v[256];
    if (!peer_read(pp, "renderer", r->renderer, sizeof r->renderer) ||
        !peer_read(pp, "version", r->version, sizeof r->version) ||
        !peer_read(pp, "pipeline", r->pipeline, sizeof r->pipeline) || !peer_read(pp, "aniso", v, sizeof v) ||
        (r->aniso = atof(v), !peer_read(pp, "frames", v, sizeof v)) || (r->stats.frames = atoi(v)) < 1) {
        int rc = peer_reap(pp, o, CLI_OK);
        return rc != CLI_OK ? rc : cli_error(CLI_FAIL, "bench: unreadable output from the %s peer", o->peer);
    }
    r->stats.reps = 0;
    return CLI_OK;
}

static int peer_run(peer_proc *pp, const bench_opts *o, peer_result *r)
{
    char v[64];
    fputs("run\n", pp->to);
    fflush(pp->to);
    if (!peer_read(pp, "seconds", v, sizeof v)) {
        int rc = peer_reap(pp, o, CLI_OK);
        return rc != CLI_OK ? rc : cli_error(CLI_FAIL, "bench: unreadable output from the %s peer", o->peer);
    }
    r->stats.mpix[r->stats.reps++] = mpix(o->width, o->height, r->stats.frames, atof(v));
    return CLI_OK;
}

static int peer_end(peer_proc *pp, const bench_opts *o, peer_result *r)
{
    char v[64];
    fputs("end\n", pp->to);
    fflush(pp->to);
    int rc = CLI_OK;
    int w = 0, h = 0;
    if (!peer_read(pp, "maxrss_mib", v, sizeof v)) {
        rc = cli_error(CLI_FAIL, "bench: unreadable output from the %s peer", o->peer);
    } else {
        r->maxrss_mib = atof(v);
        if (!peer_read(pp, "pixels", v, sizeof v) || sscanf(v, "%d %d", &w, &h) != 2 || w != o->width ||
            h != o->height) {
            rc = cli_error(CLI_FAIL, "bench: the %s peer sent no image", o->peer);
        } else {
            size_t need = (size_t)w * (size_t)h * 4;
            if (!(r->pixels = malloc(need))) {
                rc = cli_error(CLI_FAIL, "bench: out of memory for the peer image");
            } else if (fread(r->pixels, 1, need, pp->from) != need) {
                rc = cli_error(CLI_FAIL, "bench: the %s peer sent no complete image", o->peer);
                free(r->pixels);
                r->pixels = NULL;
            } else {
                r->width = w;
                r->height = h;
            }
        }
    }
    rc = peer_reap(pp, o, rc);
    if (rc == CLI_OK) {
        finish_stats(&r->stats);
        r->ok = 1;
    }
    return rc;
}

/* Per-channel and per-pixel differences of two RGBA8 images of equal size,
 * over the pixels either renderer covered: those persp's depth buffer shows
 * drawn (depth below the cleared 1) and those where the peer's differs from
 * the clear colour. Background both leave alone would only dilute the
 * error. */
static image_diff compare_images(const uint8_t *a, const uint8_t *b, const float *depth,
                                 const uint8_t clear[4], size_t pixels)
{
    image_diff d;
    memset(&d, 0, sizeof d);
    size_t gt1 = 0, gt2 = 0, gt8 = 0, covered = 0;
    double sq = 0.0;
    for (size_t i = 0; i < pixels; i++) {
        if (!(depth[i] < 1.0f) && !memcmp(b + 4 * i, clear, 3)) continue;
        covered++;
        int worst = 0;
        for (int c = 0; c < 4; c++) {
            int x = abs((int)a[4 * i + (size_t)c] - (int)b[4 * i + (size_t)c]);
            if (x > d.max_abs[c]) d.max_abs[c] = x;
            if (x > worst) worst = x;
            if (c < 3) sq += (double)x * (double)x;
        }
        gt1 += worst > 1, gt2 += worst > 2, gt8 += worst > 8;
    }
    d.covered_pct = pixels ? 100.0 * (double)covered / (double)pixels : 0.0;
    double n = covered ? (double)covered : 1.0;
    d.pct_gt1 = 100.0 * (double)gt1 / n;
    d.pct_gt2 = 100.0 * (double)gt2 / n;
    d.pct_gt8 = 100.0 * (double)gt8 / n;
    double mse = sq / (3.0 * n);
    /* PSNR over R, G, B with peak 255. */
    d.psnr = mse > 0.0 ? 10.0 * log10(255.0 * 255.0 / mse) : INFINITY;
    return d;
}
#endif


/* ------------------------------------------------------------------ output */

/* A number, or null where it is not finite (a rate over no time). */
static json_t *json_num(double x) { return isfinite(x) ? json_real(x) : json_null(); }

static void json_stats(json_t *o, const run_stats *s)
{
    json_object_set_new(o, "frames", json_integer(s->frames));
    json_object_set_new(o, "reps", json_integer(s->reps));
    json_object_set_new(o, "mpix_median", json_num(s->median));
    json_object_set_new(o, "mpix_min", json_num(s->min));
    json_object_set_new(o, "mpix_max", json_num(s->max));
    json_t *runs = json_array();
    for (int i = 0; i < s->reps; i++) json_array_append_new(runs, json_num(s->mpix[i]));
    json_object_set_new(o, "mpix_runs", runs);
}

typedef struct bench_report {
    const bench_opts *o;
    const method_result *results;
    size_t count;
    const method_result *exact;
    const peer_result *peer;
    const image_diff *diff;
    double rss_mib, rss_start_mib;
    const cli_xcore *xcore; /* [2], or NULL */
    const cli_xcore *run_xcore; /* before each run of the first method (results[0]) */
} bench_report;

static json_t *json_results(const bench_report *r)
{
    json_t *results = json_array();
    for (size_t i = 0; i < r->count; i++) {
        const method_result *m = &r->results[i];
        json_t *o = json_object();
        json_object_set_new(o, "method", json_string(m->spec));
        if (!m->ok) {
            json_object_set_new(o, "error", json_string(m->error));
        } else {
            json_stats(o, &m->stats);
            if (r->o->threads > 1) {
                json_t *sf = json_array();
                for (int k = 0; k < m->stats.reps; k++) json_array_append_new(sf, json_integer(m->stats.sort_first[k]));
                json_object_set_new(o, "sort_first_frames", sf);
            }
            if (r->exact) json_object_set_new(o, "vs_exact", json_num(m->stats.median / r->exact->stats.median));
            if (r->peer && r->peer->ok)
                json_object_set_new(o, "vs_peer", json_num(m->stats.median / r->peer->stats.median));
        }
        json_array_append_new(results, o);
    }
    return results;
}

static json_t *json_peer(const bench_opts *o, const peer_result *p)
{
    json_t *j = json_object();
    json_object_set_new(j, "driver", json_string(o->peer));
    json_object_set_new(j, "renderer", json_string(p->renderer));
    json_object_set_new(j, "version", json_string(p->version));
    json_object_set_new(j, "pipeline", json_string(p->pipeline));
    json_object_set_new(j, "lp_num_threads", json_integer(o->peer_threads));
    json_object_set_new(j, "aniso", json_num(p->aniso));
    json_object_set_new(j, "peak_rss_mib", json_num(p->maxrss_mib));
    json_stats(j, &p->stats);
    return j;
}

static json_t *json_diff(const bench_opts *o, const image_diff *d)
{
    json_t *j = json_object();
    json_object_set_new(j, "file", o->peer_image ? json_string(o->peer_image) : json_null());
    json_object_set_new(j, "compared_with", json_string("exact"));
    json_object_set_new(j, "covered_pct", json_num(d->covered_pct));
    json_object_set_new(j, "max_abs",
                        json_pack("[iiii]", d->max_abs[0], d->max_abs[1], d->max_abs[2], d->max_abs[3]));
    json_object_set_new(j, "pct_gt1", json_num(d->pct_gt1));
    json_object_set_new(j, "pct_gt2", json_num(d->pct_gt2));
    json_object_set_new(j, "pct_gt8", json_num(d->pct_gt8));
    json_object_set_new(j, "psnr_db", json_num(d->psnr));
    return j;
}

/* The results as one JSON object (jansson: strings escaped, numbers to six
 * significant digits, non-finite ones null). CLI_FAIL when out of memory. */
static int print_json(FILE *out, const bench_report *r)
{
    const bench_opts *o = r->o;
    json_t *j = json_object();
    json_object_set_new(j, "scene", json_string(o->scene));
    json_object_set_new(j, "width", json_integer(o->width));
    json_object_set_new(j, "height", json_integer(o->height));
    json_object_set_new(j, "filter", json_string(o->filter_name));
    json_object_set_new(j, "shading", json_string(o->shading_name));
    json_object_set_new(j, "threads", json_integer(o->threads));
    json_object_set_new(j, "simd", json_string(persp_simd_name(o->simd)));
    json_object_set_new(j, "simd_asked", json_string(persp_simd_name(o->simd_asked)));
    json_object_set_new(j, "simd_lighting", json_string(persp_simd_name(o->simd_lighting)));
    json_object_set_new(j, "peak_rss_mib", json_num(r->rss_mib));
    json_object_set_new(j, "rss_at_start_mib", json_num(r->rss_start_mib));
    if (r->xcore && r->xcore[0].pairs) {
        json_t *x = json_object();
        json_object_set_new(x, "pairs", json_integer(r->xcore[0].pairs));
        static const char *const when[2] = {"before", "after"};
        for (int k = 0; k < 2; k++)
            json_object_set_new(x, when[k],
                                json_pack("[oo]", json_num(r->xcore[k].min_ns), json_num(r->xcore[k].max_ns)));
        json_t *runs = json_array();
        for (int k = 0; r->count && k < r->results[0].stats.reps; k++)
            json_array_append_new(runs, json_pack("[oo]", json_num(r->run_xcore[k].min_ns),
                                                  json_num(r->run_xcore[k].max_ns)));
        json_object_set_new(x, "runs", runs);
        json_object_set_new(j, "xcore_round_trip_ns", x);
    }
    json_object_set_new(j, "results", json_results(r));
    if (r->peer && r->peer->ok) json_object_set_new(j, "peer", json_peer(o, r->peer));
    if (r->diff) json_object_set_new(j, "peer_image", json_diff(o, r->diff));
    int rc = json_dumpf(j, out, JSON_INDENT(1) | JSON_REAL_PRECISION(6)) == 0 && fputc('\n', out) != EOF
                 ? CLI_OK
                 : cli_error(CLI_FAIL, "bench: cannot write the JSON results");
    json_decref(j);
    return rc;
}

/* The text table is printed as it is measured: the head once the scene is
 * loaded, each method's row when its runs are done, the peer and the image
 * comparison at the end. */
static void print_text_head(FILE *out, const bench_opts *o)
{
    fprintf(out, "bench %s %dx%d filter %s threads %d simd %s reps %d\n", o->scene, o->width,
            o->height, o->filter_name, o->threads, persp_simd_name(o->simd), o->reps);
    fprintf(out, "shading %s\n", o->shading_name);
    fprintf(out, "%-20s %8s %10s %10s %10s %9s", "method", "frames", "median", "min", "max",
            "vs_exact");
    if (o->peer) fprintf(out, " %9s", "vs_peer");
    fprintf(out, "   (Mpixels/s)\n");
    fflush(out);
}

static void print_text_row(FILE *out, const bench_opts *o, const method_result *m,
                           const method_result *exact, const peer_result *peer)
{
    if (!m->ok) {
        fprintf(out, "%-20s error: %s\n", m->spec, m->error);
    } else {
        fprintf(out, "%-20s %8d %10.2f %10.2f %10.2f", m->spec, m->stats.frames, m->stats.median,
                m->stats.min, m->stats.max);
        if (exact)
            fprintf(out, " %9.3f", m->stats.median / exact->stats.median);
        else
            fprintf(out, " %9s", "-");
        if (o->peer) {
            if (peer)
                fprintf(out, " %9.3f", m->stats.median / peer->stats.median);
            else
                fprintf(out, " %9s", "-");
        }
        fprintf(out, "\n");
    }
    fflush(out);
}

static void print_text_tail(FILE *out, const bench_report *r)
{
    const bench_opts *o = r->o;
    const char *peer_col = r->peer && r->peer->ok ? o->peer : NULL;
    if (peer_col) {
        const peer_result *p = r->peer;
        char label[40];
        snprintf(label, sizeof label, "peer:%s", o->peer);
        fprintf(out, "%-20s %8d %10.2f %10.2f %10.2f %9s %9.3f\n", label, p->stats.frames,
                p->stats.median, p->stats.min, p->stats.max, "-", 1.0);
        fprintf(out, "peer renderer: %s, OpenGL %s, LP_NUM_THREADS=%d", p->renderer, p->version,
                o->peer_threads);
        if (p->aniso > 0.0) fprintf(out, ", anisotropy %g", p->aniso);
        fprintf(out, "\npeer pipeline: %s\n", p->pipeline);
    }
    fprintf(out, "vector variants: samplers %s, lighting loops %s\n", persp_simd_name(o->simd),
            persp_simd_name(o->simd_lighting));
    fprintf(out, "peak resident memory: persp %.1f MiB (%.1f MiB above the %.1f MiB at start)",
            r->rss_mib, r->rss_mib - r->rss_start_mib, r->rss_start_mib);
    if (peer_col) fprintf(out, ", peer process %.1f MiB", r->peer->maxrss_mib);
    fprintf(out, "\n");
    if (r->xcore && r->xcore[0].pairs) {
        /* One pair: its figure; more: the least and the most. */
        const cli_xcore *x = r->xcore;
        char when[2][48];
        for (int k = 0; k < 2; k++)
            if (x[k].pairs == 1)
                snprintf(when[k], sizeof when[k], "%.0f ns", x[k].min_ns);
            else
                snprintf(when[k], sizeof when[k], "%.0f-%.0f ns", x[k].min_ns, x[k].max_ns);
        fprintf(out,
                "cross-core round trip of a cache line: %s before the runs, %s after "
                "(first processor with %d other%s)\n",
                when[0], when[1], x[0].pairs, x[0].pairs == 1 ? "" : "s");
        if (r->count && r->results[0].stats.reps > 1) {
            fprintf(out, "  before each run of %s (the most over the pairs):", r->results[0].spec);
            for (int k = 0; k < r->results[0].stats.reps; k++)
                fprintf(out, "%s %.0f", k ? "," : "", r->run_xcore[k].max_ns);
            fprintf(out, " ns\n");
        }
    }
    if (o->threads > 1 && r->count && r->results[0].ok) {
        const run_stats *rs = &r->results[0].stats;
        fprintf(out, "frames drawn sort first (--sort-first %s), each run of %s, of %d:",
                o->sort_first == PERSP_TOGGLE_ON ? "on" : o->sort_first == PERSP_TOGGLE_OFF ? "off" : "auto",
                r->results[0].spec, rs->frames);
        for (int k = 0; k < rs->reps; k++) fprintf(out, "%s %d", k ? "," : "", rs->sort_first[k]);
        fprintf(out, "\n");
    }
    if (r->diff) {
        const image_diff *d = r->diff;
        fprintf(out,
                "peer image%s%s vs persp exact over the %.1f%% covered pixels: max |diff| R %d G %d "
                "B %d A %d; pixels differing by >1: %.3f%%, >2: %.3f%%, >8: %.3f%%; PSNR ",
                o->peer_image ? " " : "", o->peer_image ? o->peer_image : "", d->covered_pct,
                d->max_abs[0], d->max_abs[1], d->max_abs[2], d->max_abs[3], d->pct_gt1, d->pct_gt2,
                d->pct_gt8);
        if (isfinite(d->psnr))
            fprintf(out, "%.2f dB\n", d->psnr);
        else
            fprintf(out, "inf (identical)\n");
    }
}

/* ------------------------------------------------------------------ driver */

/* --method: one method, checked, or "all". */
static int parse_bench_method(const cli_command *cmd, const cli_option *opt, char *value)
{
    if (strcmp(value, "all") != 0) {
        int bad = cli_check_method(cmd->name, value);
        if (bad) return bad;
    }
    const char *v = value;
    memcpy(opt->dest, &v, sizeof v);
    return CLI_OK;
}

static const char *const peer_names[] = {"llvmpipe", "softpipe", NULL};
static const cli_spec opt_bench_method = {
    .name = "method",
    .kind = CLI_KIND_CUSTOM,
    .metavar = "M|all",
    .parse = parse_bench_method,
    .accepts = "a method of `persp methods`, or all",
    .help = "texture-coordinate method, or every registered one with its\n"
            "ratio to exact (default exact)"};
static const cli_spec opt_frames = {.name = "frames",
                                    .kind = CLI_KIND_INT,
                                    .metavar = "N",
                                    .lo = 1,
                                    .hi = (double)BENCH_MAX_FRAMES,
                                    .help =
                                        "frames per run (default: as many as fill --time seconds)"};
static const cli_spec opt_reps = {.name = "reps",
                                  .kind = CLI_KIND_INT,
                                  .metavar = "N",
                                  .lo = 1,
                                  .hi = BENCH_MAX_REPS,
                                  .help =
                                      "timed runs; median and min/max are reported (default 5)"};
static const cli_spec opt_time = {
    .name = "time",
    .kind = CLI_KIND_REAL,
    .metavar = "S",
    .lo = 0.001,
    .hi = 60.0,
    .accepts = "0.001..60 seconds",
    .help = "target seconds per run when --frames is not given (default 0.5)"};
static const cli_spec opt_peer = {
    .name = "peer",
    .kind = CLI_KIND_STRING,
    .metavar = "D",
    .names = peer_names,
    .help = "also measure Mesa D = llvmpipe | softpipe through OSMesa drawing\n"
            "the same scene, in a child process; report persp's ratio to it\n"
            "and the PSNR of its image against persp's exact one"};
static const cli_spec opt_peer_threads = {.name = "peer-threads",
                                          .kind = CLI_KIND_INT,
                                          .metavar = "N",
                                          .lo = 0,
                                          .hi = 256,
                                          .help =
                                              "LP_NUM_THREADS for the peer (default: --threads)"};
static const cli_spec opt_peer_image = {
    .name = "peer-image",
    .kind = CLI_KIND_STRING,
    .metavar = "FILE",
    .help = "also write the peer's frame as PNG"};
/* The peer's own process (peer_start): the driver it renders with. Not for
 * people. */
static const cli_spec opt_peer_child = {
    .name = "peer-child", .kind = CLI_KIND_STRING, .metavar = "D"};

/* The methods to measure: one spec, or every registry entry for "all". */
static int collect_methods(const char *method, method_result *out, size_t *count)
{
    *count = 0;
    if (strcmp(method, "all") != 0) {
        persp_status st = persp_method_check(method);
        if (st == PERSP_ERR_NOT_FOUND)
            return cli_error(CLI_USAGE, "bench: unknown method '%s' (see persp methods)", method);
        if (st != PERSP_OK) return cli_error(CLI_USAGE, "bench: bad parameters in method '%s'", method);
        if (strlen(method) >= sizeof out[0].spec)
            return cli_error(CLI_USAGE, "bench: method spec too long");
        snprintf(out[0].spec, sizeof out[0].spec, "%s", method);
        *count = 1;
        return CLI_OK;
    }
    persp_method_info info;
    for (size_t i = 0; *count < BENCH_MAX_METHODS && persp_method_get(i, &info) == PERSP_OK; i++) {
        if (persp_method_check(info.name) != PERSP_OK) {
            cli_error(CLI_OK, "bench: leaving out method %s (its parameters %s have no default)",
                      info.name, info.params);
            continue;
        }
        snprintf(out[*count].spec, sizeof out[0].spec, "%s", info.name);
        (*count)++;
    }
    /* exact first: every later row gives its ratio to it as it is printed. */
    for (size_t i = 1; i < *count; i++)
        if (!strcmp(out[i].spec, "exact")) {
            method_result e = out[i];
            memmove(out + 1, out, i * sizeof *out);
            out[0] = e;
            break;
        }
    return CLI_OK;
}

/* Everything one `persp bench` holds, released by bench_close. */
typedef struct bench_session {
    bench_opts o;
    persp_bench b;
    method_result *results;
    size_t count;
    const method_result *exact;
    peer_result peer;
    uint8_t *exact_image;
    image_diff diff;
    int have_diff, failures, streaming;
    int peer_timed; /* the peer's runs are done: rows can give their ratio to it */
    cli_output *out;
    size_t max_memory;
    double rss_start_mib, rss_mib;
    cli_xcore xcore[2]; /* before and after the runs; measured with two threads or more */
    /* Before each run of the first method, the first before the runs: the
     * host may move the vCPUs apart for seconds, and a run between two far
     * figures ran with them apart (docs/PERFORMANCE.md, "Measuring"). */
    cli_xcore run_xcore[BENCH_MAX_REPS];
} bench_session;

/* Options into s->o; CLI_HELP after --help. *child: the hidden --peer-child. */
static int bench_parse(int argc, char **argv, bench_session *s, size_t *max_memory, const char **output,
                       int *child)
{
    bench_opts *o = &s->o;
    o->method = "exact";
    o->threads = 1;
    o->peer_threads = -1;
    o->reps = 5;
    o->run_seconds = 0.5;
    cli_filter filter = {"bilinear", PERSP_FILTER_BILINEAR, 16};
    cli_shading shading = {NULL, PERSP_SHADING_DEFAULT};
    cli_size size = {0, 0};
    persp_report_format format = PERSP_REPORT_TABLE;
    cli_option opts[] = {
        CLI_OPT(opt_bench_method, &o->method),
        CLI_OPT(cli_opt_any_folder, &o->load.any_folder),
        CLI_OPT(cli_opt_up, &o->load.model_up),
        CLI_OPT(cli_opt_formats, &o->load.formats),
        CLI_OPT(cli_opt_import, &o->load.import),
        CLI_OPT(cli_opt_import_timeout, &o->load.import_time_limit_ms),
        CLI_OPT(cli_opt_crease, &o->load.crease_deg),
        CLI_OPT_HELP(cli_opt_filter, &filter,
                     "texture filter for every texture (default: the scene's)"),
        CLI_OPT_HELP(cli_opt_shading, &shading, "shading mode (default: the scene's)"),
        CLI_OPT_HELP(cli_opt_threads, &o->threads, "persp worker threads, 1..256 (default 1)"),
        CLI_OPT(cli_opt_max_memory, max_memory),
        CLI_OPT(cli_opt_simd, &o->simd),
        CLI_OPT(cli_opt_sort_first, &o->sort_first),
        CLI_OPT(opt_frames, &o->frames),
        CLI_OPT(opt_reps, &o->reps),
        CLI_OPT(opt_time, &o->run_seconds),
        CLI_OPT_HELP(cli_opt_size, &size, "image size (default: the scene's, else 1024x768)"),
        CLI_OPT(opt_peer, &o->peer),
        CLI_OPT(opt_peer_threads, &o->peer_threads),
        CLI_OPT(opt_peer_image, &o->peer_image),
        CLI_OPT_HELP(cli_opt_json, &format, "print the results as one JSON object"),
        CLI_OPT_HELP(cli_opt_output, output,
                     "write the results to FILE (default, and -: standard output)"),
        CLI_OPT_NO_DEST(cli_opt_help),
        CLI_OPT(opt_peer_child, &o->peer),
    };
    cli_command cmd = {
        "bench", "persp bench --help", NULL, opts, sizeof opts / sizeof opts[0], &o->scene, 1, 0,
        "scene"};
    int rc = cli_parse_or_usage(&cmd, argc, argv, bench_usage);
    if (rc != CLI_OK) return rc;
    *child = cli_given(&cmd, &opt_peer_child) > 0;
    o->filter_given = cli_given(&cmd, &cli_opt_filter) > 0;
    o->filter_name = filter.name;
    o->filter = o->filter_given ? filter.filter : PERSP_FILTER_DEFAULT;
    o->max_aniso = o->filter_given ? filter.max_aniso : 0;
    o->shading_given = cli_given(&cmd, &cli_opt_shading) > 0;
    o->shading = shading.shading;
    o->shading_name = shading.name;
    o->width = size.width;
    o->height = size.height;
    o->json = format == PERSP_REPORT_JSON;
    if (!o->scene) o->scene = "corridor";
    if (o->peer_threads < 0) o->peer_threads = o->threads;
    if (o->peer_image && !o->peer)
        return cli_error(CLI_USAGE, "bench: --peer-image needs --peer llvmpipe|softpipe");
#ifndef PERSP_HAVE_OSMESA
    if (o->peer || *child)
        return cli_error(CLI_FAIL, "bench: --peer is unavailable: persp was not built with OSMesa "
                                   "(install libosmesa6-dev and rebuild)");
#else
    if (o->peer && !bench_peer_supports(o->filter))
        return cli_error(CLI_USAGE, "bench: filter '%s' has no OpenGL counterpart for the peer",
                         o->filter_name);
#endif
    return CLI_OK;
}

/* The scene, the image size and the framebuffer, in the context cli_run made. */
static int bench_open(bench_session *s, persp_context *ctx)
{
    bench_opts *o = &s->o;
    persp_bench *b = &s->b;
    persp_status st;
    b->ctx = ctx;
    o->simd_asked = o->simd;
    o->simd = persp_context_simd(b->ctx);
    o->simd_lighting = persp_context_lighting_simd(b->ctx);
    if (cli_is_builtin(o->scene)) st = persp_scene_builtin(b->ctx, o->scene, &b->scene);
    else st = persp_scene_load_ex(b->ctx, o->scene, &o->load, &b->scene);
    if (st != PERSP_OK) return cli_status(b->ctx, st, o->scene);
    if (!o->width) persp_scene_default_size(b->scene, &o->width, &o->height);
    /* What the scene renders with unless overridden, for the report. */
    persp_scene_info info;
    persp_scene_get_info(b->scene, &info);
    if (!o->filter_given)
        o->filter_name = info.filter_count == 0   ? "none"
                         : info.filter_count == 1 ? persp_filter_name(info.filter)
                                                  : "scene";
    if (!o->shading_given) o->shading_name = persp_shading_name(info.shading);
    if (!o->width) o->width = 1024, o->height = 768;
    size_t pixels = (size_t)o->width * (size_t)o->height;
    if (pixels > PERSP_IMAGE_MAX_PIXELS)
        return cli_error(CLI_USAGE, "bench: %dx%d exceeds %u pixels", o->width, o->height,
                         PERSP_IMAGE_MAX_PIXELS);
    b->fb.width = o->width;
    b->fb.height = o->height;
    /* Rows start on cache lines (persp.h, persp_framebuffer): with a
     * misaligned buffer, tiles drawn at once by two threads share a line at
     * every row of their common border. */
    b->fb.color = aligned_alloc(64, (pixels * 4 + 63) / 64 * 64);
    b->fb.depth = aligned_alloc(64, (pixels * sizeof(float) + 63) / 64 * 64);
    if (!b->fb.color || !b->fb.depth)
        return cli_error(CLI_FAIL, "bench: out of memory for a %dx%d framebuffer", o->width, o->height);
    return CLI_OK;
}

/* A method's row, once its runs are done: into the table as it grows, or,
 * when the results are JSON or go to a file, as progress on a terminal. */
static void bench_row_done(bench_session *s, method_result *m)
{
    if (m->ok) finish_stats(&m->stats);
    if (m->ok && !strcmp(m->spec, "exact")) s->exact = m;
    const peer_result *peer = s->peer_timed ? &s->peer : NULL;
    if (s->streaming)
        print_text_row(s->out->f, &s->o, m, s->exact, peer);
    else if (isatty(STDERR_FILENO))
        print_text_row(stderr, &s->o, m, s->exact, peer);
}

#ifdef PERSP_HAVE_OSMESA
/* persp's exact image with the filter and shading the peer draws, the
 * peer's last frame, and their differences over the covered pixels. */
static int bench_compare(bench_session *s, peer_proc *pp)
{
    const bench_opts *o = &s->o;
    persp_bench *b = &s->b;
    const size_t pixels = (size_t)o->width * (size_t)o->height;
    persp_render_desc desc;
    memset(&desc, 0, sizeof desc);
    desc.method = "exact";
    desc.filter = o->filter;
    desc.max_aniso = o->max_aniso;
    desc.shading = o->shading;
    persp_status st = persp_render(b->ctx, b->scene, &desc, &b->fb, NULL);
    if (st != PERSP_OK) {
        cli_status(b->ctx, st, "bench: exact reference image");
        s->failures++;
    } else if ((s->exact_image = malloc(pixels * 4)) != NULL) {
        memcpy(s->exact_image, b->fb.color, pixels * 4);
    }
    int rc = peer_end(pp, o, &s->peer);
    if (rc != CLI_OK || !s->peer.pixels) return rc;
    persp_image img = {o->width, o->height, (size_t)o->width * 4, s->peer.pixels};
    if (o->peer_image && (st = persp_image_write_png(b->ctx, o->peer_image, &img)) != PERSP_OK)
        rc = cli_status(b->ctx, st, o->peer_image);
    if (s->exact_image) {
        persp_scene_info info;
        persp_scene_get_info(b->scene, &info);
        s->diff = compare_images(s->exact_image, s->peer.pixels, b->fb.depth, info.clear, pixels);
        s->have_diff = 1;
    }
    return rc;
}
#endif

/* Fill rates. The first method (exact, when measured) runs alternately
 * with the peer, so that the ratio that matters most sees one load on a
 * shared machine; every other method then runs its reps back to back and
 * its row is printed at once, rather than all rows after the last run. A
 * failing peer still leaves persp's results to print. Returns the peer's
 * status. */
static int bench_measure(bench_session *s)
{
    bench_opts *o = &s->o;
    int rc = CLI_OK;
    if (s->streaming) print_text_head(s->out->f, o);
    prepare_method(&s->b, o, &s->results[0]);
#ifdef PERSP_HAVE_OSMESA
    peer_proc pp;
    memset(&pp, 0, sizeof pp);
    int peer_live = 0;
    if (o->peer) peer_live = (rc = peer_start(o, &pp, &s->peer)) == CLI_OK;
#endif
    for (int rep = 0; rep < o->reps; rep++) {
        if (o->threads > 1) s->run_xcore[rep] = rep ? cli_xcore_measure() : s->xcore[0];
        if (s->results[0].ok) run_method(&s->b, o, &s->results[0]);
#ifdef PERSP_HAVE_OSMESA
        if (peer_live) peer_live = (rc = peer_run(&pp, o, &s->peer)) == CLI_OK;
#endif
    }
#ifdef PERSP_HAVE_OSMESA
    /* The peer's last frame is taken after persp's reference image below;
     * its statistics are final now, for every row's ratio. */
    if (peer_live) finish_stats(&s->peer.stats), s->peer_timed = 1;
#endif
    bench_row_done(s, &s->results[0]);
    for (size_t i = 1; i < s->count; i++) {
        method_result *m = &s->results[i];
        prepare_method(&s->b, o, m);
        for (int rep = 0; rep < o->reps && m->ok; rep++) run_method(&s->b, o, m);
        bench_row_done(s, m);
    }
    for (size_t i = 0; i < s->count; i++) s->failures += !s->results[i].ok;
#ifdef PERSP_HAVE_OSMESA
    if (peer_live) rc = bench_compare(s, &pp);
#endif
    s->rss_mib = peak_rss_mib(RUSAGE_SELF);
    return rc;
}

static int bench_report_out(bench_session *s);

/* The measurements and the report, in the skeleton's context and output. */
static int bench_body(persp_context *ctx, cli_output *out, void *user)
{
    bench_session *s = user;
    s->out = out;
    int rc = bench_open(s, ctx);
    if (rc == CLI_OK) rc = bench_report_out(s);
    /* The scene is the context's, which cli_run destroys after this. */
    persp_scene_destroy(s->b.scene);
    s->b.scene = NULL;
    return rc;
}

static int bench_report_out(bench_session *s)
{
    cli_output *out = s->out;
    int rc;
    s->streaming = !s->o.json;
    /* Before and after, as the host may move the vCPUs during the runs. */
    if (s->o.threads > 1) s->xcore[0] = cli_xcore_measure();
    rc = bench_measure(s);
    if (s->o.threads > 1) s->xcore[1] = cli_xcore_measure();
    bench_report report = {&s->o, s->results, s->count, s->exact, s->o.peer && s->peer.ok ? &s->peer : NULL,
                           s->have_diff ? &s->diff : NULL, s->rss_mib, s->rss_start_mib,
                           s->o.threads > 1 ? s->xcore : NULL, s->run_xcore};
    if (s->o.json)
        rc = print_json(out->f, &report) != CLI_OK && rc == CLI_OK ? CLI_FAIL : rc;
    else
        print_text_tail(out->f, &report);
    if (s->failures && rc == CLI_OK) rc = CLI_FAIL;
    for (size_t i = 0; i < s->count; i++)
        if (!s->results[i].ok)
            cli_error(CLI_FAIL, "bench: method %s failed: %s", s->results[i].spec, s->results[i].error);
    return rc;
}

int cmd_bench(int argc, char **argv)
{
    bench_session s;
    memset(&s, 0, sizeof s);
    /* Resident size before any rendering: shared libraries (with OSMesa
     * linked in, mostly libLLVM's relocated pages) that persp does not use. */
    s.rss_start_mib = peak_rss_mib(RUSAGE_SELF);
    const char *output = NULL;
    int child = 0;
    int rc = bench_parse(argc, argv, &s, &s.max_memory, &output, &child);
    if (rc != CLI_OK) return rc == CLI_HELP ? CLI_OK : rc;
#ifdef PERSP_HAVE_OSMESA
    if (child) {
        if (!s.o.width) s.o.width = 1024, s.o.height = 768;
        return peer_child(&s.o);
    }
#endif
    if ((rc = cli_check_output("bench", "--peer-image", s.o.peer_image)) != CLI_OK) return rc;
    if ((rc = cli_check_scene("bench", s.o.scene)) != CLI_OK) return rc;
    if (!(s.results = calloc(BENCH_MAX_METHODS, sizeof *s.results)))
        return cli_error(CLI_FAIL, "bench: out of memory");
    if ((rc = collect_methods(s.o.method, s.results, &s.count)) == CLI_OK) {
        cli_run_desc d = {.command = "bench", .threads = s.o.threads, .max_memory = s.max_memory,
                          .simd = s.o.simd, .report = 1, .output = output};
        rc = cli_run(&d, bench_body, &s);
    }
    free(s.exact_image);
    free(s.peer.pixels);
    free(s.b.fb.color);
    free(s.b.fb.depth);
    free(s.results);
    return rc;
}
