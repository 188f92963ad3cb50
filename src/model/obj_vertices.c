/*
 * The vertices of one OBJ run (src/model/obj.c): one per distinct corner with
 * the file's normals, or, where the file gives none, normals made the way
 * Assimp 5.2's GenVertexNormals step made them (80 degree crease), so that
 * images stay as they were (docs/SCENES.md, "Models").
 */
#include "model/obj_reader.h"

#include "core/internal.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

static void face_normal(const float *a, const float *b, const float *c, float *n)
{
    const float u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    const float v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    n[0] = u[1] * v[2] - u[2] * v[1];
    n[1] = u[2] * v[0] - u[0] * v[2];
    n[2] = u[0] * v[1] - u[1] * v[0];
    persp__obj_normalize(n);
}

static void fill_vertex(const obj_reader *r, const uint32_t *t, const float *normal,
                        persp_vertex *v)
{
    memset(v, 0, sizeof *v);
    memcpy(v->pos, r->pos + 3 * (size_t)t[0], sizeof v->pos);
    if (t[1] != NO_INDEX && isfinite(r->tc[2 * (size_t)t[1]]) &&
        isfinite(r->tc[2 * (size_t)t[1] + 1]))
        memcpy(v->uv, r->tc + 2 * (size_t)t[1], sizeof v->uv);
    if (normal && isfinite(normal[0]) && isfinite(normal[1]) && isfinite(normal[2]))
        memcpy(v->normal, normal, sizeof v->normal);
    for (int k = 0; k < 4; k++)
        v->color[k] = 1.0f;
    if (r->col)
        for (int k = 0; k < 3; k++) {
            float c = r->col[3 * (size_t)t[0] + (size_t)k];
            v->color[k] = isfinite(c) ? fminf(fmaxf(c, 0.0f), 1.0f) : 1.0f;
        }
}

/* Positions equal to an earlier one map to it: Assimp smoothed normals
 * across corners at one place whatever their position index. Filled as the
 * positions are read (a hash of the positions so far). */
persp_status persp__obj_canon_init(obj_reader *r)
{
    size_t n = r->nv ? r->nv : 1, cap = 16;
    while (cap < 2 * n)
        cap *= 2;
    r->canon = persp__alloc(r->ctx, n * sizeof *r->canon);
    r->group_of = persp__alloc(r->ctx, n * sizeof *r->group_of);
    r->ctable = persp__calloc(r->ctx, cap, sizeof *r->ctable);
    if (!r->canon || !r->group_of || !r->ctable) return persp__obj_oom(r);
    r->ctable_cap = cap;
    return PERSP_OK;
}

void persp__obj_canon_add(obj_reader *r, size_t i)
{
    float p[3];
    for (int k = 0; k < 3; k++) /* -0 and +0 are one place */
        p[k] = r->pos[3 * i + (size_t)k] == 0.0f ? 0.0f : r->pos[3 * i + (size_t)k];
    uint32_t b[3];
    memcpy(b, p, sizeof b);
    uint64_t h = ((uint64_t)b[0] * 0x9e3779b97f4a7c15ull) ^
                 ((uint64_t)b[1] * 0xc2b2ae3d27d4eb4full) ^
                 ((uint64_t)b[2] * 0x165667b19e3779f9ull);
    h ^= h >> 29;
    r->group_of[i] = NO_INDEX;
    for (size_t slot = (size_t)h & (r->ctable_cap - 1);; slot = (slot + 1) & (r->ctable_cap - 1)) {
        if (!r->ctable[slot]) {
            r->ctable[slot] = (uint32_t)i + 1;
            r->canon[i] = (uint32_t)i;
            return;
        }
        size_t j = r->ctable[slot] - 1;
        float q[3];
        for (int k = 0; k < 3; k++)
            q[k] = r->pos[3 * j + (size_t)k] == 0.0f ? 0.0f : r->pos[3 * j + (size_t)k];
        if (!memcmp(p, q, sizeof p)) {
            r->canon[i] = (uint32_t)j;
            return;
        }
    }
}

