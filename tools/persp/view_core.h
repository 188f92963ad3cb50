/*
 * persp view: what the interactive window and the headless camera-path
 * player share (camera, render settings, the composed frame, camera paths).
 * Plain C on the public API, so `persp view --play` needs no SDL.
 */
#ifndef PERSP_VIEW_CORE_H
#define PERSP_VIEW_CORE_H

#include "persp.h"

#ifdef __cplusplus
extern "C" {
#endif

/* A y-up camera: position, yaw (degrees, 0 looks down -z, positive turns
 * right) and pitch (degrees, positive looks up). */
typedef struct view_camera {
    double eye[3];
    double yaw, pitch;
    double fovy, znear, zfar;
    double orbit_target[3], orbit_dist; /* orbit mode turns around this point */
    int scene_own;                      /* 1: untouched, render with the scene's exact matrices */
} view_camera;

/* The scene's camera for a width x height image (its matrices decomposed;
 * a camera whose up is not +y gets +y). */
void view_camera_from_scene(view_camera *cam, const persp_scene *scene, int width, int height);
void view_camera_forward(const view_camera *cam, double f[3]);
void view_camera_matrices(const view_camera *cam, int width, int height, persp_mat4 *view,
                          persp_mat4 *proj);
/* Fly: moves along forward / right / world up by the amounts given. */
void view_camera_move(view_camera *cam, double fwd, double right, double up);
/* Fly: turns the view; orbit: turns the eye around orbit_target. */
void view_camera_turn(view_camera *cam, double dyaw, double dpitch, int orbit);
/* Sets orbit_target orbit_dist ahead of the eye. */
void view_camera_set_orbit(view_camera *cam, double dist);
/* Orbit: scales the distance to the target (zoom). */
void view_camera_zoom(view_camera *cam, double factor);

/* One side's render settings; names as the CLI takes them. */
typedef struct view_settings {
    char method[64]; /* "" : the scene's */
    persp_filter filter;
    int max_aniso;
    persp_wrap wrap;
    persp_shading shading;
    persp_depth_mode depth;
    persp_lod_mode lod;
    float lod_bias;
    persp_pipeline pipeline;
    int count_ops;
    int mip_levels; /* render the scene whose mip levels are flat colours */
} view_settings;

void view_settings_desc(const view_settings *s, persp_render_desc *d);

typedef enum view_layout {
    VIEW_LAYOUT_SINGLE, /* the left settings only */
    VIEW_LAYOUT_SPLIT,  /* left | right of the divider */
    VIEW_LAYOUT_DIFF,   /* heat map of |left - right| per pixel */
    VIEW_LAYOUT_TEXEL   /* heat map of the texture-coordinate error, in texels of VIEW_COORD_SIZE */
} view_layout;

/* The texture that encodes its own texel index (VIEW_LAYOUT_TEXEL): texel
 * (i, j) is R = i & 255, G = j & 255, B = (i >> 8) | (j >> 8) << 4. Drawn
 * with nearest filtering and no shading, a pixel's colour says which texel
 * (of a VIEW_COORD_SIZE² texture) its texture coordinates fell in. */
#define VIEW_COORD_SIZE 1024
persp_status view_coord_image(persp_context *ctx, persp_image *out);

/* The scene in the forms the layouts need. */
typedef struct view_scenes {
    const persp_scene *plain;
    const persp_scene *tinted; /* persp_scene_tint_mip_levels; NULL: none */
    const persp_scene *coords; /* its textures replaced by view_coord_image; NULL: none */
} view_scenes;

/* The colour error of left against right over the whole image. */
typedef struct view_error {
    int max;           /* largest channel difference, in levels */
    double mean;       /* mean of the per-pixel largest channel difference */
    double share_diff; /* share of pixels that differ at all */
    double psnr;       /* dB over RGB; INFINITY when identical */
    /* VIEW_LAYOUT_TEXEL: the distance of the two sides' texels (wrapping
     * around the texture), in texels of VIEW_COORD_SIZE. */
    double texel_max, texel_mean; /* mean over the pixels that differ */
} view_error;

/* Two framebuffers (left, right) and the composed image. */
typedef struct view_frame {
    int width, height;
    uint8_t *left, *right, *out; /* RGBA rows bottom-to-top */
    float *depth;
    persp_render_stats stats[2];
    double ms[2]; /* render time of each side */
    view_error err;
    int have_err;
    view_layout layout; /* of the last render */
} view_frame;

persp_status view_frame_resize(view_frame *f, int width, int height);
void view_frame_free(view_frame *f);
/* Renders what layout needs (both sides unless SINGLE without error
 * statistics) and composes f->out: sides with mip_levels render
 * scenes->tinted, VIEW_LAYOUT_TEXEL renders scenes->coords (else
 * PERSP_ERR_UNAVAILABLE). divider in 0..1 of the width; heat_max: the
 * difference (levels, or texels for TEXEL) shown as the hottest colour. */
persp_status view_frame_render(persp_context *ctx, const view_scenes *scenes,
                               const view_camera *cam, const view_settings *left,
                               const view_settings *right, view_layout layout, double divider,
                               int heat_max, int want_error, view_frame *f);
/* The heat-map colour of a difference d with d >= heat_max hottest; 0 is black. */
void view_heat_color(double d, double heat_max, uint8_t rgb[3]);

/* A recorded flight: camera keys at times (seconds). */
typedef struct view_key {
    double t;
    double eye[3], yaw, pitch, fovy, znear, zfar;
} view_key;

typedef struct view_path {
    view_key *keys;
    size_t count, cap;
} view_path;

int view_path_add(view_path *p, double t, const view_camera *cam);
void view_path_free(view_path *p);
/* Loads / saves {"version": 1, "keys": [{"t", "eye", "yaw", "pitch", "fovy",
 * "near", "far"}, ...]}; on failure writes a message into err. */
int view_path_load(const char *path, view_path *p, char *err, size_t err_size);
/* Creates the folder path and the folders above it that are missing (the
 * default out/frames where out/ is missing too); 0, or -1 with errno. */
int view_make_dirs(const char *path);
int view_path_save(const char *path, const view_path *p, char *err, size_t err_size);
/* The camera at time t (keys interpolated linearly, clamped at the ends). */
void view_path_sample(const view_path *p, double t, view_camera *cam);

#ifdef __cplusplus
}
#endif
#endif
