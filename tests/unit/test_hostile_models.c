/* Hostile model files (tests/hostile/README.md) loaded one after another in
 * one process through the public API, every format enabled, under a
 * 128 MiB budget: each load must fail with a one-line error naming the file
 * while the process goes on to the next, and every byte persp took from the
 * context's allocator must be back when the context is destroyed.
 *
 * The loads run in a child process that this one watches: a case that
 * crashes the loading process, hangs it (PERSP_HOSTILE_KILL_S on one case)
 * or makes it hold more than PERSP_HOSTILE_SAFETY_MB resident is named, the
 * child killed and the test failed. (A handler in the loading process
 * itself cannot report a stack overflow on a thread that persp started.)
 *
 * The cases: the folder tests/hostile/gen_hostile.py wrote, from argv[1] or
 * PERSP_HOSTILE_DIR; without either the test runs the generator itself
 * (python3) into hostile-run/cases/ of the build folder (PERSP_BINARY_DIR).
 * The FIFO cases are made in hostile-run/fifo/.
 *   PERSP_HOSTILE_IMPORT   isolated | in-process | default (the default):
 *                          persp_scene_load_desc.import; in-process shows
 *                          what the cases do without the helper
 *   PERSP_HOSTILE_ONLY     a substring: only the cases whose file holds it
 *   PERSP_HOSTILE_TIME_LIMIT_MS  persp_scene_load_desc.import_time_limit_ms
 *                          (0: persp's default, 5 s for a small file, which
 *                          stops a reader that loops within the 10 s a case
 *                          may take)
 *   PERSP_HOSTILE_OVERHEAD_MB  what the loading process may hold beyond the
 *                          budget while a case loads, as seen every 20 ms
 *                          (64; 256 in a build with AddressSanitizer)
 *   PERSP_HOSTILE_SAFETY_MB, PERSP_HOSTILE_KILL_S (1024, 20)
 */
#define _XOPEN_SOURCE 700 /* mkfifo, kill */
#include "support.h"

#include "persp.h"

#include <poll.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#define BUDGET ((size_t)128 << 20)
#define MAX_CASES 128
#define PATH_BYTES 1024 /* the cases' folder */
#define CASE_LIMIT_MS 10000

#if defined(__SANITIZE_ADDRESS__)
#define OVERHEAD_MB 256
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define OVERHEAD_MB 256
#endif
#endif
#ifndef OVERHEAD_MB
#define OVERHEAD_MB 64
#endif

typedef struct hostile_case {
    char dir[PATH_BYTES];
    char file[128];
    char klass[16];
    char expect[64]; /* "fail", or "fail-or-warn:FIFO" for a FIFO the model names */
} hostile_case;

static const char *cases_arg;

/* --------------------------------------------------------------- the cases */

static void write_text(const char *dir, const char *name, const char *text)
{
    char path[PATH_BYTES + 64];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_true(fputs(text, f) >= 0);
    assert_int_equal(fclose(f), 0);
}

static void make_fifo(const char *dir, const char *name)
{
    char path[PATH_BYTES + 64];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    if (mkfifo(path, 0600) != 0) fail_msg("mkfifo %s failed", path);
}

static hostile_case *add_case(hostile_case *cases, int *n, const char *dir, const char *file,
                              const char *klass, const char *expect)
{
    if (*n == MAX_CASES) fail_msg("more than %d cases", MAX_CASES);
    hostile_case *c = &cases[(*n)++];
    memset(c, 0, sizeof *c);
    snprintf(c->dir, sizeof c->dir, "%s", dir);
    snprintf(c->file, sizeof c->file, "%s", file);
    snprintf(c->klass, sizeof c->klass, "%s", klass);
    snprintf(c->expect, sizeof c->expect, "%s", expect);
    return c;
}

static void read_manifest(const char *dir, hostile_case *cases, int *n)
{
    char path[PATH_BYTES + 16], line[1024];
    snprintf(path, sizeof path, "%s/cases.tsv", dir);
    FILE *f = fopen(path, "r");
    if (!f) fail_msg("%s: cannot open (run tests/hostile/gen_hostile.py DIR first)", path);
    int before = *n;
    while (fgets(line, sizeof line, f)) {
        char *file = strtok(line, "\t\n"), *formats = strtok(NULL, "\t\n"),
             *klass = strtok(NULL, "\t\n");
        if (!file || !formats || !klass || !strcmp(file, "file")) continue;
        add_case(cases, n, dir, file, klass, "fail");
    }
    fclose(f);
    if (*n == before) fail_msg("%s: no cases", path);
}

