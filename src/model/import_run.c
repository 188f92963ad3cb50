/*
 * Where the model importer runs (src/model/import_wire.h): persp-import, a
 * helper process started for each import, or a thread of the caller's
 * process when the caller asks for it (PERSP_MODEL_IMPORT_IN_PROCESS).
 *
 * The process is the default because the readers it runs were not written
 * for hostile input: the browsers' and GNOME's thumbnailers run theirs the
 * same way, each parse in a process with limits, so that a crash, a loop
 * or an allocation without bound ends that process and is reported, and
 * the program that asked goes on. persp-import gets a socket for stdin,
 * /dev/null for stdout and stderr, no other descriptor, an empty
 * environment, the memory the budget leaves (RLIMIT_AS, set by the helper
 * over its own start-up size), a CPU-time limit, no core files and no
 * files to write (tools/import/persp_import.cpp); persp enforces the
 * wall-clock limit and kills it when it passes.
 */
#define _GNU_SOURCE /* dladdr, posix_spawn_file_actions_addclosefrom_np */
#include "model/import_run.h"

#include "core/internal.h"
#include "model/import_wire.h"
#include "io/text.h"

#include <dlfcn.h>
#include <errno.h>
#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#define HELPER_NAME "persp-import"

/* An object of this library: dladdr names the file it was loaded from. */
static const int locate_anchor = 0;

/* 1 when path is a regular file this process may run. */
static int runnable(const char *path)
{
    struct stat sb;
    return stat(path, &sb) == 0 && S_ISREG(sb.st_mode) && access(path, X_OK) == 0;
}

int persp__import_helper_path(const char *given, char *out, size_t cap)
{
    if (given) {
        snprintf(out, cap, "%s", given);
        return runnable(out);
    }
    /* Beside the library (the build tree, or a program linking libpersp.a
     * with the helper installed next to it), then where `cmake --install`
     * puts it relative to lib/ or bin/: PREFIX/libexec/persp/. */
    Dl_info info;
    if (!dladdr(&locate_anchor, &info) || !info.dli_fname) return 0;
    char dir[PERSP_PATH_MAX];
    const char *self = info.dli_fname;
    char resolved[PERSP_PATH_MAX];
    /* In the program itself (libpersp.a linked in), glibc names the
     * program by its argv[0], which has no folder when it was found on
     * PATH or exec'd with a bare name (the bench peer's child): the
     * executable's own link says where it is. */
    if (!strchr(self, '/')) {
        const ssize_t n = readlink("/proc/self/exe", resolved, sizeof resolved - 1);
        if (n > 0) resolved[n] = '\0', self = resolved;
    } else if (realpath(self, resolved)) {
        self = resolved;
    }
    const char *slash = strrchr(self, '/');
    if (!slash) return 0;
    snprintf(dir, sizeof dir, "%.*s", (int)(slash - self), self);
    static const char *const places[] = {"%s/" HELPER_NAME, "%s/../libexec/persp/" HELPER_NAME,
                                         "%s/../../libexec/persp/" HELPER_NAME};
    for (size_t i = 0; i < sizeof places / sizeof places[0]; i++) {
        snprintf(out, cap, places[i], dir);
        if (runnable(out)) return 1;
    }
#ifdef PERSP_IMPORT_INSTALLED
    snprintf(out, cap, "%s", PERSP_IMPORT_INSTALLED);
    if (runnable(out)) return 1;
#endif
    return 0;
}

static void *serve_thread(void *arg)
{
    persp_importer *imp = arg;
    persp__import_serve(imp->thread_fd, NULL);
    /* The socket closes with the answer, so that persp sees its end. */
    shutdown(imp->thread_fd, SHUT_RDWR);
    return NULL;
}

persp_status persp__importer_start(persp_context *ctx, const persp_importer_opts *o, const char *display,
                                   persp_importer *imp)
{
    memset(imp, 0, sizeof *imp);
    imp->fd = imp->thread_fd = -1;
    int sv[2];
    if (socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, sv) != 0)
        return persp__fail(ctx, PERSP_ERR_IO, "%s: cannot start the model importer: %s", display,
                           strerror(errno));
    imp->fd = sv[0];
    if (o->in_process) {
        imp->thread_fd = sv[1];
        int e = pthread_create(&imp->thread, NULL, serve_thread, imp);
        if (e != 0) {
            close(sv[0]), close(sv[1]);
            imp->fd = imp->thread_fd = -1;
            return persp__fail(ctx, PERSP_ERR_IO, "%s: cannot start the model importer: %s", display,
                               strerror(e));
        }
        imp->has_thread = 1;
        return PERSP_OK;
    }
    char mem[32], cpu[32];
    snprintf(mem, sizeof mem, "%zu", o->memory);
    /* The wall clock is persp's to watch; the CPU limit only backs it up,
     * at the most a growing default limit can reach. */
    const unsigned cpu_ms = o->time_scales ? PERSP_IMPORT_TIME_LIMIT_MAX_MS : o->time_limit_ms;
    snprintf(cpu, sizeof cpu, "%u", (cpu_ms + 999) / 1000 + 1);
    char *const argv[] = {(char *)HELPER_NAME, (char *)"--memory", mem, (char *)"--cpu", cpu, NULL};
    /* The helper finds its libraries as the program did; nothing else of
     * the caller's environment goes with it. */
    char ldpath[PERSP_PATH_MAX + 32];
    char *envp[3];
    int ne = 0;
    const char *ld = getenv("LD_LIBRARY_PATH");
    if (ld && strlen(ld) < PERSP_PATH_MAX) {
        snprintf(ldpath, sizeof ldpath, "LD_LIBRARY_PATH=%s", ld);
        envp[ne++] = ldpath;
    }
