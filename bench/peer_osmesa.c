/*
 * The `corridor` workload of docs/WORKLOADS.md rendered by Mesa through OSMesa,
 * with nothing but legacy OpenGL 1.x state so that llvmpipe and softpipe run
 * their ordinary fixed-function paths: glFrustum projection, identity
 * model-view, one 256×256 RGBA8 texture with GL_REPEAT and GL_REPLACE, depth
 * test GL_LESS against a cleared far plane, and the five quads split into the
 * triangles (c0, c1, c2), (c0, c2, c3) drawn from client vertex arrays.
 *
 * Mesa 22.3's OSMesa offers OSMesaCreateContextAttribs (compatibility
 * profile, GL 4.5 on llvmpipe, 3.3 on softpipe) and
 * GL_EXT_texture_filter_anisotropic on both drivers.
 */
#include "peer.h"

#include <GL/gl.h>
#include <GL/osmesa.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef GL_TEXTURE_MAX_ANISOTROPY_EXT
#define GL_TEXTURE_MAX_ANISOTROPY_EXT 0x84FE
#endif
#ifndef GL_MAX_TEXTURE_MAX_ANISOTROPY_EXT
#define GL_MAX_TEXTURE_MAX_ANISOTROPY_EXT 0x84FF
#endif

#if defined(__SANITIZE_ADDRESS__)
/* OSMesa keeps every framebuffer it creates on a process-wide list that it
 * never frees (Mesa 22.3, src/gallium/frontends/osmesa); LeakSanitizer would
 * report that as ours. This is LeakSanitizer's documented hook for default
 * suppressions, built only into sanitizer builds. */
const char *__lsan_default_suppressions(void);
const char *__lsan_default_suppressions(void) { return "leak:libOSMesa.so\n"; }
const char *__lsan_default_options(void);
const char *__lsan_default_options(void) { return "print_suppressions=0"; }
#endif

#define TEX_SIZE 256
#define TEX_LEVELS 9 /* 256 .. 1 */

struct bench_peer {
    OSMesaContext gl;
    int width, height;
    uint8_t *color;
    GLuint texture;
    float aniso;
    char renderer[128], version[128];
    /* 5 quads × 4 corners, interleaved (x, y, z, s, t); 5 × 2 triangles. */
    float vertices[20 * 5];
    GLuint indices[30];
};

/* docs/WORKLOADS.md corridor geometry, L = 64: per quad four corners (u, v | x, y, z). */
static const float corridor_quads[5][4][5] = {
    {{0, 0, -1, -1, 0}, {2, 0, 1, -1, 0}, {2, 64, 1, -1, -64}, {0, 64, -1, -1, -64}},
    {{0, 0, -1, 1, 0}, {0, 64, -1, 1, -64}, {2, 64, 1, 1, -64}, {2, 0, 1, 1, 0}},
    {{0, 0, -1, -1, 0}, {0, 64, -1, -1, -64}, {2, 64, -1, 1, -64}, {2, 0, -1, 1, 0}},
    {{0, 0, 1, -1, 0}, {2, 0, 1, 1, 0}, {2, 64, 1, 1, -64}, {0, 64, 1, -1, -64}},
    {{0, 0, -1, -1, -64}, {2, 0, 1, -1, -64}, {2, 2, 1, 1, -64}, {0, 2, -1, 1, -64}},
};

/* docs/WORKLOADS.md checker: texel (x, y), y = 0 the first row given to GL. */
static void checker_texel(int x, int y, uint8_t out[4])
{
    static const uint8_t a[4] = {230, 200, 40, 255}, b[4] = {30, 60, 160, 255},
                         white[4] = {255, 255, 255, 255};
    const uint8_t *c = (((x / 32) ^ (y / 32)) & 1) ? a : b;
    if (x % 32 == 0 || y % 32 == 0) c = white;
    memcpy(out, c, 4);
}

/* The next mip level by a 2×2 box filter, rounded to nearest: the reduction
 * the GL spec suggests for glGenerateMipmap (GL 4.5 §8.14.4) done in integer
 * arithmetic so it does not depend on how the driver builds its chain. */
static void box_reduce(const uint8_t *src, int src_size, uint8_t *dst)
{
    int n = src_size / 2;
    for (int y = 0; y < n; y++)
        for (int x = 0; x < n; x++)
            for (int c = 0; c < 4; c++) {
                const uint8_t *p = src + ((size_t)(2 * y) * (size_t)src_size + (size_t)(2 * x)) * 4 + c;
                size_t row = (size_t)src_size * 4;
                unsigned sum = (unsigned)p[0] + p[4] + p[row] + p[row + 4];
                dst[((size_t)y * (size_t)n + (size_t)x) * 4 + (size_t)c] = (uint8_t)((sum + 2) / 4);
            }
}

