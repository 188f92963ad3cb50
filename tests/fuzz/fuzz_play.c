/* libFuzzer harness: the camera path of `persp view --play FILE`
 * (view_path_load of tools/persp/view_core.c, JSON {"keys": [{"t", "eye",
 * "yaw", "pitch", "fovy", "near", "far"}, ...]}), read from a file as the
 * command reads it: the input is written to a memory file (memfd_create)
 * and loaded through its /proc/self/fd/N name, so that Jansson's
 * json_load_file runs as it does for a real path. The loader follows no
 * file references, so nothing else is opened. Then the path is sampled as
 * play_path in cmd_view.c samples it (one frame per key, and 7 frames).
 * Checked besides crashes: a refused path leaves no keys and a one-line
 * message that starts with the file's name; an accepted one has at least
 * one key, every value finite, times not decreasing, fovy in (0, 180) and
 * 0 < near < far; where no key value exceeds 1e150 in magnitude (so that
 * no difference of two overflows), every sampled camera is finite with its
 * pitch in [-89, 89]. (Larger values are accepted and may interpolate to
 * infinities; fovy, near and far may round to 0 between extreme keys; the
 * renderer refuses such a camera, "a camera matrix is not finite", which
 * the corpus's huge-eye-swing and near-rounds-to-zero reach.) */
#define _GNU_SOURCE
#include "view_core.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <unistd.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void broken(const char *what, const char *detail)
{
    fprintf(stderr, "fuzz_play: invariant broken: %s%s%s%s\n", what, detail ? " ('" : "",
            detail ? detail : "", detail ? "')" : "");
    abort();
}

/* A memory file holding the input; its name in path. 0 if none. */
static int memory_file(const uint8_t *data, size_t size, char *path, size_t path_size)
{
    static int fd = -1;
    if (fd < 0 && (fd = memfd_create("fuzz_play", MFD_CLOEXEC)) < 0) return 0;
    if (ftruncate(fd, 0) != 0) return 0;
    for (size_t at = 0; at < size;) {
        ssize_t n = pwrite(fd, data + at, size - at, (off_t)at);
        if (n <= 0) return 0;
        at += (size_t)n;
    }
    snprintf(path, path_size, "/proc/self/fd/%d", fd);
    return 1;
}

static void check_camera(const view_camera *c)
{
    for (int i = 0; i < 3; i++)
        if (!isfinite(c->eye[i]) || !isfinite(c->orbit_target[i]))
            broken("a sampled camera's position is not finite", NULL);
    if (!isfinite(c->yaw) || !(c->pitch >= -89.0 && c->pitch <= 89.0))
        broken("a sampled camera's yaw is not finite or its pitch is outside [-89, 89]", NULL);
    if (!isfinite(c->fovy) || !isfinite(c->znear) || !isfinite(c->zfar))
        broken("a sampled camera's fovy, near or far is not finite", NULL);
}

/* The times play_path samples for frames frames; moderate: check the cameras. */
static void sample(const view_path *p, long frames, int moderate)
{
    const double t0 = p->keys[0].t, t1 = p->keys[p->count - 1].t;
    for (long i = 0; i < frames; i++) {
        double t = frames > 1 ? t0 + (t1 - t0) * (double)i / (double)(frames - 1) : t0;
        view_camera cam;
        view_path_sample(p, t, &cam);
        if (moderate) check_camera(&cam);
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size > 65536) return 0;
    char path[64];
    if (!memory_file(data, size, path, sizeof path)) broken("no memory file", NULL);
    view_path p;
    memset(&p, 0x5a, sizeof p);
    char err[512];
    strcpy(err, "(unchanged)");
    if (!view_path_load(path, &p, err, sizeof err)) {
        if (p.keys || p.count) broken("a refused path left keys", NULL);
        const size_t n = strlen(path);
        if (strncmp(err, path, n) != 0 || err[n] != ':')
            broken("a refused path's message does not start with the file's name", err);
        if (strpbrk(err, "\r\n")) broken("a refused path's message is not one line", err);
        view_path_free(&p);
        return 0;
    }
    if (p.count < 1 || !p.keys || p.count > p.cap) broken("an accepted path has no keys", NULL);
    int moderate = 1;
    for (size_t i = 0; i < p.count; i++) {
        const view_key *k = &p.keys[i];
        const double v[] = {k->t,     k->eye[0], k->eye[1], k->eye[2], k->yaw,
                            k->pitch, k->fovy,   k->znear,  k->zfar};
        for (size_t j = 0; j < sizeof v / sizeof v[0]; j++)
            if (!isfinite(v[j]))
                broken("an accepted key has a value that is not finite", NULL);
            else if (fabs(v[j]) > 1e150)
                moderate = 0;
        if (i > 0 && k->t < p.keys[i - 1].t) broken("an accepted path's times decrease", NULL);
        if (!(k->fovy > 0.0 && k->fovy < 180.0) || !(k->znear > 0.0) || !(k->zfar > k->znear))
            broken("an accepted key's fovy, near or far are out of range", NULL);
    }
    sample(&p, (long)p.count, moderate);
    sample(&p, 7, moderate);
    view_path_free(&p);
    return 0;
}
