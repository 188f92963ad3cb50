/* Scene container: ownership, growth and defaults. */
#include "core/internal.h"
#include "geom/scene.h"

#include <math.h>
#include <string.h>

persp_material persp__material_default(void)
{
    persp_material m;
    memset(&m, 0, sizeof m);
    for (int i = 0; i < 3; i++) {
        m.ambient[i] = 0.2f;
        m.diffuse[i] = 0.8f;
        m.specular[i] = 0.0f;
    }
    m.shininess = 32.0f;
    m.texture = -1;
    m.specular_texture = -1;
    m.env = PERSP_TEXENV_REPLACE;
    return m;
}

persp_status persp__scene_new(persp_context *ctx, persp_scene **out)
{
    if (!ctx || !out) return PERSP_ERR_INVALID_ARGUMENT;
    persp_scene *s = persp__calloc(ctx, 1, sizeof *s);
    if (!s) return persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "scene: out of memory");
    s->ctx = ctx;
    s->camera.eye = (persp_vec3){0, 0, 0};
    s->camera.target = (persp_vec3){0, 0, -1};
    s->camera.up = (persp_vec3){0, 1, 0};
    s->camera.fovy_deg = 60.0f;
    s->camera.znear = 0.1f;
    s->camera.zfar = 100.0f;
    s->clear[3] = 255;
    for (int i = 0; i < 3; i++) s->ambient[i] = 0.1f;
    *out = s;
    return PERSP_OK;
}

void persp__mesh_free(persp_context *ctx, persp_mesh *mesh)
{
    if (!mesh) return;
    persp__free(ctx, mesh->vertices);
    persp__free(ctx, mesh->indices);
    persp__free(ctx, mesh->clusters);
    memset(mesh, 0, sizeof *mesh);
}

/* Room for one more entry of a scene's list of count entries. A list at its
 * limit is TOO_LARGE; a refused allocation below it is OUT_OF_MEMORY, with a
 * detail that says so. */
static persp_status grow_list(persp_scene *s, void **list, size_t *cap, size_t count, size_t max,
                              size_t elem, const char *what)
{
    if (count >= max) return persp__fail(s->ctx, PERSP_ERR_TOO_LARGE, "scene: too many %s", what);
    persp_status st = persp__grow(s->ctx, list, cap, count + 1, elem);
    if (st != PERSP_OK) return persp__fail(s->ctx, st, "scene: out of memory for its %s", what);
    return PERSP_OK;
}

persp_status persp__scene_add_mesh(persp_scene *s, persp_mesh *mesh, int *index)
{
    persp_status st = grow_list(s, (void **)&s->meshes, &s->mesh_cap, s->mesh_count,
                                PERSP_SCENE_MAX_OBJECTS, sizeof *s->meshes, "meshes");
    if (st != PERSP_OK) {
        persp__mesh_free(s->ctx, mesh);
        return st;
    }
    mesh->colored = 0;
    for (size_t i = 0; i < mesh->vertex_count && !mesh->colored; i++) {
        const float *c = mesh->vertices[i].color;
        mesh->colored = !(c[0] == 1.0f && c[1] == 1.0f && c[2] == 1.0f);
    }
    if (persp__mesh_build_clusters(s->ctx, mesh) != PERSP_OK) {
        persp__mesh_free(s->ctx, mesh);
        return persp__fail(s->ctx, PERSP_ERR_OUT_OF_MEMORY, "scene: out of memory for a mesh's clusters");
    }
    s->meshes[s->mesh_count] = *mesh;
    memset(mesh, 0, sizeof *mesh);
    if (index) *index = (int)s->mesh_count;
    s->mesh_count++;
    return PERSP_OK;
}

persp_status persp__scene_add_texture(persp_scene *s, persp_texture *tex, int *index)
{
    persp_status st = grow_list(s, (void **)&s->textures, &s->texture_cap, s->texture_count,
                                PERSP_SCENE_MAX_TEXTURES, sizeof *s->textures, "textures");
    if (st != PERSP_OK) {
        persp_texture_destroy(tex);
        return st;
    }
    s->textures[s->texture_count] = tex;
    if (index) *index = (int)s->texture_count;
    s->texture_count++;
    return PERSP_OK;
}

persp_status persp__scene_add_material(persp_scene *s, const persp_material *m, int *index)
{
    persp_status st = grow_list(s, (void **)&s->materials, &s->material_cap, s->material_count,
                                PERSP_SCENE_MAX_OBJECTS, sizeof *s->materials, "materials");
    if (st != PERSP_OK) return st;
    s->materials[s->material_count] = *m;
    if (index) *index = (int)s->material_count;
    s->material_count++;
    return PERSP_OK;
}

