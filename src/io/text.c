/* Loader helpers: file reading and paths. */
#define _XOPEN_SOURCE 700 /* fileno, fdopen, realpath, O_CLOEXEC */
#include "io/text.h"

#include "core/internal.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* The size of the open stream f of the regular file path, positioned at
 * its start; f is closed on failure. The size is taken from the stream
 * itself so that limits are checked before any buffer exists. */
static persp_status stream_size(persp_context *ctx, FILE *f, const char *path, size_t *size)
{
    if (fseek(f, 0, SEEK_END) != 0) {
        fclose(f);
        return persp__fail(ctx, PERSP_ERR_IO, "%s: cannot seek", path);
    }
    long end = ftell(f);
    if (end < 0 || fseek(f, 0, SEEK_SET) != 0) {
        fclose(f);
        return persp__fail(ctx, PERSP_ERR_IO, "%s: cannot determine the file size", path);
    }
    *size = (size_t)end;
    return PERSP_OK;
}

const char *persp__not_regular_what(const char *path)
{
    struct stat sb;
    if (stat(path, &sb) != 0) return "not a regular file";
    if (S_ISDIR(sb.st_mode)) return "a directory";
    if (S_ISFIFO(sb.st_mode)) return "a FIFO (named pipe)";
    if (S_ISCHR(sb.st_mode) || S_ISBLK(sb.st_mode)) return "a device";
    if (S_ISSOCK(sb.st_mode)) return "a socket";
    return "not a regular file";
}

const char *persp__not_regular_why(const char *path)
{
    struct stat sb;
    if (stat(path, &sb) != 0 || S_ISREG(sb.st_mode)) return NULL;
    if (S_ISDIR(sb.st_mode)) return "a directory, not a file";
    if (S_ISFIFO(sb.st_mode)) return "a FIFO (named pipe), not a regular file";
    if (S_ISCHR(sb.st_mode) || S_ISBLK(sb.st_mode)) return "a device, not a regular file";
    if (S_ISSOCK(sb.st_mode)) return "a socket, not a regular file";
    return "not a regular file";
}

/* Opens path for reading, a regular file only. A FIFO's open blocks until
 * a writer comes (forever, for one an unpacked archive left in a scene's
 * folder), and a device's may do anything: the open does not wait
 * (O_NONBLOCK, which a regular file ignores) and the type is checked on
 * the descriptor, so it is the file that is then read. -1 (errno) or
 * PERSP_OPEN_NOT_REGULAR. */
static int open_regular(const char *path)
{
    int fd = open(path, O_RDONLY | O_CLOEXEC | O_NONBLOCK | O_NOCTTY);
    if (fd < 0) return -1;
    struct stat sb;
    if (fstat(fd, &sb) != 0 || !S_ISREG(sb.st_mode)) {
        int e = errno;
        close(fd);
        errno = e;
        return PERSP_OPEN_NOT_REGULAR;
    }
    int flags = fcntl(fd, F_GETFL);
    if (flags >= 0) (void)fcntl(fd, F_SETFL, flags & ~O_NONBLOCK);
    return fd;
}

static persp_status open_failed(persp_context *ctx, const char *path, int fd, int err)
{
    if (fd == PERSP_OPEN_NOT_REGULAR) {
        const char *what = persp__not_regular_what(path);
        return persp__fail(ctx, PERSP_ERR_IO, "%s: is %s, not a %sfile", path, what,
                           strcmp(what, "a directory") ? "regular " : "");
    }
    return persp__fail(ctx, PERSP_ERR_IO, "%s: cannot open: %s", path, strerror(err));
}

/* Reads the open stream f (closed here) of the file path, n bytes, into a
 * buffer. */
static persp_status read_stream(persp_context *ctx, FILE *f, const char *path, size_t n, char **data,
                                size_t *size)
{
    if (n > PERSP_TEXT_MAX_BYTES) {
        fclose(f);
        return persp__fail(ctx, PERSP_ERR_TOO_LARGE, "%s: %zu bytes exceeds the limit of %zu", path,
                           n, (size_t)PERSP_TEXT_MAX_BYTES);
    }
    char *buf = persp__alloc(ctx, n + 1);
    if (!buf) {
        fclose(f);
        return persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "%s: out of memory", path);
    }
    size_t got = n ? fread(buf, 1, n, f) : 0;
    int bad = ferror(f);
    fclose(f);
    if (got != n || bad) {
        persp__free(ctx, buf);
        return persp__fail(ctx, PERSP_ERR_IO, "%s: read error", path);
    }
    buf[n] = '\0';
    *data = buf;
    *size = n;
    return PERSP_OK;
}

persp_status persp__read_file(persp_context *ctx, const char *path, char **data, size_t *size)
{
    return persp__read_file_inside(ctx, NULL, path, data, size);
}

