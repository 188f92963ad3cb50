/* persp_render, persp_draw and the analysis capture: scene → frame. */
#include "core/internal.h"
#include "objspace/objspace.h"
#include "raster/frame.h"
#include "render/render.h"
#include "shade/shade.h"

#include <math.h>
#include <string.h>

void persp_framebuffer_clear(persp_framebuffer *fb, const uint8_t rgba[4], persp_depth_mode mode)
{
    if (!fb || !fb->color || !fb->depth || fb->width <= 0 || fb->height <= 0) return;
    size_t n = (size_t)fb->width * (size_t)fb->height;
    uint8_t c[4] = {0, 0, 0, 255};
    if (rgba) memcpy(c, rgba, 4);
    uint32_t packed;
    memcpy(&packed, c, 4);
    uint32_t *px = (uint32_t *)(void *)fb->color;
    for (size_t i = 0; i < n; i++) px[i] = packed;
    float d = mode == PERSP_DEPTH_INVW ? 0.0f : 1.0f;
    for (size_t i = 0; i < n; i++) fb->depth[i] = d;
}

static int mat4_finite(const persp_mat4 *m)
{
    for (int i = 0; i < 16; i++)
        if (!isfinite(m->m[i])) return 0;
    return 1;
}

static void eye_lights(const persp_scene *s, const persp_mat4 *view, persp_lighting *L)
{
    memset(L, 0, sizeof *L);
    memcpy(L->ambient, s->ambient, sizeof L->ambient);
    L->count = (int)s->light_count;
    for (size_t i = 0; i < s->light_count; i++) {
        const persp_light *in = &s->lights[i];
        persp_eye_light *o = &L->light[i];
        o->type = in->type;
        memcpy(o->color, in->color, sizeof o->color);
        memcpy(o->atten, in->attenuation, sizeof o->atten);
        persp_vec4 p = {in->position[0], in->position[1], in->position[2],
                        in->type == PERSP_LIGHT_POINT ? 1.0f : 0.0f};
        persp_vec4 e = persp_mat4_apply(*view, p);
        o->pos[0] = e.x, o->pos[1] = e.y, o->pos[2] = e.z;
        if (in->type == PERSP_LIGHT_DIRECTIONAL) {
            float len = sqrtf(e.x * e.x + e.y * e.y + e.z * e.z);
            if (len > 0.0f) o->pos[0] /= len, o->pos[1] /= len, o->pos[2] /= len;
        }
    }
}

/* The render settings against their ranges. The texture settings are the
 * sampler's, checked by the sampler's own rule (persp__sampler_desc_problem)
 * on the sampler they would give; a problem is named as persp_render_desc
 * names the field. */
persp_status persp__check_render_desc(persp_context *ctx, const persp_render_desc *dd)
{
    if ((unsigned)dd->pipeline > PERSP_PIPELINE_OBJECT)
        return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "render: persp_render_desc.pipeline is out of range");
    persp_sampler_desc probe;
    memset(&probe, 0, sizeof probe);
    probe.wrap_s = probe.wrap_t = dd->wrap;
    probe.filter = dd->filter;
    probe.max_aniso = dd->max_aniso;
    probe.lod_bias = dd->lod_bias;
    probe.lod_mode = dd->lod_mode;
    probe.lod_clamp = dd->lod_clamp;
    probe.min_lod = dd->min_lod;
    probe.max_lod = dd->max_lod;
    const char *sampler = persp__sampler_desc_problem(&probe);
    /* wrap_s and wrap_t are both the desc's wrap. */
    if (sampler && !strncmp(sampler, "wrap_", 5)) sampler = "wrap";
    const char *bad = sampler                                               ? sampler
                      : (unsigned)dd->shading >= PERSP_SHADING_COUNT        ? "shading"
                      : (unsigned)dd->cull_backfaces > PERSP_TOGGLE_OFF     ? "cull_backfaces"
                      : (unsigned)dd->count_ops > PERSP_TOGGLE_OFF          ? "count_ops"
                      : (unsigned)dd->sort_first > PERSP_TOGGLE_OFF         ? "sort_first"
                      : dd->depth_mode != PERSP_DEPTH_DEFAULT && dd->depth_mode != PERSP_DEPTH_Z &&
                              dd->depth_mode != PERSP_DEPTH_INVW
                          ? "depth_mode"
                          : NULL;
    if (bad)
        return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "render: persp_render_desc.%s is out of range", bad);
    if ((dd->view && !mat4_finite(dd->view)) || (dd->projection && !mat4_finite(dd->projection)))
        return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "render: a camera matrix is not finite");
    return PERSP_OK;
}

