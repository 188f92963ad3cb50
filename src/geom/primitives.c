/*
 * Built-in primitive meshes. All share one convention so that scene files
 * can place them without surprises:
 *   - they fit the cube [-1, 1]^3 (plane 2×2 in y = 0 facing +y, cube of
 *     side 2, sphere of radius 1, cylinder of radius 1 for y in [-1, 1]),
 *     except the torus, whose radii are given;
 *   - front faces are counter-clockwise seen from outside (OpenGL default);
 *   - the longitude θ = 2πu − π is measured by atan2(x, z) about +y, so
 *     u = 0.5 faces +z (towards the default camera) and the seam is at −z;
 *     the same convention as the cylindrical/spherical texgen (texgen.c);
 *   - seam vertices are duplicated (u = 0 and u = 1) so that no triangle
 *     interpolates u across the wrap, and pole vertices are duplicated per
 *     slice with u at the slice centre.
 */
#include "core/internal.h"
#include "geom/scene.h"

#include <math.h>
#include <string.h>

#define PRIM_MAX_DIV 1024
#define TWO_PI 6.283185307179586
#define PI 3.141592653589793

static persp_status mesh_alloc(persp_context *ctx, size_t nv, size_t ni, persp_mesh *m)
{
    memset(m, 0, sizeof *m);
    if (nv > PERSP_SCENE_MAX_VERTICES || ni > PERSP_SCENE_MAX_INDICES)
        return persp__fail(ctx, PERSP_ERR_TOO_LARGE, "primitive: %zu vertices / %zu indices exceed the limits",
                                  nv, ni);
    m->vertices = persp__calloc(ctx, nv, sizeof *m->vertices);
    m->indices = persp__calloc(ctx, ni, sizeof *m->indices);
    if (!m->vertices || !m->indices) {
        persp__mesh_free(ctx, m);
        return persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "primitive: out of memory");
    }
    m->vertex_count = nv;
    m->index_count = 0; /* counted up as triangles are emitted */
    m->has_normals = 1;
    return PERSP_OK;
}

static void set_vertex(persp_vertex *v, double x, double y, double z, double nx, double ny, double nz,
                       double u, double t)
{
    v->pos[0] = (float)x, v->pos[1] = (float)y, v->pos[2] = (float)z;
    v->normal[0] = (float)nx, v->normal[1] = (float)ny, v->normal[2] = (float)nz;
    v->uv[0] = (float)u, v->uv[1] = (float)t;
    v->color[0] = v->color[1] = v->color[2] = v->color[3] = 1.0f;
}

static void tri(persp_mesh *m, size_t a, size_t b, size_t c)
{
    m->indices[m->index_count++] = (uint32_t)a;
    m->indices[m->index_count++] = (uint32_t)b;
    m->indices[m->index_count++] = (uint32_t)c;
}

/* Triangles of a (rows+1)×(cols+1) vertex grid starting at base, where
 * column j runs "right" (u) and row i runs "up" (v) as seen from the front:
 * (LL, LR, UR) and (LL, UR, UL) are then counter-clockwise. With poles, the
 * bottom row's first and the top row's second triangle collapse onto the
 * pole vertex and are left out. */
static void grid(persp_mesh *m, size_t base, int rows, int cols, int poles)
{
    size_t w = (size_t)cols + 1;
    for (int i = 0; i < rows; i++)
        for (int j = 0; j < cols; j++) {
            size_t ll = base + (size_t)i * w + (size_t)j, lr = ll + 1, ul = ll + w, ur = ul + 1;
            if (!(poles && i == 0)) tri(m, ll, lr, ur);
            if (!(poles && i == rows - 1)) tri(m, ll, ur, ul);
        }
}

static int check_div(persp_context *ctx, const char *what, const char *name, int n, int lo)
{
    if (n < lo || n > PRIM_MAX_DIV) {
        persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "%s: %s must be %d..%d (got %d)", what, name, lo,
                           PRIM_MAX_DIV, n);
        return 0;
    }
    return 1;
}

persp_status persp__mesh_plane(persp_context *ctx, int subdiv, persp_mesh *out)
{
    if (!check_div(ctx, "plane", "subdivisions", subdiv, 1)) return PERSP_ERR_INVALID_ARGUMENT;
    size_t n = (size_t)subdiv;
    persp_status st = mesh_alloc(ctx, (n + 1) * (n + 1), 6 * n * n, out);
    if (st != PERSP_OK) return st;
    /* Seen from above with −z up the texture reads upright: u along +x, v along −z. */
    for (size_t i = 0; i <= n; i++)
        for (size_t j = 0; j <= n; j++) {
            double u = (double)j / (double)n, v = (double)i / (double)n;
            set_vertex(&out->vertices[i * (n + 1) + j], 2.0 * u - 1.0, 0.0, 1.0 - 2.0 * v, 0, 1, 0, u, v);
        }
    grid(out, 0, subdiv, subdiv, 0);
    return PERSP_OK;
}

