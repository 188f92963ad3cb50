/* Clusters of back faces culled whole (src/raster/cluster_cull.c) must cull
 * only what the rasterizer's own test culls: every triangle of a culled
 * cluster has a negative (or zero) area in the vertex stage's 1/256-pixel
 * fixed point and all its vertices inside the clip volume. Checked on
 * clusters built to sit at the edge of the bound (slivers, sub-pixel
 * triangles, normals close to edge-on) under random perspective, off-centre
 * and orthographic projections and non-uniform model matrices. Clusters
 * culled for a sort-first region (a random run of tiles) have no triangle
 * whose pixel box reaches the run. End to end, renders with and without
 * cluster culling are the same bit for bit. */
/* ctest-labels: threads (renders with several worker threads) */
/* ctest-split: each (minutes in all under ThreadSanitizer) */
#include "support.h"

#include "core/internal.h"
#include "geom/scene.h"
#include "raster/raster.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The vertex stage's arithmetic (frame.c transform_block and
 * window_block): clip position summed in double from 0.0 and rounded to
 * float, window position in double, rounded to 1/256 pixel. */
static unsigned snap(const persp_mat4 *m, const float p[3], double W, double H, double gx,
                     double gy, int64_t *X, int64_t *Y)
{
    float cp[4];
    for (int r = 0; r < 4; r++) {
        double o = 0.0;
        o += m->m[r] * (double)p[0];
        o += m->m[4 + r] * (double)p[1];
        o += m->m[8 + r] * (double)p[2];
        o += m->m[12 + r] * 1.0;
        cp[r] = (float)o;
    }
    const unsigned code = persp__clip_outcode_pos(cp[0], cp[1], cp[2], cp[3], gx, gy);
    if (code) return code;
    const double q = 1.0 / cp[3];
    *X = llround(((cp[0] * q + 1.0) * 0.5 * W) * PERSP_SUBPIXEL);
    *Y = llround(((cp[1] * q + 1.0) * 0.5 * H) * PERSP_SUBPIXEL);
    return 0;
}

/* A random rotation (axis, angle) times a non-uniform scale and a shear. */
static persp_mat4 random_model(test_rng *rng)
{
    persp_mat4 m = persp_mat4_rotate(
        (float)test_rng_uniform(rng, 0, 360), (float)test_rng_uniform(rng, -1, 1),
        (float)test_rng_uniform(rng, -1, 1), (float)test_rng_uniform(rng, 0.1, 1));
    m = persp_mat4_mul(m, persp_mat4_scale((float)test_rng_uniform(rng, 0.3, 3),
                                           (float)test_rng_uniform(rng, 0.3, 3),
                                           (float)test_rng_uniform(rng, 0.3, 3)));
    persp_mat4 shear = persp_mat4_identity();
    shear.m[4] = (float)test_rng_uniform(rng, -0.5, 0.5); /* x += s·y */
    return persp_mat4_mul(m, shear);
}

/* Projections: symmetric perspective, an off-centre frustum (the first two
 * rows' third column set), and orthographic (w = 1: the eye at infinity). */
static persp_mat4 random_projection(test_rng *rng, int kind, double aspect)
{
    if (kind == 2) {
        persp_mat4 o = persp_mat4_identity();
        const double s = test_rng_uniform(rng, 0.05, 0.5);
        o.m[0] = (float)(s / aspect), o.m[5] = (float)s, o.m[10] = -0.01f, o.m[14] = -0.5f;
        return o;
    }
    persp_mat4 p = persp_perspective(test_rng_uniform(rng, 15, 110), aspect,
                                     test_rng_uniform(rng, 0.01, 0.5), 200);
    if (kind == 1) {
        p.m[8] = (float)test_rng_uniform(rng, -0.8, 0.8);
        p.m[9] = (float)test_rng_uniform(rng, -0.8, 0.8);
    }
    return p;
}

