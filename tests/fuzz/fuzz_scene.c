/* libFuzzer harness: JSON scene from memory, as persp_scene_load reads a
 * scene file. File references (textures, models) resolve in
 * tests/fuzz/files/, which holds a texture, a model and its material library
 * the seeds name; confine.c keeps every other file out of reach, so a
 * fuzzed "../../x" or "/etc/x" reads nothing. The meshes of one input are
 * held to 2^18 vertices so that a short input cannot ask for gigabytes of
 * primitives. Checked besides crashes: a loaded scene's objects name meshes
 * and materials it has; a refused one yields no scene and a one-line
 * detail. */
#include "confine.h"
#include "geom/scene.h"
#include "model/model.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* Scenes import models with Assimp: see fuzz_model.c. */
const char *__lsan_default_suppressions(void);
const char *__lsan_default_suppressions(void)
{
    return "leak:libassimp.so\nleak:libstdc++.so\n";
}

/* detail: the context's, or NULL. */
static void broken(const char *what, const char *detail)
{
    fprintf(stderr, "fuzz_scene: invariant broken: %s%s%s%s\n", what, detail ? " ('" : "",
            detail ? detail : "", detail ? "')" : "");
    abort();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    persp_context *ctx = NULL;
    if (persp_context_create(NULL, &ctx) != PERSP_OK) return 0;
    persp_scene *scene = (persp_scene *)1;
    fuzz_confine(1);
    persp_status st = persp__scene_load_memory(ctx, (const char *)data, size, "fuzz.json",
                                               PERSP_FUZZ_FILES, (size_t)1 << 18, &scene);
    fuzz_confine(0);
    if (st == PERSP_OK) {
        for (size_t i = 0; i < scene->object_count; i++) {
            const persp_object *o = &scene->objects[i];
            if (o->mesh < 0 || (size_t)o->mesh >= scene->mesh_count || o->material < 0 ||
                (size_t)o->material >= scene->material_count)
                broken("an object names a mesh or material the scene lacks", NULL);
        }
        persp_scene_destroy(scene);
    } else {
        if (scene) broken("a refused scene was handed out", NULL);
        const char *e = persp_context_error(ctx);
        if (!e[0]) broken("a refused scene left no detail", NULL);
        if (strpbrk(e, "\r\n")) broken("a refused scene's detail is not one line", e);
    }
    persp_context_destroy(ctx);
    return 0;
}
