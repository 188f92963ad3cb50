/*
 * Where a command's output goes (-o FILE, default standard output), with
 * the same rules as the library's files (src/io/outfile.h): a regular file
 * or a new one is written to a temporary file renamed over FILE only when
 * everything was written, so a failed run leaves no half report; through a
 * symbolic link the file it points to is replaced and the link stays;
 * devices and pipes are written in place; a read-only file is refused.
 *
 * Temporary files, the library's and these, are registered here so that
 * SIGINT or SIGTERM during a write removes them before the process dies
 * (unlink is async-signal-safe, POSIX.1-2008 XSH 2.4.3).
 */
#define _GNU_SOURCE /* realpath, sigaction (POSIX); fopencookie (glibc) for the capped output */
#include "cli.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <pthread.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* ------------------------------------------------ temporary files, signals */

/* Slot 0: the library's file of the moment (one context writes one file at
 * a time and the CLI writes from one thread); slot 1: cli_output's. The
 * handler reads a slot only while its flag is set; the path is complete
 * before the flag is raised. */
#define TEMP_SLOTS 2
static char temp_path[TEMP_SLOTS][PATH_MAX];
static volatile sig_atomic_t temp_set[TEMP_SLOTS];

static void temp_register(int slot, const char *path)
{
    temp_set[slot] = 0;
    if (!path || strlen(path) >= sizeof temp_path[slot]) return;
    memcpy(temp_path[slot], path, strlen(path) + 1);
    temp_set[slot] = 1;
}

void cli_temp_file(void *user, const char *path)
{
    (void)user;
    temp_register(0, path);
}

/* The thread that installed the handlers: the one that writes the files. */
static pthread_t writer;

static void on_signal(int sig)
{
    /* While the writer holds signals off (a temporary file created and not
     * yet registered) the kernel gives them to another thread, a render
     * worker for one, where the unlink below would come too early and the
     * file stay: passed on, the signal waits for the registration.
     * pthread_self and pthread_kill are async-signal-safe as well. */
    if (!pthread_equal(pthread_self(), writer)) {
        pthread_kill(writer, sig);
        return;
    }
    for (int i = 0; i < TEMP_SLOTS; i++)
        if (temp_set[i]) unlink(temp_path[i]);
    /* Die of the signal itself, so the parent sees how the command ended. */
    signal(sig, SIG_DFL);
    raise(sig);
}

void cli_install_signal_handlers(void)
{
    writer = pthread_self();
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
}

void cli_restore_signal_handlers(void)
{
    signal(SIGINT, SIG_DFL);
    signal(SIGTERM, SIG_DFL);
}

/* ------------------------------------------------------------ checks */

int cli_check_output(const char *command, const char *option, const char *path)
{
    if (!path || !strcmp(path, "-")) return CLI_OK;
    struct stat sb;
    if (stat(path, &sb) == 0) {
        if (S_ISDIR(sb.st_mode))
            return cli_error(CLI_FAIL, "%s: %s '%s' is a directory", command, option, path);
        if (!S_ISREG(sb.st_mode)) return CLI_OK; /* a device or pipe, written in place */
        if (access(path, W_OK) != 0 || !(sb.st_mode & (S_IWUSR | S_IWGRP | S_IWOTH)))
            return cli_error(CLI_FAIL, "%s: %s '%s' is read-only", command, option, path);
    }
    /* The folder the temporary file goes to (the link's, for a link). */
    char *real = realpath(path, NULL);
    const char *target = real ? real : path;
    const char *slash = strrchr(target, '/');
    char dir[PATH_MAX];
    if (!slash)
        snprintf(dir, sizeof dir, ".");
    else if (slash == target)
        snprintf(dir, sizeof dir, "/");
    else
        snprintf(dir, sizeof dir, "%.*s", (int)(slash - target), target);
    free(real);
    int rc = CLI_OK;
    if (stat(dir, &sb) != 0)
        rc = cli_error(CLI_FAIL, "%s: %s '%s': folder '%s' does not exist", command, option, path,
                       dir);
    else if (!S_ISDIR(sb.st_mode))
        rc = cli_error(CLI_FAIL, "%s: %s '%s': '%s' is not a folder", command, option, path, dir);
    else if (access(dir, W_OK | X_OK) != 0)
        rc = cli_error(CLI_FAIL, "%s: %s '%s': folder '%s' is not writable", command, option,
                       path, dir);
    return rc;
}

