/* Loader helpers: file reading and paths. */
#include "io/text.h"

#include "core/internal.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>

persp_status persp__read_file(persp_context *ctx, const char *path, char **data, size_t *size)
{
    *data = NULL;
    *size = 0;
    FILE *f = fopen(path, "rb");
    if (!f) return persp__fail(ctx, PERSP_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    /* The size is taken from the stream itself so that the limit is checked
     * before the buffer exists. */
    if (fseek(f, 0, SEEK_END) != 0) {
        fclose(f);
        return persp__fail(ctx, PERSP_ERR_IO, "%s: cannot seek (not a regular file?)", path);
    }
    long end = ftell(f);
    if (end < 0 || fseek(f, 0, SEEK_SET) != 0) {
        fclose(f);
        return persp__fail(ctx, PERSP_ERR_IO, "%s: cannot determine the file size", path);
    }
    if ((unsigned long)end > PERSP_TEXT_MAX_BYTES) {
        fclose(f);
        return persp__fail(ctx, PERSP_ERR_TOO_LARGE, "%s: %ld bytes exceeds the limit of %zu",
                                  path, end, (size_t)PERSP_TEXT_MAX_BYTES);
    }
    size_t n = (size_t)end;
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
