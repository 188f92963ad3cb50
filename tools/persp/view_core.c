#include "view_core.h"

#include <errno.h>
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

#define DEG (3.14159265358979323846 / 180.0)

/* ------------------------------------------------------------- camera */

void view_camera_forward(const view_camera *cam, double f[3])
{
    double cy = cos(cam->yaw * DEG), sy = sin(cam->yaw * DEG);
    double cp = cos(cam->pitch * DEG), sp = sin(cam->pitch * DEG);
    f[0] = sy * cp;
    f[1] = sp;
    f[2] = -cy * cp;
}

void view_camera_from_scene(view_camera *cam, const persp_scene *scene, int width, int height)
{
    persp_mat4 v, p;
    persp_scene_get_camera(scene, width, height, &v, &p);
    const float *m = v.m;
    memset(cam, 0, sizeof *cam);
    /* eye = -R^T t, forward = -(third row of R). */
    for (int j = 0; j < 3; j++)
        cam->eye[j] = -((double)m[j * 4 + 0] * m[12] + (double)m[j * 4 + 1] * m[13] +
                        (double)m[j * 4 + 2] * m[14]);
    double fx = -(double)m[2], fy = -(double)m[6], fz = -(double)m[10];
    double len = sqrt(fx * fx + fy * fy + fz * fz);
    if (len > 0) fx /= len, fy /= len, fz /= len;
    cam->yaw = atan2(fx, -fz) / DEG;
    cam->pitch = asin(fy < -1 ? -1 : fy > 1 ? 1 : fy) / DEG;
    /* gluPerspective: P11 = cot(fovy/2), P22 = -(f+n)/(f-n), P32 = -2fn/(f-n). */
    if (p.m[11] == -1.0f && p.m[5] > 0.0f && p.m[10] != 1.0f && p.m[10] != -1.0f) {
        cam->fovy = 2.0 * atan(1.0 / p.m[5]) / DEG;
        cam->znear = (double)p.m[14] / ((double)p.m[10] - 1.0);
        cam->zfar = (double)p.m[14] / ((double)p.m[10] + 1.0);
    }
    if (!(cam->fovy > 1.0 && cam->fovy < 179.0)) cam->fovy = 60.0;
    if (!(cam->znear > 0.0)) cam->znear = 0.1;
    if (!(cam->zfar > cam->znear)) cam->zfar = cam->znear * 1000.0;
    double d =
        sqrt(cam->eye[0] * cam->eye[0] + cam->eye[1] * cam->eye[1] + cam->eye[2] * cam->eye[2]);
    view_camera_set_orbit(cam, d > 1.0 ? d : 1.0);
    cam->scene_own = 1;
}

void view_camera_matrices(const view_camera *cam, int width, int height, persp_mat4 *view,
                          persp_mat4 *proj)
{
    double f[3];
    view_camera_forward(cam, f);
    persp_vec3 eye = {(float)cam->eye[0], (float)cam->eye[1], (float)cam->eye[2]};
    persp_vec3 at = {(float)(cam->eye[0] + f[0]), (float)(cam->eye[1] + f[1]),
                     (float)(cam->eye[2] + f[2])};
    persp_vec3 up = {0.0f, 1.0f, 0.0f};
    *view = persp_look_at(eye, at, up);
    *proj = persp_perspective(cam->fovy, (double)width / (double)(height > 0 ? height : 1),
                              cam->znear, cam->zfar);
}

void view_camera_move(view_camera *cam, double fwd, double right, double up)
{
    double f[3];
    view_camera_forward(cam, f);
    double r[3] = {cos(cam->yaw * DEG), 0.0, sin(cam->yaw * DEG)};
    for (int i = 0; i < 3; i++) {
        double d = f[i] * fwd + r[i] * right + (i == 1 ? up : 0.0);
        cam->eye[i] += d;
        cam->orbit_target[i] += d;
    }
    cam->scene_own = 0;
}

static void clamp_pitch(view_camera *cam)
{
    if (cam->pitch > 89.0) cam->pitch = 89.0;
    if (cam->pitch < -89.0) cam->pitch = -89.0;
}

