/*
 * Built-in scenes (docs/WORKLOADS.md). `corridor` is the fixed reference
 * workload (projection, texture and geometry exactly as specified there,
 * so images and timings compare with OpenGL renderers); `floor` and `cube`
 * are small companions for other kinds of perspective.
 */
#include "core/internal.h"
#include "geom/scene.h"

#include <string.h>

static const struct {
    const char *name, *summary;
} builtins[] = {
    {"corridor", "five textured quads of a 64-unit corridor (the reference benchmark)"},
    {"floor", "one large textured ground plane reaching to the horizon"},
    {"cube", "a textured cube seen at an angle"},
};

size_t persp_builtin_scene_count(void) { return sizeof builtins / sizeof builtins[0]; }

const char *persp_builtin_scene_name(size_t i)
{
    return i < persp_builtin_scene_count() ? builtins[i].name : NULL;
}

const char *persp_builtin_scene_summary(size_t i)
{
    return i < persp_builtin_scene_count() ? builtins[i].summary : NULL;
}

/* The corridor checker (docs/WORKLOADS.md): 32-texel cells, white grid lines on multiples of 32. */
static persp_status corridor_texture(persp_context *ctx, persp_image *img)
{
    persp_status st = persp_image_alloc(ctx, 256, 256, img);
    if (st != PERSP_OK) return st;
    for (int y = 0; y < 256; y++)
        for (int x = 0; x < 256; x++) {
            uint8_t *p = img->pixels + (size_t)y * img->stride + 4 * (size_t)x;
            static const uint8_t a[4] = {230, 200, 40, 255}, b[4] = {30, 60, 160, 255},
                                 w[4] = {255, 255, 255, 255};
            const uint8_t *c = (((x / 32) ^ (y / 32)) & 1) ? a : b;
            if (x % 32 == 0 || y % 32 == 0) c = w;
            memcpy(p, c, 4);
        }
    return PERSP_OK;
}

/* A texture whose distortion is easy to read: 8×8 cells with a colour
 * gradient across the image, dark cell borders and a small dot per cell. */
static persp_status grid_texture(persp_context *ctx, int size, persp_image *img)
{
    persp_status st = persp_image_alloc(ctx, size, size, img);
    if (st != PERSP_OK) return st;
    int cell = size / 8;
    for (int y = 0; y < size; y++)
        for (int x = 0; x < size; x++) {
            uint8_t *p = img->pixels + (size_t)y * img->stride + 4 * (size_t)x;
            int cx = x % cell, cy = y % cell;
            int r = 60 + 180 * x / size, g = 60 + 180 * y / size, b = ((x / cell + y / cell) & 1) ? 200 : 90;
            if (cx < cell / 16 + 1 || cy < cell / 16 + 1) r = g = b = 25;
            int dx = cx - cell / 2, dy = cy - cell / 2;
            if (dx * dx + dy * dy < (cell * cell) / 64) r = g = b = 245;
            p[0] = (uint8_t)r, p[1] = (uint8_t)g, p[2] = (uint8_t)b, p[3] = 255;
        }
    return PERSP_OK;
}

typedef struct quad {
    float uv[4][2];
    float pos[4][3];
} quad;

/* Quads become (c0, c1, c2) and (c0, c2, c3), as in docs/WORKLOADS.md. */
static persp_status quads_mesh(persp_context *ctx, const quad *q, size_t count, persp_mesh *m)
{
    memset(m, 0, sizeof *m);
    m->vertices = persp__calloc(ctx, 4 * count, sizeof *m->vertices);
    m->indices = persp__calloc(ctx, 6 * count, sizeof *m->indices);
    if (!m->vertices || !m->indices) {
        persp__mesh_free(ctx, m);
        return persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "scene: out of memory");
    }
    for (size_t i = 0; i < count; i++) {
        for (int k = 0; k < 4; k++) {
            persp_vertex *v = &m->vertices[4 * i + (size_t)k];
            memcpy(v->pos, q[i].pos[k], sizeof v->pos);
            memcpy(v->uv, q[i].uv[k], sizeof v->uv);
            v->color[0] = v->color[1] = v->color[2] = v->color[3] = 1.0f;
        }
        static const uint32_t fan[6] = {0, 1, 2, 0, 2, 3};
        for (int k = 0; k < 6; k++) m->indices[6 * i + (size_t)k] = (uint32_t)(4 * i) + fan[k];
    }
    m->vertex_count = 4 * count;
    m->index_count = 6 * count;
    persp__mesh_compute_normals(m);
    return PERSP_OK;
}

static persp_status textured_object(persp_scene *s, const quad *q, size_t count, persp_image *img,
                                    persp_filter filter, persp_mat4 model)
{
    persp_context *ctx = s->ctx;
    persp_texture *tex = NULL;
    persp_status st = persp_texture_create(ctx, img, &tex);
    persp_image_free(ctx, img);
    if (st != PERSP_OK) return st;
    int ti, mi, me;
    if ((st = persp__scene_add_texture(s, tex, &ti)) != PERSP_OK) return st;
    persp_material mat = persp__material_default();
    mat.texture = ti;
    mat.sampler.wrap_s = mat.sampler.wrap_t = PERSP_WRAP_REPEAT;
    mat.sampler.filter = filter;
    if ((st = persp__scene_add_material(s, &mat, &mi)) != PERSP_OK) return st;
    persp_mesh mesh;
    if ((st = quads_mesh(ctx, q, count, &mesh)) != PERSP_OK) return st;
    if ((st = persp__scene_add_mesh(s, &mesh, &me)) != PERSP_OK) return st;
    persp_object o;
    memset(&o, 0, sizeof o);
    o.mesh = me;
    o.material = mi;
    o.model = model;
    return persp__scene_add_object(s, &o);
}

