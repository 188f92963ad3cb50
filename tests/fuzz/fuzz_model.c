/* libFuzzer harness: model import from memory as persp uses it. The first
 * byte picks the format hint (the name's extension; Assimp also sniffs the
 * content), the rest is the file. No other files are opened (no base
 * folder), and the vertices of one input are held to 2^18. */
#include "geom/scene.h"
#include "io/model.h"

#include <stdint.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

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

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const char *const names[] = {"fuzz.obj", "fuzz.gltf", "fuzz.glb",
                                        "fuzz.ply", "fuzz.stl",  "fuzz.off"};
    if (size < 1) return 0;
    const char *name = names[data[0] % (sizeof names / sizeof names[0])];
    persp_context *ctx = NULL;
    if (persp_context_create(NULL, &ctx) != PERSP_OK) return 0;
    persp_scene *scene = NULL;
    if (persp__scene_new(ctx, &scene) == PERSP_OK) {
        persp_model model;
        if (persp__model_load_memory(scene, data + 1, size - 1, name, NULL, NULL, (size_t)1 << 18,
                                     &model) == PERSP_OK)
            persp__model_free(ctx, &model);
        persp_scene_destroy(scene);
    }
    persp_context_destroy(ctx);
    return 0;
}
