/* Output files written through a temporary file and a rename (outfile.h). */
#define _XOPEN_SOURCE 700 /* realpath, fchown */
#include "io/outfile.h"

#include "core/internal.h"

#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static void tell_temp(persp_context *ctx, const char *tmp)
{
    if (ctx->temp_fn) ctx->temp_fn(ctx->temp_user, tmp);
}

/* A fresh file next to target, created with mode 0666 so that the umask
 * applies as for any new file: mkstemp picks a free name (and creates it
 * 0600), which is then re-created with O_EXCL, so a name another process
 * takes meanwhile is an error, never a file of theirs overwritten. */
static int create_temp(persp_context *ctx, char *tmp, size_t len)
{
    /* The file exists from inside mkstemp on, but the handler hears of it
     * only once mkstemp has returned: a signal handled in between (on a
     * loaded machine the process is often descheduled right there) found
     * nothing to remove and left the file behind. Signals to this thread
     * wait until the file is announced, or is gone. */
    sigset_t all, old;
    sigfillset(&all);
    pthread_sigmask(SIG_BLOCK, &all, &old);
    int fd = -1, err = EEXIST;
    for (int tries = 0; tries < 8; tries++) {
        memcpy(tmp + len, ".tmp-XXXXXX", 12);
        fd = mkstemp(tmp);
        if (fd < 0) {
            err = errno;
            break;
        }
        tell_temp(ctx, tmp);
        close(fd);
        unlink(tmp);
        fd = open(tmp, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd >= 0) break;
        err = errno;
        tell_temp(ctx, NULL);
        if (err != EEXIST) break;
    }
    pthread_sigmask(SIG_SETMASK, &old, NULL);
    if (fd < 0) errno = err;
    return fd;
}

persp_status persp__outfile_open(persp_context *ctx, const char *path, persp_outfile *out)
{
    memset(out, 0, sizeof *out);
    out->path = path;
    struct stat sb, lsb;
    int exists = stat(path, &sb) == 0;
    if (exists && S_ISDIR(sb.st_mode))
        return persp__fail(ctx, PERSP_ERR_IO, "%s: is a directory", path);
    if (exists && !S_ISREG(sb.st_mode)) {
        if (!(out->f = fopen(path, "wb")))
            return persp__fail(ctx, PERSP_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
        return PERSP_OK;
    }
    int link = lstat(path, &lsb) == 0 && S_ISLNK(lsb.st_mode);
    if (link && !exists)
        return persp__fail(ctx, PERSP_ERR_IO,
                           "%s: is a symbolic link to a missing file (not replaced)", path);
    /* A read-only file stays as it is: replacing it by a rename would
     * succeed (only the folder's permissions matter), and root passes
     * access() regardless, so the mode bits are checked as well. */
    if (exists && (access(path, W_OK) != 0 || !(sb.st_mode & (S_IWUSR | S_IWGRP | S_IWOTH))))
        return persp__fail(ctx, PERSP_ERR_IO, "%s: the file is read-only (not replaced)", path);
    char *resolved = link ? realpath(path, NULL) : NULL;
    const char *target = resolved ? resolved : path;
    size_t len = strlen(target);
    out->target = persp__alloc(ctx, len + 1);
    out->tmp = persp__alloc(ctx, len + 12);
    if (!out->target || !out->tmp) {
        free(resolved);
        persp__free(ctx, out->target);
        persp__free(ctx, out->tmp);
        memset(out, 0, sizeof *out);
        return persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "%s: out of memory", path);
    }
    memcpy(out->target, target, len + 1);
    memcpy(out->tmp, target, len);
    free(resolved);
    int fd = create_temp(ctx, out->tmp, len);
    if (fd < 0) {
        int err = errno;
        persp__free(ctx, out->target);
        persp__free(ctx, out->tmp);
        memset(out, 0, sizeof *out);
        return persp__fail(ctx, PERSP_ERR_IO, "%s: cannot create a file there: %s", path,
                           strerror(err));
    }
    if (exists) {
        /* The replacement keeps the permission bits (and, where allowed,
         * the owner) of the file it replaces. */
        (void)fchmod(fd, sb.st_mode & 07777);
        if (fchown(fd, sb.st_uid, sb.st_gid) != 0) {
            /* Only root may give a file away; others keep their own. */
        }
    }
    if (!(out->f = fdopen(fd, "wb"))) {
        int err = errno;
        close(fd);
        unlink(out->tmp);
        tell_temp(ctx, NULL);
        persp__free(ctx, out->target);
        persp__free(ctx, out->tmp);
        memset(out, 0, sizeof *out);
        return persp__fail(ctx, PERSP_ERR_IO, "%s: cannot open: %s", path, strerror(err));
    }
    return PERSP_OK;
}

persp_status persp__outfile_close(persp_context *ctx, persp_outfile *out, persp_status st)
{
    if (out->f) {
        int err = 0;
        errno = 0;
        if (fflush(out->f) != 0 || ferror(out->f)) err = errno ? errno : EIO;
        if (fclose(out->f) != 0 && !err) err = errno ? errno : EIO;
        if (err && st == PERSP_OK)
            st = persp__fail(ctx, PERSP_ERR_IO, "%s: write failed: %s", out->path, strerror(err));
    }
    if (out->tmp) {
        if (st == PERSP_OK && rename(out->tmp, out->target) != 0)
            st = persp__fail(ctx, PERSP_ERR_IO, "%s: cannot replace it: %s", out->path,
                             strerror(errno));
        if (st != PERSP_OK) unlink(out->tmp);
        tell_temp(ctx, NULL);
    }
    persp__free(ctx, out->tmp);
    persp__free(ctx, out->target);
    memset(out, 0, sizeof *out);
    return st;
}