void view_camera_turn(view_camera *cam, double dyaw, double dpitch, int orbit)
{
    cam->yaw += dyaw;
    cam->pitch += dpitch;
    clamp_pitch(cam);
    double f[3];
    view_camera_forward(cam, f);
    if (orbit)
        for (int i = 0; i < 3; i++)
            cam->eye[i] = cam->orbit_target[i] - f[i] * cam->orbit_dist;
    else
        for (int i = 0; i < 3; i++)
            cam->orbit_target[i] = cam->eye[i] + f[i] * cam->orbit_dist;
    cam->scene_own = 0;
}

void view_camera_set_orbit(view_camera *cam, double dist)
{
    double f[3];
    view_camera_forward(cam, f);
    cam->orbit_dist = dist;
    for (int i = 0; i < 3; i++)
        cam->orbit_target[i] = cam->eye[i] + f[i] * dist;
}

void view_camera_zoom(view_camera *cam, double factor)
{
    double f[3];
    view_camera_forward(cam, f);
    cam->orbit_dist *= factor;
    if (cam->orbit_dist < 1e-3) cam->orbit_dist = 1e-3;
    for (int i = 0; i < 3; i++)
        cam->eye[i] = cam->orbit_target[i] - f[i] * cam->orbit_dist;
    cam->scene_own = 0;
}

/* ----------------------------------------------------------- settings */

void view_settings_desc(const view_settings *s, persp_render_desc *d)
{
    memset(d, 0, sizeof *d);
    d->method = s->method[0] ? s->method : NULL;
    d->filter = s->filter;
    d->max_aniso = s->max_aniso;
    d->wrap = s->wrap;
    d->shading = s->shading;
    d->depth_mode = s->depth;
    d->lod_mode = s->lod;
    d->lod_bias = s->lod_bias;
    d->pipeline = s->pipeline;
    d->count_ops = s->count_ops ? PERSP_TOGGLE_ON : PERSP_TOGGLE_DEFAULT;
}

/* -------------------------------------------------------------- frame */

/* 64-byte-aligned rows render faster with several threads. */
static void *alloc64(size_t n)
{
    return aligned_alloc(64, (n + 63) / 64 * 64);
}

persp_status view_frame_resize(view_frame *f, int width, int height)
{
    if (width < 1 || height < 1 || width > PERSP_IMAGE_MAX_SIDE || height > PERSP_IMAGE_MAX_SIDE)
        return PERSP_ERR_INVALID_ARGUMENT;
    if (f->width == width && f->height == height && f->out) return PERSP_OK;
    view_frame_free(f);
    size_t n = (size_t)width * (size_t)height;
    f->left = alloc64(n * 4);
    f->right = alloc64(n * 4);
    f->out = alloc64(n * 4);
    f->depth = alloc64(n * sizeof(float));
    if (!f->left || !f->right || !f->out || !f->depth) {
        view_frame_free(f);
        return PERSP_ERR_OUT_OF_MEMORY;
    }
    f->width = width;
    f->height = height;
    return PERSP_OK;
}

void view_frame_free(view_frame *f)
{
    free(f->left);
    free(f->right);
    free(f->out);
    free(f->depth);
    f->left = f->right = f->out = NULL;
    f->depth = NULL;
    f->width = f->height = 0;
}

void view_heat_color(double d, double heat_max, uint8_t rgb[3])
{
    /* black -> blue -> cyan -> green -> yellow -> red over 1..heat_max;
     * stops on a square-root scale so one-level differences still show. */
    static const double stops[6][3] = {{0, 0, 80},  {0, 0, 255},   {0, 255, 255},
                                       {0, 255, 0}, {255, 255, 0}, {255, 0, 0}};
    if (d <= 0) {
        rgb[0] = rgb[1] = rgb[2] = 0;
        return;
    }
    if (!(heat_max > 0.0)) heat_max = 1.0;
    double x = sqrt((d > heat_max ? heat_max : d) / heat_max) * 5.0;
    int i = (int)x;
    if (i >= 5) i = 4;
    double w = x - i;
    if (w > 1.0) w = 1.0;
    for (int c = 0; c < 3; c++)
        rgb[c] = (uint8_t)(stops[i][c] + (stops[i + 1][c] - stops[i][c]) * w + 0.5);
}

