/*
 * Texture-coordinate generation: the "map shapes" and "entities" of the
 * texture-mapping lecture ([CS300-TexMap]): planar, cylindrical, spherical and
 * cube (six planar maps) shapes, projected from the object position, and
 * the reflection entity as the OpenGL sphere map.
 *
 * Conventions (shared with primitives.c so that a generated map on the
 * matching primitive reproduces the primitive's own coordinates):
 *   - positions are taken relative to obj->texgen_center, in object space;
 *   - cylindrical/spherical: about axis a (0 x, 1 y, 2 z) with the two other
 *     coordinates in cyclic order (p, q) = (d[a+2], d[a+1]); the lecture's
 *     θ = tan⁻¹(y/x) about z is atan2(p, q) with a = z; u = 1/2 + θ/(2π);
 *   - cylindrical v = 1/2 + h/2 (the height h in [-1, 1] of the unit
 *     cylinder maps to [0, 1]); spherical v = 1 − φ/π with the lecture's
 *     φ = cos⁻¹(h/r) measured from the +axis pole;
 *   - cube: the face is the dominant axis of the vertex normal (of the
 *     position when the normal is zero); (a, b) in [-1, 1] on that face map
 *     to u = 1/2 + a/2, v = 1/2 + b/2 with the face orientation of the cube
 *     primitive (upright seen from outside);
 *   - planar: u = P_s·(x, y, z, 1), v = P_t·(x, y, z, 1)
 *     (OpenGL GL_OBJECT_LINEAR, OpenGL 2.1 §2.12.4);
 *   - reflection: OpenGL GL_SPHERE_MAP (OpenGL 2.1 §2.12.4): with the unit
 *     eye-space position û and eye normal n, r = û − 2 (n·û) n,
 *     m = 2 √(rx² + ry² + (rz + 1)²), (u, v) = (rx/m + 1/2, ry/m + 1/2).
 * Generated coordinates (not PERSP_TEXGEN_UV) are multiplied by
 * texgen_scale (0 counts as 1), so a scale of 4 repeats the map four times.
 */
#include "geom/scene.h"

#include <math.h>
#include <string.h>

#define TWO_PI 6.283185307179586
#define PI 3.141592653589793

static double angle_u(const double d[3], int a)
{
    double p = d[(a + 2) % 3], q = d[(a + 1) % 3];
    if (p == 0.0 && q == 0.0) return 0.5;
    return 0.5 + atan2(p, q) / TWO_PI;
}

static void cube_uv(const double d[3], const float n[3], double *u, double *v)
{
    double s[3] = {n[0], n[1], n[2]};
    if (s[0] == 0.0 && s[1] == 0.0 && s[2] == 0.0) memcpy(s, d, sizeof s);
    int ax = 0;
    if (fabs(s[1]) > fabs(s[ax])) ax = 1;
    if (fabs(s[2]) > fabs(s[ax])) ax = 2;
    int pos = s[ax] >= 0.0;
    double a, b;
    switch (ax) {
    case 0: a = pos ? -d[2] : d[2], b = d[1]; break;
    case 1: a = d[0], b = pos ? -d[2] : d[2]; break;
    default: a = pos ? d[0] : -d[0], b = d[1]; break;
    }
    *u = 0.5 + 0.5 * a;
    *v = 0.5 + 0.5 * b;
}

static void sphere_map(const persp_mat4 *mv, const float nm[9], const persp_vertex *vx, double *u, double *v)
{
    const float *m = mv->m, *p = vx->pos, *n0 = vx->normal;
    double e[3], n[3];
    for (int r = 0; r < 3; r++) {
        e[r] = (double)m[r] * p[0] + (double)m[4 + r] * p[1] + (double)m[8 + r] * p[2] + (double)m[12 + r];
        n[r] = (double)nm[r] * n0[0] + (double)nm[3 + r] * n0[1] + (double)nm[6 + r] * n0[2];
    }
    double el = sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
    double nl = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (el > 0.0)
        for (int c = 0; c < 3; c++) e[c] /= el;
    if (nl > 0.0)
        for (int c = 0; c < 3; c++) n[c] /= nl;
    double dn = e[0] * n[0] + e[1] * n[1] + e[2] * n[2];
    double r[3] = {e[0] - 2.0 * dn * n[0], e[1] - 2.0 * dn * n[1], e[2] - 2.0 * dn * n[2]};
    double mm = 2.0 * sqrt(r[0] * r[0] + r[1] * r[1] + (r[2] + 1.0) * (r[2] + 1.0));
    /* r = (0, 0, -1) points straight into the screen: the map's rim, any point of it. */
    if (!(mm > 0.0)) {
        *u = 0.5, *v = 0.5;
        return;
    }
    *u = r[0] / mm + 0.5;
    *v = r[1] / mm + 0.5;
}

void persp__texgen_apply(const persp_object *obj, const persp_mat4 *modelview, const persp_vertex *in,
                         size_t count, float *uv_out)
{
    double su = obj->texgen_scale[0] != 0.0f ? obj->texgen_scale[0] : 1.0;
    double sv = obj->texgen_scale[1] != 0.0f ? obj->texgen_scale[1] : 1.0;
    int axis = obj->texgen_axis >= 0 && obj->texgen_axis <= 2 ? obj->texgen_axis : 1;
    float nm[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    persp_mat4 mv = modelview ? *modelview : persp_mat4_identity();
    if (obj->texgen == PERSP_TEXGEN_REFLECTION && !persp_mat4_normal_matrix(mv, nm)) {
        /* A singular modelview flattens the object; keep the identity normals. */
        memcpy(nm, (const float[9]){1, 0, 0, 0, 1, 0, 0, 0, 1}, sizeof nm);
    }
    for (size_t i = 0; i < count; i++) {
        const persp_vertex *vx = &in[i];
        double d[3], u = 0.0, v = 0.0;
        for (int c = 0; c < 3; c++) d[c] = (double)vx->pos[c] - (double)obj->texgen_center[c];
        switch (obj->texgen) {
        case PERSP_TEXGEN_UV:
            uv_out[2 * i] = vx->uv[0];
            uv_out[2 * i + 1] = vx->uv[1];
            continue;
        case PERSP_TEXGEN_PLANAR: {
            const float *s = obj->texgen_s, *t = obj->texgen_t;
            const float *p = vx->pos;
            u = (double)s[0] * p[0] + (double)s[1] * p[1] + (double)s[2] * p[2] + (double)s[3];
            v = (double)t[0] * p[0] + (double)t[1] * p[1] + (double)t[2] * p[2] + (double)t[3];
            break;
        }
        case PERSP_TEXGEN_CYLINDRICAL:
            u = angle_u(d, axis);
            v = 0.5 + 0.5 * d[axis];
            break;
        case PERSP_TEXGEN_SPHERICAL: {
            double r = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
            u = angle_u(d, axis);
            v = r > 0.0 ? 1.0 - acos(fmax(-1.0, fmin(1.0, d[axis] / r))) / PI : 0.5;
            break;
        }
        case PERSP_TEXGEN_CUBE: cube_uv(d, vx->normal, &u, &v); break;
        case PERSP_TEXGEN_REFLECTION: sphere_map(&mv, nm, vx, &u, &v); break;
        }
        uv_out[2 * i] = (float)(u * su);
        uv_out[2 * i + 1] = (float)(v * sv);
    }
}
