/*
 * Vertex normals for a mesh whose file gives none (docs/SCENES.md, "Models"):
 * each triangle corner gets the sum of the normals of the triangles around
 * its position that turn less than the crease angle from its own, each
 * weighted by the triangle's angle at that position (Thürmer and Wüthrich,
 * "Computing vertex normals from polygonal facets", JGT 3(1), 1998: the
 * result does not change when a face is cut into more triangles). Corners of
 * one vertex that get different normals become vertices of their own, so a
 * cube keeps its edges (8 shared vertices become 24) and a tessellated
 * sphere stays smooth. With a crease of zero only coplanar neighbours are
 * summed: flat normals, as glTF 2.0 §3.7.2.1 requires of a mesh without
 * NORMAL.
 *
 * Memory: per corner one position-group index, one normal and a hash slot,
 * all from the context's allocator and freed before return.
 */
#include "geom/scene.h"

#include "core/internal.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

/* A position shared by more corners than this (a fan of thousands of
 * triangles round one point) gets the angle-weighted sum of all of them
 * without the crease test, which would otherwise cost the square of the
 * count. */
#define CREASE_MAX_FAN 512

static void unit(float n[3])
{
    float len = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (len > 0.0f && isfinite(len)) {
        n[0] /= len, n[1] /= len, n[2] /= len;
    } else {
        n[0] = 0.0f, n[1] = 0.0f, n[2] = 1.0f;
    }
}

static float corner_angle(const float *p, const float *a, const float *b)
{
    const float u[3] = {a[0] - p[0], a[1] - p[1], a[2] - p[2]};
    const float v[3] = {b[0] - p[0], b[1] - p[1], b[2] - p[2]};
    float lu = sqrtf(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    float lv = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (!(lu > 0.0f) || !(lv > 0.0f)) return 0.0f;
    float c = (u[0] * v[0] + u[1] * v[1] + u[2] * v[2]) / (lu * lv);
    return acosf(fminf(fmaxf(c, -1.0f), 1.0f));
}

static uint64_t hash_bits(const void *p, size_t n, uint64_t h)
{
    const unsigned char *b = p;
    for (size_t k = 0; k < n; k++) h = (h ^ b[k]) * 1099511628211ull;
    return h;
}

#define EMPTY UINT32_MAX

/* Each triangle's unit normal (fn, 4 floats a triangle) and each corner's
 * angle, its weight in the vertex normal. */
static void face_normals(const persp_mesh *m, float *fn, float *weight)
{
    for (size_t t = 0; t < m->index_count / 3; t++) {
        const float *p[3];
        for (int k = 0; k < 3; k++) p[k] = m->vertices[m->indices[3 * t + (size_t)k]].pos;
        const float u[3] = {p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]};
        const float v[3] = {p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]};
        float *n = fn + 4 * t;
        n[0] = u[1] * v[2] - u[2] * v[1];
        n[1] = u[2] * v[0] - u[0] * v[2];
        n[2] = u[0] * v[1] - u[1] * v[0];
        unit(n);
        for (int k = 0; k < 3; k++)
            weight[3 * t + (size_t)k] = corner_angle(p[k], p[(k + 1) % 3], p[(k + 2) % 3]);
    }
}

/* Vertices grouped by position, bit for bit: vertices that differ only in
 * texture coordinates or colour (a seam) are smoothed together. group[i]
 * is vertex i's; returns the number of groups. table: cap slots (a power
 * of two, at least twice the vertices). */
static size_t position_groups(const persp_mesh *m, uint32_t *table, size_t cap, uint32_t *group)
{
    memset(table, 0xff, cap * sizeof *table);
    size_t groups = 0;
    for (size_t i = 0; i < m->vertex_count; i++) {
        const float *p = m->vertices[i].pos;
        for (size_t s = (size_t)hash_bits(p, 3 * sizeof *p, 1469598103934665603ull) & (cap - 1);;
             s = (s + 1) & (cap - 1)) {
            if (table[s] == EMPTY) {
                table[s] = (uint32_t)i;
                group[i] = (uint32_t)groups++;
                break;
            }
            if (!memcmp(m->vertices[table[s]].pos, p, 3 * sizeof *p)) {
                group[i] = group[table[s]];
                break;
            }
        }
    }
    return groups;
}

/* Each corner's normal (cn, 3 floats a corner): the angle-weighted sum of
 * the normals of the faces at its position within the crease limit of its
 * own, unit length. off[g] .. off[g + 1] index list[], the corners at
 * position g. */
static void corner_normals(const uint32_t *off, const uint32_t *list, size_t groups, const float *fn,
                           const float *weight, float limit, float *cn)
{
    for (size_t g = 0; g < groups; g++) {
        const uint32_t a = off[g], b = off[g + 1];
        float all[3] = {0, 0, 0};
        if (b - a > CREASE_MAX_FAN)
            for (uint32_t k = a; k < b; k++)
                for (int d = 0; d < 3; d++) all[d] += weight[list[k]] * fn[4 * (list[k] / 3) + (size_t)d];
        for (uint32_t k = a; k < b; k++) {
            const size_t c = list[k];
            const float *own = fn + 4 * (c / 3);
            float *sum = cn + 3 * c;
            if (b - a > CREASE_MAX_FAN) {
                memcpy(sum, all, sizeof all);
            } else {
                sum[0] = sum[1] = sum[2] = 0.0f;
                for (uint32_t j = a; j < b; j++) {
                    const float *o = fn + 4 * (list[j] / 3);
                    if (list[j] == c || o[0] * own[0] + o[1] * own[1] + o[2] * own[2] >= limit)
                        for (int d = 0; d < 3; d++) sum[d] += weight[list[j]] * o[d];
                }
            }
            /* A corner of no angle (a degenerate triangle) takes its face's normal. */
            if (!(sum[0] * sum[0] + sum[1] * sum[1] + sum[2] * sum[2] > 0.0f)) memcpy(sum, own, 3 * sizeof *sum);
            unit(sum);
        }
    }
}