#if defined(__SANITIZE_ADDRESS__)
    /* A sanitizer's shadow memory does not fit under RLIMIT_AS: the
     * instrumented helper is held by the sanitizer's own limits, on one
     * allocation and on its resident memory (checked about once a
     * second), which its reports of them tell the helper apart from a bug
     * (tools/import/persp_import.cpp). Assimp's own leaks are not its. */
    char asan[160];
    const size_t mb = o->memory / (1024 * 1024) + 1;
    snprintf(asan, sizeof asan,
             "ASAN_OPTIONS=abort_on_error=1:detect_leaks=0:max_allocation_size_mb=%zu:hard_rss_limit_mb=%zu",
             mb, mb + 64);
    envp[ne++] = asan;
#elif defined(__SANITIZE_THREAD__)
    char tsan[128];
    const size_t mb = o->memory / (1024 * 1024) + 1;
    snprintf(tsan, sizeof tsan, "TSAN_OPTIONS=abort_on_error=1:max_allocation_size_mb=%zu:hard_rss_limit_mb=%zu", mb,
             mb + 64);
    envp[ne++] = tsan;
#endif
    envp[ne] = NULL;
    posix_spawn_file_actions_t fa;
    posix_spawnattr_t attr;
    int e = posix_spawn_file_actions_init(&fa);
    if (e == 0) {
        posix_spawn_file_actions_adddup2(&fa, sv[1], 0);
        posix_spawn_file_actions_addopen(&fa, 1, "/dev/null", O_WRONLY, 0);
        posix_spawn_file_actions_adddup2(&fa, 1, 2);
        posix_spawn_file_actions_addclosefrom_np(&fa, 3);
        e = posix_spawnattr_init(&attr);
        if (e == 0) {
            sigset_t none, all;
            sigemptyset(&none);
            sigfillset(&all);
            /* Signals the caller ignores or blocks are not the helper's. */
            posix_spawnattr_setsigmask(&attr, &none);
            posix_spawnattr_setsigdefault(&attr, &all);
            posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);
            e = posix_spawn(&imp->pid, o->helper, &fa, &attr, argv, envp);
            posix_spawnattr_destroy(&attr);
        }
        posix_spawn_file_actions_destroy(&fa);
    }
    close(sv[1]);
    if (e != 0) {
        close(sv[0]);
        imp->fd = -1;
        imp->pid = 0;
        return persp__fail(ctx, PERSP_ERR_IO, "%s: cannot start the model importer %s: %s", display,
                           o->helper, strerror(e));
    }
    return PERSP_OK;
}

void persp__importer_finish(persp_importer *imp, int stop, persp_importer_end *end)
{
    memset(end, 0, sizeof *end);
    if (imp->fd >= 0) {
        /* The helper's next read or write fails: it ends on its own. */
        shutdown(imp->fd, SHUT_RDWR);
        close(imp->fd);
        imp->fd = -1;
    }
    if (imp->has_thread) {
        pthread_join(imp->thread, NULL);
        close(imp->thread_fd);
        imp->has_thread = 0;
        imp->thread_fd = -1;
        return;
    }
    if (imp->pid <= 0) return;
    if (stop) kill(imp->pid, SIGKILL);
    int status = 0;
    struct rusage ru;
    memset(&ru, 0, sizeof ru);
    pid_t r;
    /* A helper that answered exits at once; one that does not within a
     * second is stopped. */
    for (int waited = 0;; waited++) {
        r = wait4(imp->pid, &status, WNOHANG, &ru);
        if (r > 0 || (r < 0 && errno != EINTR)) break;
        if (waited == 100) kill(imp->pid, SIGKILL);
        usleep(waited < 100 ? 10000 : 1000);
    }
    imp->pid = 0;
    if (r < 0) return; /* reaped elsewhere (SIGCHLD ignored): nothing known */
    end->known = 1;
    end->peak_bytes = (size_t)ru.ru_maxrss * 1024u;
    if (WIFSIGNALED(status)) end->signal = WTERMSIG(status);
    else if (WIFEXITED(status)) end->exit_code = WEXITSTATUS(status);
}
