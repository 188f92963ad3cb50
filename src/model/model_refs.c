/*
 * What persp's OBJ reader (src/model/obj.c) and the Assimp importer
 * (src/model/model.c) share: the files a model names (found relative to its
 * folder, by its last part, in any case, inside the load root; glTF's names
 * as URIs), its textures, its materials' colours and its parts.
 */
#include "core/internal.h"
#include "model/model.h"
#include "io/text.h"

#include <ctype.h>
#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

int persp__model_has_ext(const char *name, const char *ext)
{
    const char *dot = strrchr(name, '.');
    const char *slash = strrchr(name, '/');
    if (!dot || (slash && slash > dot)) return 0;
    dot++;
    size_t n = strlen(ext);
    if (strlen(dot) != n) return 0;
    for (size_t i = 0; i < n; i++)
        if (tolower((unsigned char)dot[i]) != ext[i]) return 0;
    return 1;
}

/* Windows separators and "./" prefixes as real models have them. */
void persp__model_clean_rel(const char *in, char *out, size_t size)
{
    size_t n = 0;
    for (; *in && n + 1 < size; in++)
        out[n++] = *in == '\\' ? '/' : *in;
    out[n] = '\0';
    /* Blender writes paths relative to the .blend file as "//name": they
     * are relative to the model's folder here (the folder rule stays). */
    if (out[0] == '/' && out[1] == '/') memmove(out, out + 2, strlen(out + 2) + 1);
    while (out[0] == '.' && out[1] == '/')
        memmove(out, out + 2, strlen(out + 2) + 1);
}

int persp__uri_decode(const char *in, char *out, size_t size)
{
    size_t n = 0;
    int changed = 0;
    for (const char *p = in; *p; p++) {
        int c = (unsigned char)*p;
        if (c == '%' && isxdigit((unsigned char)p[1]) && isxdigit((unsigned char)p[2])) {
            const char hex[3] = {p[1], p[2], '\0'};
            c = (int)strtol(hex, NULL, 16);
            if (c == 0) return 0;
            p += 2, changed = 1;
        }
        if (n + 1 >= size) return 0;
        out[n++] = (char)c;
    }
    out[n] = '\0';
    return changed;
}

/* Models made on systems blind to case name their files in a case the
 * files do not carry (3DS's 8.3 names in capitals, for one): when the exact
 * name is missing, its folder is searched for the name in any case. The
 * path is rewritten to the file found; 0 when there is none other. */
static int any_case(char *path, size_t size)
{
    char *slash = strrchr(path, '/');
    const char *name = slash ? slash + 1 : path;
    char folder[PERSP_PATH_MAX];
    int n = slash ? snprintf(folder, sizeof folder, "%.*s/", (int)(slash - path), path)
                  : snprintf(folder, sizeof folder, "./");
    if (!name[0] || n < 0 || (size_t)n >= sizeof folder) return 0;
    DIR *d = opendir(folder);
    if (!d) return 0;
    int found = 0;
    for (struct dirent *e; !found && (e = readdir(d)) != NULL;) {
        if (strcasecmp(e->d_name, name) != 0 || !strcmp(e->d_name, name)) continue;
        size_t at = (size_t)(name - path), len = strlen(e->d_name);
        if (at + len < size) {
            memcpy(path + at, e->d_name, len + 1);
            found = 1;
        }
    }
    closedir(d);
    return found;
}

/* Where a file the model names may be, in the order tried: the name
 * relative to the model's folder; its last part next to the model (files
 * named by an absolute path from another machine usually sit there); then
 * both in any case. 0 when candidate k does not apply. */
static int candidate(const char *base_dir, const char *rel, int k, char *path, size_t size)
{
    const char *base = persp__path_base(rel);
    if ((k & 1) && base == rel) return 0;
    if (!persp__path_join(base_dir, (k & 1) ? base : rel, path, size)) return 0;
    return k < 2 || any_case(path, size);
}

/* The first of the candidate paths of rel that exists inside root. 1 when
 * found; otherwise 0, with *outside set when one existed but lay outside. */
static int find_candidate(const char *base_dir, const char *root, const char *rel, int k,
                          char *path, size_t size, int *outside)
{
    if (!candidate(base_dir, rel, k, path, size)) return 0;
    int in = persp__path_inside(root, path);
    if (in == 0) *outside = 1;
    return in != 0;
}