static int pixel_diff(const uint8_t *a, const uint8_t *b)
{
    int m = 0;
    for (int c = 0; c < 3; c++) {
        int d = abs((int)a[c] - (int)b[c]);
        if (d > m) m = d;
    }
    return m;
}

static persp_status render_side(persp_context *ctx, const persp_scene *scene,
                                const view_camera *cam, const view_settings *s, view_frame *f,
                                uint8_t *color, persp_render_stats *stats, double *ms)
{
    persp_render_desc d;
    view_settings_desc(s, &d);
    persp_mat4 v, p;
    if (!cam->scene_own) {
        view_camera_matrices(cam, f->width, f->height, &v, &p);
        d.view = &v;
        d.projection = &p;
    }
    persp_framebuffer fb = {f->width, f->height, color, f->depth};
    struct timespec t0, t1;
    timespec_get(&t0, TIME_UTC);
    persp_status st = persp_render(ctx, scene, &d, &fb, stats);
    timespec_get(&t1, TIME_UTC);
    *ms = (double)(t1.tv_sec - t0.tv_sec) * 1e3 + (double)(t1.tv_nsec - t0.tv_nsec) * 1e-6;
    return st;
}

persp_status view_coord_image(persp_context *ctx, persp_image *out)
{
    persp_status st = persp_image_alloc(ctx, VIEW_COORD_SIZE, VIEW_COORD_SIZE, out);
    if (st != PERSP_OK) return st;
    for (int j = 0; j < VIEW_COORD_SIZE; j++) {
        uint8_t *row = out->pixels + (size_t)j * out->stride;
        for (int i = 0; i < VIEW_COORD_SIZE; i++) {
            row[4 * i + 0] = (uint8_t)(i & 255);
            row[4 * i + 1] = (uint8_t)(j & 255);
            row[4 * i + 2] = (uint8_t)((i >> 8) | (j >> 8) << 4);
            row[4 * i + 3] = 255;
        }
    }
    return PERSP_OK;
}

static void coord_decode(const uint8_t *p, int *i, int *j)
{
    *i = p[0] | (p[2] & 15) << 8;
    *j = p[1] | (p[2] >> 4) << 8;
}

/* Distance of two texel indices on a texture that wraps around. */
static int wrapped(int a, int b)
{
    int d = abs(a - b) % VIEW_COORD_SIZE;
    return d > VIEW_COORD_SIZE / 2 ? VIEW_COORD_SIZE - d : d;
}

static persp_status render_texel(persp_context *ctx, const view_scenes *scenes,
                                 const view_camera *cam, const view_settings *left,
                                 const view_settings *right, int heat_max, view_frame *f)
{
    if (!scenes->coords) return PERSP_ERR_UNAVAILABLE;
    /* Each pixel must show the one texel its coordinates name. */
    view_settings l = *left, r = *right;
    l.filter = r.filter = PERSP_FILTER_NEAREST;
    l.shading = r.shading = PERSP_SHADING_NONE;
    l.mip_levels = r.mip_levels = 0;
    persp_status st =
        render_side(ctx, scenes->coords, cam, &l, f, f->left, &f->stats[0], &f->ms[0]);
    if (st == PERSP_OK)
        st = render_side(ctx, scenes->coords, cam, &r, f, f->right, &f->stats[1], &f->ms[1]);
    if (st != PERSP_OK) return st;
    size_t n = (size_t)f->width * (size_t)f->height;
    uint64_t differ = 0;
    double sum = 0.0, mx = 0.0;
    for (size_t k = 0; k < n; k++) {
        const uint8_t *a = f->left + k * 4, *b = f->right + k * 4;
        uint8_t *o = f->out + k * 4;
        int ai, aj, bi, bj;
        coord_decode(a, &ai, &aj);
        coord_decode(b, &bi, &bj);
        double di = wrapped(ai, bi), dj = wrapped(aj, bj);
        double d = memcmp(a, b, 3) ? sqrt(di * di + dj * dj) : 0.0;
        if (d > 0.0) {
            differ++;
            sum += d;
            if (d > mx) mx = d;
            view_heat_color(d, heat_max, o);
        } else {
            /* Where both agree: a dim checkerboard of 32-texel cells shows
             * how the texture lies on the surfaces. */
            uint8_t g = (uint8_t)(((ai >> 5) + (aj >> 5)) & 1 ? 48 : 24);
            o[0] = o[1] = o[2] = g;
        }
        o[3] = 255;
    }
    memset(&f->err, 0, sizeof f->err);
    f->err.share_diff = (double)differ / (double)n;
    f->err.texel_max = mx;
    f->err.texel_mean = differ ? sum / (double)differ : 0.0;
    f->err.psnr = INFINITY;
    f->have_err = 1;
    return PERSP_OK;
}

