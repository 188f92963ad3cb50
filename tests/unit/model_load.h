/* Loading a model into a fresh scene for the model tests (test_model.c,
 * test_obj.c): the context, scene, parts, status and warnings of one load. */
#ifndef PERSP_TESTS_MODEL_LOAD_H
#define PERSP_TESTS_MODEL_LOAD_H

#include "support.h"

#include "core/internal.h"
#include "geom/scene.h"
#include "model/model.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct warnings {
    int count;
    char last[512];
} warnings;

static inline void on_warning(void *user, const char *message)
{
    warnings *w = user;
    w->count++;
    if (getenv("PERSP_TEST_VERBOSE")) fprintf(stderr, "warning: %s\n", message);
    snprintf(w->last, sizeof w->last, "%s", message);
}

typedef struct loaded {
    persp_context *ctx;
    persp_scene *scene;
    persp_model model;
    persp_status st;
    warnings warn;
} loaded;

static inline void begin(loaded *l)
{
    memset(l, 0, sizeof *l);
    l->ctx = test_context();
    persp_context_set_warning_handler(l->ctx, on_warning, &l->warn);
    assert_int_equal(persp__scene_new(l->ctx, &l->scene), PERSP_OK);
}

static inline void load_bytes(loaded *l, const char *text, size_t size, const char *name)
{
    begin(l);
    l->st = persp__model_load_memory(l->scene, text, size, name, NULL, NULL, 0, &l->model);
}

static inline void load_text(loaded *l, const char *text, const char *name)
{
    load_bytes(l, text, strlen(text), name);
}

static inline void load_path(loaded *l, const char *path)
{
    begin(l);
    l->st = persp__model_load_file(l->scene, path, NULL, 0, &l->model);
}

static inline void unload(loaded *l)
{
    persp__model_free(l->ctx, &l->model);
    persp_scene_destroy(l->scene);
    persp_context_destroy(l->ctx);
}

/* The mesh of a part; fails the test when the load failed. */
static inline const persp_mesh *mesh_of(const loaded *l, size_t part)
{
    if (l->st != PERSP_OK) fail_msg("load failed: %s", persp_context_error(l->ctx));
    assert_true(l->model.part_count > part);
    return &l->scene->meshes[l->model.parts[part].mesh];
}

static inline const persp_material *material_of(const loaded *l, size_t part)
{
    return &l->scene->materials[l->model.parts[part].material];
}

#endif