persp_status persp__model_read_ref(persp_context *ctx, const char *base_dir, const char *root,
                                   const char *rel, char **data, size_t *size, const char **why)
{
    char path[PERSP_PATH_MAX];
    persp_status st = PERSP_ERR_IO;
    int outside = 0;
    *data = NULL;
    *size = 0;
    const char *special = NULL;
    for (int k = 0; k < 4 && st != PERSP_OK && st != PERSP_ERR_OUT_OF_MEMORY; k++)
        if (find_candidate(base_dir, root, rel, k, path, sizeof path, &outside)) {
            st = persp__read_file_inside(ctx, root, path, data, size);
            if (st != PERSP_OK && !special) special = persp__not_regular_why(path);
        }
    if (st != PERSP_OK)
        *why = special ? special
               : outside ? "outside the folder the model may read from"
                         : "no such file or unreadable";
    return st;
}

void persp__model_set_colours(persp_material *m, const float *kd, const float *ks,
                              const float *ka, float shininess)
{
    if (kd && persp__model_finite3(kd[0], kd[1], kd[2]))
        m->diffuse[0] = kd[0], m->diffuse[1] = kd[1], m->diffuse[2] = kd[2];
    if (ks && persp__model_finite3(ks[0], ks[1], ks[2]))
        m->specular[0] = ks[0], m->specular[1] = ks[1], m->specular[2] = ks[2];
    /* Black ambient is what most exporters write when they mean none;
     * persp's default keeps unlit sides from going black. */
    if (ka && persp__model_finite3(ka[0], ka[1], ka[2]) && (ka[0] > 0 || ka[1] > 0 || ka[2] > 0))
        m->ambient[0] = ka[0], m->ambient[1] = ka[1], m->ambient[2] = ka[2];
    if (isfinite(shininess) && shininess > 0) m->shininess = fminf(shininess, 1000.0f);
    for (int k = 0; k < 3; k++) {
        m->diffuse[k] = fminf(fmaxf(m->diffuse[k], 0.0f), 1000.0f);
        m->specular[k] = fminf(fmaxf(m->specular[k], 0.0f), 1000.0f);
        m->ambient[k] = fminf(fmaxf(m->ambient[k], 0.0f), 1000.0f);
    }
}

int persp__model_set_emission(persp_material *m, const float *ke)
{
    for (int k = 0; k < 3; k++)
        m->emission[k] = ke && isfinite(ke[k]) ? fminf(fmaxf(ke[k], 0.0f), 1.0f) : 0.0f;
    return m->emission[0] > 0.0f || m->emission[1] > 0.0f || m->emission[2] > 0.0f;
}

void persp__model_set_glow_map(persp_context *ctx, const char *display, const char *material, persp_material *m,
                               int glow, persp_wrap wrap_s, persp_wrap wrap_t)
{
    if (glow < 0 || glow == m->texture) return;
    if (m->texture < 0) {
        m->texture = glow;
        m->env = PERSP_TEXENV_MODULATE;
        m->sampler.wrap_s = wrap_s;
        m->sampler.wrap_t = wrap_t;
        return;
    }
    char q[PERSP_QUOTE_BYTES];
    persp__warn(ctx,
                "%s: material '%s': its emissive map is not its base colour texture; the glow is drawn "
                "through the base colour texture instead",
                display, persp__quote(material, strlen(material), q, sizeof q));
}

/* Prefixes the context's detail of a texture refused for want of memory
 * (what was refused, the budget) with the model, texture and material. */
void persp__model_texture_oom(persp_context *ctx, const char *display, const char *texture,
                              const char *material)
{
    char detail[PERSP_ERRMSG_BYTES];
    snprintf(detail, sizeof detail, "%s", persp_context_error(ctx));
    persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "%s: texture '%s' of material '%s': %s", display, texture,
                material, detail);
}

/* The scene texture for a texture file a material names, or -1 with a
 * warning: the candidates of persp__model_read_ref, each inside the load
 * root, decoded once per load (the cache). */
static int texture_file(persp_model_refs *r, const char *material, const char *file, const char *shown);

int persp__model_texture_file(persp_model_refs *r, const char *material, const char *file)
{
    /* A URI's decoded name first (glTF), the name as written after it. */
    char decoded[PERSP_PATH_MAX];
    if (r->uri && persp__uri_decode(file, decoded, sizeof decoded)) {
        persp_model_refs quiet = *r;
        quiet.quiet = 1;
        int index = texture_file(&quiet, material, decoded, file);
        if (quiet.out_of_memory) r->out_of_memory = 1;
        if (index >= 0 || quiet.out_of_memory) return index;
        int raw = texture_file(&quiet, material, file, file);
        if (quiet.out_of_memory) r->out_of_memory = 1;
        if (raw >= 0 || quiet.out_of_memory) return raw;
        return texture_file(r, material, decoded, file);
    }
    return texture_file(r, material, file, file);
}

