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

/* Assimp's scan and crease test cost the square of the corners at or near
 * one place: 10^5 triangles round one vertex (1.6 MB of "f 1 2 3") took
 * 36 s, a 300x300 grid in the plane across the sort direction 28 s. Past
 * this many scan steps and corner pairs in one file (under a second on the
 * development machine) it is refused, as the object-space pipeline refuses
 * a walk over its limit; the 1M-triangle grid of docs/RELIABILITY.md
 * takes 1.1e8. */
#define OBJ_NORMALS_MAX_WORK (1ull << 28)

typedef struct extra {
    uint32_t tuple;
    float n[3];
} extra;

typedef struct group_key {
    float d;        /* along Assimp's SpatialSort direction */
    uint32_t group; /* of corners at one position */
    uint32_t pos;   /* that position */
    float p[3];     /* its coordinates, beside d for the scan (near_add) */
} group_key;

static int by_distance(const void *a, const void *b)
{
    float x = ((const group_key *)a)->d, y = ((const group_key *)b)->d;
    return (x > y) - (x < y);
}

/* What generate_normals works with, freed in one place (normals_free). */
typedef struct normals_work {
    float *fn;     /* face normal of each triangle */
    float *first;  /* the first normal met at each tuple (NaN: none yet) */
    uint32_t *off; /* corners of group g: list[off[g] .. off[g + 1]) */
    uint32_t *list;
    group_key *keys; /* the groups sorted along the SpatialSort direction */
    size_t groups;
    float eps;       /* Assimp's: 1e-4 of the run's bounding box diagonal */
    uint32_t *near;  /* the groups within eps of the one at hand */
    size_t near_cap;
    extra *extras;   /* vertices beyond the tuples: a tuple with another normal */
    size_t nextra, extras_cap;
    uint32_t *xtable; /* open-addressing hash of extras by (tuple, normal) */
    size_t xcap;
} normals_work;

/* The arrays of the scan over the groups; the group marks go back to
 * NO_INDEX for the next run. */
static void normals_free_scan(obj_reader *r, normals_work *w)
{
    for (size_t u = 0; u < r->ntuples && r->group_of; u++)
        r->group_of[r->canon[r->tuples[3 * u]]] = NO_INDEX;
    void *blocks[] = {w->fn, w->off, w->list, w->xtable, w->near, w->keys};
    for (size_t i = 0; i < sizeof blocks / sizeof blocks[0]; i++)
        persp__free(r->ctx, blocks[i]);
    w->fn = NULL, w->off = w->list = w->xtable = w->near = NULL, w->keys = NULL;
}

static void normals_free(obj_reader *r, normals_work *w)
{
    normals_free_scan(r, w);
    persp__free(r->ctx, w->first);
    persp__free(r->ctx, w->extras);
    w->first = NULL, w->extras = NULL;
}

static uint32_t corner_tuple(const obj_reader *r, size_t c) { return r->idx[c] & ~OWNER_BIT; }

static uint32_t corner_group(const obj_reader *r, size_t c)
{
    return r->group_of[r->canon[r->tuples[3 * (size_t)corner_tuple(r, c)]]];
}

static void face_normals(const obj_reader *r, normals_work *w)
{
    for (size_t t = 0; t < r->nidx / 3; t++) {
        const float *p[3];
        for (int k = 0; k < 3; k++) p[k] = r->pos + 3 * (size_t)r->tuples[3 * (size_t)corner_tuple(r, 3 * t + (size_t)k)];
        face_normal(p[0], p[1], p[2], w->fn + 3 * t);
    }
}

/* Corners grouped by position (canonical); the groups sorted along one
 * direction, so that the groups within eps of one are found by a short
 * scan, as Assimp's SpatialSort finds them. 0: out of memory. */