persp_status persp__scene_add_object(persp_scene *s, const persp_object *o)
{
    if (o->mesh < 0 || (size_t)o->mesh >= s->mesh_count || o->material < 0 ||
        (size_t)o->material >= s->material_count)
        return persp__fail(s->ctx, PERSP_ERR_INVALID_ARGUMENT, "scene: object refers to a missing mesh or material");
    persp_status st = grow_list(s, (void **)&s->objects, &s->object_cap, s->object_count,
                                PERSP_SCENE_MAX_OBJECTS, sizeof *s->objects, "objects");
    if (st != PERSP_OK) return st;
    s->objects[s->object_count++] = *o;
    return PERSP_OK;
}

void persp_scene_destroy(persp_scene *s)
{
    if (!s) return;
    persp_context *ctx = s->ctx;
    for (size_t i = 0; i < s->mesh_count; i++) persp__mesh_free(ctx, &s->meshes[i]);
    for (size_t i = 0; i < s->texture_count; i++) persp_texture_destroy(s->textures[i]);
    persp__free(ctx, s->meshes);
    persp__free(ctx, s->textures);
    persp__free(ctx, s->materials);
    persp__free(ctx, s->objects);
    persp__free(ctx, s);
}

persp_status persp_scene_set_texture(persp_scene *s, const persp_image *img)
{
    if (!s || !img || !img->pixels || img->width <= 0 || img->height <= 0)
        return PERSP_ERR_INVALID_ARGUMENT;
    /* A copy made opaque: the scene's surfaces are (persp__image_set_opaque). */
    persp_image copy;
    persp_status st = persp_image_alloc(s->ctx, img->width, img->height, &copy);
    if (st != PERSP_OK) return st;
    for (int y = 0; y < img->height; y++)
        memcpy(copy.pixels + (size_t)y * copy.stride, img->pixels + (size_t)y * img->stride,
               4 * (size_t)img->width);
    persp__image_set_opaque(&copy);
    persp_texture *tex = NULL;
    st = persp_texture_create(s->ctx, &copy, &tex);
    persp_image_free(s->ctx, &copy);
    if (st != PERSP_OK) return st;
    int index = -1;
    st = persp__scene_add_texture(s, tex, &index);
    if (st != PERSP_OK) return st;
    for (size_t i = 0; i < s->material_count; i++)
        if (s->materials[i].texture >= 0) s->materials[i].texture = index;
    return PERSP_OK;
}

void persp_scene_default_size(const persp_scene *s, int *width, int *height)
{
    if (width) *width = s ? s->width : 0;
    if (height) *height = s ? s->height : 0;
}

void persp_scene_get_info(const persp_scene *s, persp_scene_info *out)
{
    if (!out) return;
    memset(out, 0, sizeof *out);
    if (!s) return;
    out->objects = s->object_count;
    out->textures = s->texture_count;
    out->lights = s->light_count;
    out->method = s->method[0] ? s->method : "exact";
    out->shading = s->shading == PERSP_SHADING_DEFAULT ? PERSP_SHADING_NONE : s->shading;
    out->cull_backfaces = s->cull_backfaces != 0;
    memcpy(out->clear, s->clear, sizeof out->clear);
    memcpy(out->ambient, s->ambient, sizeof out->ambient);
    for (size_t i = 0; i < s->object_count; i++) {
        const persp_material *m = &s->materials[s->objects[i].material];
        if (persp__object_texture(s, &s->objects[i]) < 0) continue;
        persp_filter f = m->sampler.filter == PERSP_FILTER_DEFAULT ? PERSP_FILTER_BILINEAR : m->sampler.filter;
        if (out->filter_count == 0) {
            out->filter = f;
            out->max_aniso = m->sampler.max_aniso;
            out->filter_count = 1;
        } else if (f != out->filter || m->sampler.max_aniso != out->max_aniso) {
            out->filter_count = 2;
        }
    }
}

int persp__object_texture(const persp_scene *s, const persp_object *o)
{
    const persp_material *m = &s->materials[o->material];
    if (m->texture < 0 || (size_t)m->texture >= s->texture_count) return -1;
    return s->meshes[o->mesh].no_uv && o->texgen == PERSP_TEXGEN_UV ? -1 : m->texture;
}

size_t persp_scene_object_count(const persp_scene *s) { return s ? s->object_count : 0; }

