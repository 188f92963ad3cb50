/* JSON scene files: every section's values, the transform order, errors
 * located by file:line:col and JSON path, files resolved relative to the
 * scene, and the example scenes of scenes/. */
#include "support.h"

#include "core/internal.h"
#include "geom/scene.h"
#include "model/model.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static persp_status load(persp_context *ctx, const char *text, persp_scene **out)
{
    return persp__scene_load_memory(ctx, text, strlen(text), "s.json", NULL, 0, out);
}

static const char *full_scene =
    "{\n"
    "  \"comment\": \"all sections\",\n"
    "  \"camera\": {\"position\": [1, 2, 3], \"target\": [0, 1, 0], \"up\": [0, 1, 0],\n"
    "             \"fov\": 45, \"near\": 0.5, \"far\": 80},\n"
    "  \"render\": {\"size\": [320, 200], \"method\": \"exact\", \"shading\": \"gouraud-pc\",\n"
    "             \"clear\": [1, 0.5, 0], \"cull\": true},\n"
    "  \"ambient\": [0.3, 0.2, 0.1],\n"
    "  \"lights\": [{\"type\": \"point\", \"position\": [0, 5, 0], \"color\": [1, 0.5, 0.25],\n"
    "              \"attenuation\": [1, 0.1, 0.01]},\n"
    "             {\"type\": \"directional\", \"direction\": [0, -3, -4]}],\n"
    "  \"materials\": {\"red\": {\"ambient\": [0.1, 0, 0], \"diffuse\": [1, 0, 0], \"specular\": [0.5, 0.5, 0.5],\n"
    "                          \"shininess\": 20, \"env\": \"modulate\"},\n"
    "                \"blue\": {\"diffuse\": [0, 0, 1]}},\n"
    "  \"objects\": [\n"
    "    {\"name\": \"a\", \"mesh\": \"sphere\", \"material\": \"red\",\n"
    "     \"transform\": {\"translate\": [1, 2, 3], \"rotate\": [[90, 0, 0, 1], [90, 0, 1, 0]], \"scale\": [2, 3, 4]}},\n"
    "    {\"mesh\": {\"primitive\": \"torus\", \"major\": 2, \"minor\": 0.5, \"slices\": 8, \"rings\": 4},\n"
    "     \"material\": \"blue\", \"texgen\": {\"mode\": \"planar\", \"s\": [1, 0, 0, 0.5], \"t\": [0, 1, 0, 0], \"scale\": 2}},\n"
    "    {\"mesh\": {\"primitive\": \"plane\", \"subdivisions\": 3},\n"
    "     \"texgen\": {\"mode\": \"cylindrical\", \"axis\": \"z\", \"center\": [1, 2, 3], \"scale\": [3, 4]}},\n"
    "    {\"mesh\": \"cube\", \"texgen\": \"reflection\"},\n"
    "    {\"mesh\": {\"primitive\": \"cylinder\", \"slices\": 5}, \"texgen\": \"spherical\"}\n"
    "  ]\n"
    "}\n";

static void apply(const persp_mat4 *m, const double p[3], double out[3])
{
    for (int r = 0; r < 3; r++)
        out[r] = m->m[r] * p[0] + m->m[4 + r] * p[1] + m->m[8 + r] * p[2] + m->m[12 + r];
}

