/* Oracles of the golden images (oracle.h). */
#include "oracle.h"

#include "diffref.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

oracle_interval_result oracle_check_interval(const persp_scene *scene, const persp_image *img, persp_filter filter,
                                             double tol, const uint8_t *clear)
{
    oracle_interval_result r;
    memset(&r, 0, sizeof r);
    r.first_x = r.first_y = -1;
    diff_ref *ref = diff_ref_create(scene, img->width, img->height, filter);
    if (!ref) {
        r.off = (size_t)img->width * (size_t)img->height + 1; /* cannot check: fail loudly */
        return r;
    }
    for (int y = 0; y < img->height; y++)
        for (int x = 0; x < img->width; x++) {
            const uint8_t *p = img->pixels + (size_t)y * img->stride + 4 * (size_t)x;
            diff_ref_pixel q = diff_ref_eval(ref, x, y);
            int inside = q.covered;
            for (int c = 0; c < 3 && inside; c++) inside = p[c] >= q.lo[c] - tol && p[c] <= q.hi[c] + tol;
            int ok = inside || (q.background_ok && !memcmp(p, clear, 3));
            r.checked++;
            r.covered += q.covered && !q.background_ok;
            r.background += q.background_ok && !q.covered;
            if (!ok) {
                if (!r.off) r.first_x = x, r.first_y = y;
                r.off++;
            }
        }
    diff_ref_destroy(ref);
    return r;
}

int oracle_area_image(const persp_scene *scene, int w, int h, int k, int step, double *rgb, unsigned char *inside)
{
    diff_ref *ref = diff_ref_create(scene, w * k, h * k, PERSP_FILTER_TRILINEAR);
    if (!ref) return -1;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            size_t at = (size_t)y * (size_t)w + (size_t)x;
            if (x % step || y % step) {
                inside[at] = 0;
                continue;
            }
            double sum[3] = {0.0, 0.0, 0.0};
            int all = 1;
            for (int j = 0; j < k; j++)
                for (int i = 0; i < k; i++) {
                    diff_ref_pixel q = diff_ref_eval(ref, x * k + i, y * k + j);
                    if (!q.covered || q.background_ok) all = 0;
                    for (int c = 0; c < 3; c++) sum[c] += 0.5 * (q.lo[c] + q.hi[c]);
                }
            for (int c = 0; c < 3; c++) rgb[at * 3 + (size_t)c] = sum[c] / (double)(k * k);
            inside[at] = (unsigned char)all;
        }
    diff_ref_destroy(ref);
    return 0;
}

oracle_error oracle_area_error(const persp_image *img, const double *rgb, const unsigned char *inside)
{
    oracle_error e;
    memset(&e, 0, sizeof e);
    double abs_sum = 0.0, sq_sum = 0.0;
    for (int y = 0; y < img->height; y++)
        for (int x = 0; x < img->width; x++) {
            size_t at = (size_t)y * (size_t)img->width + (size_t)x;
            if (!inside[at]) continue;
            const uint8_t *p = img->pixels + (size_t)y * img->stride + 4 * (size_t)x;
            for (int c = 0; c < 3; c++) {
                double d = (double)p[c] - rgb[at * 3 + (size_t)c];
                abs_sum += fabs(d);
                sq_sum += d * d;
            }
            e.pixels++;
        }
    if (e.pixels) {
        double n = 3.0 * (double)e.pixels;
        e.mean_abs = abs_sum / n;
        e.psnr = sq_sum > 0.0 ? 10.0 * log10(255.0 * 255.0 / (sq_sum / n)) : INFINITY;
    }
    return e;
}

/* ------------------------------------------------------------ lighting */

typedef struct lit_object {
    double *eye_pos, *eye_nrm; /* 3 per vertex */
    double *color;             /* 3 per vertex: vertex colour, or NULL when all are white */
} lit_object;

typedef struct lit_light {
    int directional;
    double pos[3]; /* eye space; directional: unit vector towards the light */
    double color[3], att[3];
} lit_light;