persp_status persp_scene_get_object(const persp_scene *s, size_t index, persp_scene_object *out)
{
    if (!s || !out) return PERSP_ERR_INVALID_ARGUMENT;
    memset(out, 0, sizeof *out);
    if (index >= s->object_count) return PERSP_ERR_NOT_FOUND;
    const persp_object *o = &s->objects[index];
    const persp_mesh *mesh = &s->meshes[o->mesh];
    const persp_material *m = &s->materials[o->material];
    out->vertices = mesh->vertices;
    out->vertex_count = mesh->vertex_count;
    out->indices = mesh->indices;
    out->index_count = mesh->index_count;
    out->model = o->model;
    persp_scene_material *om = &out->material;
    memcpy(om->ambient, m->ambient, sizeof om->ambient);
    memcpy(om->diffuse, m->diffuse, sizeof om->diffuse);
    memcpy(om->specular, m->specular, sizeof om->specular);
    om->shininess = m->shininess;
    om->texture = persp__object_texture(s, o);
    om->specular_texture = om->texture >= 0 && m->specular_texture >= 0;
    om->env = m->env == PERSP_TEXENV_MODULATE ? PERSP_SCENE_TEXENV_MODULATE : PERSP_SCENE_TEXENV_REPLACE;
    om->sampler = m->sampler;
    memcpy(om->emission, m->emission, sizeof om->emission);
    om->unlit = m->unlit;
    return PERSP_OK;
}

persp_status persp_scene_object_texcoords(const persp_scene *s, size_t index, const persp_mat4 *view,
                                          float *uv_out)
{
    if (!s || !view || !uv_out) return PERSP_ERR_INVALID_ARGUMENT;
    if (index >= s->object_count) return PERSP_ERR_NOT_FOUND;
    const persp_object *o = &s->objects[index];
    const persp_mesh *mesh = &s->meshes[o->mesh];
    const persp_mat4 mv = persp_mat4_mul(*view, o->model);
    persp__texgen_apply(o, &mv, mesh->vertices, mesh->vertex_count, uv_out);
    return PERSP_OK;
}

size_t persp_scene_light_count(const persp_scene *s) { return s ? s->light_count : 0; }

persp_status persp_scene_get_light(const persp_scene *s, size_t index, persp_scene_light *out)
{
    if (!s || !out) return PERSP_ERR_INVALID_ARGUMENT;
    memset(out, 0, sizeof *out);
    if (index >= s->light_count) return PERSP_ERR_NOT_FOUND;
    const persp_light *l = &s->lights[index];
    out->directional = l->type == PERSP_LIGHT_DIRECTIONAL;
    memcpy(out->position, l->position, sizeof out->position);
    memcpy(out->color, l->color, sizeof out->color);
    memcpy(out->attenuation, l->attenuation, sizeof out->attenuation);
    return PERSP_OK;
}

const persp_texture *persp_scene_get_texture(const persp_scene *s, int index)
{
    return s && index >= 0 && (size_t)index < s->texture_count ? s->textures[index] : NULL;
}

/* The one definition of the camera persp_render uses. */
persp_status persp_scene_get_camera(const persp_scene *s, int width, int height, persp_mat4 *view,
                                    persp_mat4 *projection)
{
    if (!s || width < 1 || height < 1) return PERSP_ERR_INVALID_ARGUMENT;
    persp_mat4 p, v;
    if (s->camera.use_matrix) {
        p = s->camera.projection;
        v = s->camera.view;
    } else {
        const double aspect = (double)width / (double)height;
        double fovy = s->camera.fovy_deg;
        if (s->camera.fov_shorter_side && aspect < 1.0)
            fovy = atan(tan(fovy * (3.14159265358979323846 / 360.0)) / aspect) * (360.0 / 3.14159265358979323846);
        p = persp_perspective(fovy, aspect, s->camera.znear, s->camera.zfar);
        v = persp_look_at(s->camera.eye, s->camera.target, s->camera.up);
    }
    if (view) *view = v;
    if (projection) *projection = p;
    return PERSP_OK;
}

void persp__mesh_compute_normals(persp_mesh *m)
{
    for (size_t i = 0; i < m->vertex_count; i++)
        m->vertices[i].normal[0] = m->vertices[i].normal[1] = m->vertices[i].normal[2] = 0.0f;
    for (size_t t = 0; t + 2 < m->index_count; t += 3) {
        const uint32_t *ix = &m->indices[t];
        if (ix[0] >= m->vertex_count || ix[1] >= m->vertex_count || ix[2] >= m->vertex_count) continue;
        const float *p0 = m->vertices[ix[0]].pos, *p1 = m->vertices[ix[1]].pos, *p2 = m->vertices[ix[2]].pos;
        float e1[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]};
        float e2[3] = {p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2]};
        /* The cross product's length is twice the area: area weighting for free. */
        float n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                      e1[0] * e2[1] - e1[1] * e2[0]};
        for (int k = 0; k < 3; k++)
            for (int c = 0; c < 3; c++) m->vertices[ix[k]].normal[c] += n[c];
    }
    for (size_t i = 0; i < m->vertex_count; i++) {
        float *n = m->vertices[i].normal;
        float len = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (len > 0.0f) {
            n[0] /= len, n[1] /= len, n[2] /= len;
        } else {
            n[0] = 0.0f, n[1] = 0.0f, n[2] = 1.0f;
        }
    }
    m->has_normals = 0;
}
