/*
 * Error statistics for persp accuracy: an accumulator with exact
 * percentiles, and the texture-coordinate metrics built on it (absolute
 * error in texels, nearest-texel mismatch, point-wise and span-relative
 * error). Nothing here allocates per value.
 */
#include "analysis/analysis.h"
#include "core/internal.h"

#include <math.h>
#include <string.h>

void persp__errstats_init(persp_errstats *s, persp_context *ctx)
{
    memset(s, 0, sizeof *s);
    s->ctx = ctx;
}

void persp__errstats_free(persp_errstats *s)
{
    if (!s) return;
    persp__free(s->ctx, s->v);
    s->v = NULL;
    s->n = s->cap = 0;
}

void persp__errstats_reset(persp_errstats *s)
{
    s->n = 0;
    s->count = s->dropped = 0;
    s->sum = s->max = 0.0;
}

persp_status persp__errstats_reserve(persp_errstats *s, size_t extra)
{
    if (extra > (size_t)-1 / 2 - s->n) return PERSP_ERR_TOO_LARGE;
    return persp__grow(s->ctx, (void **)&s->v, &s->cap, s->n + extra, sizeof *s->v);
}

double persp__errstats_mean(const persp_errstats *s)
{
    return s->count ? s->sum / (double)s->count : 0.0;
}

/* k-th smallest (0-based) of v[0..n-1] by selection with a three-way
 * partition, so runs of equal errors (e.g. all zero) stay linear. */
static double select_kth(double *v, size_t n, size_t k)
{
    size_t lo = 0, hi = n - 1;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        double a = v[lo], b = v[mid], c = v[hi];
        double pivot = a < b ? (b < c ? b : (a < c ? c : a)) : (a < c ? a : (b < c ? c : b));
        /* [lo, lt) < pivot, [lt, i) == pivot, (gt, hi] > pivot. An element
         * equal to the pivot stays in range, so gt never passes below lt. */
        size_t lt = lo, i = lo, gt = hi;
        while (i <= gt) {
            double x = v[i];
            if (x < pivot) {
                v[i++] = v[lt];
                v[lt++] = x;
            } else if (x > pivot) {
                v[i] = v[gt];
                v[gt--] = x;
            } else {
                i++;
            }
        }
        if (k < lt)
            hi = lt - 1;
        else if (k > gt)
            lo = gt + 1;
        else
            return pivot;
    }
    return v[k];
}

double persp__errstats_percentile(persp_errstats *s, double p)
{
    if (!s->n || !(p > 0.0)) return 0.0;
    if (p > 100.0) p = 100.0;
    /* Nearest rank: rank = ceil(p/100 · n), 1-based. */
    double r = ceil(p / 100.0 * (double)s->n);
    size_t rank = r < 1.0 ? 1 : (size_t)r;
    if (rank > s->n) rank = s->n;
    return select_kth(s->v, s->n, rank - 1);
}

void persp__acc_metrics_init(persp_acc_metrics *m, persp_context *ctx, double rel_floor)
{
    memset(m, 0, sizeof *m);
    persp__errstats_init(&m->eu, ctx);
    persp__errstats_init(&m->ev, ctx);
    m->rel_floor = rel_floor;
}

void persp__acc_metrics_reset(persp_acc_metrics *m)
{
    persp__errstats_reset(&m->eu);
    persp__errstats_reset(&m->ev);
    m->pixels = m->spans = m->triangles = m->texel_miss = 0;
    m->relpt_u = m->relpt_v = m->relspan_u = m->relspan_v = 0.0;
    memset(&m->ops, 0, sizeof m->ops);
}

void persp__acc_metrics_free(persp_acc_metrics *m)
{
    persp__errstats_free(&m->eu);
    persp__errstats_free(&m->ev);
}

void persp__acc_metrics_span(persp_acc_metrics *m, int n, const double *s1x, const double *s2x,
                             const float *s1, const float *s2, double scale1, double scale2,
                             float *err_out)
{
    if (n <= 0) return;
    const double fl = m->rel_floor;
    double lo1 = s1x[0], hi1 = s1x[0], lo2 = s2x[0], hi2 = s2x[0];
    double dmax1 = 0.0, dmax2 = 0.0;
    for (int k = 0; k < n; k++) {
        double d1 = fabs((double)s1[k] - s1x[k]), d2 = fabs((double)s2[k] - s2x[k]);
        /* A NaN from a method must count as an error, not vanish in max(). */
        if (d1 != d1) d1 = INFINITY;
        if (d2 != d2) d2 = INFINITY;
        double t1 = d1 * scale1, t2 = d2 * scale2;
        persp__errstats_add(&m->eu, t1);
        persp__errstats_add(&m->ev, t2);
        if (err_out) err_out[k] = (float)(t1 > t2 ? t1 : t2);
        /* Nearest texel (GL_NEAREST before wrapping): floor(s · size). */
        if (floor((double)s1[k] * scale1) != floor(s1x[k] * scale1) ||
            floor((double)s2[k] * scale2) != floor(s2x[k] * scale2))
            m->texel_miss++;
        if (fabs(s1x[k]) >= fl && d1 / fabs(s1x[k]) > m->relpt_u) m->relpt_u = d1 / fabs(s1x[k]);
        if (fabs(s2x[k]) >= fl && d2 / fabs(s2x[k]) > m->relpt_v) m->relpt_v = d2 / fabs(s2x[k]);
        if (d1 > dmax1) dmax1 = d1;
        if (d2 > dmax2) dmax2 = d2;
        if (s1x[k] < lo1) lo1 = s1x[k];
        if (s1x[k] > hi1) hi1 = s1x[k];
        if (s2x[k] < lo2) lo2 = s2x[k];
        if (s2x[k] > hi2) hi2 = s2x[k];
    }
    if (hi1 - lo1 >= fl && fl > 0.0 && dmax1 / (hi1 - lo1) > m->relspan_u)
        m->relspan_u = dmax1 / (hi1 - lo1);
    if (hi2 - lo2 >= fl && fl > 0.0 && dmax2 / (hi2 - lo2) > m->relspan_v)
        m->relspan_v = dmax2 / (hi2 - lo2);
    m->pixels += (uint64_t)n;
    m->spans++;
}