static void m4_mul(const double a[16], const double b[16], double out[16])
{
    for (int c = 0; c < 4; c++)
        for (int r = 0; r < 4; r++) {
            double s = 0.0;
            for (int k = 0; k < 4; k++) s += a[k * 4 + r] * b[c * 4 + k];
            out[c * 4 + r] = s;
        }
}

static void m4_of(persp_mat4 m, double out[16])
{
    for (int i = 0; i < 16; i++) out[i] = (double)m.m[i];
}

static void normalize3(double v[3])
{
    double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (l > 0.0) v[0] /= l, v[1] /= l, v[2] /= l;
}

/* Blinn–Phong at eye-space point e with unit normal n (docs/SCENES.md):
 * ambient + diffuse into d, specular into s. */
static void blinn_phong(const persp_scene_material *m, const double amb[3], const lit_light *lights, size_t nl,
                        const double n[3], const double e[3], double d[3], double s[3])
{
    double v[3] = {-e[0], -e[1], -e[2]};
    normalize3(v);
    for (int c = 0; c < 3; c++) d[c] = amb[c] * m->ambient[c], s[c] = 0.0;
    for (size_t i = 0; i < nl; i++) {
        const lit_light *l = &lights[i];
        double dir[3], att = 1.0;
        if (l->directional) {
            memcpy(dir, l->pos, sizeof dir);
        } else {
            for (int c = 0; c < 3; c++) dir[c] = l->pos[c] - e[c];
            double dist = sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
            normalize3(dir);
            att = 1.0 / (l->att[0] + l->att[1] * dist + l->att[2] * dist * dist);
        }
        double ndl = n[0] * dir[0] + n[1] * dir[1] + n[2] * dir[2];
        if (ndl <= 0.0) continue;
        double h[3] = {dir[0] + v[0], dir[1] + v[1], dir[2] + v[2]};
        normalize3(h);
        double ndh = n[0] * h[0] + n[1] * h[1] + n[2] * h[2];
        double sp = ndh > 0.0 && m->shininess > 0.0f ? pow(ndh, m->shininess) : 0.0;
        for (int c = 0; c < 3; c++) {
            d[c] += att * l->color[c] * m->diffuse[c] * ndl;
            s[c] += att * l->color[c] * m->specular[c] * sp;
        }
    }
}

/* The scene's lights in eye space (view matrix V, column-major). */
static void eye_lights(const persp_scene *scene, const double V[16], lit_light *lights, size_t nl)
{
    for (size_t i = 0; i < nl; i++) {
        persp_scene_light l;
        persp_scene_get_light(scene, i, &l);
        lights[i].directional = l.directional;
        for (int c = 0; c < 3; c++) lights[i].color[c] = l.color[c], lights[i].att[c] = l.attenuation[c];
        for (int row = 0; row < 3; row++) {
            double s = l.directional ? 0.0 : V[12 + row];
            for (int c = 0; c < 3; c++) s += V[c * 4 + row] * l.position[c];
            lights[i].pos[row] = s;
        }
        if (l.directional) normalize3(lights[i].pos);
    }
}

/* An object's vertices in eye space: positions, unit normals and (where
 * any differs from white) colours. 0 when out of memory. */