persp_status view_frame_render(persp_context *ctx, const view_scenes *scenes,
                               const view_camera *cam, const view_settings *left,
                               const view_settings *right, view_layout layout, double divider,
                               int heat_max, int want_error, view_frame *f)
{
    f->layout = layout;
    if (layout == VIEW_LAYOUT_TEXEL)
        return render_texel(ctx, scenes, cam, left, right, heat_max, f);
    const persp_scene *scene = scenes->plain, *tinted = scenes->tinted;
    persp_status st = render_side(ctx, left->mip_levels && tinted ? tinted : scene, cam, left, f,
                                  f->left, &f->stats[0], &f->ms[0]);
    if (st != PERSP_OK) return st;
    int need_right = layout != VIEW_LAYOUT_SINGLE || want_error;
    memset(&f->stats[1], 0, sizeof f->stats[1]);
    f->ms[1] = 0.0;
    if (need_right) {
        st = render_side(ctx, right->mip_levels && tinted ? tinted : scene, cam, right, f, f->right,
                         &f->stats[1], &f->ms[1]);
        if (st != PERSP_OK) return st;
    }
    size_t n = (size_t)f->width * (size_t)f->height;
    f->have_err = need_right;
    if (need_right) {
        uint64_t sum = 0, differ = 0;
        double sq = 0.0;
        int mx = 0;
        for (size_t i = 0; i < n; i++) {
            const uint8_t *a = f->left + i * 4, *b = f->right + i * 4;
            int d = pixel_diff(a, b);
            sum += (uint64_t)d;
            differ += d != 0;
            if (d > mx) mx = d;
            for (int c = 0; c < 3; c++) {
                double e = (double)a[c] - (double)b[c];
                sq += e * e;
            }
        }
        f->err.max = mx;
        f->err.mean = (double)sum / (double)n;
        f->err.share_diff = (double)differ / (double)n;
        double mse = sq / (3.0 * (double)n);
        f->err.psnr = mse > 0.0 ? 10.0 * log10(255.0 * 255.0 / mse) : INFINITY;
    }
    if (layout == VIEW_LAYOUT_SINGLE) {
        memcpy(f->out, f->left, n * 4);
    } else if (layout == VIEW_LAYOUT_SPLIT) {
        int split = (int)lround(divider * f->width);
        if (split < 0) split = 0;
        if (split > f->width) split = f->width;
        for (int y = 0; y < f->height; y++) {
            size_t row = (size_t)y * (size_t)f->width * 4;
            memcpy(f->out + row, f->left + row, (size_t)split * 4);
            memcpy(f->out + row + (size_t)split * 4, f->right + row + (size_t)split * 4,
                   (size_t)(f->width - split) * 4);
        }
    } else {
        /* Equal pixels show the left image dimmed, for orientation. */
        for (size_t i = 0; i < n; i++) {
            const uint8_t *a = f->left + i * 4, *b = f->right + i * 4;
            uint8_t *o = f->out + i * 4;
            int d = pixel_diff(a, b);
            if (d == 0) {
                for (int c = 0; c < 3; c++)
                    o[c] = (uint8_t)(a[c] / 4);
            } else {
                view_heat_color(d, heat_max, o);
            }
            o[3] = 255;
        }
    }
    return PERSP_OK;
}

/* --------------------------------------------------------- camera paths */