persp_status persp__mesh_cube(persp_context *ctx, persp_mesh *out)
{
    /* Per face: outward normal n, right r and up u with r × u = n, so the
     * corners n ± r ± u listed anticlockwise are front-facing. The r/u pairs
     * are those of the cube texgen (texgen.c). */
    static const int face[6][3][3] = {
        {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}},   {{0, 0, -1}, {-1, 0, 0}, {0, 1, 0}},
        {{1, 0, 0}, {0, 0, -1}, {0, 1, 0}},  {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}},
        {{0, 1, 0}, {1, 0, 0}, {0, 0, -1}},  {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}},
    };
    static const int corner[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    persp_status st = mesh_alloc(ctx, 24, 36, out);
    if (st != PERSP_OK) return st;
    for (size_t f = 0; f < 6; f++) {
        const int *n = face[f][0], *r = face[f][1], *u = face[f][2];
        for (size_t k = 0; k < 4; k++) {
            double p[3];
            for (int c = 0; c < 3; c++) p[c] = n[c] + corner[k][0] * r[c] + corner[k][1] * u[c];
            set_vertex(&out->vertices[4 * f + k], p[0], p[1], p[2], n[0], n[1], n[2],
                       0.5 * (corner[k][0] + 1), 0.5 * (corner[k][1] + 1));
        }
        tri(out, 4 * f, 4 * f + 1, 4 * f + 2);
        tri(out, 4 * f, 4 * f + 2, 4 * f + 3);
    }
    return PERSP_OK;
}

persp_status persp__mesh_sphere(persp_context *ctx, int slices, int stacks, persp_mesh *out)
{
    if (!check_div(ctx, "sphere", "slices", slices, 3) || !check_div(ctx, "sphere", "stacks", stacks, 2))
        return PERSP_ERR_INVALID_ARGUMENT;
    size_t w = (size_t)slices + 1, h = (size_t)stacks + 1;
    persp_status st = mesh_alloc(ctx, w * h, 3 * (size_t)slices * (2 * (size_t)stacks - 2), out);
    if (st != PERSP_OK) return st;
    /* Row i has latitude v = i/stacks (south pole at 0); polar angle φ from +y. */
    for (size_t i = 0; i < h; i++)
        for (size_t j = 0; j < w; j++) {
            double v = (double)i / (double)stacks, u = (double)j / (double)slices;
            /* Pole vertices take u at the centre of the one slice whose
             * triangle uses them (south: vertex j, north: vertex j + 1, see
             * grid()); the unused last/first one is clamped into [0, 1]. */
            if (i == 0) u = fmin(1.0, ((double)j + 0.5) / (double)slices);
            if (i == h - 1) u = fmax(0.0, ((double)j - 0.5) / (double)slices);
            double th = TWO_PI * u - PI, ph = PI * (1.0 - v);
            double x = sin(ph) * sin(th), y = cos(ph), z = sin(ph) * cos(th);
            if (i == 0 || i == h - 1) x = 0.0, z = 0.0, y = i == 0 ? -1.0 : 1.0;
            set_vertex(&out->vertices[i * w + j], x, y, z, x, y, z, u, v);
        }
    grid(out, 0, stacks, slices, 1);
    return PERSP_OK;
}

persp_status persp__mesh_cylinder(persp_context *ctx, int slices, persp_mesh *out)
{
    if (!check_div(ctx, "cylinder", "slices", slices, 3)) return PERSP_ERR_INVALID_ARGUMENT;
    size_t w = (size_t)slices + 1, ns = (size_t)slices;
    /* Side: 2 rows of w; each cap: centre + w ring vertices with the cap's normal. */
    persp_status st = mesh_alloc(ctx, 2 * w + 2 * (1 + w), 6 * ns + 2 * 3 * ns, out);
    if (st != PERSP_OK) return st;
    for (size_t i = 0; i < 2; i++)
        for (size_t j = 0; j < w; j++) {
            double u = (double)j / (double)slices, th = TWO_PI * u - PI;
            double x = sin(th), z = cos(th);
            set_vertex(&out->vertices[i * w + j], x, i ? 1.0 : -1.0, z, x, 0, z, u, (double)i);
        }
    grid(out, 0, 1, slices, 0);
    for (int cap = 0; cap < 2; cap++) {
        double y = cap ? 1.0 : -1.0;
        size_t c = 2 * w + (size_t)cap * (1 + w);
        set_vertex(&out->vertices[c], 0, y, 0, 0, y, 0, 0.5, 0.5);
        for (size_t j = 0; j < w; j++) {
            double th = TWO_PI * (double)j / (double)slices - PI, x = sin(th), z = cos(th);
            /* Top seen from above (−z up), bottom seen from below (+z up). */
            set_vertex(&out->vertices[c + 1 + j], x, y, z, 0, y, 0, 0.5 + 0.5 * x, 0.5 - 0.5 * y * z);
        }
        for (size_t j = 0; j < ns; j++) {
            if (cap) tri(out, c, c + 1 + j, c + 2 + j);
            else tri(out, c, c + 2 + j, c + 1 + j);
        }
    }
    return PERSP_OK;
}