static int eye_object(const persp_scene_object *so, const double V[16], lit_object *lo)
{
    double M[16], VM[16];
    m4_of(so->model, M);
    m4_mul(V, M, VM);
    /* Normals by the inverse transpose of the linear part (cofactors;
     * the determinant's scale is removed by normalising). */
    const double a = VM[0], b = VM[4], c = VM[8], d = VM[1], e = VM[5], f = VM[9], g = VM[2], hh = VM[6],
                 k = VM[10];
    const double cof[3][3] = {{e * k - f * hh, -(d * k - f * g), d * hh - e * g},
                              {-(b * k - c * hh), a * k - c * g, -(a * hh - b * g)},
                              {b * f - c * e, -(a * f - c * d), a * e - b * d}};
    const double det = a * cof[0][0] + b * cof[0][1] + c * cof[0][2];
    size_t nv = so->vertex_count ? so->vertex_count : 1;
    lo->eye_pos = malloc(nv * 3 * sizeof(double));
    lo->eye_nrm = malloc(nv * 3 * sizeof(double));
    int colored = 0;
    for (size_t i = 0; i < so->vertex_count; i++)
        for (int ch = 0; ch < 3; ch++) colored |= so->vertices[i].color[ch] != 1.0f;
    lo->color = colored ? malloc(nv * 3 * sizeof(double)) : NULL;
    if (!lo->eye_pos || !lo->eye_nrm || (colored && !lo->color)) return 0;
    for (size_t i = 0; i < so->vertex_count; i++) {
        const persp_vertex *v = &so->vertices[i];
        for (int row = 0; row < 3; row++) {
            double s = VM[12 + row];
            for (int col = 0; col < 3; col++) s += VM[col * 4 + row] * v->pos[col];
            lo->eye_pos[i * 3 + (size_t)row] = s;
            double nn = 0.0;
            for (int col = 0; col < 3; col++) nn += cof[row][col] * v->normal[col];
            lo->eye_nrm[i * 3 + (size_t)row] = det < 0.0 ? -nn : nn;
            if (colored) lo->color[i * 3 + (size_t)row] = v->color[row];
        }
        normalize3(&lo->eye_nrm[i * 3]);
    }
    return 1;
}

/* The lit colour at a hit, diffuse (with ambient) into d and specular into
 * s: per pixel (Phong) or per vertex, linear on the screen (Gouraud). */
static void hit_lighting(const persp_scene_object *so, const lit_object *ob, const diff_ref_hit *hit,
                         const double amb[3], const lit_light *lights, size_t nl, int gouraud, double d[3],
                         double s[3])
{
    size_t vi[3];
    for (int k = 0; k < 3; k++) vi[k] = so->indices[hit->first_index + (size_t)k];
    /* Two-sided: the triangle is lit from behind when its summed vertex
     * normals face away from the eye. */
    double facing = 0.0;
    for (int c = 0; c < 3; c++) {
        double ns = 0.0, es = 0.0;
        for (int k = 0; k < 3; k++) {
            ns += ob->eye_nrm[vi[k] * 3 + (size_t)c];
            es += ob->eye_pos[vi[k] * 3 + (size_t)c];
        }
        facing += ns * es;
    }
    const double side = facing > 0.0 ? -1.0 : 1.0;
    if (!gouraud) {
        double n[3] = {0, 0, 0}, e[3] = {0, 0, 0}, col[3] = {0, 0, 0};
        for (int k = 0; k < 3; k++)
            for (int c = 0; c < 3; c++) {
                n[c] += hit->b[k] * side * ob->eye_nrm[vi[k] * 3 + (size_t)c];
                e[c] += hit->b[k] * ob->eye_pos[vi[k] * 3 + (size_t)c];
                if (ob->color) col[c] += hit->b[k] * ob->color[vi[k] * 3 + (size_t)c];
            }
        normalize3(n);
        blinn_phong(&so->material, amb, lights, nl, n, e, d, s);
        if (ob->color)
            for (int c = 0; c < 3; c++) d[c] *= col[c];
        return;
    }
    /* Vertex colours (ambient + diffuse + specular), linear on the screen;
     * no separate specular. */
    for (int c = 0; c < 3; c++) d[c] = s[c] = 0.0;
    for (int k = 0; k < 3; k++) {
        double n[3], dk[3], sk[3];
        for (int c = 0; c < 3; c++) n[c] = side * ob->eye_nrm[vi[k] * 3 + (size_t)c];
        blinn_phong(&so->material, amb, lights, nl, n, &ob->eye_pos[vi[k] * 3], dk, sk);
        for (int c = 0; c < 3; c++) {
            double col = ob->color ? ob->color[vi[k] * 3 + (size_t)c] : 1.0;
            d[c] += hit->screen_b[k] * (dk[c] * col + sk[c]);
        }
    }
}

/* The range a lit pixel may take: the lighting combined with the texel's
 * range q by the material's texture environment. */
