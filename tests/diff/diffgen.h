/*
 * Random but valid scenes for the differential test against Mesa
 * (tests/diff/difftest.c, docs/RELIABILITY.md "Differential testing against
 * Mesa"). A seed determines everything: the folder written holds scene.json
 * and its textures (tex*.png), loadable by persp_scene_load and by
 * `persp render` / `persp bench --peer llvmpipe`, so a failing case can be
 * replayed from the folder alone.
 */
#ifndef PERSP_TESTS_DIFFGEN_H
#define PERSP_TESTS_DIFFGEN_H

#include "persp.h"

#include <stddef.h>
#include <stdint.h>

typedef struct diff_case {
    uint64_t seed;
    int width, height;
    persp_filter filter;    /* one filter for every texture of the scene */
    persp_depth_mode depth; /* Z or INVW */
} diff_case;

/* The filters OpenGL defines exactly enough to compare with (GL 4.6
 * §8.14-8.15). Anisotropic filtering is left out: EXT_texture_filter_anisotropic
 * leaves the footprint and sample placement to the implementation. */
#define DIFF_FILTER_COUNT 6
extern const persp_filter diff_filters[DIFF_FILTER_COUNT];

/* Writes DIR/scene.json and DIR/tex*.png for the seed (DIR must exist) and
 * fills out. The render settings the JSON cannot carry (the depth mode)
 * are written into the scene's top-level "comment" as "depth=z" or
 * "depth=invw", which diff_case_read reads back. 0 on success, else a
 * message in err. */
int diff_generate(persp_context *ctx, uint64_t seed, const char *dir, diff_case *out, char *err,
                  size_t err_size);

/* Reads the size, filter and depth mode of DIR/scene.json written by
 * diff_generate (the seed comes from the comment as well). 0 on success. */
int diff_case_read(const char *scene_path, diff_case *out, char *err, size_t err_size);

#endif