/* One mesh of four clusters: each cluster's triangles lie around a plane
 * through a point near the origin, tilted by up to a degree, of one size
 * scale per cluster (from a fraction of a pixel to many pixels), and every
 * third cluster of slivers (the third vertex within 1/100 to 1/1000 of the
 * size from the opposite edge). */
static void random_mesh(test_rng *rng, const double eye[3], persp_vertex *v, uint32_t *idx,
                        int tris)
{
    for (int c0 = 0; c0 < tris; c0 += PERSP_CLUSTER_TRIANGLES) {
        const double nx = test_rng_uniform(rng, -1, 1), ny = test_rng_uniform(rng, -1, 1),
                     nz = test_rng_uniform(rng, -1, 1);
        const double nl = sqrt(nx * nx + ny * ny + nz * nz) + 1e-12;
        double n[3] = {nx / nl, ny / nl, nz / nl};
        const double base[3] = {test_rng_uniform(rng, -0.3, 0.3), test_rng_uniform(rng, -0.3, 0.3),
                                test_rng_uniform(rng, -0.3, 0.3)};
        /* Three clusters in four face away from the eye (the ones to cull). */
        const double away =
            n[0] * (base[0] - eye[0]) + n[1] * (base[1] - eye[1]) + n[2] * (base[2] - eye[2]);
        if ((away < 0) == (c0 / PERSP_CLUSTER_TRIANGLES % 4 != 3))
            for (int k = 0; k < 3; k++)
                n[k] = -n[k];
        double a[3] = {n[1], -n[0], 0};
        if (fabs(n[2]) > 0.9) a[0] = 0, a[1] = n[2], a[2] = -n[1];
        const double al = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
        for (int k = 0; k < 3; k++)
            a[k] /= al;
        const double b[3] = {n[1] * a[2] - n[2] * a[1], n[2] * a[0] - n[0] * a[2],
                             n[0] * a[1] - n[1] * a[0]};
        const double scale = pow(10.0, test_rng_uniform(rng, -3.5, -0.5));
        const int slivers = test_rng_next(rng) % 3 == 0;
        for (int t = c0; t < c0 + PERSP_CLUSTER_TRIANGLES && t < tris; t++) {
            const double size = scale * test_rng_uniform(rng, 0.5, 2.0);
            const double cx = test_rng_uniform(rng, -0.2, 0.2),
                         cy = test_rng_uniform(rng, -0.2, 0.2);
            double uv[3][2];
            for (int k = 0; k < 3; k++)
                uv[k][0] = cx + size * test_rng_uniform(rng, -1, 1),
                uv[k][1] = cy + size * test_rng_uniform(rng, -1, 1);
            if (slivers) {
                const double s = test_rng_uniform(rng, 0, 1),
                             f = size * pow(10.0, test_rng_uniform(rng, -3, -2));
                uv[2][0] = uv[0][0] + s * (uv[1][0] - uv[0][0]) + f * test_rng_uniform(rng, -1, 1);
                uv[2][1] = uv[0][1] + s * (uv[1][1] - uv[0][1]) + f * test_rng_uniform(rng, -1, 1);
            }
            /* Counter-clockwise about n, so that n is (nearly) the face normal. */
            const double cross = (uv[1][0] - uv[0][0]) * (uv[2][1] - uv[0][1]) -
                                 (uv[2][0] - uv[0][0]) * (uv[1][1] - uv[0][1]);
            if (cross < 0)
                for (int c = 0; c < 2; c++) {
                    const double tmp = uv[1][c];
                    uv[1][c] = uv[2][c], uv[2][c] = tmp;
                }
            const double tilt = test_rng_uniform(rng, -0.02, 0.02);
            for (int k = 0; k < 3; k++) {
                persp_vertex *p = &v[3 * t + k];
                memset(p, 0, sizeof *p);
                for (int c = 0; c < 3; c++)
                    p->pos[c] = (float)(base[c] + uv[k][0] * a[c] + uv[k][1] * b[c] +
                                        tilt * uv[k][0] * n[c]);
                p->normal[2] = 1.0f;
                idx[3 * t + k] = (uint32_t)(3 * t + k);
            }
        }
    }
}