/* The FIFO cases of tests/cli/test_hostile_models.sh, in dir: FIFOs with
 * no writer, as the model or named by one. A model that names one may
 * fail, or load without it with one warning naming it. */
static void make_special(const char *dir, hostile_case *cases, int *n)
{
    static const char tri[] =
        "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\","
        "\"min\":[0,0,0],\"max\":[1,1,0]}],\"bufferViews\":[{\"buffer\":0,\"byteLength\":36}],"
        "\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],"
        "\"nodes\":[{\"mesh\":0}]";
    /* the triangle (0,0,0) (1,0,0) (0,1,0) as 9 little-endian floats */
    static const char tri_b64[] = "AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA";
    char text[2048];
    make_fifo(dir, "90-fifo-model.obj");
    make_fifo(dir, "91-fifo-model.gltf");
    make_fifo(dir, "92-fifo.mtl");
    make_fifo(dir, "93-fifo.png");
    make_fifo(dir, "94-fifo.bin");
    make_fifo(dir, "95-fifo.png");
    write_text(dir, "92-fifo-mtllib.obj",
               "mtllib 92-fifo.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl m\nf 1 2 3\n");
    write_text(dir, "93-texture.mtl", "newmtl m\nKd 1 1 1\nmap_Kd 93-fifo.png\n");
    write_text(dir, "93-fifo-texture.obj",
               "mtllib 93-texture.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n"
               "usemtl m\nf 1/1 2/2 3/3\n");
    snprintf(text, sizeof text,
             "{%s,\"buffers\":[{\"uri\":\"94-fifo.bin\",\"byteLength\":36}],"
             "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0}}]}]}\n",
             tri);
    write_text(dir, "94-fifo-buffer.gltf", text);
    snprintf(text, sizeof text,
             "{%s,\"buffers\":[{\"uri\":\"data:application/octet-stream;base64,%s\","
             "\"byteLength\":36}],\"meshes\":[{\"primitives\":[{\"attributes\":"
             "{\"POSITION\":0},\"material\":0}]}],\"materials\":[{\"pbrMetallicRoughness\":"
             "{\"baseColorTexture\":{\"index\":0}}}],\"textures\":[{\"source\":0}],"
             "\"images\":[{\"uri\":\"95-fifo.png\"}]}\n",
             tri, tri_b64);
    write_text(dir, "95-fifo-image.gltf", text);
    add_case(cases, n, dir, "90-fifo-model.obj", "special", "fail");
    add_case(cases, n, dir, "91-fifo-model.gltf", "special", "fail");
    add_case(cases, n, dir, "92-fifo-mtllib.obj", "special", "fail-or-warn:92-fifo.mtl");
    add_case(cases, n, dir, "93-fifo-texture.obj", "special", "fail-or-warn:93-fifo.png");
    add_case(cases, n, dir, "94-fifo-buffer.gltf", "special", "fail");
    add_case(cases, n, dir, "95-fifo-image.gltf", "special", "fail-or-warn:95-fifo.png");
}

/* ------------------------------------------------- loading (in the child) */

typedef struct warnings {
    int count;
    char first[512];
} warnings;

static void on_warning(void *user, const char *message)
{
    warnings *w = user;
    if (w->count++ == 0) snprintf(w->first, sizeof w->first, "%s", message);
}

static long now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (long)ts.tv_sec * 1000 + ts.tv_nsec / 1000000;
}

/* The bytes of a size as persp writes one ("12 bytes", "96.1 MiB") at p,
 * *end past it; -1 when there is none. */
static double size_at(const char *p, const char **end)
{
    static const struct {
        const char *name;
        double bytes;
    } units[] = {{" bytes", 1.0}, {" KiB", 1024.0}, {" MiB", 1048576.0}, {" GiB", 1073741824.0}};
    char *q;
    double v = strtod(p, &q);
    if (q == p) return -1.0;
    for (size_t i = 0; i < sizeof units / sizeof units[0]; i++)
        if (!strncmp(q, units[i].name, strlen(units[i].name))) {
            *end = q + strlen(units[i].name);
            return v * units[i].bytes;
        }
    return -1.0;
}

/* Whether an out-of-memory error says how much (a size somewhere), and
 * where it reads "needs A, over the memory budget of B (C already in use)"
 * whether A + C is over B, as the refusal it reports was (each rounded to
 * a tenth of its unit). */