static void lit_range(const persp_scene_material *m, const diff_ref_pixel *q, const double d[3],
                      const double s[3], double lo[3], double hi[3])
{
    const int textured = m->texture >= 0;
    const int replace = textured && m->env == PERSP_SCENE_TEXENV_REPLACE;
    const int spec_tex = textured && m->specular_texture;
    for (int c = 0; c < 3; c++) {
        /* The filtered texel is an 8-bit value before it is combined
         * (persp's samplers return RGBA8): half a level either side of
         * GL's real-valued interval. */
        double tlo = textured ? fmax(q->lo[c] - 0.5, 0.0) / 255.0 : 1.0;
        double thi = textured ? fmin(q->hi[c] + 0.5, 255.0) / 255.0 : 1.0;
        if (replace) {
            lo[c] = 255.0 * tlo, hi[c] = 255.0 * thi;
        } else {
            lo[c] = 255.0 * (d[c] * tlo + s[c] * (spec_tex ? tlo : 1.0));
            hi[c] = 255.0 * (d[c] * thi + s[c] * (spec_tex ? thi : 1.0));
        }
        lo[c] = fmin(fmax(lo[c], 0.0), 255.0), hi[c] = fmin(fmax(hi[c], 0.0), 255.0);
    }
}

oracle_lit_result oracle_check_lit(const persp_scene *scene, const persp_image *img, int gouraud, double tol)
{
    oracle_lit_result r;
    memset(&r, 0, sizeof r);
    r.first_x = r.first_y = -1;
    const int w = img->width, h = img->height;
    persp_scene_info info;
    persp_scene_get_info(scene, &info);
    persp_mat4 view;
    persp_scene_get_camera(scene, w, h, &view, NULL);
    double V[16];
    m4_of(view, V);
    diff_ref *ref = diff_ref_create(scene, w, h, info.filter);
    size_t nobj = persp_scene_object_count(scene), nl = persp_scene_light_count(scene);
    lit_object *objs = calloc(nobj ? nobj : 1, sizeof *objs);
    lit_light *lights = calloc(nl ? nl : 1, sizeof *lights);
    int ready = ref && objs && lights;
    if (ready) eye_lights(scene, V, lights, nl);
    for (size_t o = 0; ready && o < nobj; o++) {
        persp_scene_object so;
        persp_scene_get_object(scene, o, &so);
        ready = eye_object(&so, V, &objs[o]);
    }
    if (!ready) {
        r.off = (size_t)w * (size_t)h + 1; /* cannot check: fail loudly */
        goto done;
    }
    double amb[3] = {info.ambient[0], info.ambient[1], info.ambient[2]};
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            const uint8_t *p = img->pixels + (size_t)y * img->stride + 4 * (size_t)x;
            diff_ref_pixel q = diff_ref_eval(ref, x, y);
            diff_ref_hit hit;
            double lo[3], hi[3];
            if (q.background_ok && !q.covered) {
                for (int c = 0; c < 3; c++) lo[c] = hi[c] = info.clear[c];
                r.background++;
            } else if (diff_ref_front(ref, x, y, &hit) && (!gouraud || hit.screen_ok)) {
                persp_scene_object so;
                persp_scene_get_object(scene, (size_t)hit.object, &so);
                double d[3], s[3];
                hit_lighting(&so, &objs[hit.object], &hit, amb, lights, nl, gouraud, d, s);
                lit_range(&so.material, &q, d, s, lo, hi);
                r.lit++;
            } else {
                continue; /* an edge or a depth tie: the surface is in doubt */
            }
            r.checked++;
            int ok = 1;
            for (int c = 0; c < 3; c++) ok &= p[c] >= lo[c] - tol && p[c] <= hi[c] + tol;
            if (!ok) {
                if (!r.off) {
                    r.first_x = x, r.first_y = y;
                    for (int c = 0; c < 3; c++) r.first_lo[c] = lo[c], r.first_hi[c] = hi[c], r.first_got[c] = p[c];
                }
                r.off++;
            }
        }
done:
    for (size_t o = 0; objs && o < nobj; o++) {
        free(objs[o].eye_pos);
        free(objs[o].eye_nrm);
        free(objs[o].color);
    }
    free(objs);
    free(lights);
    diff_ref_destroy(ref);
    return r;
}