/* The mesh's vertices stored in a random order: a cluster's indices then
 * spread over the whole array (sorted into runs, then merged). Each swap of
 * two slots is recorded in where[] (slot of each vertex as first stored)
 * and the indices are renamed once at the end: the order of renaming all
 * of them at every swap, without its n² cost (minutes under
 * ThreadSanitizer). */
static void shuffle_vertices(test_rng *rng, persp_vertex *v, uint32_t *idx, uint32_t *where, uint32_t *who, int n)
{
    for (int i = 0; i < n; i++) where[i] = who[i] = (uint32_t)i;
    for (int i = n - 1; i > 0; i--) {
        const int j = (int)(test_rng_next(rng) % (uint64_t)(i + 1));
        const persp_vertex tv = v[i];
        v[i] = v[j], v[j] = tv;
        const uint32_t oi = who[i], oj = who[j];
        who[i] = oj, who[j] = oi;
        where[oi] = (uint32_t)j, where[oj] = (uint32_t)i;
    }
    for (int k = 0; k < n; k++) idx[k] = where[idx[k]];
}

/* Every vertex a cluster uses lies in one of its runs (the frame leaves
 * the others out of the vertex stage). */
static void check_runs(const persp_mesh *mesh, int trial)
{
    for (size_t k = 0; k < mesh->cluster_count; k++) {
        const persp_cluster *cl = &mesh->clusters[k];
        assert_true(cl->runs >= 1 && cl->runs <= PERSP_CLUSTER_RUNS);
        for (size_t i = 3 * k * PERSP_CLUSTER_TRIANGLES; i < 3 * (k + 1) * PERSP_CLUSTER_TRIANGLES; i++) {
            const uint32_t ix = mesh->indices[i];
            int in = 0;
            for (int r = 0; r < cl->runs; r++) in |= ix >= cl->run[r][0] && ix < cl->run[r][1];
            if (!in) fail_msg("trial %d cluster %zu: vertex %u in no run", trial, k, ix);
        }
    }
}

/* One trial's frame: its view of the mesh and how it snaps vertices. */
typedef struct trial_view {
    const persp_mesh *mesh;
    persp_mat4 mvp;
    int W, H, cull, trial;
    double gx, gy;
} trial_view;

/* Every triangle of a cluster culled as back-facing has all its vertices
 * inside the clip volume and a back-facing (or zero) snapped area; returns
 * the clusters culled, and adds the triangles checked to *checked. */
static size_t check_back_faces(const trial_view *tv, const persp_cluster_view *cv, size_t *checked)
{
    uint8_t culled[4];
    const size_t n = persp__clusters_cull(cv, tv->mesh->clusters, tv->mesh->cluster_count, culled);
    for (int k = 0; k < 4; k++) {
        if (!culled[k]) continue;
        for (int t = k * PERSP_CLUSTER_TRIANGLES; t < (k + 1) * PERSP_CLUSTER_TRIANGLES; t++) {
            int64_t X[3], Y[3];
            for (int i = 0; i < 3; i++) {
                const unsigned code = snap(&tv->mvp, tv->mesh->vertices[tv->mesh->indices[3 * t + i]].pos, tv->W,
                                           tv->H, tv->gx, tv->gy, &X[i], &Y[i]);
                if (code)
                    fail_msg("trial %d cluster %d triangle %d: vertex outside the clip volume", tv->trial, k, t);
            }
            const int64_t area = (X[1] - X[0]) * (Y[2] - Y[0]) - (X[2] - X[0]) * (Y[1] - Y[0]);
            if (tv->cull == PERSP_CULL_CW ? area > 0 : area < 0)
                fail_msg("trial %d cluster %d triangle %d: culled whole but its area is %lld "
                         "(front)",
                         tv->trial, k, t, (long long)area);
            (*checked)++;
        }
    }
    return n;
}