/* An object's sampler: its material's, with what the desc overrides. */
static persp_sampler_desc object_sampler(const persp_render_desc *dd, const persp_material *mat)
{
    persp_sampler_desc sd = mat->sampler;
    if (dd->filter != PERSP_FILTER_DEFAULT) sd.filter = dd->filter;
    if (dd->max_aniso != 0) sd.max_aniso = dd->max_aniso;
    if (dd->wrap != PERSP_WRAP_DEFAULT) sd.wrap_s = sd.wrap_t = dd->wrap;
    if (dd->lod_mode != PERSP_LOD_DEFAULT) sd.lod_mode = dd->lod_mode;
    /* Scene surfaces are opaque (textures are made so at load): the
     * border colour too, or clamp-to-border would draw see-through
     * pixels with the default border (0, 0, 0, 0). */
    sd.border[3] = 255;
    sd.lod_bias += dd->lod_bias;
    if (dd->lod_clamp != PERSP_TOGGLE_DEFAULT) {
        sd.lod_clamp = dd->lod_clamp;
        sd.min_lod = dd->min_lod;
        sd.max_lod = dd->max_lod;
    }
    return sd;
}

/* What one frame's objects share. */
typedef struct frame_setup {
    const persp_scene *scene;
    const persp_render_desc *dd;
    persp_method_sel method;
    persp_mat4 view, proj;
    int cull_backfaces;
    persp_draw_state ds; /* the lights; the rest is set per object */
} frame_setup;

/* Sets up object i's draw state and queues its mesh. */
static persp_status draw_object(persp_context *ctx, frame_setup *fs, size_t i, persp_frame *f)
{
    const persp_scene *scene = fs->scene;
    const persp_render_desc *dd = fs->dd;
    persp_draw_state *ds = &fs->ds;
    const persp_object *o = &scene->objects[i];
    const persp_material *mat = &scene->materials[o->material];
    persp_status st;
    ds->method = fs->method;
    ds->material = *mat;
    ds->shading = dd->shading != PERSP_SHADING_DEFAULT ? dd->shading : scene->shading;
    /* An unlit material is unlit under every shading mode: its colour is
     * the file's, whatever lights the rest of the scene. */
    if (mat->unlit) ds->shading = PERSP_SHADING_NONE;
    ds->depth_test = ds->depth_write = 1;
    const int tex = persp__object_texture(scene, o);
    ds->tex = tex >= 0 ? scene->textures[tex] : NULL;
    if (!ds->tex) ds->material.texture = ds->material.specular_texture = -1;
    if (ds->tex) {
        persp_sampler_desc sd = object_sampler(dd, mat);
        st = persp__sampler_init_isa(&ds->sampler, ds->tex, &sd, ctx->isa);
        if (st != PERSP_OK) {
            const char *bad_sampler = persp__sampler_desc_problem(&sd);
            return persp__fail(ctx, st, "render: sampler setting %s is out of range", bad_sampler ? bad_sampler : "?");
        }
    }
    ds->color_material = scene->meshes[o->mesh].colored;
    if ((st = persp__shade_resolve(ctx, ds)) != PERSP_OK) return st;
    uint32_t si;
    if ((st = persp__frame_add_state(f, ds, &si)) != PERSP_OK) return st;
    /* A mirrored object's front faces wind clockwise (PERSP_CULL_CCW). */
    const int cull = !fs->cull_backfaces                   ? PERSP_CULL_NONE
                     : persp_mat4_det3(o->model) < 0.0 ? PERSP_CULL_CCW
                                                       : PERSP_CULL_CW;
    /* Texture-coordinate generation ([CS300-TexMap] map shapes and the
     * sphere map, src/geom/texgen.c) per frame: the reflection map
     * follows the view. The coordinates persp_scene_object_texcoords
     * hands to other renderers. */
    const persp_mesh *mesh = &scene->meshes[o->mesh];
    float *uv = NULL;
    if (o->texgen != PERSP_TEXGEN_UV) {
        if (!(uv = persp__frame_uv_buffer(f, mesh->vertex_count)))
            return persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "render: out of memory");
        (void)persp_scene_object_texcoords(scene, i, &fs->view, uv);
    }
    return persp__frame_add_mesh(f, mesh, &o->model, &fs->view, &fs->proj, si, uv, cull);
}

