/* The interactive window of `persp view` (tools/view/, built only with SDL2
 * and Dear ImGui; PERSP_HAVE_VIEWER says whether it was). */
#ifndef PERSP_VIEW_WINDOW_H
#define PERSP_VIEW_WINDOW_H

#include "view_core.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct view_window_args {
    persp_context *ctx;
    persp_scene *scene;
    persp_scene *tinted; /* its mip levels as colours (persp_scene_tint_mip_levels) */
    persp_scene *coords; /* its textures replaced by view_coord_image */
    const char *scene_name;
    view_settings left, right;
    view_layout layout;
    double divider;
    int heat_max;
    int width, height; /* window size */
    int threads;
    int frames;              /* > 0: close after that many frames (smoke tests) */
    const char *record_path; /* where a recorded flight is saved */
    const view_path *play;   /* NULL: none loaded */
    const char *shot_dir;    /* screenshots go here */
    const char *window_shot; /* with frames: the last frame, panels included, as PNG */
    const char *script;      /* input actions to replay (docs/VIEWER.md); NULL: none */
    int quiet;
    /* Told of the temporary file of each PNG the window writes
     * (persp_context_set_temp_file_handler), so that the CLI's signal
     * handlers remove it as they do for render; NULL: nobody is. */
    persp_temp_file_fn temp_file;
    /* Installs those handlers; called once SDL is set up where SDL took
     * SIGINT and SIGTERM for its quit event; NULL: left as they are. */
    void (*install_signal_handlers)(void);
} view_window_args;

/* CLI exit code (0 ok, 1 failure). */
int view_window_run(const view_window_args *args);

#ifdef __cplusplus
}
#endif
#endif