persp_status persp__mesh_torus(persp_context *ctx, float major, float minor, int slices, int rings,
                               persp_mesh *out)
{
    if (!check_div(ctx, "torus", "slices", slices, 3) || !check_div(ctx, "torus", "rings", rings, 3))
        return PERSP_ERR_INVALID_ARGUMENT;
    if (!(major > 0.0f) || !(minor > 0.0f) || !isfinite(major) || !isfinite(minor) || minor > major)
        return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT,
                                  "torus: radii must satisfy 0 < minor <= major (got %g, %g)", (double)major,
                                  (double)minor);
    size_t w = (size_t)slices + 1, h = (size_t)rings + 1;
    persp_status st = mesh_alloc(ctx, w * h, 6 * (size_t)slices * (size_t)rings, out);
    if (st != PERSP_OK) return st;
    /* Tube angle φ = 2πv − π: v = 0 on the inner equator (seam hidden), v
     * grows upwards over the outside, so u right / v up holds from outside. */
    for (size_t i = 0; i < h; i++)
        for (size_t j = 0; j < w; j++) {
            double u = (double)j / (double)slices, v = (double)i / (double)rings;
            double th = TWO_PI * u - PI, ph = TWO_PI * v - PI;
            double nx = cos(ph) * sin(th), ny = sin(ph), nz = cos(ph) * cos(th);
            double rr = (double)major + (double)minor * cos(ph);
            set_vertex(&out->vertices[i * w + j], rr * sin(th), (double)minor * ny, rr * cos(th), nx, ny, nz,
                       u, v);
        }
    grid(out, 0, rings, slices, 0);
    return PERSP_OK;
}

/* SplitMix64 (Steele, Lea, Flood 2014): a fixed generator, so a soup's
 * triangles depend only on its seed, on every platform and build. */
static uint64_t splitmix64(uint64_t *state)
{
    uint64_t z = (*state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

/* Uniform in [0, 1) with 53 bits. */
static double uniform01(uint64_t *state) { return (double)(splitmix64(state) >> 11) * 0x1.0p-53; }

persp_status persp__mesh_soup(persp_context *ctx, int count, uint64_t seed, float size_min, float size_max,
                              persp_mesh *out)
{
    if (count < 1 || (size_t)count > PERSP_SCENE_MAX_VERTICES / 3)
        return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "soup: count must be 1..%u (got %d)",
                           PERSP_SCENE_MAX_VERTICES / 3, count);
    if (!(size_min > 0.0f) || !(size_max >= size_min) || !isfinite(size_max))
        return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT,
                           "soup: sizes must satisfy 0 < min <= max (got %g, %g)", (double)size_min,
                           (double)size_max);
    size_t n = (size_t)count;
    persp_status st = mesh_alloc(ctx, 3 * n, 3 * n, out);
    if (st != PERSP_OK) return st;
    uint64_t rng = seed;
    for (size_t t = 0; t < n; t++) {
        /* An equilateral triangle of side s facing +z, turned by a random
         * angle about z, then tilted by up to 45° about a random axis in
         * its plane (so lighting varies), centred uniformly in [-1, 1]^3. */
        double s = (double)size_min + ((double)size_max - (double)size_min) * uniform01(&rng);
        double spin = TWO_PI * uniform01(&rng);
        double axis = TWO_PI * uniform01(&rng), tilt = (PI / 4.0) * uniform01(&rng);
        double c[3] = {2.0 * uniform01(&rng) - 1.0, 2.0 * uniform01(&rng) - 1.0, 2.0 * uniform01(&rng) - 1.0};
        /* Rotation by `tilt` about the unit axis a = (cos axis, sin axis, 0) (Rodrigues). */
        double ax = cos(axis), ay = sin(axis), ct = cos(tilt), st_ = sin(tilt);
        double r = s / sqrt(3.0); /* circumradius */
        double nrm[3] = {ay * st_, -ax * st_, ct}; /* R·(0, 0, 1) */
        for (int k = 0; k < 3; k++) {
            double a = spin + (double)k * TWO_PI / 3.0; /* counter-clockwise seen from +z */
            double p[3] = {r * cos(a), r * sin(a), 0.0};
            double d = ax * p[0] + ay * p[1];
            double q[3] = {p[0] * ct + ax * d * (1.0 - ct), p[1] * ct + ay * d * (1.0 - ct),
                           (ax * p[1] - ay * p[0]) * st_};
            double x = c[0] + q[0], y = c[1] + q[1], z = c[2] + q[2];
            set_vertex(&out->vertices[3 * t + (size_t)k], x, y, z, nrm[0], nrm[1], nrm[2],
                       0.5 + 0.5 * x, 0.5 + 0.5 * y);
        }
        tri(out, 3 * t, 3 * t + 1, 3 * t + 2);
    }
    return PERSP_OK;
}