persp_status persp__render_frame(persp_context *ctx, const persp_scene *scene, const persp_render_desc *desc,
                                 persp_framebuffer *fb, persp_frame *f, persp_capture *cap, int regions,
                                 int tile0, int tile1)
{
    persp_render_desc dd;
    memset(&dd, 0, sizeof dd);
    if (desc) dd = *desc;
    persp_status st = persp__check_render_desc(ctx, &dd);
    if (st != PERSP_OK) return st;
    frame_setup fs;
    memset(&fs, 0, sizeof fs);
    fs.scene = scene;
    fs.dd = &dd;
    st = persp__method_resolve(ctx, dd.method ? dd.method : scene->method[0] ? scene->method : "exact", &fs.method);
    if (st != PERSP_OK) return st;
    if (dd.depth_mode == PERSP_DEPTH_DEFAULT) dd.depth_mode = PERSP_DEPTH_Z;

    st = persp__frame_begin(ctx, fb, dd.depth_mode, f);
    if (st != PERSP_OK) return st;
    f->capture = cap;
    f->count_ops = dd.count_ops == PERSP_TOGGLE_ON;
    f->regions = regions;
    f->tile0 = tile0;
    f->tile1 = tile1;
    if (regions) f->run = persp__tile_run((fb->width + PERSP_TILE - 1) / PERSP_TILE, tile0, tile1);
    persp__frame_clear(f, scene->clear);

    persp_scene_get_camera(scene, fb->width, fb->height, &fs.view, &fs.proj);
    if (dd.view) fs.view = *dd.view;
    if (dd.projection) fs.proj = *dd.projection;
    f->proj = fs.proj;
    eye_lights(scene, &fs.view, &fs.ds.lighting);
    fs.cull_backfaces = dd.cull_backfaces == PERSP_TOGGLE_ON ||
                        (dd.cull_backfaces == PERSP_TOGGLE_DEFAULT && scene->cull_backfaces);
    for (size_t i = 0; i < scene->object_count; i++)
        if ((st = draw_object(ctx, &fs, i, f)) != PERSP_OK) return st;
    return persp__frame_flush(f);
}