persp_status persp__open_stream_inside(persp_context *ctx, const char *root, const char *path,
                                       FILE **out, size_t *size)
{
    *out = NULL;
    *size = 0;
    int fd = persp__open_inside(root, path);
    if (fd == PERSP_OPEN_OUTSIDE) {
        char q[PERSP_QUOTE_BYTES];
        return persp__fail(ctx, PERSP_ERR_IO,
                           "'%s' is outside the folder it may be read from (%s), or was replaced "
                           "while being opened",
                           persp__quote(path, strlen(path), q, sizeof q), root ? root : "");
    }
    if (fd < 0) return open_failed(ctx, path, fd, errno);
    FILE *f = fdopen(fd, "rb");
    if (!f) {
        int e = errno;
        close(fd);
        return persp__fail(ctx, PERSP_ERR_IO, "%s: cannot open: %s", path, strerror(e));
    }
    persp_status st = stream_size(ctx, f, path, size);
    if (st == PERSP_OK) *out = f;
    return st;
}

persp_status persp__read_file_inside(persp_context *ctx, const char *root, const char *path,
                                     char **data, size_t *size)
{
    *data = NULL;
    *size = 0;
    FILE *f = NULL;
    size_t n = 0;
    persp_status st = persp__open_stream_inside(ctx, root, path, &f, &n);
    return st == PERSP_OK ? read_stream(ctx, f, path, n, data, size) : st;
}

void persp__path_dir(const char *path, char *out, size_t size)
{
    if (size == 0) return;
    const char *slash = strrchr(path, '/');
    size_t n = slash ? (size_t)(slash - path) + 1 : 0;
    if (n >= size) n = size - 1;
    memcpy(out, path, n);
    out[n] = '\0';
}

int persp__path_join(const char *dir, const char *rel, char *out, size_t size)
{
    int n;
    if (rel[0] == '/' || !dir || !dir[0])
        n = snprintf(out, size, "%s", rel);
    else
        n = snprintf(out, size, "%s%s%s", dir, dir[strlen(dir) - 1] == '/' ? "" : "/", rel);
    return n >= 0 && (size_t)n < size;
}

const char *persp__path_base(const char *path)
{
    const char *slash = strrchr(path, '/');
    return slash ? slash + 1 : path;
}

persp_status persp__path_root(persp_context *ctx, const char *path, char *out, size_t size)
{
    char dir[PERSP_PATH_MAX];
    persp__path_dir(path, dir, sizeof dir);
    char *real = realpath(dir[0] ? dir : ".", NULL);
    if (!real) return persp__fail(ctx, PERSP_ERR_IO, "%s: cannot resolve its folder: %s", path,
                                  strerror(errno));
    int fits = strlen(real) < size;
    if (fits) memcpy(out, real, strlen(real) + 1);
    free(real);
    if (!fits) return persp__fail(ctx, PERSP_ERR_TOO_LARGE, "%s: folder name too long", path);
    return PERSP_OK;
}

/* 1 when the resolved name real lies in root or below. "/" as the root
 * allows everything under it; otherwise the next byte after the prefix must
 * end the name or start a component, so that /a/bc is not inside /a/b. */
static int real_under(const char *root, const char *real)
{
    size_t n = strlen(root);
    return !strncmp(real, root, n) &&
           (real[n] == '\0' || real[n] == '/' || (n > 0 && root[n - 1] == '/'));
}

int persp__path_inside(const char *root, const char *path)
{
    if (!root) return 1;
    /* realpath resolves every link and "..", so what is compared is where
     * an open at this moment would land (POSIX realpath()). */
    char *real = realpath(path, NULL);
    if (!real) return -1;
    int inside = real_under(root, real);
    free(real);
    return inside;
}

int persp__fd_inside(int fd, const char *root, const char *path)
{
    struct stat opened, named;
    if (fstat(fd, &opened) != 0) return -1;
    char *real = realpath(path, NULL);
    if (!real) return -1;
    /* A file is identified by st_dev and st_ino together (POSIX
     * <sys/stat.h>): the same pair means the open landed on the very file
     * that the resolved name, checked against root, names now. */
    int same = stat(real, &named) == 0 && named.st_dev == opened.st_dev &&
               named.st_ino == opened.st_ino;
    int inside = same && (!root || real_under(root, real));
    free(real);
    return inside;
}

int persp__open_inside(const char *root, const char *path)
{
    /* Opened first, checked second: a check before the open would let a
     * link swapped in between send the open elsewhere. What is read is the
     * file behind this descriptor, so it is the one that must lie in root.
     * O_CLOEXEC keeps it from leaking into a child a threaded caller
     * starts meanwhile (POSIX open()). */
    int fd = open_regular(path);
    if (fd < 0 || !root) return fd;
    if (persp__fd_inside(fd, root, path) != 1) {
        close(fd);
        return PERSP_OPEN_OUTSIDE;
    }
    return fd;
}