typedef struct extra {
    uint32_t tuple;
    float n[3];
} extra;

typedef struct group_key {
    float d;        /* along Assimp's SpatialSort direction */
    uint32_t group; /* of corners at one position */
    uint32_t pos;   /* that position */
} group_key;

static int by_distance(const void *a, const void *b)
{
    float x = ((const group_key *)a)->d, y = ((const group_key *)b)->d;
    return (x > y) - (x < y);
}

/* Normals as Assimp's GenVertexNormals step made them with a crease
 * angle: each polygon corner's normal is the sum of the face normals of the
 * polygon corners at its position whose face turns less than the crease
 * angle from its own (its own always counted), normalised. Corners of one
 * tuple with different results become different vertices. Fills
 * mesh->vertices and rewrites r->idx to vertex numbers. */
static persp_status generate_normals(obj_reader *r, persp_mesh *mesh)
{
    const size_t ntri = r->nidx / 3, U = r->ntuples;
    const float limit = cosf(r->crease_deg * 0.0174532925f);
    float *fn = persp__alloc(r->ctx, (ntri ? ntri : 1) * 3 * sizeof *fn);
    float *first = persp__alloc(r->ctx, (U ? U : 1) * 3 * sizeof *first);
    uint32_t *off = NULL, *list = NULL, *near = NULL;
    group_key *keys = NULL;
    extra *extras = NULL;
    uint32_t *xtable = NULL;
    size_t nextra = 0, extras_cap = 0, xcap = 0, near_cap = 0;
    size_t groups = 0;
    if (!fn || !first) goto nomem;
    for (size_t t = 0; t < ntri; t++) {
        const float *p[3];
        for (int k = 0; k < 3; k++)
            p[k] = r->pos +
                   3 * (size_t)r->tuples[3 * (size_t)(r->idx[3 * t + (size_t)k] & ~OWNER_BIT)];
        face_normal(p[0], p[1], p[2], fn + 3 * t);
    }
    /* Corners grouped by position (canonical); the groups sorted along one
     * direction, so that the groups within eps of one are found by a short
     * scan, as Assimp's SpatialSort finds them. eps is Assimp's: 1e-4 of
     * the run's bounding box diagonal. */
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t u = 0; u < U; u++) {
        uint32_t c = r->canon[r->tuples[3 * u]];
        if (r->group_of[c] == NO_INDEX) r->group_of[c] = (uint32_t)groups++;
        for (int k = 0; k < 3; k++) {
            float v = r->pos[3 * (size_t)c + (size_t)k];
            lo[k] = fminf(lo[k], v), hi[k] = fmaxf(hi[k], v);
        }
    }
    const float dx = hi[0] - lo[0], dy = hi[1] - lo[1], dz = hi[2] - lo[2];
    const float eps = sqrtf(dx * dx + dy * dy + dz * dz) * 1e-4f;
    off = persp__calloc(r->ctx, groups + 2, sizeof *off);
    list = persp__alloc(r->ctx, (r->nidx ? r->nidx : 1) * sizeof *list);
    keys = persp__alloc(r->ctx, (groups ? groups : 1) * sizeof *keys);
    if (!off || !list || !keys) goto nomem;
    for (size_t u = 0; u < U; u++) {
        uint32_t c = r->canon[r->tuples[3 * u]], g = r->group_of[c];
        const float *p = r->pos + 3 * (size_t)c;
        keys[g].d = 0.8523f * p[0] + 0.34321f * p[1] + 0.5736f * p[2];
        keys[g].group = g;
        keys[g].pos = c;
    }
    qsort(keys, groups, sizeof *keys, by_distance);
    for (size_t c = 0; c < r->nidx; c++)
        off[r->group_of[r->canon[r->tuples[3 * (size_t)(r->idx[c] & ~OWNER_BIT)]]] + 2]++;
    for (size_t g = 0; g < groups; g++)
        off[g + 2] += off[g + 1];
    for (size_t c = 0; c < r->nidx; c++)
        list[off[r->group_of[r->canon[r->tuples[3 * (size_t)(r->idx[c] & ~OWNER_BIT)]]] + 1]++] =
            (uint32_t)c;
    /* off[g] .. off[g + 1] now spans group g. */
    for (size_t u = 0; u < 3 * U; u++)
        first[u] = NAN;
    for (size_t i = 0; i < groups; i++) {
        const float *p = r->pos + 3 * (size_t)keys[i].pos;
        size_t nnear = 0;
        for (size_t j = i + 1; j-- > 0;) {
            if (j < i && !(keys[i].d - keys[j].d < eps)) break;
            const float *q = r->pos + 3 * (size_t)keys[j].pos;
            float ex = q[0] - p[0], ey = q[1] - p[1], ez = q[2] - p[2];
            if (j != i && !(ex * ex + ey * ey + ez * ez < eps * eps)) continue;
            if (persp__grow(r->ctx, (void **)&near, &near_cap, nnear + 1, sizeof *near) != PERSP_OK)
                goto nomem;
            near[nnear++] = keys[j].group;
        }
        for (size_t j = i + 1; j < groups && keys[j].d - keys[i].d < eps; j++) {
            const float *q = r->pos + 3 * (size_t)keys[j].pos;
            float ex = q[0] - p[0], ey = q[1] - p[1], ez = q[2] - p[2];
            if (!(ex * ex + ey * ey + ez * ez < eps * eps)) continue;
            if (persp__grow(r->ctx, (void **)&near, &near_cap, nnear + 1, sizeof *near) != PERSP_OK)
                goto nomem;
            near[nnear++] = keys[j].group;
        }
        const uint32_t g = keys[i].group;
        for (uint32_t k = off[g]; k < off[g + 1]; k++) {
            const size_t c = list[k];
            uint32_t t = r->idx[c] & ~OWNER_BIT;
            const float *own = fn + 3 * (c / 3);
            float sum[3] = {0, 0, 0};
            /* Only the corner standing for each polygon corner counts. */
            for (size_t h = 0; h < nnear; h++)
                for (uint32_t m = off[near[h]]; m < off[near[h] + 1]; m++) {
                    if (!(r->idx[list[m]] & OWNER_BIT)) continue;
                    const float *o = fn + 3 * (list[m] / 3);
                    if (list[m] == c || o[0] * own[0] + o[1] * own[1] + o[2] * own[2] >= limit)
                        sum[0] += o[0], sum[1] += o[1], sum[2] += o[2];
                }
            persp__obj_normalize(sum);
            float *f = first + 3 * (size_t)t;
            uint32_t vid = t;
            if (isnan(f[0])) {
                memcpy(f, sum, sizeof sum);
            } else if (memcmp(f, sum, sizeof sum) != 0) {
                /* Another normal at this tuple: a vertex of its own, found again
                 * through a small hash of (tuple, normal). */
                if (nextra * 2 >= xcap) {
                    size_t ncap = xcap ? 2 * xcap : 64;
                    uint32_t *nt = persp__calloc(r->ctx, ncap, sizeof *nt);
                    if (!nt) goto nomem;
                    for (size_t x = 0; x < nextra; x++) {
                        uint32_t hb[3];
                        memcpy(hb, extras[x].n, sizeof hb);
                        size_t s = (size_t)((extras[x].tuple * 2654435761u) ^ hb[0] ^
                                            (hb[1] * 31u) ^ (hb[2] * 131u)) &
                                   (ncap - 1);
                        while (nt[s])
                            s = (s + 1) & (ncap - 1);
                        nt[s] = (uint32_t)x + 1;
                    }
                    persp__free(r->ctx, xtable);
                    xtable = nt;
                    xcap = ncap;
                }
                uint32_t hb[3];
                memcpy(hb, sum, sizeof hb);
                size_t s = (size_t)((t * 2654435761u) ^ hb[0] ^ (hb[1] * 31u) ^ (hb[2] * 131u)) &
                           (xcap - 1);
                for (;; s = (s + 1) & (xcap - 1)) {
                    if (!xtable[s]) {
                        if (persp__grow(r->ctx, (void **)&extras, &extras_cap, nextra + 1,
                                        sizeof *extras) != PERSP_OK)
                            goto nomem;
                        extras[nextra].tuple = t;
                        memcpy(extras[nextra].n, sum, sizeof sum);
                        xtable[s] = (uint32_t)++nextra;
                        vid = (uint32_t)(U + nextra - 1);
                        break;
                    }
                    const extra *x = &extras[xtable[s] - 1];
                    if (x->tuple == t && !memcmp(x->n, sum, sizeof sum)) {
                        vid = (uint32_t)(U + xtable[s] - 1);
                        break;
                    }
                }
            }
            r->idx[c] = vid | (r->idx[c] & OWNER_BIT);
        }
    }
    for (size_t u = 0; u < U; u++)
        r->group_of[r->canon[r->tuples[3 * u]]] = NO_INDEX;
    persp__free(r->ctx, fn);
    persp__free(r->ctx, off);
    persp__free(r->ctx, list);
    persp__free(r->ctx, xtable);
    persp__free(r->ctx, near);
    persp__free(r->ctx, keys);
    fn = NULL, off = list = xtable = near = NULL;
    keys = NULL;
    if (U + nextra > PERSP_SCENE_MAX_VERTICES || U + nextra > r->max_vertices - r->vertices_used) {
        persp__free(r->ctx, first);
        persp__free(r->ctx, extras);
        return persp__obj_too_large(r);
    }
    mesh->vertex_count = U + nextra;
    mesh->vertices = persp__alloc(r->ctx, mesh->vertex_count * sizeof *mesh->vertices);
    if (!mesh->vertices) goto nomem;
    for (size_t u = 0; u < U; u++)
        fill_vertex(r, r->tuples + 3 * u, first + 3 * u, &mesh->vertices[u]);
    for (size_t i = 0; i < nextra; i++)
        fill_vertex(r, r->tuples + 3 * (size_t)extras[i].tuple, extras[i].n,
                    &mesh->vertices[U + i]);
    persp__free(r->ctx, first);
    persp__free(r->ctx, extras);
    return PERSP_OK;