int view_path_add(view_path *p, double t, const view_camera *cam)
{
    if (p->count == p->cap) {
        size_t cap = p->cap ? p->cap * 2 : 64;
        view_key *k = realloc(p->keys, cap * sizeof *k);
        if (!k) return 0;
        p->keys = k;
        p->cap = cap;
    }
    view_key *k = &p->keys[p->count++];
    k->t = t;
    memcpy(k->eye, cam->eye, sizeof k->eye);
    k->yaw = cam->yaw;
    k->pitch = cam->pitch;
    k->fovy = cam->fovy;
    k->znear = cam->znear;
    k->zfar = cam->zfar;
    return 1;
}

void view_path_free(view_path *p)
{
    free(p->keys);
    memset(p, 0, sizeof *p);
}

static int get_number(json_t *o, const char *key, double *out, int required)
{
    json_t *v = json_object_get(o, key);
    if (!v) return !required;
    if (!json_is_number(v)) return 0;
    *out = json_number_value(v);
    return isfinite(*out);
}

/* The line of the key `key` of the top-level object (elem < 0) or of the
 * elem-th object of its "keys" array, for messages as the scene loader
 * gives them (file:line); 0 where it is not found as written (escaped). */
static size_t key_line(const char *t, size_t n, long elem, const char *key)
{
    size_t line = 1, klen = strlen(key);
    int depth = 0, in_keys = 0;
    long count = -1;
    for (size_t i = 0; i < n; i++) {
        char c = t[i];
        if (c == '\n') {
            line++;
        } else if (c == '{' || c == '[') {
            depth++;
            if (c == '{' && depth == 3 && in_keys) count++;
        } else if (c == '}' || c == ']') {
            depth--;
        } else if (c == '"') {
            size_t start = i + 1, j = start;
            while (j < n && t[j] != '"') j += t[j] == '\\' ? 2 : 1;
            size_t len = (j < n ? j : n) - start, k = j + 1;
            while (k < n && (t[k] == ' ' || t[k] == '\t' || t[k] == '\r' || t[k] == '\n')) k++;
            int is_key = k < n && t[k] == ':';
            if (is_key && depth == 1) in_keys = len == 4 && !memcmp(t + start, "keys", 4);
            if (is_key && len == klen && !memcmp(t + start, key, len) &&
                ((elem < 0 && depth == 1) || (elem >= 0 && depth == 3 && in_keys && count == elem)))
                return line;
            i = j;
        }
    }
    return 0;
}

/* "path:LINE: " where the key's line is known, else "path: ". */
static void where(char *buf, size_t size, const char *path, size_t line)
{
    if (line) snprintf(buf, size, "%s:%zu: ", path, line);
    else snprintf(buf, size, "%s: ", path);
}

/* key for a one-line message: control bytes as '?', at most 64 bytes. */
static void printable_key(const char *key, char *buf, size_t size)
{
    size_t n = 0;
    for (; key[n] && n + 1 < size && n < 64; n++) buf[n] = (unsigned char)key[n] < 0x20 || key[n] == 0x7f ? '?' : key[n];
    buf[n] = '\0';
}

/* A key that is none of allowed (NULL-terminated; "comment" is allowed
 * everywhere, as in scene files): 0 after the message naming file, line
 * and key. */
static int known_keys(json_t *obj, const char *const *allowed, const char *text, size_t n, long elem,
                      const char *path, char *err, size_t err_size)
{
    const char *key;
    json_t *v;
    json_object_foreach(obj, key, v) {
        int ok = !strcmp(key, "comment");
        for (size_t i = 0; allowed[i] && !ok; i++) ok = !strcmp(key, allowed[i]);
        if (ok) continue;
        char at[1024], list[256] = "", shown[80];
        where(at, sizeof at, path, key_line(text, n, elem, key));
        printable_key(key, shown, sizeof shown);
        for (size_t i = 0; allowed[i]; i++)
            snprintf(list + strlen(list), sizeof list - strlen(list), "%s%s", i ? ", " : "", allowed[i]);
        if (elem < 0) snprintf(err, err_size, "%s%s: unknown key (expected one of: %s)", at, shown, list);
        else snprintf(err, err_size, "%skeys[%ld].%s: unknown key (expected one of: %s)", at, elem, shown, list);
        return 0;
    }
    return 1;
}

/* The camera path format's version: 1, the one view_path_save writes. */
#define VIEW_PATH_VERSION 1