/* Sort first (src/render/sort_first.c): with a random run of tiles as the
 * region, a cluster culled for the region (2) has no triangle whose pixel
 * box, as set-up finds it from the snapped vertices, reaches a tile of the
 * run. Adds the clusters culled so and their triangles checked. */
static void check_region(test_rng *rng, const trial_view *tv, persp_cluster_view *cv, size_t *clusters,
                         size_t *checked)
{
    const int W = tv->W, H = tv->H;
    const int tiles_x = (W + PERSP_TILE - 1) / PERSP_TILE, tiles = tiles_x * ((H + PERSP_TILE - 1) / PERSP_TILE);
    const int tile0 = (int)(test_rng_next(rng) % (uint64_t)tiles);
    const int tile1 = tile0 + 1 + (int)(test_rng_next(rng) % (uint64_t)(tiles - tile0));
    cv->regions = 2;
    cv->tiles_x = tiles_x;
    cv->run = persp__tile_run(tiles_x, tile0, tile1);
    uint8_t culled[4];
    (void)persp__clusters_cull(cv, tv->mesh->clusters, tv->mesh->cluster_count, culled);
    for (int k = 0; k < 4; k++) {
        if (culled[k] != 2) continue;
        (*clusters)++;
        for (int t = k * PERSP_CLUSTER_TRIANGLES; t < (k + 1) * PERSP_CLUSTER_TRIANGLES; t++) {
            int64_t X[3], Y[3];
            unsigned any = 0;
            for (int i = 0; i < 3; i++)
                any |= snap(&tv->mvp, tv->mesh->vertices[tv->mesh->indices[3 * t + i]].pos, W, H, tv->gx, tv->gy,
                            &X[i], &Y[i]);
            if (any) continue; /* clipped: the box of its pieces is not tested here */
            int64_t lo[2] = {X[0], Y[0]}, hi[2] = {X[0], Y[0]};
            for (int i = 1; i < 3; i++) {
                lo[0] = X[i] < lo[0] ? X[i] : lo[0], hi[0] = X[i] > hi[0] ? X[i] : hi[0];
                lo[1] = Y[i] < lo[1] ? Y[i] : lo[1], hi[1] = Y[i] > hi[1] ? Y[i] : hi[1];
            }
            const int64_t bx0 = persp__ceil_div(lo[0] - PERSP_SUBPIXEL / 2, PERSP_SUBPIXEL);
            const int64_t bx1 = persp__floor_div(hi[0] - PERSP_SUBPIXEL / 2, PERSP_SUBPIXEL);
            const int64_t by0 = persp__ceil_div(lo[1] - PERSP_SUBPIXEL / 2, PERSP_SUBPIXEL);
            const int64_t by1 = persp__floor_div(hi[1] - PERSP_SUBPIXEL / 2, PERSP_SUBPIXEL);
            const int64_t cx0 = bx0 < 0 ? 0 : bx0, cy0 = by0 < 0 ? 0 : by0;
            const int64_t cx1 = bx1 > W - 1 ? W - 1 : bx1, cy1 = by1 > H - 1 ? H - 1 : by1;
            if (cx0 > cx1 || cy0 > cy1) continue; /* no pixel centre in the window */
            if (persp__box_reaches_run(&cv->run, cx0 / PERSP_TILE, cx1 / PERSP_TILE, cy0 / PERSP_TILE,
                                       cy1 / PERSP_TILE))
                fail_msg("trial %d cluster %d triangle %d: culled for tiles %d..%d but reaches them", tv->trial, k,
                         t, tile0, tile1 - 1);
            (*checked)++;
        }
    }
}