static void test_full_scene(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    persp_scene *s = NULL;
    persp_status st = load(ctx, full_scene, &s);
    if (st != PERSP_OK) fail_msg("%s", persp_context_error(ctx));
    const persp_camera *c = &s->camera;
    assert_true(c->eye.x == 1.0f && c->eye.y == 2.0f && c->eye.z == 3.0f);
    assert_true(c->target.y == 1.0f && c->up.y == 1.0f);
    assert_true(c->fovy_deg == 45.0f && c->znear == 0.5f && c->zfar == 80.0f);
    assert_int_equal(s->width, 320);
    assert_int_equal(s->height, 200);
    assert_string_equal(s->method, "exact");
    assert_int_equal(s->shading, PERSP_SHADING_GOURAUD_PC);
    assert_int_equal(s->clear[0], 255);
    assert_int_equal(s->clear[1], 128);
    assert_int_equal(s->clear[2], 0);
    assert_int_equal(s->clear[3], 255);
    assert_int_equal(s->cull_backfaces, 1);
    assert_true(s->ambient[0] == 0.3f && s->ambient[2] == 0.1f);
    /* lights: the directional one is stored as the unit vector towards the light */
    assert_int_equal(s->light_count, 2);
    assert_int_equal(s->lights[0].type, PERSP_LIGHT_POINT);
    assert_true(s->lights[0].position[1] == 5.0f && s->lights[0].color[2] == 0.25f);
    assert_true(s->lights[0].attenuation[1] == 0.1f && s->lights[0].attenuation[2] == 0.01f);
    assert_int_equal(s->lights[1].type, PERSP_LIGHT_DIRECTIONAL);
    assert_true(fabs(s->lights[1].position[0]) < 1e-7 && fabs(s->lights[1].position[1] - 0.6) < 1e-6 &&
                fabs(s->lights[1].position[2] - 0.8) < 1e-6);
    assert_true(s->lights[1].color[0] == 1.0f && s->lights[1].attenuation[0] == 1.0f);
    /* five objects; the three without a material get a default one each */
    assert_int_equal(s->object_count, 5);
    assert_int_equal(s->mesh_count, 5);
    const persp_material *red = &s->materials[s->objects[0].material];
    assert_true(red->diffuse[0] == 1.0f && red->diffuse[1] == 0.0f && red->ambient[0] == 0.1f);
    assert_true(red->specular[1] == 0.5f && red->shininess == 20.0f && red->env == PERSP_TEXENV_MODULATE);
    assert_int_equal(red->texture, -1);
    assert_true(s->materials[s->objects[1].material].diffuse[2] == 1.0f);
    /* M = T · R2 · R1 · S: scale, rotate 90° about z, then 90° about y, translate */
    const double p[3] = {1, 1, 1};
    double got[3], sc[3] = {2, 3, 4};
    double r1[3] = {-sc[1], sc[0], sc[2]};     /* about z: (x, y) -> (-y, x) */
    double r2[3] = {r1[2], r1[1], -r1[0]};     /* about y: (x, z) -> (z, -x) */
    double want[3] = {r2[0] + 1, r2[1] + 2, r2[2] + 3};
    apply(&s->objects[0].model, p, got);
    for (int k = 0; k < 3; k++) assert_true(fabs(got[k] - want[k]) < 1e-5);
    /* sphere defaults 32 × 16 */
    assert_int_equal(s->meshes[s->objects[0].mesh].vertex_count, 33 * 17);
    assert_int_equal(s->meshes[s->objects[1].mesh].vertex_count, 9 * 5);
    assert_int_equal(s->objects[1].texgen, PERSP_TEXGEN_PLANAR);
    assert_true(s->objects[1].texgen_s[3] == 0.5f && s->objects[1].texgen_t[1] == 1.0f);
    assert_true(s->objects[1].texgen_scale[0] == 2.0f && s->objects[1].texgen_scale[1] == 2.0f);
    assert_int_equal(s->objects[2].texgen, PERSP_TEXGEN_CYLINDRICAL);
    assert_int_equal(s->objects[2].texgen_axis, 2);
    assert_true(s->objects[2].texgen_center[2] == 3.0f && s->objects[2].texgen_scale[1] == 4.0f);
    assert_int_equal(s->meshes[s->objects[2].mesh].index_count, 6 * 9);
    assert_int_equal(s->objects[3].texgen, PERSP_TEXGEN_REFLECTION);
    assert_int_equal(s->objects[4].texgen, PERSP_TEXGEN_SPHERICAL);
    assert_int_equal(s->objects[4].texgen_axis, 1);
    persp_scene_destroy(s);
    persp_context_destroy(ctx);
}

typedef struct bad_case {
    const char *text;
    persp_status status;
    const char *message;
} bad_case;