static int filter_uses_mips(persp_filter f)
{
    return f == PERSP_FILTER_NEAREST_MIP_NEAREST || f == PERSP_FILTER_BILINEAR_MIP_NEAREST ||
           f == PERSP_FILTER_NEAREST_MIP_LINEAR || f == PERSP_FILTER_TRILINEAR ||
           f == PERSP_FILTER_ANISO;
}

/* persp filter -> GL min / mag filter (GL 4.5 §8.14, Table 8.19). */
static int gl_filters(persp_filter f, GLint *min_filter, GLint *mag_filter)
{
    switch (f) {
    case PERSP_FILTER_NEAREST: *min_filter = GL_NEAREST, *mag_filter = GL_NEAREST; return 1;
    case PERSP_FILTER_BILINEAR: *min_filter = GL_LINEAR, *mag_filter = GL_LINEAR; return 1;
    case PERSP_FILTER_NEAREST_MIP_NEAREST:
        *min_filter = GL_NEAREST_MIPMAP_NEAREST, *mag_filter = GL_NEAREST;
        return 1;
    case PERSP_FILTER_BILINEAR_MIP_NEAREST:
        *min_filter = GL_LINEAR_MIPMAP_NEAREST, *mag_filter = GL_LINEAR;
        return 1;
    case PERSP_FILTER_NEAREST_MIP_LINEAR:
        *min_filter = GL_NEAREST_MIPMAP_LINEAR, *mag_filter = GL_NEAREST;
        return 1;
    case PERSP_FILTER_TRILINEAR:
    case PERSP_FILTER_ANISO:
        *min_filter = GL_LINEAR_MIPMAP_LINEAR, *mag_filter = GL_LINEAR;
        return 1;
    default: return 0;
    }
}

int bench_peer_supports(persp_filter filter)
{
    GLint min_filter, mag_filter;
    return gl_filters(filter, &min_filter, &mag_filter);
}

static int upload_texture(bench_peer *p, persp_filter filter, char *err, size_t err_size)
{
    uint8_t *level = malloc((size_t)TEX_SIZE * TEX_SIZE * 4);
    uint8_t *next = malloc((size_t)(TEX_SIZE / 2) * (TEX_SIZE / 2) * 4 + 4);
    if (!level || !next) {
        free(level), free(next);
        snprintf(err, err_size, "peer: out of memory for the texture");
        return 0;
    }
    for (int y = 0; y < TEX_SIZE; y++)
        for (int x = 0; x < TEX_SIZE; x++)
            checker_texel(x, y, level + ((size_t)y * TEX_SIZE + (size_t)x) * 4);
    glGenTextures(1, &p->texture);
    glBindTexture(GL_TEXTURE_2D, p->texture);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    int levels = filter_uses_mips(filter) ? TEX_LEVELS : 1;
    int size = TEX_SIZE;
    for (int l = 0; l < levels; l++) {
        glTexImage2D(GL_TEXTURE_2D, l, GL_RGBA8, size, size, 0, GL_RGBA, GL_UNSIGNED_BYTE, level);
        if (l + 1 < levels) {
            box_reduce(level, size, next);
            size /= 2;
            memcpy(level, next, (size_t)size * (size_t)size * 4);
        }
    }
    free(level);
    free(next);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_BASE_LEVEL, 0);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, levels - 1);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
    GLint min_filter = GL_NEAREST, mag_filter = GL_NEAREST;
    gl_filters(filter, &min_filter, &mag_filter);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, min_filter);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, mag_filter);
    glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_REPLACE);
    glEnable(GL_TEXTURE_2D);
    return 1;
}

static int set_aniso(bench_peer *p, int max_aniso, char *err, size_t err_size)
{
    const char *ext = (const char *)glGetString(GL_EXTENSIONS);
    if (!ext || !strstr(ext, "GL_EXT_texture_filter_anisotropic")) {
        snprintf(err, err_size, "peer: %s does not offer GL_EXT_texture_filter_anisotropic",
                 p->renderer);
        return 0;
    }
    GLfloat limit = 1.0f;
    glGetFloatv(GL_MAX_TEXTURE_MAX_ANISOTROPY_EXT, &limit);
    float want = (float)(max_aniso > 0 ? max_aniso : 16);
    p->aniso = want < limit ? want : limit;
    glTexParameterf(GL_TEXTURE_2D, GL_TEXTURE_MAX_ANISOTROPY_EXT, p->aniso);
    return 1;
}

