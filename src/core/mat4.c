/* Matrices with OpenGL conventions (OpenGL 2.1 spec §2.11; gluPerspective,
 * gluLookAt as documented in the GLU 1.3 specification). Column-major. */
#include "persp.h"

#include <math.h>

#define M(mat, r, c) ((mat).m[(c)*4 + (r)])

persp_mat4 persp_mat4_identity(void)
{
    persp_mat4 m = {{0}};
    m.m[0] = m.m[5] = m.m[10] = m.m[15] = 1.0f;
    return m;
}

persp_mat4 persp_mat4_mul(persp_mat4 a, persp_mat4 b)
{
    persp_mat4 r;
    for (int c = 0; c < 4; c++)
        for (int i = 0; i < 4; i++) {
            double s = 0.0;
            for (int k = 0; k < 4; k++) s += (double)M(a, i, k) * (double)M(b, k, c);
            M(r, i, c) = (float)s;
        }
    return r;
}

persp_vec4 persp_mat4_apply(persp_mat4 m, persp_vec4 v)
{
    double in[4] = {v.x, v.y, v.z, v.w}, o[4];
    for (int i = 0; i < 4; i++) {
        o[i] = 0.0;
        for (int k = 0; k < 4; k++) o[i] += (double)M(m, i, k) * in[k];
    }
    persp_vec4 r = {(float)o[0], (float)o[1], (float)o[2], (float)o[3]};
    return r;
}

persp_mat4 persp_mat4_translate(float x, float y, float z)
{
    persp_mat4 m = persp_mat4_identity();
    M(m, 0, 3) = x;
    M(m, 1, 3) = y;
    M(m, 2, 3) = z;
    return m;
}

persp_mat4 persp_mat4_scale(float x, float y, float z)
{
    persp_mat4 m = persp_mat4_identity();
    M(m, 0, 0) = x;
    M(m, 1, 1) = y;
    M(m, 2, 2) = z;
    return m;
}

persp_mat4 persp_mat4_rotate(float degrees, float ax, float ay, float az)
{
    double len = sqrt((double)ax * ax + (double)ay * ay + (double)az * az);
    persp_mat4 m = persp_mat4_identity();
    if (!(len > 0.0)) return m;
    double x = ax / len, y = ay / len, z = az / len;
    double a = degrees * (3.14159265358979323846 / 180.0);
    double c = cos(a), s = sin(a), t = 1.0 - c;
    M(m, 0, 0) = (float)(x * x * t + c);
    M(m, 0, 1) = (float)(x * y * t - z * s);
    M(m, 0, 2) = (float)(x * z * t + y * s);
    M(m, 1, 0) = (float)(y * x * t + z * s);
    M(m, 1, 1) = (float)(y * y * t + c);
    M(m, 1, 2) = (float)(y * z * t - x * s);
    M(m, 2, 0) = (float)(z * x * t - y * s);
    M(m, 2, 1) = (float)(z * y * t + x * s);
    M(m, 2, 2) = (float)(z * z * t + c);
    return m;
}

persp_mat4 persp_frustum(double l, double r, double b, double t, double n, double f)
{
    persp_mat4 m = {{0}};
    /* glFrustum refuses these (GL_INVALID_VALUE); the matrix is then NaN,
     * which persp_render refuses as not finite, rather than a division by
     * zero. */
    if (!(n > 0.0 && f > 0.0) || l == r || b == t || n == f) {
        for (int i = 0; i < 16; i++) m.m[i] = NAN;
        return m;
    }
    M(m, 0, 0) = (float)(2.0 * n / (r - l));
    M(m, 0, 2) = (float)((r + l) / (r - l));
    M(m, 1, 1) = (float)(2.0 * n / (t - b));
    M(m, 1, 2) = (float)((t + b) / (t - b));
    M(m, 2, 2) = (float)(-(f + n) / (f - n));
    M(m, 2, 3) = (float)(-2.0 * f * n / (f - n));
    M(m, 3, 2) = -1.0f;
    return m;
}

persp_mat4 persp_perspective(double fovy_deg, double aspect, double n, double f)
{
    double t = n * tan(fovy_deg * (3.14159265358979323846 / 360.0));
    return persp_frustum(-t * aspect, t * aspect, -t, t, n, f);
}

persp_mat4 persp_look_at(persp_vec3 eye, persp_vec3 center, persp_vec3 up)
{
    double fx = center.x - eye.x, fy = center.y - eye.y, fz = center.z - eye.z;
    double fl = sqrt(fx * fx + fy * fy + fz * fz);
    persp_mat4 m = persp_mat4_identity();
    if (!(fl > 0.0)) return m;
    fx /= fl, fy /= fl, fz /= fl;
    double sx = fy * up.z - fz * up.y, sy = fz * up.x - fx * up.z, sz = fx * up.y - fy * up.x;
    double sl = sqrt(sx * sx + sy * sy + sz * sz);
    if (!(sl > 0.0)) return m;
    sx /= sl, sy /= sl, sz /= sl;
    double ux = sy * fz - sz * fy, uy = sz * fx - sx * fz, uz = sx * fy - sy * fx;
    M(m, 0, 0) = (float)sx, M(m, 0, 1) = (float)sy, M(m, 0, 2) = (float)sz;
    M(m, 1, 0) = (float)ux, M(m, 1, 1) = (float)uy, M(m, 1, 2) = (float)uz;
    M(m, 2, 0) = (float)-fx, M(m, 2, 1) = (float)-fy, M(m, 2, 2) = (float)-fz;
    M(m, 0, 3) = (float)-(sx * eye.x + sy * eye.y + sz * eye.z);
    M(m, 1, 3) = (float)-(ux * eye.x + uy * eye.y + uz * eye.z);
    M(m, 2, 3) = (float)(fx * eye.x + fy * eye.y + fz * eye.z);
    return m;
}

double persp_mat4_det3(persp_mat4 m)
{
    double a[3][3];
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) a[r][c] = M(m, r, c);
    return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
           a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
}

int persp_mat4_normal_matrix(persp_mat4 m, float out[9])
{
    if (!out) return 0;
    double a[3][3];
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) a[r][c] = M(m, r, c);
    double c00 = a[1][1] * a[2][2] - a[1][2] * a[2][1];
    double c01 = a[1][2] * a[2][0] - a[1][0] * a[2][2];
    double c02 = a[1][0] * a[2][1] - a[1][1] * a[2][0];
    double det = a[0][0] * c00 + a[0][1] * c01 + a[0][2] * c02;
    if (!(fabs(det) > 1e-30)) return 0;
    /* inverse-transpose = cofactor matrix / det; out is column-major 3x3 */
    double cof[3][3] = {
        {c00, c01, c02},
        {a[0][2] * a[2][1] - a[0][1] * a[2][2], a[0][0] * a[2][2] - a[0][2] * a[2][0],
         a[0][1] * a[2][0] - a[0][0] * a[2][1]},
        {a[0][1] * a[1][2] - a[0][2] * a[1][1], a[0][2] * a[1][0] - a[0][0] * a[1][2],
         a[0][0] * a[1][1] - a[0][1] * a[1][0]},
    };
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) out[c * 3 + r] = (float)(cof[r][c] / det);
    return 1;
}