static void test_malformed(void **state)
{
    (void)state;
    static const bad_case cases[] = {
        {"{\n  \"camra\": {}\n}", PERSP_ERR_FORMAT, "s.json:2:3: camra: unknown key (expected one of: camera, render"},
        {"{\"objects\": [\n  {\"mesh\": \"cube\"},\n  {\"mesh\": \"cube\", \"transform\": {\"rotation\": [1, 0, 0, 1]}}]}",
         PERSP_ERR_FORMAT, "s.json:3:34: objects[1].transform.rotation: unknown key"},
        {"{\"camera\": {\"fov\": 200}, \"objects\": [{\"mesh\": \"cube\"}]}", PERSP_ERR_FORMAT,
         "s.json:1:20: camera.fov: expected a number in [0.001, 179]"},
        {"{\"camera\": {\"fov\": \"wide\"}}", PERSP_ERR_FORMAT, "s.json:1:20: camera.fov: expected a number"},
        {"{\"camera\": {\"position\": [0, 0, 0], \"target\": [0, 0, 0]}}", PERSP_ERR_FORMAT,
         "s.json:1:12: camera: camera target must differ from its position"},
        {"{\"camera\": {\"near\": 10, \"far\": 1}}", PERSP_ERR_FORMAT, "s.json:1:32: camera.far: expected far > near"},
        {"{\"camera\": {\"position\": [0, 1]}}", PERSP_ERR_FORMAT,
         "s.json:1:25: camera.position: expected an array of 3 numbers"},
        {"{\"camera\": {\"up\": [0, \"x\", 0]}}", PERSP_ERR_FORMAT, "s.json:1:23: camera.up[1]: expected a number"},
        {"{\"render\": {\"method\": \"nosuch\"}}", PERSP_ERR_NOT_FOUND,
         "s.json:1:23: render.method: unknown method or bad parameters 'nosuch'"},
        {"{\"render\": {\"filter\": \"blurry\"}}", PERSP_ERR_FORMAT, "s.json:1:23: render.filter: unknown filter 'blurry'"},
        {"{\"render\": {\"shading\": \"toon\"}}", PERSP_ERR_FORMAT, "s.json:1:24: render.shading: unknown shading 'toon'"},
        {"{\"render\": {\"size\": [100000, 10]}}", PERSP_ERR_FORMAT, "s.json:1:22: render.size[0]: expected a number in [1, 16384]"},
        {"{\"render\": {\"size\": [16384, 16384]}}", PERSP_ERR_TOO_LARGE, "s.json:1:21: render.size: more than"},
        {"{\"render\": {\"cull\": 1}}", PERSP_ERR_FORMAT, "s.json:1:21: render.cull: expected true or false"},
        {"{\"lights\": [{\"type\": \"spot\"}]}", PERSP_ERR_FORMAT,
         "s.json:1:22: lights[0].type: expected \"point\" or \"directional\""},
        {"{\"lights\": [{\"type\": \"point\"}]}", PERSP_ERR_FORMAT, "s.json:1:13: lights[0]: missing key 'position'"},
        {"{\"lights\": [{\"type\": \"directional\", \"direction\": [0, 0, 0]}]}", PERSP_ERR_FORMAT,
         "s.json:1:50: lights[0].direction: expected a non-zero direction"},
        {"{\"lights\": [{\"type\": \"directional\", \"position\": [0, 0, 0]}]}", PERSP_ERR_FORMAT,
         "s.json:1:37: lights[0].position: a directional light has no 'position'"},
        {"{\"lights\": [{}, {}, {}, {}, {}, {}, {}, {}, {}]}", PERSP_ERR_TOO_LARGE, "s.json:1:12: lights: more than 8 lights"},
        {"{\"materials\": {\"m\": {\"env\": \"add\"}}}", PERSP_ERR_FORMAT,
         "s.json:1:29: materials.m.env: expected \"replace\" or \"modulate\""},
        {"{\"materials\": {\"m\": {\"texture\": \"t.png\"}}}", PERSP_ERR_UNSUPPORTED,
         "s.json:1:33: materials.m.texture: file references are not allowed here"},
        {"{\"materials\": {\"m\": {\"texture\": {\"file\": \"t.png\", \"wrap\": \"around\"}}}}", PERSP_ERR_FORMAT,
         "s.json:1:59: materials.m.texture.wrap: unknown wrap mode"},
        {"{\"objects\": [{\"mesh\": \"cube\", \"material\": \"gold\"}]}", PERSP_ERR_NOT_FOUND,
         "s.json:1:43: objects[0].material: no material named 'gold'"},
        {"{\"objects\": [{\"name\": \"x\"}]}", PERSP_ERR_FORMAT, "s.json:1:14: objects[0]: missing key 'mesh'"},
        {"{\"objects\": [{\"mesh\": {\"primitive\": \"cone\"}}]}", PERSP_ERR_FORMAT,
         "s.json:1:37: objects[0].mesh.primitive: unknown primitive 'cone'"},
        {"{\"objects\": [{\"mesh\": {\"primitive\": \"sphere\", \"slices\": 2}}]}", PERSP_ERR_FORMAT,
         "s.json:1:57: objects[0].mesh.slices: expected an integer in [3, 1024]"},
        {"{\"objects\": [{\"mesh\": {\"primitive\": \"cube\", \"slices\": 8}}]}", PERSP_ERR_FORMAT,
         "s.json:1:45: objects[0].mesh.slices: unknown key (expected one of: primitive)"},
        {"{\"objects\": [{\"mesh\": {\"primitive\": \"torus\", \"major\": 1, \"minor\": 2}}]}", PERSP_ERR_INVALID_ARGUMENT,
         "s.json:1:23: objects[0].mesh: torus: radii must satisfy"},
        {"{\"objects\": [{\"mesh\": \"m.obj\"}]}", PERSP_ERR_UNSUPPORTED,
         "s.json:1:23: objects[0].mesh: file references are not allowed here"},
        {"{\"objects\": [{\"mesh\": {\"file\": \"a.obj\", \"primitive\": \"cube\"}}]}", PERSP_ERR_FORMAT,
         "s.json:1:23: objects[0].mesh: expected exactly one of 'file' and 'primitive'"},
        {"{\"objects\": [{\"mesh\": \"cube\", \"texgen\": \"warp\"}]}", PERSP_ERR_FORMAT,
         "s.json:1:41: objects[0].texgen: expected uv, planar, cylindrical"},
        {"{\"objects\": [{\"mesh\": \"cube\", \"texgen\": {\"mode\": \"cylindrical\", \"axis\": \"w\"}}]}", PERSP_ERR_FORMAT,
         "s.json:1:73: objects[0].texgen.axis: expected \"x\", \"y\" or \"z\""},
        {"{\"objects\": [{\"mesh\": \"cube\", \"texgen\": {\"mode\": \"uv\", \"scale\": [4, 1]}}]}", PERSP_ERR_FORMAT,
         "s.json:1:56: objects[0].texgen.scale: not used by mode uv"},
        {"{\"objects\": [{\"mesh\": \"cube\", \"texgen\": {\"mode\": \"planar\", \"axis\": \"x\"}}]}", PERSP_ERR_FORMAT,
         "s.json:1:60: objects[0].texgen.axis: not used by mode planar"},
        {"{\"objects\": [{\"mesh\": \"cube\", \"texgen\": {\"mode\": \"cube\", \"scale\": [1, 0]}}]}", PERSP_ERR_FORMAT,
         "s.json:1:67: objects[0].texgen.scale: expected non-zero repeats"},
        {"{\"objects\": [{\"mesh\": \"cube\", \"transform\": {\"rotate\": [90, 0, 0, 0]}}]}", PERSP_ERR_FORMAT,
         "s.json:1:55: objects[0].transform.rotate: expected a non-zero rotation axis"},
        {"{\"objects\": [{\"mesh\": \"cube\", \"transform\": {\"scale\": [1, 0, 1]}}]}", PERSP_ERR_FORMAT,
         "s.json:1:54: objects[0].transform.scale: expected non-zero scale factors"},
        {"{\"objects\": []}", PERSP_ERR_FORMAT, "s.json:1:1: the scene has no objects"},
        {"{}", PERSP_ERR_FORMAT, "s.json:1:1: the scene has no objects"},
        {"[1, 2]", PERSP_ERR_FORMAT, "s.json:1:1: expected an object"},
        {"{\"camera\": {\"fov\": 60,}}", PERSP_ERR_FORMAT,
         "s.json:1:23: invalid JSON: string or '}' expected near '}' (a comma before the closing bracket"},
        {"{\"objects\": [{\"mesh\": \"plane\"},\n]}", PERSP_ERR_FORMAT,
         "s.json:2:1: invalid JSON: unexpected token near ']' (a comma before the closing bracket"},
        {"{\"camera\": {\"fov\": 60}}}", PERSP_ERR_FORMAT, "s.json:1:24: invalid JSON: end of file expected near '}'"},
        {"{\"a\": 1, \"a\": 2}", PERSP_ERR_FORMAT, "s.json:1:12: invalid JSON: duplicate object key"},
        {"{\n\"camera\": {\"fov\": 1e999}}", PERSP_ERR_FORMAT, "s.json:2:23: invalid JSON: real number overflow"},
        {"", PERSP_ERR_FORMAT, "s.json:1:0: invalid JSON"},
        {"{\"lights\": [{\"type\": \"directional\", \"direction\": [0, -1, 0], \"attenuation\": [0, 0, 5]}],"
         " \"objects\": [{\"mesh\": \"cube\"}]}",
         PERSP_ERR_FORMAT, "s.json:1:62: lights[0].attenuation: a directional light has no 'attenuation'"},
        {"{\"render\": {\"clear\": [1, 0]}, \"objects\": [{\"mesh\": \"cube\"}]}", PERSP_ERR_FORMAT,
         "s.json:1:22: render.clear: expected an array of 3 or 4 numbers in [0, 1]"},
        {"{\"objects\": [{\"mesh\": \"cube\", \"transform\": {\"scale\": 0}}]}", PERSP_ERR_FORMAT,
         "objects[0].transform.scale: expected non-zero scale factors"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        persp_context *ctx = test_context();
        persp_scene *s = (persp_scene *)&cases; /* must be reset to NULL */
        persp_status st = load(ctx, cases[i].text, &s);
        const char *err = persp_context_error(ctx);
        if (st != cases[i].status || !strstr(err, cases[i].message))
            fail_msg("case %zu: status %d, message \"%s\", expected \"%s\"", i, (int)st, err, cases[i].message);
        assert_null(s);
        persp_context_destroy(ctx);
    }
}

static void write_text(const char *dir, const char *name, const char *text)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
}