static void test_culled_clusters_are_culled_triangles(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    enum { TRIS = 4 * PERSP_CLUSTER_TRIANGLES };
    persp_vertex *v = calloc(3 * TRIS, sizeof *v);
    uint32_t *idx = calloc(3 * TRIS, sizeof *idx);
    uint32_t *where = calloc(3 * TRIS, sizeof *where), *who = calloc(3 * TRIS, sizeof *who);
    assert_non_null(v);
    assert_non_null(idx);
    assert_non_null(where);
    assert_non_null(who);
    test_rng rng = {4242};
    size_t culled_total = 0, culled_mirrored = 0, checked = 0, region_culled = 0, region_checked = 0;
    for (int trial = 0; trial < 10000; trial++) {
        /* The eye a few units away, looking near the clusters. */
        const double d = pow(10.0, test_rng_uniform(&rng, -0.3, 1.3));
        const double ex = test_rng_uniform(&rng, -1, 1), ey = test_rng_uniform(&rng, -1, 1),
                     ez = test_rng_uniform(&rng, -1, 1);
        const double el = sqrt(ex * ex + ey * ey + ez * ez) + 1e-9;
        const double eye[3] = {d * ex / el, d * ey / el, d * ez / el};
        random_mesh(&rng, eye, v, idx, TRIS);
        persp_mesh mesh;
        memset(&mesh, 0, sizeof mesh);
        mesh.vertices = v, mesh.indices = idx;
        mesh.vertex_count = 3 * TRIS, mesh.index_count = 3 * TRIS;
        if (trial % 5 == 4) shuffle_vertices(&rng, v, idx, where, who, 3 * TRIS);
        assert_int_equal(persp__mesh_build_clusters(ctx, &mesh), PERSP_OK);
        assert_int_equal(mesh.cluster_count, 4);
        check_runs(&mesh, trial);
        trial_view tv = {.mesh = &mesh, .trial = trial};
        tv.W = 64 + (int)(test_rng_next(&rng) % 2000);
        tv.H = 64 + (int)(test_rng_next(&rng) % 1500);
        tv.gx = PERSP_GUARD_PIXELS / (0.5 * tv.W), tv.gy = PERSP_GUARD_PIXELS / (0.5 * tv.H);
        const persp_mat4 view =
            persp_look_at((persp_vec3){(float)eye[0], (float)eye[1], (float)eye[2]},
                          (persp_vec3){(float)test_rng_uniform(&rng, -0.3, 0.3),
                                       (float)test_rng_uniform(&rng, -0.3, 0.3), 0},
                          (persp_vec3){0, 1, 0});
        const persp_mat4 proj = random_projection(&rng, trial % 3, (double)tv.W / tv.H);
        /* One trial in four mirrors the object: its front faces wind
         * clockwise, and culling drops counter-clockwise ones. */
        persp_mat4 model = trial % 2 ? random_model(&rng) : persp_mat4_identity();
        if (trial % 4 == 3) model = persp_mat4_mul(model, persp_mat4_scale(-1, 1, 1));
        tv.cull = persp_mat4_det3(model) < 0.0 ? PERSP_CULL_CCW : PERSP_CULL_CW;
        assert_int_equal(tv.cull == PERSP_CULL_CCW, trial % 4 == 3);
        tv.mvp = persp_mat4_mul(proj, persp_mat4_mul(view, model));
        persp_cluster_view cv;
        persp__cluster_view_init(&cv, &tv.mvp, tv.W, tv.H, tv.gx, tv.gy, tv.cull);
        const size_t n = check_back_faces(&tv, &cv, &checked);
        culled_total += n;
        if (tv.cull == PERSP_CULL_CCW) culled_mirrored += n;
        check_region(&rng, &tv, &cv, &region_culled, &region_checked);
        persp__free(ctx, mesh.clusters);
    }
    print_message("culled %zu clusters for a region, %zu of their triangles checked\n", region_culled,
                  region_checked);
    assert_true(region_culled > 500);
    assert_true(region_checked > 20000);
    /* The test means something only if clusters were culled (a bound
     * without the snapping margin culls clusters of small triangles that
     * snap to front faces, and fails it). */
    print_message("culled %zu clusters (%zu of mirrored objects), %zu triangles checked\n", culled_total,
                  culled_mirrored, checked);
    assert_true(culled_total > 500);
    assert_true(culled_mirrored > 100);
    assert_true(checked > 32000);
    free(v);
    free(idx);
    free(where);
    free(who);
    persp_context_destroy(ctx);
}