/* Looking for a name in any case reads the whole folder: a model naming
 * 3000 missing or unusable textures beside 30 000 files took 17 s. A file
 * found but unusable (not an image, a texture over the scene's limit) is
 * not looked for again in any case, and after this many textures a load
 * did not find in any case, the rest are looked for as written only. */
#define TEXTURE_CASE_MISSES_MAX 64

/* persp__model_texture_file for one spelling of the name; shown: the name
 * as the model writes it, where the warning looks for its line. */
static int texture_file(persp_model_refs *r, const char *material, const char *file, const char *shown)
{
    int index = -1;
    char qm[PERSP_QUOTE_BYTES];
    persp__quote(material, strlen(material), qm, sizeof qm);
    char rel[PERSP_PATH_MAX], path[PERSP_PATH_MAX], shown_rel[PERSP_PATH_MAX];
    persp__model_clean_rel(file, rel, sizeof rel);
    persp__model_clean_rel(shown, shown_rel, sizeof shown_rel);
    char qr[PERSP_QUOTE_BYTES];
    persp__quote(rel, strlen(rel), qr, sizeof qr);
    if (!r->base_dir) {
        if (r->quiet) return -1;
        persp__warn(r->scene->ctx,
                    "%s: material '%s': texture '%s' not read (no folder to read it from)",
                    r->display, qm, qr);
        return -1;
    }
    persp_status st = PERSP_ERR_IO;
    char why[PERSP_ERRMSG_BYTES] = "";
    int outside = 0, decoded_fail = 0, found_bad = 0, scanned = 0;
    /* "C:/..." (after persp__model_clean_rel): an absolute path of the
     * machine the model was made on, which joined to the model's folder
     * names nothing; only its last part is looked for. */
    const int drive = isalpha((unsigned char)rel[0]) && rel[1] == ':' && rel[2] == '/';
    const char *base = persp__path_base(rel);
    for (int k = drive ? 1 : 0; k < 4 && st != PERSP_OK; k++) {
        if (k >= 2 && (found_bad || (r->cache && r->cache->case_misses >= TEXTURE_CASE_MISSES_MAX))) break;
        scanned |= k >= 2;
        /* A missing first candidate still reports why (the open's error). */
        if (k == 0 ? !candidate(r->base_dir, rel, k, path, sizeof path)
                   : !find_candidate(r->base_dir, r->root, rel, k, path, sizeof path, &outside))
            continue;
        if (k == 0 && persp__path_inside(r->root, path) == 0) {
            outside = 1;
            continue;
        }
        st = persp__texcache_load(r->scene, r->cache, path, &index);
        if (st == PERSP_ERR_OUT_OF_MEMORY) {
            /* The caller fails with this detail, which says what was
             * refused and the budget, prefixed with where. */
            r->out_of_memory = 1;
            persp__model_texture_oom(r->scene->ctx, r->display, qr, qm);
            return -1;
        }
        found_bad |= st != PERSP_OK && st != PERSP_ERR_IO;
        if (st != PERSP_OK && k == 0) {
            snprintf(why, sizeof why, "%s", persp_context_error(r->scene->ctx));
            /* There but not readable as an image: that is the reason, not
             * a missing file looked for elsewhere. */
            decoded_fail = st != PERSP_ERR_IO;
        }
    }
    if (st != PERSP_OK && scanned && r->cache) r->cache->case_misses++;
    if (st != PERSP_OK) {
        if (r->quiet) return -1;
        /* The texture's name usually sits in a material library, not in the
         * model's own text: the line is given only where it is found. */
        char at[PERSP_PATH_MAX + 32];
        if (r->where)
            r->where(r->where_user, shown_rel, at, sizeof at);
        else
            snprintf(at, sizeof at, "%s", r->display);
        if (outside && !why[0])
            snprintf(why, sizeof why, "outside the folder the model may read from");
        char qb[PERSP_QUOTE_BYTES];
        persp__quote(base, strlen(base), qb, sizeof qb);
        if (drive && !why[0])
            snprintf(why, sizeof why, "a Windows path; no '%s' beside the model either", qb);
        else if (base != rel && !outside && !decoded_fail && strlen(why) + strlen(qb) + 40 < sizeof why)
            snprintf(why + strlen(why), sizeof why - strlen(why), "; no '%s' beside the model either", qb);
        persp__warn(r->scene->ctx,
                    "%s: material '%s': cannot load texture '%s' (%s); drawing it untextured",
                    at, qm, qr, why[0] ? why : "bad path");
        return -1;
    }
    return index;
}