/* Files named by the scene resolve relative to it; errors inside a model
 * name the model. */
static void test_files(void **state)
{
    (void)state;
    char dir[] = "/tmp/persp_scene_XXXXXX", path[1100];
    assert_non_null(mkdtemp(dir));
    persp_context *ctx = test_context();
    write_text(dir, "tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\n");
    write_text(dir, "s.json",
               "{\"materials\": {\"m\": {\"diffuse\": [0, 1, 0]}},\n"
               " \"objects\": [{\"mesh\": \"tri.obj\"}, {\"mesh\": {\"file\": \"tri.obj\"}, \"material\": \"m\",\n"
               "               \"transform\": {\"translate\": [0, 0, -2]}}]}\n");
    snprintf(path, sizeof path, "%s/s.json", dir);
    persp_scene *s = NULL;
    persp_status st = persp_scene_load(ctx, path, &s);
    if (st != PERSP_OK) fail_msg("%s", persp_context_error(ctx));
    assert_int_equal(s->object_count, 2);
    assert_int_equal(s->meshes[s->objects[0].mesh].index_count, 6);
    /* smooth normals generated on import where the file has none */
    assert_true(s->meshes[s->objects[0].mesh].has_normals);
    assert_true(s->materials[s->objects[1].material].diffuse[1] == 1.0f);
    assert_true(s->materials[s->objects[0].material].diffuse[1] != 1.0f);
    assert_true(s->objects[1].model.m[14] == -2.0f);
    persp_scene_destroy(s);

    write_text(dir, "bad.obj", "v 0 0 0\nv 1 0 0\nf 1 2 3\n");
    write_text(dir, "s.json", "{\"objects\": [{\"mesh\": \"bad.obj\"}]}");
    assert_int_equal(persp_scene_load(ctx, path, &s), PERSP_ERR_FORMAT);
    assert_non_null(strstr(persp_context_error(ctx), "bad.obj:3: vertex index 3 out of range"));
    assert_null(s);
    write_text(dir, "s.json", "{\"objects\": [{\"mesh\": \"none.obj\"}]}");
    assert_int_equal(persp_scene_load(ctx, path, &s), PERSP_ERR_IO);
    assert_non_null(strstr(persp_context_error(ctx), "none.obj: cannot open"));
    /* pointed at in the scene, as a missing texture is */
    assert_non_null(strstr(persp_context_error(ctx), "s.json:1:23: objects[0].mesh: "));
    write_text(dir, "s.json", "{\"materials\": {\"m\": {\"texture\": \"missing.png\"}}, \"objects\": []}");
    assert_int_equal(persp_scene_load(ctx, path, &s), PERSP_ERR_IO);
    assert_non_null(strstr(persp_context_error(ctx), "s.json:1:33: materials.m.texture: "));
    assert_non_null(strstr(persp_context_error(ctx), "missing.png"));
    snprintf(path, sizeof path, "%s/nothere.json", dir);
    assert_int_equal(persp_scene_load(ctx, path, &s), PERSP_ERR_IO);
    assert_non_null(strstr(persp_context_error(ctx), "nothere.json: cannot open"));

    const char *names[] = {"tri.obj", "bad.obj", "s.json"};
    for (size_t i = 0; i < 3; i++) {
        snprintf(path, sizeof path, "%s/%s", dir, names[i]);
        remove(path);
    }
    rmdir(dir);
    persp_context_destroy(ctx);
}

