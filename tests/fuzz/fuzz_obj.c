/* libFuzzer harness: OBJ text from memory (no files are opened). */
#include "geom/scene.h"
#include "io/obj.h"

#include <stdint.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    persp_context *ctx = NULL;
    if (persp_context_create(NULL, &ctx) != PERSP_OK) return 0;
    persp_scene *scene = NULL;
    if (persp__scene_new(ctx, &scene) == PERSP_OK) {
        persp_obj_result res;
        if (persp__obj_load_memory(scene, (const char *)data, size, "fuzz.obj", NULL, NULL, &res) == PERSP_OK)
            persp__obj_result_free(ctx, &res);
        persp_scene_destroy(scene);
    }
    persp_context_destroy(ctx);
    return 0;
}
