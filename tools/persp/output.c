/*
 * Where a command's report goes (-o FILE, default standard output). A file
 * is written like persp_image_write writes images: to a temporary file
 * renamed over FILE only when everything was written, so a failed run
 * leaves no half report; devices and pipes are written in place.
 */
#define _XOPEN_SOURCE 700 /* realpath */
#include "cli.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

int cli_output_open(const char *command, const char *path, cli_output *out)
{
    memset(out, 0, sizeof *out);
    if (!path || !strcmp(path, "-")) {
        out->f = stdout;
        return CLI_OK;
    }
    out->path = path;
    struct stat sb;
    if (stat(path, &sb) == 0 && !S_ISREG(sb.st_mode)) {
        if (!(out->f = fopen(path, "w")))
            return cli_error(CLI_FAIL, "%s: cannot open '%s': %s", command, path, strerror(errno));
        return CLI_OK;
    }
    /* Through a link, the file it names is replaced, not the link. */
    if (lstat(path, &sb) == 0 && S_ISLNK(sb.st_mode)) out->target = realpath(path, NULL);
    const char *target = out->target ? out->target : path;
    size_t len = strlen(target);
    if (!(out->tmp = malloc(len + 12))) return cli_error(CLI_FAIL, "%s: out of memory", command);
    memcpy(out->tmp, target, len);
    memcpy(out->tmp + len, ".tmp-XXXXXX", 12);
    int fd = mkstemp(out->tmp);
    if (fd < 0 || fchmod(fd, 0644) != 0 || !(out->f = fdopen(fd, "w"))) {
        int err = errno;
        if (fd >= 0) {
            close(fd);
            unlink(out->tmp);
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
    }
    free(out->tmp);
    free(out->target);
    memset(out, 0, sizeof *out);
    return rc;
}