/* The whole file, NUL-terminated, at most 64 MiB (a path of a million
 * keys); NULL after the message. */
static char *read_text(const char *path, size_t *size, char *err, size_t err_size)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        snprintf(err, err_size, "%s: cannot open: %s", path, strerror(errno));
        return NULL;
    }
    const size_t limit = (size_t)64 << 20;
    size_t cap = 0, n = 0;
    char *text = NULL;
    int bad = 0, large = 0;
    for (;;) {
        if (n == cap) {
            if (cap == limit) {
                /* Full: one more byte says whether the file goes on. */
                large = fgetc(f) != EOF;
                break;
            }
            cap = cap ? (cap * 2 < limit ? cap * 2 : limit) : 4096;
            char *grown = realloc(text, cap + 1);
            if (!grown) {
                bad = ENOMEM;
                break;
            }
            text = grown;
        }
        size_t got = fread(text + n, 1, cap - n, f);
        n += got;
        if (got == 0) break;
    }
    if (!bad && ferror(f)) bad = errno ? errno : EIO;
    fclose(f);
    if (bad || large || !text) {
        if (large) snprintf(err, err_size, "%s: larger than %zu bytes", path, limit);
        else snprintf(err, err_size, "%s: cannot read: %s", path, strerror(bad ? bad : ENOMEM));
        free(text);
        return NULL;
    }
    text[n] = '\0';
    *size = n;
    return text;
}

/* The top-level object: known keys, and a version this reader knows. */
static int check_root(json_t *root, const char *text, size_t n, const char *path, char *err, size_t err_size)
{
    static const char *const top[] = {"version", "keys", NULL};
    if (json_is_object(root) && !known_keys(root, top, text, n, -1, path, err, err_size)) return 0;
    json_t *version = json_object_get(root, "version");
    if (version && !(json_is_integer(version) && json_integer_value(version) == VIEW_PATH_VERSION)) {
        char at[1024];
        where(at, sizeof at, path, key_line(text, n, -1, "version"));
        snprintf(err, err_size, "%sversion: unsupported camera path version (expected %d)", at, VIEW_PATH_VERSION);
        return 0;
    }
    json_t *keys = json_object_get(root, "keys");
    if (!json_is_array(keys) || json_array_size(keys) == 0) {
        snprintf(err, err_size, "%s: expected an object with a non-empty array \"keys\"", path);
        return 0;
    }
    return 1;
}

/* Key i of the path into c and *t: 0 after the message. */
static int read_key(json_t *k, size_t i, double last_t, const char *text, size_t n, const char *path,
                    view_camera *c, double *t, char *err, size_t err_size)
{
    static const char *const fields[] = {"t", "eye", "yaw", "pitch", "fovy", "near", "far", NULL};
    memset(c, 0, sizeof *c);
    *t = 0.0;
    c->fovy = 60.0, c->znear = 0.1, c->zfar = 100.0;
    if (json_is_object(k) && !known_keys(k, fields, text, n, (long)i, path, err, err_size)) return 0;
    json_t *eye = json_object_get(k, "eye");
    int ok = json_is_object(k) && get_number(k, "t", t, 1) && json_is_array(eye) && json_array_size(eye) == 3 &&
             get_number(k, "yaw", &c->yaw, 1) && get_number(k, "pitch", &c->pitch, 1) &&
             get_number(k, "fovy", &c->fovy, 0) && get_number(k, "near", &c->znear, 0) &&
             get_number(k, "far", &c->zfar, 0);
    for (size_t j = 0; ok && j < 3; j++) {
        json_t *e = json_array_get(eye, j);
        ok = json_is_number(e) && isfinite(c->eye[j] = json_number_value(e));
    }
    if (!ok) {
        snprintf(err, err_size,
                 "%s: key %zu: expected {\"t\": S, \"eye\": [X, Y, Z], \"yaw\": DEG, "
                 "\"pitch\": DEG} and optional \"fovy\", \"near\", \"far\"",
                 path, i);
        return 0;
    }
    if (!(*t >= last_t && c->fovy > 0.0 && c->fovy < 180.0 && c->znear > 0.0 && c->zfar > c->znear)) {
        snprintf(err, err_size,
                 "%s: key %zu: times must not decrease, fovy must be in (0, 180) and 0 < near < far", path, i);
        return 0;
    }
    return 1;
}