persp_status persp_render(persp_context *ctx, const persp_scene *scene, const persp_render_desc *desc,
                          persp_framebuffer *fb, persp_render_stats *stats)
{
    if (!ctx) return PERSP_ERR_INVALID_ARGUMENT;
    persp__clear_error(ctx);
    if (!scene || !fb) return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "render: no scene or framebuffer");
    persp_frame f;
    if (desc && desc->pipeline == PERSP_PIPELINE_OBJECT) {
        /* [Romaniuk-ObjSpace]: the screen pipeline decides visibility (which triangle
         * owns each pixel), then texels walked in object space re-colour it. */
        persp_capture cap;
        memset(&cap, 0, sizeof cap);
        size_t n = (size_t)fb->width * (size_t)fb->height;
        cap.width = fb->width;
        cap.height = fb->height;
        cap.tri = persp__calloc(ctx, n, sizeof *cap.tri);
        cap.s1 = persp__calloc(ctx, n, sizeof *cap.s1);
        cap.s2 = persp__calloc(ctx, n, sizeof *cap.s2);
        persp_status st = PERSP_ERR_OUT_OF_MEMORY;
        if (cap.tri && cap.s1 && cap.s2) {
            for (size_t i = 0; i < n; i++) cap.tri[i] = -1;
            st = persp__render_frame(ctx, scene, desc, fb, &f, &cap, 0, 0, 0);
            persp_objspace_stats os;
            if (st == PERSP_OK) st = persp__objspace_resolve(&f, &cap, &os);
            if (st == PERSP_OK && stats) {
                *stats = f.stats;
                stats->objspace_samples = os.texels_walked;
                stats->objspace_splats = os.splats;
                stats->objspace_pieces = os.pieces;
                stats->objspace_holes = os.holes;
                stats->objspace_visited = os.visited;
            }
        } else {
            persp__fail(ctx, st, "render: out of memory for the object-space pipeline");
        }
        persp__capture_free(ctx, &cap);
        return st;
    }
    persp_status st;
    if (persp__render_sort_first(ctx, scene, desc, fb, stats, &st)) return st;
    st = persp__render_frame(ctx, scene, desc, fb, &f, NULL, 0, 0, 0);
    if (st == PERSP_OK && stats) *stats = f.stats;
    return st;
}

void persp__capture_free(persp_context *ctx, persp_capture *cap)
{
    if (!cap) return;
    persp__free(ctx, cap->tri);
    persp__free(ctx, cap->s1);
    persp__free(ctx, cap->s2);
    persp__free(ctx, cap->rats);
    persp__free(ctx, cap->rat_vertices);
    memset(cap, 0, sizeof *cap);
}

persp_status persp__render_capture(persp_context *ctx, const persp_scene *scene,
                                   const persp_render_desc *desc, int width, int height,
                                   persp_capture *cap)
{
    if (!ctx || !scene || !cap || width <= 0 || height <= 0 || width > PERSP_IMAGE_MAX_SIDE ||
        height > PERSP_IMAGE_MAX_SIDE)
        return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "capture: bad arguments");
    memset(cap, 0, sizeof *cap);
    size_t n = (size_t)width * (size_t)height;
    cap->width = width;
    cap->height = height;
    cap->tri = persp__calloc(ctx, n, sizeof *cap->tri);
    cap->s1 = persp__calloc(ctx, n, sizeof *cap->s1);
    cap->s2 = persp__calloc(ctx, n, sizeof *cap->s2);
    persp_framebuffer fb = {width, height, persp__calloc(ctx, n, 4), persp__calloc(ctx, n, sizeof(float))};
    persp_status st = PERSP_OK;
    if (!cap->tri || !cap->s1 || !cap->s2 || !fb.color || !fb.depth) {
        st = persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "capture: out of memory");
    } else {
        for (size_t i = 0; i < n; i++) cap->tri[i] = -1;
        persp_frame f;
        st = persp__render_frame(ctx, scene, desc, &fb, &f, cap, 0, 0, 0);
        if (st == PERSP_OK) cap->ops = f.stats.ops;
        if (st == PERSP_OK && f.tri_count) {
            cap->rats = persp__calloc(ctx, f.tri_count, sizeof *cap->rats);
            cap->rat_vertices = persp__calloc(ctx, f.tri_count, sizeof *cap->rat_vertices);
            if (!cap->rats || !cap->rat_vertices) {
                st = persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "capture: out of memory");
            } else {
                const persp_tri *t = persp__frame_tris(&f);
                for (size_t i = 0; i < f.tri_count; i++) cap->rats[i] = t[i].rat;
                memcpy(cap->rat_vertices, persp__frame_fits(&f), f.tri_count * sizeof *cap->rat_vertices);
                cap->rat_count = f.tri_count;
            }
        }
    }
    persp__free(ctx, fb.color);
    persp__free(ctx, fb.depth);
    if (st != PERSP_OK) persp__capture_free(ctx, cap);
    return st;
}