persp_status persp__model_add_part(persp_scene *scene, persp_model *o, size_t *cap, int mesh,
                                   int material, const char *material_name, const persp_mat4 *xf,
                                   const char *display)
{
    if (o->part_count >= PERSP_SCENE_MAX_OBJECTS)
        return persp__fail(scene->ctx, PERSP_ERR_TOO_LARGE, "%s: more than %d mesh instances",
                           display, PERSP_SCENE_MAX_OBJECTS);
    if (persp__grow(scene->ctx, (void **)&o->parts, cap, o->part_count + 1, sizeof *o->parts) !=
        PERSP_OK)
        return persp__fail(scene->ctx, PERSP_ERR_OUT_OF_MEMORY, "%s: out of memory", display);
    persp_model_part *p = &o->parts[o->part_count++];
    p->mesh = mesh;
    p->material = material;
    p->transform = *xf;
    const persp_mesh *pm = &scene->meshes[mesh];
    if (pm->no_uv && scene->materials[material].texture >= 0 && o->no_uv_parts++ == 0)
        snprintf(o->no_uv_material, sizeof o->no_uv_material, "%s", material_name ? material_name : "");
    for (size_t i = 0; i < pm->vertex_count; i++) {
        const float *q = pm->vertices[i].pos;
        persp_vec4 w = persp_mat4_apply(*xf, (persp_vec4){q[0], q[1], q[2], 1.0f});
        float x = w.x, y = w.y, z = w.z;
        if (w.w != 0.0f && w.w != 1.0f) x /= w.w, y /= w.w, z /= w.w;
        if (!persp__model_finite3(x, y, z)) continue;
        const float v[3] = {x, y, z};
        for (int k = 0; k < 3; k++) {
            if (v[k] < o->bbox_min[k]) o->bbox_min[k] = v[k];
            if (v[k] > o->bbox_max[k]) o->bbox_max[k] = v[k];
        }
    }
    return PERSP_OK;
}

void persp__model_warn_no_uv(const persp_scene *scene, const persp_model *model, const char *display,
                             int material, int texgen)
{
    if (texgen != PERSP_TEXGEN_UV) return;
    char q[PERSP_QUOTE_BYTES];
    if (material >= 0) {
        size_t bare = 0;
        for (size_t i = 0; i < model->part_count; i++) bare += scene->meshes[model->parts[i].mesh].no_uv != 0;
        if (bare && scene->materials[material].texture >= 0)
            persp__warn(scene->ctx,
                        "%s: %zu of its %zu meshes have no texture coordinates for the object's textured "
                        "material; drawing them untextured (a \"texgen\" would generate some)",
                        display, bare, model->part_count);
        return;
    }
    if (!model->no_uv_parts) return;
    persp__quote(model->no_uv_material, strlen(model->no_uv_material), q, sizeof q);
    if (model->no_uv_parts == 1)
        persp__warn(scene->ctx,
                    "%s: material '%s' has a texture, but the mesh it is on has no texture coordinates; "
                    "drawing it untextured",
                    display, q);
    else
        persp__warn(scene->ctx,
                    "%s: material '%s' and others have a texture, but %zu meshes they are on have no "
                    "texture coordinates; drawing those untextured",
                    display, q, model->no_uv_parts);
}

int persp__model_triangle_has_area(const float *a, const float *b, const float *c)
{
    double ux = (double)b[0] - a[0], uy = (double)b[1] - a[1], uz = (double)b[2] - a[2];
    double vx = (double)c[0] - a[0], vy = (double)c[1] - a[1], vz = (double)c[2] - a[2];
    double cx = uy * vz - uz * vy, cy = uz * vx - ux * vz, cz = ux * vy - uy * vx;
    double cross2 = cx * cx + cy * cy + cz * cz;
    double lens2 = (ux * ux + uy * uy + uz * uz) * (vx * vx + vy * vy + vz * vz);
    return cross2 > 1e-12 * lens2 && cross2 > 0.0;
}
