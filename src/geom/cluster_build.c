/*
 * Triangle clusters of a mesh (persp_cluster, src/geom/scene.h): what a
 * frame needs to cull a run of back faces whole, and to skip the vertex
 * work of vertices only culled runs use (src/raster/cluster_cull.c). The
 * bounds are those of cone culling of clustered meshes (normal cones of
 * Shirman and Abi-Ezzi 1993, as GPU mesh pipelines use them); what persp
 * adds is a bound under which a cluster's test implies the rasterizer's own
 * per-triangle decision, so that culling whole clusters changes no pixel.
 */
#include "core/internal.h"
#include "geom/scene.h"

#include <math.h>
#include <string.h>

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
/* fmin and fmax without their NaN rules (every value here is finite), so
 * that they compile to one instruction instead of a libm call. */
static double lesser(double a, double b)
{
    return a < b ? a : b;
}
static double greater(double a, double b)
{
    return a > b ? a : b;
}

/* The first bit at or after pos that is set (set) or clear (!set) in the
 * bitmap of nw words, or nw·64. */
static size_t next_bit(const uint64_t *b, size_t nw, size_t pos, int set)
{
    while (pos < nw * 64) {
        const size_t w = pos / 64;
        const uint64_t x = (set ? b[w] : ~b[w]) & (~0ull << (pos % 64));
        if (x) return w * 64 + (size_t)__builtin_ctzll(x);
        pos = (w + 1) * 64;
    }
    return nw * 64;
}

/* Sorts the few indices of a cluster spread too far for the bitmap. */
static void sort_u32(uint32_t *v, int n)
{
    for (int i = 1; i < n; i++) {
        const uint32_t x = v[i];
        int j = i - 1;
        while (j >= 0 && v[j] > x) {
            v[j + 1] = v[j];
            j--;
        }
        v[j + 1] = x;
    }
}

/* The cluster's vertex indices as at most PERSP_CLUSTER_RUNS ranges: the
 * ranges of consecutive indices it uses (from a bitmap of the span of its
 * indices when that is short, as in a grid mesh's two rows, else by
 * sorting), then the closest ranges merged until few enough remain (a range
 * may then hold vertices the cluster does not use; never the reverse). */
static void vertex_runs(uint32_t *idx, int n, persp_cluster *cl)
{
    enum { SPAN_WORDS = 64 };
    uint32_t run[3 * PERSP_CLUSTER_TRIANGLES][2];
    int runs = 0;
    if (n < 1) return;
    uint32_t lo = idx[0], hi = idx[0];
    for (int i = 1; i < n; i++)
        lo = idx[i] < lo ? idx[i] : lo, hi = idx[i] > hi ? idx[i] : hi;
    if (hi - lo < SPAN_WORDS * 64) {
        uint64_t bits[SPAN_WORDS];
        const size_t nw = (hi - lo) / 64 + 1;
        memset(bits, 0, nw * sizeof bits[0]);
        for (int i = 0; i < n; i++)
            bits[(idx[i] - lo) / 64] |= 1ull << ((idx[i] - lo) % 64);
        for (size_t pos = next_bit(bits, nw, 0, 1); pos < nw * 64;
             pos = next_bit(bits, nw, pos, 1)) {
            const size_t end = next_bit(bits, nw, pos, 0);
            run[runs][0] = lo + (uint32_t)pos;
            run[runs][1] = lo + (uint32_t)end;
            runs++;
            pos = end;
        }
    } else {
        sort_u32(idx, n);
        for (int i = 0; i < n; i++) {
            if (runs && idx[i] <= run[runs - 1][1]) {
                if (idx[i] == run[runs - 1][1]) run[runs - 1][1] = idx[i] + 1;
                continue;
            }
            run[runs][0] = idx[i];
            run[runs][1] = idx[i] + 1;
            runs++;
        }
    }
    while (runs > PERSP_CLUSTER_RUNS) {
        int best = 0;
        for (int k = 1; k + 1 < runs; k++)
            if (run[k + 1][0] - run[k][1] < run[best + 1][0] - run[best][1]) best = k;
        run[best][1] = run[best + 1][1];
        memmove(&run[best + 1], &run[best + 2], (size_t)(runs - best - 2) * sizeof run[0]);
        runs--;
    }
    memcpy(cl->run, run, (size_t)runs * sizeof run[0]);
    cl->runs = runs;
}

/* Triangles [t0, t1) of mesh. Unusable when any triangle has an index out
 * of range (the frame refuses the mesh then), a position that is not
 * finite, zero area or the shape of a needle, or when the normals spread
 * over a half-space or more. */