static int group_corners(obj_reader *r, normals_work *w)
{
    const size_t U = r->ntuples;
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t u = 0; u < U; u++) {
        uint32_t c = r->canon[r->tuples[3 * u]];
        if (r->group_of[c] == NO_INDEX) r->group_of[c] = (uint32_t)w->groups++;
        for (int k = 0; k < 3; k++) {
            float v = r->pos[3 * (size_t)c + (size_t)k];
            lo[k] = fminf(lo[k], v), hi[k] = fmaxf(hi[k], v);
        }
    }
    const float dx = hi[0] - lo[0], dy = hi[1] - lo[1], dz = hi[2] - lo[2];
    w->eps = sqrtf(dx * dx + dy * dy + dz * dz) * 1e-4f;
    w->off = persp__calloc(r->ctx, w->groups + 2, sizeof *w->off);
    w->list = persp__alloc(r->ctx, (r->nidx ? r->nidx : 1) * sizeof *w->list);
    w->keys = persp__alloc(r->ctx, (w->groups ? w->groups : 1) * sizeof *w->keys);
    if (!w->off || !w->list || !w->keys) return 0;
    for (size_t u = 0; u < U; u++) {
        uint32_t c = r->canon[r->tuples[3 * u]], g = r->group_of[c];
        const float *p = r->pos + 3 * (size_t)c;
        w->keys[g].d = 0.8523f * p[0] + 0.34321f * p[1] + 0.5736f * p[2];
        w->keys[g].group = g;
        w->keys[g].pos = c;
        memcpy(w->keys[g].p, p, sizeof w->keys[g].p);
    }
    qsort(w->keys, w->groups, sizeof *w->keys, by_distance);
    for (size_t c = 0; c < r->nidx; c++) w->off[corner_group(r, c) + 2]++;
    for (size_t g = 0; g < w->groups; g++) w->off[g + 2] += w->off[g + 1];
    for (size_t c = 0; c < r->nidx; c++) w->list[w->off[corner_group(r, c) + 1]++] = (uint32_t)c;
    return 1;
}

/* Sorted group j into w->near when its position is within eps of group
 * i's (i itself always); 0 when out of memory. */
static int near_add(obj_reader *r, normals_work *w, size_t i, size_t j, size_t *n)
{
    const float *p = w->keys[i].p, *q = w->keys[j].p;
    const float ex = q[0] - p[0], ey = q[1] - p[1], ez = q[2] - p[2];
    if (j != i && !(ex * ex + ey * ey + ez * ez < w->eps * w->eps)) return 1;
    if (persp__grow(r->ctx, (void **)&w->near, &w->near_cap, *n + 1, sizeof *w->near) != PERSP_OK) return 0;
    w->near[(*n)++] = w->keys[j].group;
    return 1;
}

/* The groups within eps of sorted group i (itself included), in the order
 * Assimp's scan met them (down from i, then up past it), into w->near;
 * their count, or SIZE_MAX when out of memory. */
static size_t near_groups(obj_reader *r, normals_work *w, size_t i)
{
    const group_key *keys = w->keys;
    size_t n = 0, j = i + 1;
    while (j-- > 0) {
        if (j < i && !(keys[i].d - keys[j].d < w->eps)) break;
        if (!near_add(r, w, i, j, &n)) return SIZE_MAX;
    }
    r->normals_work += i + 1 - (j + 1);
    for (j = i + 1; j < w->groups && keys[j].d - keys[i].d < w->eps; j++)
        if (!near_add(r, w, i, j, &n)) return SIZE_MAX;
    r->normals_work += j - i;
    return n;
}

/* The normal of corner c: the face normals of the polygon corners in the
 * near groups that turn less than the crease from its own (its own always
 * counted; only the corner standing for each polygon corner), normalised. */
static void corner_normal(const obj_reader *r, const normals_work *w, size_t c, size_t nnear, float limit,
                          float sum[3])
{
    const float *own = w->fn + 3 * (c / 3);
    sum[0] = sum[1] = sum[2] = 0.0f;
    for (size_t h = 0; h < nnear; h++)
        for (uint32_t m = w->off[w->near[h]]; m < w->off[w->near[h] + 1]; m++) {
            if (!(r->idx[w->list[m]] & OWNER_BIT)) continue;
            const float *o = w->fn + 3 * (w->list[m] / 3);
            if (w->list[m] == c || o[0] * own[0] + o[1] * own[1] + o[2] * own[2] >= limit)
                sum[0] += o[0], sum[1] += o[1], sum[2] += o[2];
        }
    persp__obj_normalize(sum);
}

static size_t extra_slot(uint32_t tuple, const float n[3], size_t cap)
{
    uint32_t hb[3];
    memcpy(hb, n, sizeof hb);
    return (size_t)((tuple * 2654435761u) ^ hb[0] ^ (hb[1] * 31u) ^ (hb[2] * 131u)) & (cap - 1);
}

/* The vertex of tuple t with normal n, another than its first: found
 * again through the hash of (tuple, normal), or made. UINT32_MAX: out of
 * memory. */