persp_status persp_draw(persp_context *ctx, persp_framebuffer *fb, const persp_draw_desc *desc,
                        const persp_vertex *vertices, size_t vertex_count, const uint32_t *indices,
                        size_t index_count)
{
    if (!ctx) return PERSP_ERR_INVALID_ARGUMENT;
    persp__clear_error(ctx);
    if (!fb || !desc || (!vertices && vertex_count) || (!indices && index_count) || index_count % 3)
        return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT,
                                  "draw: need a framebuffer, a desc and 3 indices per triangle");
    if (vertex_count > PERSP_IMAGE_MAX_PIXELS || index_count > 3u * PERSP_IMAGE_MAX_PIXELS)
        return persp__fail(ctx, PERSP_ERR_TOO_LARGE, "draw: too many vertices or indices");
    if (index_count && !vertex_count)
        return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "draw: indices given, but no vertices");
    /* The settings as persp_render checks its own, each named. */
    const char *bad = (unsigned)desc->depth_mode > PERSP_DEPTH_INVW          ? "depth_mode"
                      : (unsigned)desc->depth_test > PERSP_TOGGLE_OFF        ? "depth_test"
                      : (unsigned)desc->cull_backfaces > PERSP_TOGGLE_OFF    ? "cull_backfaces"
                      : !mat4_finite(&desc->mvp)                             ? "mvp (not finite)"
                                                                             : NULL;
    if (bad) return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "draw: persp_draw_desc.%s is out of range", bad);
    /* The sampler only with a texture, which alone reads it. */
    const char *bad_sampler = desc->texture ? persp__sampler_desc_problem(&desc->sampler) : NULL;
    if (bad_sampler)
        return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "draw: persp_draw_desc.sampler.%s is out of range",
                           bad_sampler);
    persp_frame f;
    persp_depth_mode dm = desc->depth_mode == PERSP_DEPTH_DEFAULT ? PERSP_DEPTH_Z : desc->depth_mode;
    persp_status st = persp__frame_begin(ctx, fb, dm, &f);
    if (st != PERSP_OK) return st;
    persp_draw_state ds;
    memset(&ds, 0, sizeof ds);
    st = persp__method_resolve(ctx, desc->method ? desc->method : "exact", &ds.method);
    if (st != PERSP_OK) return st;
    ds.material = persp__material_default();
    ds.material.diffuse[0] = ds.material.diffuse[1] = ds.material.diffuse[2] = 1.0f;
    ds.tex = desc->texture;
    ds.force_opaque = 1;
    ds.depth_test = ds.depth_write = desc->depth_test != PERSP_TOGGLE_OFF;
    if (ds.tex) {
        st = persp__sampler_init_isa(&ds.sampler, ds.tex, &desc->sampler, ctx->isa);
        if (st != PERSP_OK) return persp__fail(ctx, st, "draw: bad sampler settings");
    }
    st = persp__shade_resolve(ctx, &ds);
    if (st != PERSP_OK) return st;
    uint32_t si;
    st = persp__frame_add_state(&f, &ds, &si);
    if (st != PERSP_OK) return st;
    persp_mesh mesh = {.vertices = (persp_vertex *)(uintptr_t)vertices,
                       .indices = (uint32_t *)(uintptr_t)indices,
                       .vertex_count = vertex_count,
                       .index_count = index_count,
                       .has_normals = 1};
    persp_mat4 id = persp_mat4_identity();
    st = persp__frame_add_mesh(&f, &mesh, &id, &id, &desc->mvp, si, NULL,
                               desc->cull_backfaces == PERSP_TOGGLE_ON ? PERSP_CULL_CW : PERSP_CULL_NONE);
    if (st != PERSP_OK) return st;
    return persp__frame_flush(&f);
}