int view_path_load(const char *path, view_path *p, char *err, size_t err_size)
{
    memset(p, 0, sizeof *p);
    size_t n = 0;
    char *text = read_text(path, &n, err, err_size);
    if (!text) return 0;
    json_error_t je;
    json_t *root = json_loadb(text, n, 0, &je);
    if (!root) {
        snprintf(err, err_size, "%s:%d:%d: %s", path, je.line, je.column, je.text);
        free(text);
        return 0;
    }
    int ok = check_root(root, text, n, path, err, err_size);
    json_t *keys = json_object_get(root, "keys");
    double last_t = -INFINITY;
    for (size_t i = 0; ok && i < json_array_size(keys); i++) {
        view_camera c;
        double t;
        ok = read_key(json_array_get(keys, i), i, last_t, text, n, path, &c, &t, err, err_size);
        last_t = t;
        if (ok && !(ok = view_path_add(p, t, &c))) snprintf(err, err_size, "%s: out of memory", path);
    }
    json_decref(root);
    free(text);
    if (!ok) view_path_free(p);
    return ok;
}

int view_path_save(const char *path, const view_path *p, char *err, size_t err_size)
{
    json_t *root = json_object(), *keys = json_array();
    json_object_set_new(root, "version", json_integer(1));
    for (size_t i = 0; i < p->count; i++) {
        const view_key *k = &p->keys[i];
        json_t *o = json_object();
        json_object_set_new(o, "t", json_real(k->t));
        json_object_set_new(o, "eye", json_pack("[fff]", k->eye[0], k->eye[1], k->eye[2]));
        json_object_set_new(o, "yaw", json_real(k->yaw));
        json_object_set_new(o, "pitch", json_real(k->pitch));
        json_object_set_new(o, "fovy", json_real(k->fovy));
        json_object_set_new(o, "near", json_real(k->znear));
        json_object_set_new(o, "far", json_real(k->zfar));
        json_array_append_new(keys, o);
    }
    json_object_set_new(root, "keys", keys);
    int ok = json_dump_file(root, path, JSON_INDENT(1) | JSON_REAL_PRECISION(9)) == 0;
    json_decref(root);
    if (!ok) snprintf(err, err_size, "%s: cannot write the camera path", path);
    return ok;
}

void view_path_sample(const view_path *p, double t, view_camera *cam)
{
    const view_key *a = &p->keys[0], *b = a;
    if (t >= p->keys[p->count - 1].t) {
        a = b = &p->keys[p->count - 1];
    } else if (t > a->t) {
        size_t i = 1;
        while (i < p->count && p->keys[i].t <= t)
            i++;
        a = &p->keys[i - 1];
        b = &p->keys[i];
    }
    double w = b->t > a->t ? (t - a->t) / (b->t - a->t) : 0.0;
    memset(cam, 0, sizeof *cam);
    for (int i = 0; i < 3; i++)
        cam->eye[i] = a->eye[i] + (b->eye[i] - a->eye[i]) * w;
    cam->yaw = a->yaw + (b->yaw - a->yaw) * w;
    cam->pitch = a->pitch + (b->pitch - a->pitch) * w;
    cam->fovy = a->fovy + (b->fovy - a->fovy) * w;
    cam->znear = a->znear + (b->znear - a->znear) * w;
    cam->zfar = a->zfar + (b->zfar - a->zfar) * w;
    clamp_pitch(cam);
    view_camera_set_orbit(cam, 1.0);
    cam->scene_own = 0;
}

int view_make_dirs(const char *path)
{
    char buf[4096];
    const size_t n = strlen(path);
    if (n == 0 || n >= sizeof buf) {
        errno = n ? ENAMETOOLONG : ENOENT;
        return -1;
    }
    memcpy(buf, path, n + 1);
    for (char *p = buf + 1; *p; p++) {
        if (*p != '/') continue;
        *p = '\0';
        if (mkdir(buf, 0777) != 0 && errno != EEXIST) return -1;
        *p = '/';
    }
    return mkdir(buf, 0777) == 0 || errno == EEXIST ? 0 : -1;
}