int cli_check_not_input(const char *command, const char *option, const char *output, const char *input)
{
    if (!output || !input || !strcmp(output, "-") || !strcmp(input, "-")) return CLI_OK;
    /* stat follows links, so "s.json", "./s.json" and a link to it are the
     * same file; a path that is not there yet cannot be the input. */
    struct stat so, si;
    if (stat(output, &so) != 0 || stat(input, &si) != 0) return CLI_OK;
    if (!S_ISREG(so.st_mode) || so.st_dev != si.st_dev || so.st_ino != si.st_ino) return CLI_OK;
    return cli_error(CLI_USAGE, "%s: %s '%s' is the input file '%s'; writing it would replace the input", command,
                     option, output, input);
}

/* -------------------------------------------------------------- output */

/* The capped stream's writer (glibc fopencookie): what would pass the
 * limit is refused whole, so the file holds no part of what overflowed. */
static ssize_t capped_write(void *cookie, const char *buf, size_t size)
{
    cli_cap *cap = cookie;
    if (cap->over || size > cap->limit - cap->written) {
        cap->over = 1;
        errno = EFBIG;
        return -1;
    }
    size_t n = fwrite(buf, 1, size, cap->raw);
    cap->written += n;
    return n == size ? (ssize_t)n : -1;
}

int cli_output_full(cli_output *out)
{
    return fflush(out->f) != 0 || ferror(out->f);
}

int cli_cap_begin(const char *command, cli_output *out, cli_cap *cap, size_t limit)
{
    cookie_io_functions_t io = {NULL, capped_write, NULL, NULL};
    memset(cap, 0, sizeof *cap);
    cap->raw = out->f;
    cap->limit = limit;
    if (!(out->f = fopencookie(cap, "w", io))) {
        out->f = cap->raw;
        cap->raw = NULL;
        return cli_error(CLI_FAIL, "%s: out of memory", command);
    }
    return CLI_OK;
}

int cli_cap_end(const char *command, cli_output *out, cli_cap *cap, const char *option, int ok)
{
    if (!cap->raw) return CLI_OK;
    int rc = CLI_OK;
    /* Closing flushes what is left into raw: the last refusal may come now. */
    int failed = fclose(out->f) != 0;
    int err = errno;
    out->f = cap->raw;
    cap->raw = NULL;
    if (ok && cap->over)
        rc = cli_error(CLI_FAIL, "%s: the output would exceed %s %zu bytes; %s (raise %s to allow more)", command,
                       option, cap->limit,
                       out->path ? "nothing was written" : "standard output got the part up to it", option);
    else if (ok && failed)
        rc = cli_error(CLI_FAIL, "%s: cannot write '%s': %s", command, out->path ? out->path : "standard output",
                       strerror(err));
    return rc;
}