static persp_status build_corridor(persp_scene *s)
{
    const float L = 64.0f;
    const quad q[5] = {
        {{{0, 0}, {2, 0}, {2, L}, {0, L}}, {{-1, -1, 0}, {1, -1, 0}, {1, -1, -L}, {-1, -1, -L}}},
        {{{0, 0}, {0, L}, {2, L}, {2, 0}}, {{-1, 1, 0}, {-1, 1, -L}, {1, 1, -L}, {1, 1, 0}}},
        {{{0, 0}, {0, L}, {2, L}, {2, 0}}, {{-1, -1, 0}, {-1, -1, -L}, {-1, 1, -L}, {-1, 1, 0}}},
        {{{0, 0}, {2, 0}, {2, L}, {0, L}}, {{1, -1, 0}, {1, 1, 0}, {1, 1, -L}, {1, -1, -L}}},
        {{{0, 0}, {2, 0}, {2, 2}, {0, 2}}, {{-1, -1, -L}, {1, -1, -L}, {1, 1, -L}, {-1, 1, -L}}},
    };
    /* glFrustum(-t·a, t·a, -t, t, 0.1, 100), t = 0.1·tan 30°: exactly
     * gluPerspective(60, a, 0.1, 100) with an identity model-view. */
    s->camera.fovy_deg = 60.0f;
    s->camera.znear = 0.1f;
    s->camera.zfar = 100.0f;
    s->width = 1024;
    s->height = 768;
    persp_image img;
    persp_status st = corridor_texture(s->ctx, &img);
    if (st != PERSP_OK) return st;
    return textured_object(s, q, 5, &img, PERSP_FILTER_BILINEAR, persp_mat4_identity());
}

static persp_status build_floor(persp_scene *s)
{
    const float E = 1000.0f, R = 250.0f; /* half extent; texture repeats */
    const quad q[1] = {
        {{{-R, -R}, {R, -R}, {R, R}, {-R, R}}, {{-E, 0, E}, {E, 0, E}, {E, 0, -E}, {-E, 0, -E}}},
    };
    s->camera.eye = (persp_vec3){0.0f, 1.5f, 0.0f};
    s->camera.target = (persp_vec3){0.0f, 1.0f, -6.0f};
    s->camera.zfar = 2000.0f;
    s->width = 1024;
    s->height = 768;
    s->clear[0] = 150, s->clear[1] = 190, s->clear[2] = 235;
    persp_image img;
    persp_status st = grid_texture(s->ctx, 256, &img);
    if (st != PERSP_OK) return st;
    return textured_object(s, q, 1, &img, PERSP_FILTER_BILINEAR, persp_mat4_identity());
}

static persp_status build_cube(persp_scene *s)
{
    /* Unit cube, counter-clockwise faces seen from outside, each face the
     * whole texture. */
    const quad q[6] = {
        {{{0, 0}, {1, 0}, {1, 1}, {0, 1}}, {{-1, -1, 1}, {1, -1, 1}, {1, 1, 1}, {-1, 1, 1}}},
        {{{0, 0}, {1, 0}, {1, 1}, {0, 1}}, {{1, -1, -1}, {-1, -1, -1}, {-1, 1, -1}, {1, 1, -1}}},
        {{{0, 0}, {1, 0}, {1, 1}, {0, 1}}, {{1, -1, 1}, {1, -1, -1}, {1, 1, -1}, {1, 1, 1}}},
        {{{0, 0}, {1, 0}, {1, 1}, {0, 1}}, {{-1, -1, -1}, {-1, -1, 1}, {-1, 1, 1}, {-1, 1, -1}}},
        {{{0, 0}, {1, 0}, {1, 1}, {0, 1}}, {{-1, 1, 1}, {1, 1, 1}, {1, 1, -1}, {-1, 1, -1}}},
        {{{0, 0}, {1, 0}, {1, 1}, {0, 1}}, {{-1, -1, -1}, {1, -1, -1}, {1, -1, 1}, {-1, -1, 1}}},
    };
    s->camera.eye = (persp_vec3){2.6f, 2.0f, 3.4f};
    s->camera.target = (persp_vec3){0.0f, 0.0f, 0.0f};
    s->camera.fovy_deg = 45.0f;
    s->width = 800;
    s->height = 600;
    s->cull_backfaces = 1;
    s->clear[0] = 40, s->clear[1] = 40, s->clear[2] = 48;
    persp_image img;
    persp_status st = grid_texture(s->ctx, 256, &img);
    if (st != PERSP_OK) return st;
    return textured_object(s, q, 6, &img, PERSP_FILTER_BILINEAR, persp_mat4_rotate(20.0f, 0, 1, 0));
}

persp_status persp_scene_builtin(persp_context *ctx, const char *name, persp_scene **out)
{
    if (!ctx || !name || !out) return PERSP_ERR_INVALID_ARGUMENT;
    persp__clear_error(ctx);
    *out = NULL;
    persp_status (*build)(persp_scene *) = NULL;
    if (!strcmp(name, "corridor")) build = build_corridor;
    else if (!strcmp(name, "floor")) build = build_floor;
    else if (!strcmp(name, "cube")) build = build_cube;
    else return persp__fail(ctx, PERSP_ERR_NOT_FOUND, "unknown built-in scene '%s' (corridor, floor, cube)", name);
    persp_scene *s;
    persp_status st = persp__scene_new(ctx, &s);
    if (st != PERSP_OK) return st;
    st = build(s);
    if (st != PERSP_OK) {
        persp_scene_destroy(s);
        return st;
    }
    *out = s;
    return PERSP_OK;
}