/* A small budget refuses big primitives before building them. */
static void test_vertex_budget(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    const char *text = "{\"objects\": [{\"mesh\": {\"primitive\": \"sphere\", \"slices\": 1024, \"stacks\": 1024}}]}";
    persp_scene *s = NULL;
    assert_int_equal(persp__scene_load_memory(ctx, text, strlen(text), "s.json", NULL, 100000, &s),
                     PERSP_ERR_TOO_LARGE);
    assert_non_null(strstr(persp_context_error(ctx), "s.json:1:23: objects[0].mesh: the scene's meshes exceed 100000 vertices"));
    persp_context_destroy(ctx);
}

/* Forms the documentation allows: a negative scale as one number (a
 * mirror), an empty list of rotations, a comment among the materials. */
static void test_allowed_forms(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    persp_scene *s = NULL;
    persp_status st = load(ctx,
                           "{\"materials\": {\"comment\": \"shared\", \"m\": {\"diffuse\": [1, 0, 0]}},"
                           " \"objects\": [{\"mesh\": \"cube\", \"material\": \"m\","
                           " \"transform\": {\"scale\": -2, \"rotate\": []}}]}",
                           &s);
    if (st != PERSP_OK) fail_msg("%s", persp_context_error(ctx));
    const double p[3] = {1, 1, 1};
    double got[3];
    apply(&s->objects[0].model, p, got);
    for (int k = 0; k < 3; k++) assert_true(got[k] == -2.0);
    assert_true(s->materials[s->objects[0].material].diffuse[1] == 0.0f);
    persp_scene_destroy(s);
    persp_context_destroy(ctx);
}