static int oom_detail_sound(const char *msg)
{
    int sized = 0;
    for (const char *p = msg; *p && !sized; p++) {
        const char *e;
        sized = (p == msg || !(p[-1] >= '0' && p[-1] <= '9')) && *p >= '0' && *p <= '9' &&
                size_at(p, &e) >= 0.0;
    }
    if (!sized) return 0;
    for (const char *p = strstr(msg, "needs "); p; p = strstr(p + 1, "needs ")) {
        const char *e;
        double need = size_at(p + 6, &e), budget, used;
        if (need < 0.0 || strncmp(e, ", over the memory budget of ", 28)) continue;
        if ((budget = size_at(e + 28, &e)) < 0.0 || strncmp(e, " (", 2)) continue;
        if ((used = size_at(e + 2, &e)) < 0.0 || strncmp(e, " already in use)", 16)) continue;
        if (need + used + 0.2 * 1048576.0 < budget) return 0;
    }
    return 1;
}

/* Loads one case and prints its line; 1 when it did what it must. */
static int load_case(const hostile_case *c, persp_model_import import, unsigned time_limit_ms)
{
    char path[PATH_BYTES + sizeof c->file + 1], why[1024] = "";
    snprintf(path, sizeof path, "%s/%.127s", c->dir, c->file);
    test_tracker cnt;
    persp_allocator al = test_tracker_allocator(&cnt);
    persp_context_desc cd = {.allocator = &al, .threads = 1, .max_memory = BUDGET};
    persp_context *ctx = NULL;
    if (persp_context_create(&cd, &ctx) != PERSP_OK) {
        printf("FAIL %-28s persp_context_create failed\n", c->file);
        return 0;
    }
    warnings warn;
    memset(&warn, 0, sizeof warn);
    persp_context_set_warning_handler(ctx, on_warning, &warn);
    persp_scene_load_desc desc = {.formats = PERSP_MODEL_FORMATS_ALL,
                                  .import = import,
                                  .import_time_limit_ms = time_limit_ms};
    persp_scene *scene = NULL;
    long t0 = now_ms();
    persp_status st = persp_scene_load_ex(ctx, path, &desc, &scene);
    long ms = now_ms() - t0;

    char msg[600];
    const char *detail = persp_context_error(ctx);
    snprintf(msg, sizeof msg, "%s", detail ? detail : "");
    int good = 1;
#define WHY(...)                                                                                   \
    do {                                                                                           \
        size_t used_ = strlen(why);                                                                \
        snprintf(why + used_, sizeof why - used_, __VA_ARGS__);                                    \
        good = 0;                                                                                  \
    } while (0)
    const char *fifo = !strncmp(c->expect, "fail-or-warn:", 13) ? c->expect + 13 : NULL;
    if (st == PERSP_OK) {
        if (!fifo)
            WHY("loaded (expected a failure); ");
        else if (warn.count != 1 || !strstr(warn.first, fifo))
            WHY("loaded with %d warnings, not one naming %.63s ('%.300s'); ", warn.count, fifo,
                warn.first);
        persp_scene_destroy(scene);
    } else {
        if (!msg[0]) WHY("%s with an empty error; ", persp_status_string(st));
        if (warn.count) WHY("%d warnings before the error ('%.200s'); ", warn.count, warn.first);
        if (strchr(msg, '\n')) WHY("the error is more than one line; ");
        /* A scene's error about a model it names names that model, a file
         * of the case's folder. */
        char folder[PATH_BYTES + 2];
        snprintf(folder, sizeof folder, "%s/", c->dir);
        const size_t len = strlen(c->file);
        const int scene = len > 5 && !strcmp(c->file + len - 5, ".json");
        if (!strstr(msg, c->file) && !(scene && strstr(msg, folder)))
            WHY("the error does not name %.127s%s; ", c->file, scene ? " or a file beside it" : "");
        if (st == PERSP_ERR_OUT_OF_MEMORY && !oom_detail_sound(msg))
            WHY("out of memory without saying how much, or with numbers that do not add up; ");
    }
    if (strstr(c->file, ".md5mesh") && (strstr(msg, "md5anim") || strstr(warn.first, "md5anim")))
        WHY("blames the missing optional .md5anim; ");
    if (ms > CASE_LIMIT_MS) WHY("took %.1f s; ", (double)ms / 1000.0);
    persp_context_destroy(ctx);
    if (cnt.live != 0 || cnt.blocks != 0)
        WHY("%zu bytes in %ld blocks still held after persp_context_destroy; ", cnt.live, cnt.blocks);
#undef WHY
    printf("%s %-28s %6.2f s  %s: %s%s%s\n", good ? "PASS" : "FAIL", c->file, (double)ms / 1000.0,
           st == PERSP_OK ? "loaded" : persp_status_string(st), st == PERSP_OK ? warn.first : msg,
           good ? "" : "  -- ", why);
    fflush(stdout);
    return good;
}