bench_peer *bench_peer_create(const bench_peer_desc *desc, char *err, size_t err_size)
{
    GLint min_filter, mag_filter;
    if (!desc || desc->width < 1 || desc->height < 1) {
        snprintf(err, err_size, "peer: bad image size");
        return NULL;
    }
    if (!gl_filters(desc->filter, &min_filter, &mag_filter)) {
        snprintf(err, err_size, "peer: filter '%s' has no OpenGL counterpart",
                 persp_filter_name(desc->filter));
        return NULL;
    }
    bench_peer *p = calloc(1, sizeof *p);
    if (!p) {
        snprintf(err, err_size, "peer: out of memory");
        return NULL;
    }
    p->width = desc->width;
    p->height = desc->height;
    /* 24-bit depth: what a default GL visual gives; persp keeps float depth. */
    const int attribs[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 24,
                           OSMESA_PROFILE, OSMESA_COMPAT_PROFILE, 0};
    p->gl = OSMesaCreateContextAttribs(attribs, NULL);
    if (!p->gl) p->gl = OSMesaCreateContextExt(OSMESA_RGBA, 24, 0, 0, NULL);
    if (!p->gl) {
        snprintf(err, err_size, "peer: OSMesa could not create a context (GALLIUM_DRIVER=%s)",
                 getenv("GALLIUM_DRIVER") ? getenv("GALLIUM_DRIVER") : "");
        free(p);
        return NULL;
    }
    p->color = malloc((size_t)p->width * (size_t)p->height * 4);
    if (!p->color) {
        snprintf(err, err_size, "peer: out of memory for a %dx%d image", p->width, p->height);
        bench_peer_destroy(p);
        return NULL;
    }
    if (!OSMesaMakeCurrent(p->gl, p->color, GL_UNSIGNED_BYTE, p->width, p->height)) {
        snprintf(err, err_size, "peer: OSMesaMakeCurrent failed for %dx%d", p->width, p->height);
        bench_peer_destroy(p);
        return NULL;
    }
    const char *s = (const char *)glGetString(GL_RENDERER);
    snprintf(p->renderer, sizeof p->renderer, "%s", s ? s : "?");
    s = (const char *)glGetString(GL_VERSION);
    snprintf(p->version, sizeof p->version, "%s", s ? s : "?");

    if (!upload_texture(p, desc->filter, err, err_size) ||
        (desc->filter == PERSP_FILTER_ANISO && !set_aniso(p, desc->max_aniso, err, err_size))) {
        bench_peer_destroy(p);
        return NULL;
    }

    glViewport(0, 0, p->width, p->height);
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    /* docs/WORKLOADS.md: glFrustum(-t·a, t·a, -t, t, 0.1, 100), t = 0.1·tan 30°. */
    double t = 0.1 * tan(30.0 * 3.14159265358979323846 / 180.0);
    double a = (double)p->width / (double)p->height;
    glFrustum(-t * a, t * a, -t, t, 0.1, 100.0);
    glMatrixMode(GL_MODELVIEW);
    glLoadIdentity();
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glClearDepth(1.0);
    glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
    glDisable(GL_CULL_FACE);
    glDisable(GL_DITHER);
    glDisable(GL_BLEND);
    glDisable(GL_LIGHTING);

    for (int q = 0; q < 5; q++) {
        for (int c = 0; c < 4; c++) {
            float *v = p->vertices + (q * 4 + c) * 5;
            const float *src = corridor_quads[q][c];
            v[0] = src[2], v[1] = src[3], v[2] = src[4], v[3] = src[0], v[4] = src[1];
        }
        GLuint base = (GLuint)(q * 4);
        GLuint *ix = p->indices + q * 6;
        ix[0] = base, ix[1] = base + 1, ix[2] = base + 2;
        ix[3] = base, ix[4] = base + 2, ix[5] = base + 3;
    }
    glEnableClientState(GL_VERTEX_ARRAY);
    glEnableClientState(GL_TEXTURE_COORD_ARRAY);
    glVertexPointer(3, GL_FLOAT, 5 * (GLsizei)sizeof(float), p->vertices);
    glTexCoordPointer(2, GL_FLOAT, 5 * (GLsizei)sizeof(float), p->vertices + 3);

    GLenum e = glGetError();
    if (e != GL_NO_ERROR) {
        snprintf(err, err_size, "peer: OpenGL error 0x%04x while setting up", (unsigned)e);
        bench_peer_destroy(p);
        return NULL;
    }
    return p;
}

void bench_peer_render(bench_peer *p, int frames)
{
    for (int f = 0; f < frames; f++) {
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        glDrawElements(GL_TRIANGLES, 30, GL_UNSIGNED_INT, p->indices);
        /* Each frame complete before the next, as persp_render's are. */
        glFinish();
    }
}

const uint8_t *bench_peer_pixels(const bench_peer *p) { return p->color; }
const char *bench_peer_renderer(const bench_peer *p) { return p->renderer; }
const char *bench_peer_version(const bench_peer *p) { return p->version; }
float bench_peer_aniso(const bench_peer *p) { return p->aniso; }

void bench_peer_destroy(bench_peer *p)
{
    if (!p) return;
    if (p->gl) {
        if (p->texture) glDeleteTextures(1, &p->texture);
        /* Unbinding first lets OSMesa release the framebuffer it made for us. */
        OSMesaMakeCurrent(NULL, NULL, GL_UNSIGNED_BYTE, 0, 0);
        OSMesaDestroyContext(p->gl);
    }
    free(p->color);
    free(p);
}
