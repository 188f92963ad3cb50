/*
 * The OpenGL peer of `persp bench`: the `corridor` scene of docs/WORKLOADS.md drawn
 * with Mesa (llvmpipe or softpipe) through OSMesa, legacy fixed-function GL.
 *
 * Compiled into the persp CLI only when pkg-config finds osmesa
 * (PERSP_HAVE_OSMESA). Mesa picks its Gallium driver from GALLIUM_DRIVER and
 * llvmpipe its thread count from LP_NUM_THREADS when the first context is
 * created, once per process; the CLI therefore runs each peer configuration
 * in a child process with those variables set.
 */
#ifndef PERSP_BENCH_PEER_H
#define PERSP_BENCH_PEER_H

#include "persp.h"

#include <stddef.h>
#include <stdint.h>

typedef struct bench_peer bench_peer;

typedef struct bench_peer_desc {
    int width, height;
    persp_filter filter; /* nearest .. aniso; aniso-window and ewa have no GL form */
    int max_aniso;       /* for PERSP_FILTER_ANISO; 0: 16 */
} bench_peer_desc;

/* Whether the filter has an OpenGL counterpart (aniso-window and ewa do not). */
int bench_peer_supports(persp_filter filter);
/* Creates the OSMesa context, the texture and the vertex arrays. On failure
 * returns NULL and writes a message to err. */
bench_peer *bench_peer_create(const bench_peer_desc *desc, char *err, size_t err_size);
void bench_peer_destroy(bench_peer *peer);
/* Draws `frames` complete frames (clear + 10 triangles + glFinish each). */
void bench_peer_render(bench_peer *peer, int frames);
/* The last frame: width*height RGBA8, row 0 = bottom (OSMESA_Y_UP). */
const uint8_t *bench_peer_pixels(const bench_peer *peer);
/* GL_RENDERER and GL_VERSION of the context. */
const char *bench_peer_renderer(const bench_peer *peer);
const char *bench_peer_version(const bench_peer *peer);
/* Effective anisotropy applied (0 when the filter is not anisotropic). */
float bench_peer_aniso(const bench_peer *peer);

#endif
