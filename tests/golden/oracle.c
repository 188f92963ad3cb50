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

int oracle_area_image(const persp_scene *scene, int w, int h, int k, double *rgb, unsigned char *inside)
{
    diff_ref *ref = diff_ref_create(scene, w * k, h * k, PERSP_FILTER_TRILINEAR);
    if (!ref) return -1;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            double sum[3] = {0.0, 0.0, 0.0};
            int all = 1;
            for (int j = 0; j < k; j++)
                for (int i = 0; i < k; i++) {
                    diff_ref_pixel q = diff_ref_eval(ref, x * k + i, y * k + j);
                    if (!q.covered || q.background_ok) all = 0;
                    for (int c = 0; c < 3; c++) sum[c] += 0.5 * (q.lo[c] + q.hi[c]);
                }
            size_t at = (size_t)y * (size_t)w + (size_t)x;
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