static void test_example_scenes(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    char path[1024];
    persp_scene *s = NULL;

    test_source_path(path, sizeof path, "scenes/room.json");
    persp_status st = persp_scene_load(ctx, path, &s);
    if (st != PERSP_OK) fail_msg("%s", persp_context_error(ctx));
    /* room.obj: one object per group (floor, ceiling, 4 walls, 2 doors, 3
     * pictures, 2 carpets); plus the chest */
    assert_int_equal(s->object_count, 14);
    assert_int_equal(s->light_count, 3);
    assert_int_equal(s->texture_count, 9); /* 8 from room.mtl, wood.png shared with the chest */
    assert_int_equal(s->width, 800);
    size_t quads = 0;
    for (size_t i = 0; i < s->object_count; i++) quads += s->meshes[s->objects[i].mesh].index_count / 6;
    assert_int_equal(quads, 6 + 2 + 3 + 2 + 6); /* room surfaces, doors, pictures, carpets; chest cube */
    persp_scene_destroy(s);

    test_source_path(path, sizeof path, "scenes/spheres.json");
    st = persp_scene_load(ctx, path, &s);
    if (st != PERSP_OK) fail_msg("%s", persp_context_error(ctx));
    assert_int_equal(s->object_count, 6);
    assert_int_equal(s->light_count, 2);
    assert_int_equal(s->texture_count, 3);
    assert_int_equal(s->objects[2].texgen, PERSP_TEXGEN_REFLECTION);
    /* the torus's stripes are its specular colour too; the globe's are not */
    const persp_material *ring = &s->materials[s->objects[3].material];
    assert_true(ring->texture >= 0 && ring->specular_texture == ring->texture);
    assert_int_equal(s->materials[s->objects[1].material].specular_texture, -1);
    persp_scene_destroy(s);
    persp_context_destroy(ctx);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_full_scene), cmocka_unit_test(test_malformed),      cmocka_unit_test(test_files),
        cmocka_unit_test(test_vertex_budget), cmocka_unit_test(test_example_scenes),
        cmocka_unit_test(test_allowed_forms),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
