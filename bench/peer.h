/*
 * The OpenGL peer of `persp bench`: any persp scene (built-in or JSON) drawn
 * with Mesa (llvmpipe or softpipe) through OSMesa, from the scene's own
 * meshes, textures (every mip level persp built), camera, lights and
 * materials, read through persp.h's scene-contents API.
 *
 * Compiled into the persp CLI only when pkg-config finds osmesa
 * (PERSP_HAVE_OSMESA). Mesa picks its Gallium driver from GALLIUM_DRIVER and
 * llvmpipe its thread count from LP_NUM_THREADS when the first context is
 * created, once per process; the CLI therefore runs each peer configuration
 * in a child process with those variables set.
 *
 * GL state per shading mode (docs/PERFORMANCE.md, "The OpenGL peer"):
 * `none` is GL_REPLACE without lighting; `flat`, `gouraud` and `gouraud-pc`
 * are fixed-function lighting with GL_MODULATE; the per-pixel modes are a
 * GLSL Blinn–Phong fragment shader.
 */
#ifndef PERSP_BENCH_PEER_H
#define PERSP_BENCH_PEER_H

#include "persp.h"

#include <stddef.h>
#include <stdint.h>

typedef struct bench_peer bench_peer;

typedef struct bench_peer_desc {
    int width, height;
    const persp_scene *scene; /* read only during bench_peer_create */
    persp_shading shading;    /* DEFAULT: the scene's */
    persp_filter filter;      /* DEFAULT: each material's; nearest .. aniso (aniso-window
                                 and ewa have no GL form) */
    int max_aniso;            /* for PERSP_FILTER_ANISO; 0: 16 */
} bench_peer_desc;

/* Whether the filter has an OpenGL counterpart (aniso-window and ewa do not). */
int bench_peer_supports(persp_filter filter);
/* Creates the OSMesa context, the textures, the vertex and index buffers
 * and the shaders. On failure returns NULL and writes a message to err. */
bench_peer *bench_peer_create(const bench_peer_desc *desc, char *err, size_t err_size);
void bench_peer_destroy(bench_peer *peer);
/* Draws `frames` complete frames (clear + every object + glFinish each). */
void bench_peer_render(bench_peer *peer, int frames);
/* The last frame: width*height RGBA8, row 0 = bottom (OSMESA_Y_UP). */
const uint8_t *bench_peer_pixels(const bench_peer *peer);
/* GL_RENDERER and GL_VERSION of the context. */
const char *bench_peer_renderer(const bench_peer *peer);
const char *bench_peer_version(const bench_peer *peer);
/* Effective anisotropy applied (0 when no filter is anisotropic). */
float bench_peer_aniso(const bench_peer *peer);
/* How the peer draws the shading mode, for reports, e.g. "fixed-function
 * lighting, GL_MODULATE, GL_SEPARATE_SPECULAR_COLOR". Static string. */
const char *bench_peer_pipeline(const bench_peer *peer);

#endif