static void build_cluster(const persp_mesh *mesh, size_t t0, size_t t1, persp_cluster *cl)
{
    memset(cl, 0, sizeof *cl);
    uint32_t idx[3 * PERSP_CLUSTER_TRIANGLES];
    int n = 0;
    for (size_t t = t0; t < t1; t++)
        for (int k = 0; k < 3; k++) {
            idx[n] = mesh->indices[3 * t + (size_t)k];
            if (idx[n] >= mesh->vertex_count) return;
            n++;
        }
    /* Every cluster with valid indices gets its runs, usable or not: the
     * frame marks the vertices of every cluster it does not cull. */
    vertex_runs(idx, n, cl);
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    double sum[3] = {0, 0, 0}, unit[PERSP_CLUSTER_TRIANGLES][3];
    double alt_min = INFINITY, edge_min = INFINITY;
    for (size_t t = t0; t < t1; t++) {
        double p[3][3];
        for (int k = 0; k < 3; k++)
            for (int c = 0; c < 3; c++) {
                p[k][c] = mesh->vertices[mesh->indices[3 * t + (size_t)k]].pos[c];
                if (!isfinite(p[k][c])) return;
                lo[c] = lesser(lo[c], p[k][c]);
                hi[c] = greater(hi[c], p[k][c]);
            }
        const double a[3] = {p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]};
        const double b[3] = {p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]};
        const double c[3] = {p[2][0] - p[1][0], p[2][1] - p[1][1], p[2][2] - p[1][2]};
        const double nrm[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                               a[0] * b[1] - a[1] * b[0]};
        const double twice_area = sqrt(dot3(nrm, nrm));
        const double edge = sqrt(greater(dot3(a, a), greater(dot3(b, b), dot3(c, c))));
        /* A sliver thinner than a millionth of its longest edge would have
         * its normal's direction computed with an error near the 1e-9 the
         * cone is widened by; such a cluster is never culled anyway (its
         * least height is too small for the bound). A point (all three
         * corners one position, as some STL files hold) has no normal. */
        if (!(twice_area > 0.0 && twice_area >= 1e-6 * edge * edge) || !isfinite(twice_area)) return;
        alt_min = lesser(alt_min, twice_area / edge);
        edge_min = lesser(edge_min, edge);
        for (int k = 0; k < 3; k++) {
            unit[t - t0][k] = nrm[k] / twice_area;
            sum[k] += unit[t - t0][k];
        }
    }
    const double len = sqrt(dot3(sum, sum));
    if (!(len > 0.0)) return;
    double axis[3] = {sum[0] / len, sum[1] / len, sum[2] / len};
    double cos_a = 1.0, r2 = 0.0;
    const double center[3] = {0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])};
    for (int i = 0; i < n; i++) {
        const float *p = mesh->vertices[idx[i]].pos;
        const double d[3] = {p[0] - center[0], p[1] - center[1], p[2] - center[2]};
        r2 = greater(r2, dot3(d, d));
    }
    for (size_t t = 0; t < t1 - t0; t++)
        cos_a = lesser(cos_a, dot3(unit[t], axis));
    /* Rounding of the bounds above is absorbed by widening them by far more
     * than it can be (relative 1e-9 against double's 1e-16). */
    cos_a -= 1e-9;
    if (!(cos_a > 0.0)) return;
    memcpy(cl->center, center, sizeof center);
    cl->radius = sqrt(r2) * (1.0 + 1e-9) + 1e-30;
    for (int k = 0; k < 3; k++) cl->half[k] = 0.5 * (hi[k] - lo[k]) * (1.0 + 1e-9) + 1e-30;
    memcpy(cl->axis, axis, sizeof axis);
    cl->cos_a = cos_a;
    cl->sin_a = lesser(1.0, sqrt(greater(0.0, 1.0 - cos_a * cos_a)) + 1e-9);
    cl->alt_min = alt_min * (1.0 - 1e-9);
    cl->edge_min = edge_min * (1.0 - 1e-9);
    cl->usable = 1;
}

persp_status persp__mesh_build_clusters(persp_context *ctx, persp_mesh *mesh)
{
    const size_t ntri = mesh->index_count / 3;
    mesh->clusters = NULL;
    mesh->cluster_count = 0;
    /* A mesh of one cluster gains nothing over its triangles' own tests. */
    if (ntri < 2 * PERSP_CLUSTER_TRIANGLES) return PERSP_OK;
    const size_t count = (ntri + PERSP_CLUSTER_TRIANGLES - 1) / PERSP_CLUSTER_TRIANGLES;
    persp_cluster *cl = persp__calloc(ctx, count, sizeof *cl);
    if (!cl) return PERSP_ERR_OUT_OF_MEMORY;
    for (size_t k = 0; k < count; k++)
        build_cluster(mesh, k * PERSP_CLUSTER_TRIANGLES,
                      PERSP_MIN(ntri, (k + 1) * PERSP_CLUSTER_TRIANGLES), &cl[k]);
    mesh->clusters = cl;
    mesh->cluster_count = count;
    return PERSP_OK;
}