int cli_output_open(const char *command, const char *path, cli_output *out)
{
    memset(out, 0, sizeof *out);
    if (!path || !strcmp(path, "-")) {
        out->f = stdout;
        return CLI_OK;
    }
    out->path = path;
    struct stat sb, lsb;
    int exists = stat(path, &sb) == 0;
    if (exists && S_ISDIR(sb.st_mode))
        return cli_error(CLI_FAIL, "%s: '%s' is a directory", command, path);
    if (exists && !S_ISREG(sb.st_mode)) {
        if (!(out->f = fopen(path, "w")))
            return cli_error(CLI_FAIL, "%s: cannot open '%s': %s", command, path, strerror(errno));
        return CLI_OK;
    }
    int link = lstat(path, &lsb) == 0 && S_ISLNK(lsb.st_mode);
    if (link && !exists)
        return cli_error(CLI_FAIL, "%s: '%s' is a symbolic link to a missing file (not replaced)",
                         command, path);
    if (exists && (access(path, W_OK) != 0 || !(sb.st_mode & (S_IWUSR | S_IWGRP | S_IWOTH))))
        return cli_error(CLI_FAIL, "%s: '%s' is read-only (not replaced)", command, path);
    if (link) out->target = realpath(path, NULL);
    const char *target = out->target ? out->target : path;
    size_t len = strlen(target);
    if (!(out->tmp = malloc(len + 12))) {
        free(out->target);
        return cli_error(CLI_FAIL, "%s: out of memory", command);
    }
    memcpy(out->tmp, target, len);
    /* As in the library: mkstemp finds a free name, which is re-created
     * with O_EXCL and mode 0666 so that the umask applies as for any new
     * file; and as there, signals wait until the file that mkstemp created
     * is registered, or gone. */
    sigset_t all, old;
    sigfillset(&all);
    pthread_sigmask(SIG_BLOCK, &all, &old);
    int fd = -1;
    for (int tries = 0; tries < 8 && fd < 0; tries++) {
        memcpy(out->tmp + len, ".tmp-XXXXXX", 12);
        if ((fd = mkstemp(out->tmp)) < 0) break;
        temp_register(1, out->tmp);
        close(fd);
        unlink(out->tmp);
        fd = open(out->tmp, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd < 0) {
            int err = errno;
            temp_register(1, NULL);
            errno = err;
            if (err != EEXIST) break;
        }
    }
    int mask_err = errno;
    pthread_sigmask(SIG_SETMASK, &old, NULL);
    errno = mask_err;
    if (fd >= 0 && exists) {
        (void)fchmod(fd, sb.st_mode & 07777);
        if (fchown(fd, sb.st_uid, sb.st_gid) != 0) {
            /* Only root may give a file away; others keep their own. */
        }
    }
    if (fd < 0 || !(out->f = fdopen(fd, "w"))) {
        int err = errno;
        if (fd >= 0) {
            close(fd);
            unlink(out->tmp);
            temp_register(1, NULL);
        }
        free(out->tmp);
        free(out->target);
        memset(out, 0, sizeof *out);
        return cli_error(CLI_FAIL, "%s: cannot create '%s': %s", command, path, strerror(err));
    }
    return CLI_OK;
}

int cli_output_close(const char *command, cli_output *out, int ok)
{
    int rc = CLI_OK;
    if (out->f == stdout) {
        /* A failure already reported leaves standard output to main's check. */
        errno = 0;
        if (ok && (fflush(stdout) != 0 || ferror(stdout)))
            rc = cli_error(CLI_FAIL, "%s: write error on standard output%s%s", command,
                           errno ? ": " : "", errno ? strerror(errno) : "");
    } else if (out->f) {
        int err = 0;
        errno = 0;
        if (fflush(out->f) != 0 || ferror(out->f)) err = errno ? errno : EIO;
        if (fclose(out->f) != 0 && !err) err = errno;
        if (ok && err)
            rc =
                cli_error(CLI_FAIL, "%s: cannot write '%s': %s", command, out->path, strerror(err));
        if (ok && !err && out->tmp && rename(out->tmp, out->target ? out->target : out->path) != 0)
            rc = cli_error(CLI_FAIL, "%s: cannot write '%s': %s", command, out->path,
                           strerror(errno));
        if (out->tmp && (!ok || rc != CLI_OK)) unlink(out->tmp);
        if (out->tmp) temp_register(1, NULL);
    }
    free(out->tmp);
    free(out->target);
    memset(out, 0, sizeof *out);
    return rc;
}