/* The child: every case in turn, "B i" on fd before case i and "E i g"
 * after it (g: 1 if it did what it must). Never returns. */
static void load_all(const hostile_case *cases, int n, persp_model_import import,
                     unsigned time_limit_ms, int fd)
{
    int failed = 0;
    for (int i = 0; i < n; i++) {
        char note[64];
        int len = snprintf(note, sizeof note, "B %d\n", i);
        if (write(fd, note, (size_t)len) != len) _exit(2);
        int good = load_case(&cases[i], import, time_limit_ms);
        failed += !good;
        len = snprintf(note, sizeof note, "E %d %d\n", i, good);
        if (write(fd, note, (size_t)len) != len) _exit(2);
    }
    fflush(stdout);
    _exit(failed ? 1 : 0);
}

/* ---------------------------------------------------- watching (the parent) */

static long resident_mb(pid_t pid)
{
    char path[64];
    snprintf(path, sizeof path, "/proc/%d/statm", (int)pid);
    FILE *f = fopen(path, "r");
    long size = 0, resident = 0;
    if (!f) return 0;
    if (fscanf(f, "%ld %ld", &size, &resident) != 2) resident = 0;
    fclose(f);
    return (long)((double)resident * (double)sysconf(_SC_PAGESIZE) / (1 << 20));
}

static persp_model_import import_mode(void)
{
    const char *e = getenv("PERSP_HOSTILE_IMPORT");
    if (!e || !*e || !strcmp(e, "default")) return PERSP_MODEL_IMPORT_DEFAULT;
    if (!strcmp(e, "isolated")) return PERSP_MODEL_IMPORT_ISOLATED;
    if (!strcmp(e, "in-process")) return PERSP_MODEL_IMPORT_IN_PROCESS;
    fail_msg("PERSP_HOSTILE_IMPORT='%s': expected isolated, in-process or default", e);
    return PERSP_MODEL_IMPORT_DEFAULT;
}

static long env_long(const char *name, long fallback)
{
    const char *e = getenv(name);
    return e && atol(e) > 0 ? atol(e) : fallback;
}