nomem:
    for (size_t u = 0; u < U && r->group_of; u++)
        r->group_of[r->canon[r->tuples[3 * u]]] = NO_INDEX;
    persp__free(r->ctx, fn);
    persp__free(r->ctx, first);
    persp__free(r->ctx, off);
    persp__free(r->ctx, list);
    persp__free(r->ctx, xtable);
    persp__free(r->ctx, extras);
    persp__free(r->ctx, near);
    persp__free(r->ctx, keys);
    return persp__obj_oom(r);
}

persp_status persp__obj_run_vertices(obj_reader *r, persp_mesh *mesh)
{
    if (!r->file_normals) return generate_normals(r, mesh);
    if (r->ntuples > r->max_vertices - r->vertices_used) return persp__obj_too_large(r);
    mesh->vertex_count = r->ntuples;
    mesh->vertices = persp__alloc(r->ctx, (r->ntuples ? r->ntuples : 1) * sizeof *mesh->vertices);
    if (!mesh->vertices) return persp__obj_oom(r);
    for (size_t u = 0; u < r->ntuples; u++) {
        const uint32_t *t = r->tuples + 3 * u;
        fill_vertex(r, t, r->nrm + 3 * (size_t)t[2], &mesh->vertices[u]);
    }
    return PERSP_OK;
}
