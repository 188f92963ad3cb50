/* libFuzzer harness: model import from memory as persp_scene_load drives it
 * for a model file (persp__scene_from_model): the same importer call with a
 * texture cache and a folder to resolve references in, in this process
 * (PERSP_MODEL_IMPORT_IN_PROCESS), so that the sanitizers see Assimp's
 * readers and persp's side of the conversation together; fuzz_model_isolated
 * takes the same inputs through persp-import. The first byte picks the
 * name, whose extension picks the format among those read by default (its
 * content must agree); the rest is the file. The folder is tests/fuzz/files/, which
 * holds a material library, textures and a glTF buffer the seeds refer to;
 * confine.c keeps every other file out of reach. The vertices of one input
 * are held to 2^18 so that a short input cannot ask for gigabytes. Checked
 * besides crashes: an import that succeeds has parts whose mesh and material
 * are in the scene; one that fails leaves no parts and a one-line detail. */
#include "confine.h"
#include "geom/scene.h"
#include "model/model.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#ifndef FUZZ_IMPORT
#define FUZZ_IMPORT PERSP_MODEL_IMPORT_IN_PROCESS
#endif

/* Assimp 5.2 leaks inside some of its readers on malformed input (the STL
 * reader's number parser, the OBJ reader's material handling). Leaks of
 * C++ allocations (operator new: Assimp's, never persp's, which is C) or
 * with Assimp on the stack are not reported, so the fuzzer gets past them;
 * persp's own allocations are still checked. */
const char *__lsan_default_suppressions(void);
const char *__lsan_default_suppressions(void)
{
    return "leak:libassimp.so\nleak:libstdc++.so\n";
}

/* detail: the context's, or NULL. */
static void broken(const char *what, const char *detail)
{
    fprintf(stderr, "fuzz_model: invariant broken: %s%s%s%s\n", what, detail ? " ('" : "",
            detail ? detail : "", detail ? "')" : "");
    abort();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const char *const names[] = {"fuzz.obj", "fuzz.gltf", "fuzz.glb", "fuzz.ply", "fuzz.stl",
                                        "fuzz.off", "fuzz.fbx",  "fuzz.dae", "fuzz.3ds", "fuzz"};
    if (size < 1) return 0;
    const char *name = names[data[0] % (sizeof names / sizeof names[0])];
    persp_context *ctx = NULL;
    if (persp_context_create(NULL, &ctx) != PERSP_OK) return 0;
    persp_scene *scene = NULL;
    if (persp__scene_new(ctx, &scene) == PERSP_OK) {
        persp_texcache cache;
        memset(&cache, 0, sizeof cache);
        persp_model model;
        const persp_scene_load_desc desc = {.import = FUZZ_IMPORT};
        scene->load_desc = &desc;
        fuzz_confine(1);
        persp_status st = persp__model_load_memory(scene, data + 1, size - 1, name,
                                                   PERSP_FUZZ_FILES, &cache, (size_t)1 << 18,
                                                   &model);
        fuzz_confine(0);
        persp__texcache_free(ctx, &cache);
        if (st == PERSP_OK) {
            if (model.part_count == 0) broken("an imported model without parts", NULL);
            for (size_t i = 0; i < model.part_count; i++) {
                const persp_model_part *p = &model.parts[i];
                if (p->mesh < 0 || (size_t)p->mesh >= scene->mesh_count ||
                    p->material < 0 || (size_t)p->material >= scene->material_count)
                    broken("a model part names a mesh or material the scene lacks", NULL);
            }
            persp__model_free(ctx, &model);
        } else {
            if (model.parts || model.part_count) broken("a failed import left parts", NULL);
            const char *e = persp_context_error(ctx);
            if (!e[0]) broken("a failed import left no detail", NULL);
            if (strpbrk(e, "\r\n")) broken("a failed import's detail is not one line", e);
        }
        persp_scene_destroy(scene);
    }
    persp_context_destroy(ctx);
    return 0;
}