static void test_hostile_models(void **state)
{
    (void)state;
    const long safety_mb = env_long("PERSP_HOSTILE_SAFETY_MB", 1024);
    const long limit_mb = (long)(BUDGET >> 20) + env_long("PERSP_HOSTILE_OVERHEAD_MB", OVERHEAD_MB);
    const long kill_ms = env_long("PERSP_HOSTILE_KILL_S", 20) * 1000;
    const unsigned time_limit_ms = (unsigned)env_long("PERSP_HOSTILE_TIME_LIMIT_MS", 0);
    const char *only = getenv("PERSP_HOSTILE_ONLY");
    const persp_model_import import = import_mode();

    /* The cases given, or generated here, and the FIFOs: in the build
     * folder (PERSP_BINARY_DIR), made afresh on each run and left there. */
    char run[PATH_BYTES], dir[PATH_BYTES], sdir[PATH_BYTES], cmd[3 * PATH_BYTES];
    test_binary_path(run, sizeof run, "hostile-run");
    snprintf(cmd, sizeof cmd, "rm -rf '%s' && mkdir -p '%s/fifo'", run, run);
    if (system(cmd) != 0) fail_msg("'%s' failed", cmd);
    snprintf(sdir, sizeof sdir, "%.1000s/fifo", run);
    const char *given = cases_arg ? cases_arg : getenv("PERSP_HOSTILE_DIR");
    if (given && *given) {
        snprintf(dir, sizeof dir, "%s", given);
    } else {
        char script[PATH_BYTES];
        test_source_path(script, sizeof script, "tests/hostile/gen_hostile.py");
        snprintf(dir, sizeof dir, "%.1000s/cases", run);
        snprintf(cmd, sizeof cmd, "python3 '%s' '%s'", script, dir);
        if (system(cmd) != 0) fail_msg("'%s' failed (python3 is needed)", cmd);
    }
    static hostile_case all[MAX_CASES], cases[MAX_CASES];
    int n_all = 0, n = 0;
    read_manifest(dir, all, &n_all);
    make_special(sdir, all, &n_all);
    for (int i = 0; i < n_all; i++)
        if (!only || strstr(all[i].file, only)) cases[n++] = all[i];
    if (n == 0) fail_msg("no case matches PERSP_HOSTILE_ONLY='%s'", only);

    int fds[2];
    assert_int_equal(pipe(fds), 0);
    fflush(stdout);
    fflush(stderr);
    pid_t child = fork();
    assert_true(child >= 0);
    if (child == 0) {
        /* cmocka's handlers would catch a reader's fault in the child and
         * go on with cmocka's run there: the child dies of it instead. */
        const int fatal[] = {SIGSEGV, SIGBUS, SIGILL, SIGFPE, SIGABRT, SIGSYS, SIGPIPE};
        for (size_t k = 0; k < sizeof fatal / sizeof fatal[0]; k++)
            signal(fatal[k], SIG_DFL);
        close(fds[0]);
        load_all(cases, n, import, time_limit_ms, fds[1]);
    }
    close(fds[1]);

    /* Follow the child's notes; end it when one case runs too long or it
     * holds too much. */
    int current = -1, done = 0, failed = 0;
    long started = now_ms(), peak_mb = 0, case_peak_mb = 0;
    char killed[128] = "", buf[256];
    size_t have = 0;
    for (;;) {
        struct pollfd p = {.fd = fds[0], .events = POLLIN};
        int r = poll(&p, 1, 20);
        if (r > 0) {
            ssize_t got = read(fds[0], buf + have, sizeof buf - 1 - have);
            if (got <= 0) break; /* the child has ended */
            have += (size_t)got;
            buf[have] = '\0';
            char *line = buf, *nl;
            while ((nl = strchr(line, '\n'))) {
                *nl = '\0';
                int i = 0, good = 0;
                if (sscanf(line, "B %d", &i) == 1 && line[0] == 'B') {
                    current = i;
                    started = now_ms();
                    case_peak_mb = 0;
                } else if (sscanf(line, "E %d %d", &i, &good) == 2 && i >= 0 && i < n) {
                    current = -1;
                    done++;
                    if (good && case_peak_mb > limit_mb) {
                        printf("FAIL %-28s the loading process held %ld MiB, more than %ld "
                               "(the budget and PERSP_HOSTILE_OVERHEAD_MB)\n",
                               cases[i].file, case_peak_mb, limit_mb);
                        fflush(stdout);
                        good = 0;
                    }
                    failed += !good;
                }
                line = nl + 1;
            }
            have = strlen(line);
            memmove(buf, line, have + 1);
        }
        long mb = resident_mb(child);
        if (mb > peak_mb) peak_mb = mb;
        if (current >= 0 && mb > case_peak_mb) case_peak_mb = mb;
        if (current >= 0 && now_ms() - started > kill_ms)
            snprintf(killed, sizeof killed, "hang: no answer after %ld s", kill_ms / 1000);
        else if (mb > safety_mb)
            snprintf(killed, sizeof killed, "%ld MiB resident (PERSP_HOSTILE_SAFETY_MB %ld)", mb,
                     safety_mb);
        if (killed[0]) {
            kill(child, SIGKILL);
            break;
        }
    }
    close(fds[0]);
    int status = 0;
    assert_int_equal(waitpid(child, &status, 0), child);
    const char *culprit = current >= 0 ? cases[current].file : "between cases";
    printf("hostile models: %d of %d cases done, %d failed; the loading process peaked at %ld MiB "
           "resident (seen)\n",
           done, n, failed, peak_mb);
    if (killed[0])
        fail_msg("%s in %s: the loading process was killed, %d cases not run", killed, culprit,
                 n - done - 1);
    if (WIFSIGNALED(status))
        fail_msg("the loading process died of signal %d (%s) in %s; %d cases not run",
                 WTERMSIG(status), strsignal(WTERMSIG(status)), culprit, n - done - 1);
    if (!WIFEXITED(status) || WEXITSTATUS(status) > 1 || done < n)
        fail_msg("the loading process ended (status %d) in %s; %d cases not run", status, culprit,
                 n - done);
    if (failed || WEXITSTATUS(status) != 0)
        fail_msg("%d of %d hostile models were not refused cleanly", failed, n);
}

int main(int argc, char **argv)
{
    cases_arg = argc > 1 ? argv[1] : NULL;
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_hostile_models),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