static uint32_t extra_vertex(obj_reader *r, normals_work *w, uint32_t t, const float n[3])
{
    if (w->nextra * 2 >= w->xcap) {
        size_t ncap = w->xcap ? 2 * w->xcap : 64;
        uint32_t *nt = persp__calloc(r->ctx, ncap, sizeof *nt);
        if (!nt) return UINT32_MAX;
        for (size_t x = 0; x < w->nextra; x++) {
            size_t s = extra_slot(w->extras[x].tuple, w->extras[x].n, ncap);
            while (nt[s]) s = (s + 1) & (ncap - 1);
            nt[s] = (uint32_t)x + 1;
        }
        persp__free(r->ctx, w->xtable);
        w->xtable = nt;
        w->xcap = ncap;
    }
    const size_t U = r->ntuples;
    for (size_t s = extra_slot(t, n, w->xcap);; s = (s + 1) & (w->xcap - 1)) {
        if (!w->xtable[s]) {
            if (persp__grow(r->ctx, (void **)&w->extras, &w->extras_cap, w->nextra + 1, sizeof *w->extras) !=
                PERSP_OK)
                return UINT32_MAX;
            w->extras[w->nextra].tuple = t;
            memcpy(w->extras[w->nextra].n, n, 3 * sizeof *n);
            w->xtable[s] = (uint32_t)++w->nextra;
            return (uint32_t)(U + w->nextra - 1);
        }
        const extra *x = &w->extras[w->xtable[s] - 1];
        if (x->tuple == t && !memcmp(x->n, n, 3 * sizeof *n)) return (uint32_t)(U + w->xtable[s] - 1);
    }
}

/* Every corner's normal; corners of one tuple with different normals
 * become different vertices (r->idx rewritten to vertex numbers). 0: out
 * of memory; -1: over OBJ_NORMALS_MAX_WORK (checked before each group's
 * corner pairs are summed). */
static int corner_normals(obj_reader *r, normals_work *w)
{
    const float limit = cosf(r->crease_deg * 0.0174532925f);
    for (size_t i = 0; i < w->groups; i++) {
        const size_t nnear = near_groups(r, w, i);
        if (nnear == SIZE_MAX) return 0;
        const uint32_t g = w->keys[i].group;
        uint64_t near_corners = 0;
        for (size_t h = 0; h < nnear; h++) near_corners += w->off[w->near[h] + 1] - w->off[w->near[h]];
        r->normals_work += (uint64_t)(w->off[g + 1] - w->off[g]) * near_corners;
        if (r->normals_work > OBJ_NORMALS_MAX_WORK) return -1;
        for (uint32_t k = w->off[g]; k < w->off[g + 1]; k++) {
            const size_t c = w->list[k];
            const uint32_t t = corner_tuple(r, c);
            float sum[3];
            corner_normal(r, w, c, nnear, limit, sum);
            float *f = w->first + 3 * (size_t)t;
            uint32_t vid = t;
            if (isnan(f[0]))
                memcpy(f, sum, sizeof sum);
            else if (memcmp(f, sum, sizeof sum) != 0 && (vid = extra_vertex(r, w, t, sum)) == UINT32_MAX)
                return 0;
            r->idx[c] = vid | (r->idx[c] & OWNER_BIT);
        }
    }
    return 1;
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
    normals_work w;
    memset(&w, 0, sizeof w);
    w.fn = persp__alloc(r->ctx, (ntri ? ntri : 1) * 3 * sizeof *w.fn);
    w.first = persp__alloc(r->ctx, (U ? U : 1) * 3 * sizeof *w.first);
    int ok = w.fn && w.first;
    if (ok) {
        face_normals(r, &w);
        for (size_t u = 0; u < 3 * U; u++) w.first[u] = NAN;
        ok = group_corners(r, &w) ? corner_normals(r, &w) : 0;
    }
    /* The scan's arrays go before the vertices are made. */
    normals_free_scan(r, &w);
    if (ok < 0) {
        normals_free(r, &w);
        return persp__fail(r->ctx, PERSP_ERR_TOO_LARGE,
                           "%s: making the normals the file does not give takes more than %llu steps "
                           "(too many corners at or near one place); give the model normals (vn)",
                           r->display, (unsigned long long)OBJ_NORMALS_MAX_WORK);
    }
    if (ok && (U + w.nextra > PERSP_SCENE_MAX_VERTICES || U + w.nextra > r->max_vertices - r->vertices_used)) {
        normals_free(r, &w);
        return persp__obj_too_large(r);
    }
    if (ok) {
        mesh->vertex_count = U + w.nextra;
        mesh->vertices = persp__alloc(r->ctx, mesh->vertex_count * sizeof *mesh->vertices);
        ok = mesh->vertices != NULL;
    }
    if (ok) {
        for (size_t u = 0; u < U; u++) fill_vertex(r, r->tuples + 3 * u, w.first + 3 * u, &mesh->vertices[u]);
        for (size_t i = 0; i < w.nextra; i++)
            fill_vertex(r, r->tuples + 3 * (size_t)w.extras[i].tuple, w.extras[i].n, &mesh->vertices[U + i]);
    }
    normals_free(r, &w);
    return ok ? PERSP_OK : persp__obj_oom(r);
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