/* A cluster holding a triangle whose corners are one point (as some STL
 * files hold) has no normal cone: it is never culled, and building it
 * divides by nothing (the sanitised build checks that). Its neighbours,
 * without such a triangle, are still usable. */
static void test_point_triangle_cluster_unusable(void **state)
{
    (void)state;
    persp_context *ctx = test_context();
    enum { TRIS = 2 * PERSP_CLUSTER_TRIANGLES };
    persp_vertex *v = calloc(3 * TRIS, sizeof *v);
    uint32_t *idx = calloc(3 * TRIS, sizeof *idx);
    assert_non_null(v);
    assert_non_null(idx);
    test_rng rng = {7};
    const double eye[3] = {0, 0, 5};
    random_mesh(&rng, eye, v, idx, TRIS);
    for (int k = 1; k < 3; k++) memcpy(v[3 * 5 + k].pos, v[3 * 5].pos, sizeof v[0].pos);
    persp_mesh mesh;
    memset(&mesh, 0, sizeof mesh);
    mesh.vertices = v, mesh.indices = idx;
    mesh.vertex_count = 3 * TRIS, mesh.index_count = 3 * TRIS;
    assert_int_equal(persp__mesh_build_clusters(ctx, &mesh), PERSP_OK);
    assert_int_equal(mesh.cluster_count, 2);
    assert_false(mesh.clusters[0].usable);
    assert_true(mesh.clusters[1].usable);
    persp__free(ctx, mesh.clusters);
    free(v);
    free(idx);
    persp_context_destroy(ctx);
}

/* Renders scene from view (NULL: its camera) with or without cluster
 * culling, in a context of its own; the colour and depth hashes and the
 * counts. Returns how many clusters the frame culled whole (the context
 * counts them). The scene is shared: scenes are read-only while rendering,
 * so one load serves every frame (loading the 200k torus is a third of a
 * frame's time under ThreadSanitizer). */
static size_t render_clusters(const persp_scene *scene, const persp_mat4 *view, int threads, int off,
                              persp_shading shading, uint64_t hash[2], persp_render_stats *st)
{
    persp_context *ctx = test_context_threads(threads);
    ctx->no_cluster_cull = off;
    persp_framebuffer fb = test_framebuffer(320, 240);
    persp_render_desc d;
    memset(&d, 0, sizeof d);
    d.view = view;
    d.shading = shading;
    if (persp_render(ctx, scene, &d, &fb, st) != PERSP_OK)
        fail_msg("render: %s", persp_context_error(ctx));
    hash[0] = test_hash(fb.color, (size_t)320 * 240 * 4);
    hash[1] = test_hash(fb.depth, (size_t)320 * 240 * sizeof(float));
    const size_t culled = ctx->clusters_culled;
    test_framebuffer_free(&fb);
    persp_context_destroy(ctx);
    return culled;
}

static const char *const cull_scenes[] = {"scenes/bench/torus-20k.json", "scenes/bench/torus-200k.json",
                                          "scenes/spheres.json"};
enum { CULL_VIEWS = 6 };

/* View vi of scene si: the scene's camera (NULL) for vi 0, then eyes
 * around the torus at various distances, one grazing its surface and one
 * inside its tube (the near plane cuts triangles there). One random
 * sequence runs through every scene's views in order, so each view is the
 * same whichever scene's test draws it. */