/* The corners' normals, each with the mesh's own normal per corner (cn). */
static persp_status crease_corner_normals(persp_context *ctx, const persp_mesh *m, float limit, float *cn)
{
    const size_t nc = m->index_count, nv = m->vertex_count, nt = nc / 3;
    size_t cap = 16;
    while (cap < 2 * (nv > nc ? nv : nc)) cap *= 2;
    /* Each block only when those before it were given: a smaller one
     * granted after a refusal would clear the refusal's detail (how much,
     * over which budget) from the error. */
    float *fn = persp__alloc(ctx, (nt ? nt : 1) * 4 * sizeof *fn); /* the unit normal of each triangle */
    float *weight = fn ? persp__alloc(ctx, nc * sizeof *weight) : NULL;
    uint32_t *group = weight ? persp__alloc(ctx, nv * sizeof *group) : NULL;
    uint32_t *table = group ? persp__alloc(ctx, cap * sizeof *table) : NULL;
    uint32_t *off = table ? persp__calloc(ctx, nv + 2, sizeof *off) : NULL;
    uint32_t *list = off ? persp__alloc(ctx, nc * sizeof *list) : NULL;
    persp_status st = PERSP_ERR_OUT_OF_MEMORY;
    if (fn && weight && group && table && off && list) {
        face_normals(m, fn, weight);
        const size_t groups = position_groups(m, table, cap, group);
        for (size_t c = 0; c < nc; c++) off[group[m->indices[c]] + 2]++;
        for (size_t g = 0; g < groups; g++) off[g + 2] += off[g + 1];
        for (size_t c = 0; c < nc; c++) list[off[group[m->indices[c]] + 1]++] = (uint32_t)c;
        corner_normals(off, list, groups, fn, weight, limit, cn);
        st = PERSP_OK;
    }
    persp__free(ctx, fn);
    persp__free(ctx, weight);
    persp__free(ctx, group);
    persp__free(ctx, table);
    persp__free(ctx, off);
    persp__free(ctx, list);
    return st;
}

/* One vertex per distinct (vertex, normal): corners that agree share. The
 * mesh takes the new vertices and indices; PERSP_ERR_TOO_LARGE beyond
 * max_vertices (the mesh is then unchanged). */
static persp_status split_vertices(persp_context *ctx, persp_mesh *m, const float *cn, size_t max_vertices)
{
    const size_t nc = m->index_count;
    size_t cap = 16;
    while (cap < 2 * nc) cap *= 2;
    uint32_t *table = persp__alloc(ctx, cap * sizeof *table); /* one after another: as above */
    persp_vertex *out = table ? persp__alloc(ctx, nc * sizeof *out) : NULL;
    uint32_t *outix = out ? persp__alloc(ctx, nc * sizeof *outix) : NULL;
    uint32_t *src = outix ? persp__alloc(ctx, nc * sizeof *src) : NULL;
    persp_status st = PERSP_ERR_OUT_OF_MEMORY;
    if (table && out && outix && src) {
        memset(table, 0xff, cap * sizeof *table);
        size_t count = 0;
        for (size_t c = 0; c < nc; c++) {
            const uint32_t v = m->indices[c];
            const float *n = cn + 3 * c;
            size_t s = (size_t)hash_bits(n, 3 * sizeof *n, (uint64_t)v * 2654435761u + 1469598103934665603ull) &
                       (cap - 1);
            for (;; s = (s + 1) & (cap - 1)) {
                const uint32_t w = table[s];
                if (w == EMPTY) {
                    out[count] = m->vertices[v];
                    memcpy(out[count].normal, n, sizeof out[count].normal);
                    src[count] = v;
                    table[s] = (uint32_t)count;
                    outix[c] = (uint32_t)count++;
                    break;
                }
                if (src[w] == v && !memcmp(out[w].normal, n, sizeof out[w].normal)) {
                    outix[c] = w;
                    break;
                }
            }
        }
        if (count > PERSP_SCENE_MAX_VERTICES || count > max_vertices) {
            st = PERSP_ERR_TOO_LARGE;
        } else {
            persp__free(ctx, m->vertices);
            m->vertices = out;
            m->vertex_count = count;
            out = NULL;
            memcpy(m->indices, outix, nc * sizeof *outix);
            m->has_normals = 0;
            st = PERSP_OK;
        }
    }
    persp__free(ctx, table);
    persp__free(ctx, out);
    persp__free(ctx, outix);
    persp__free(ctx, src);
    return st;
}

persp_status persp__mesh_crease_normals(persp_context *ctx, persp_mesh *m, float crease_deg,
                                        size_t max_vertices)
{
    const size_t nc = m->index_count;
    if (nc == 0 || m->vertex_count == 0) return PERSP_OK;
    const float limit = crease_deg > 0.0f ? cosf(fminf(crease_deg, 180.0f) * 0.01745329252f) : 1.0f - 1e-6f;
    float *cn = persp__alloc(ctx, nc * 3 * sizeof *cn);
    if (!cn) return PERSP_ERR_OUT_OF_MEMORY;
    persp_status st = crease_corner_normals(ctx, m, limit, cn);
    if (st == PERSP_OK) st = split_vertices(ctx, m, cn, max_vertices);
    persp__free(ctx, cn);
    return st;
}