static const persp_mat4 *cull_view(int si, int vi, persp_mat4 *view)
{
    test_rng rng = {99};
    for (int s = 0; s <= si; s++)
        for (int v = 1; v < CULL_VIEWS; v++) {
            const double d = v == 4 ? 1.5 : v == 5 ? 1.0 : test_rng_uniform(&rng, 1.8, 8);
            const double a = test_rng_uniform(&rng, 0, 6.283), b = test_rng_uniform(&rng, -1.2, 1.2);
            if (s != si || v != vi) continue;
            persp_vec3 eye = {(float)(d * cos(a) * cos(b)), (float)(d * sin(b)),
                              (float)(d * sin(a) * cos(b))};
            if (v == 5) eye.y = 0.02f;
            *view = persp_look_at(eye, (persp_vec3){0, 0, 0}, (persp_vec3){0, 1, 0});
            return view;
        }
    return NULL;
}

/* Every view of scene si rendered with and without cluster culling, one and
 * two threads and each shading in turn: the same images, depths and counts. */
static void cluster_culling_keeps_images(int si)
{
    static const persp_shading shadings[] = {PERSP_SHADING_NONE, PERSP_SHADING_GOURAUD_PC,
                                             PERSP_SHADING_PHONG_PC};
    persp_context *load = test_context();
    char path[1024];
    test_source_path(path, sizeof path, cull_scenes[si]);
    persp_scene *scene = NULL;
    assert_int_equal(persp_scene_load(load, path, &scene), PERSP_OK);
    int frames_culling = 0;
    for (int vi = 0; vi < CULL_VIEWS; vi++) {
        persp_mat4 view;
        const persp_mat4 *vp = cull_view(si, vi, &view);
        const int threads = 1 + vi % 2;
        const persp_shading sh = shadings[(si + vi) % 3];
        uint64_t on[2], off[2];
        persp_render_stats st_on, st_off;
        frames_culling += render_clusters(scene, vp, threads, 0, sh, on, &st_on) > 0;
        assert_int_equal(render_clusters(scene, vp, threads, 1, sh, off, &st_off), 0);
        if (on[0] != off[0] || on[1] != off[1])
            fail_msg("%s view %d: clusters culled whole change the image", cull_scenes[si], vi);
        assert_int_equal(st_on.triangles_drawn, st_off.triangles_drawn);
        assert_int_equal(st_on.fragments, st_off.fragments);
        assert_int_equal(st_on.pixels_written, st_off.pixels_written);
    }
    persp_scene_destroy(scene);
    persp_context_destroy(load);
    /* Most views of each scene must cull clusters, or the comparison shows
     * nothing (5, 6 and 5 of the 6 do). */
    if (frames_culling <= CULL_VIEWS / 2)
        fail_msg("%s: only %d of %d views culled a cluster", cull_scenes[si], frames_culling, CULL_VIEWS);
}

/* One test a scene, each its own ctest entry: together they took minutes
 * under ThreadSanitizer on a loaded 2-core machine. */
static void test_cluster_culling_keeps_images_torus_20k(void **state)
{
    (void)state;
    cluster_culling_keeps_images(0);
}

static void test_cluster_culling_keeps_images_torus_200k(void **state)
{
    (void)state;
    cluster_culling_keeps_images(1);
}

static void test_cluster_culling_keeps_images_spheres(void **state)
{
    (void)state;
    cluster_culling_keeps_images(2);
}

int main(int argc, char **argv)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_culled_clusters_are_culled_triangles),
        cmocka_unit_test(test_point_triangle_cluster_unusable),
        cmocka_unit_test(test_cluster_culling_keeps_images_torus_20k),
        cmocka_unit_test(test_cluster_culling_keeps_images_torus_200k),
        cmocka_unit_test(test_cluster_culling_keeps_images_spheres),
    };
    return TEST_RUN(argc, argv, tests);
}
