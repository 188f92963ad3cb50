/* SVG line plots (see svg.h). Coordinates are written with %.2f, text is
 * escaped for XML. */
#include "analysis/svg.h"

#include <math.h>
#include <string.h>

static const char *const palette[PERSP_SVG_MAX_SERIES] = {
    "#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#17becf",
    "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#000000", "#aec7e8",
};

static void put_text(FILE *f, const char *s)
{
    for (; s && *s; s++) {
        switch (*s) {
        case '<': fputs("&lt;", f); break;
        case '>': fputs("&gt;", f); break;
        case '&': fputs("&amp;", f); break;
        case '"': fputs("&quot;", f); break;
        default: fputc(*s, f);
        }
    }
}

/* Tick step: 1, 2 or 5 × 10^k giving about `want` intervals over span. */
static double nice_step(double span, int want)
{
    double raw = span / want, p = pow(10.0, floor(log10(raw))), m = raw / p;
    return (m < 1.5 ? 1.0 : m < 3.5 ? 2.0 : m < 7.5 ? 5.0 : 10.0) * p;
}

static void fit_y(const persp_svg_panel *p, double *lo, double *hi)
{
    *lo = p->ymin, *hi = p->ymax;
    if (*hi > *lo) return;
    *lo = INFINITY, *hi = -INFINITY;
    for (int s = 0; s < p->series_count; s++)
        for (int i = 0; i < p->series[s].n; i++) {
            double y = p->series[s].y[i];
            if (!isfinite(y)) continue;
            if (y < *lo) *lo = y;
            if (y > *hi) *hi = y;
        }
    if (!(*hi > *lo)) *lo -= 1.0, *hi += 1.0;
    double st = nice_step(*hi - *lo, 5);
    *lo = floor(*lo / st) * st, *hi = ceil(*hi / st) * st;
}

static int panel(FILE *f, const persp_svg_panel *p, double ox, double w, double h)
{
    const double ml = 62, mr = 14, mt = 30, mb = 46;
    double x0 = ox + ml, x1 = ox + w - mr, y0 = h - mb, y1 = mt;
    double ylo, yhi;
    fit_y(p, &ylo, &yhi);
    if (!(p->xmax > p->xmin) || !(yhi > ylo)) return -1;
#define SX(x) (x0 + ((x) - p->xmin) / (p->xmax - p->xmin) * (x1 - x0))
#define SY(y) (y0 - ((y) - ylo) / (yhi - ylo) * (y0 - y1))
    fprintf(f, "<rect x=\"%.2f\" y=\"%.2f\" width=\"%.2f\" height=\"%.2f\" fill=\"none\" stroke=\"#000\"/>\n",
            x0, y1, x1 - x0, y0 - y1);
    double xs = nice_step(p->xmax - p->xmin, 6), ys = nice_step(yhi - ylo, 5);
    for (double t = ceil(p->xmin / xs - 1e-9) * xs; t <= p->xmax + 1e-9 * xs; t += xs) {
        double X = SX(t);
        fprintf(f, "<line x1=\"%.2f\" y1=\"%.2f\" x2=\"%.2f\" y2=\"%.2f\" stroke=\"#ddd\"/>\n", X, y0, X, y1);
        fprintf(f, "<text x=\"%.2f\" y=\"%.2f\" font-size=\"11\" text-anchor=\"middle\">%g</text>\n", X,
                y0 + 14, fabs(t) < 1e-12 * xs ? 0.0 : t);
    }
    for (double t = ceil(ylo / ys - 1e-9) * ys; t <= yhi + 1e-9 * ys; t += ys) {
        double Y = SY(t);
        fprintf(f, "<line x1=\"%.2f\" y1=\"%.2f\" x2=\"%.2f\" y2=\"%.2f\" stroke=\"#ddd\"/>\n", x0, Y, x1, Y);
        fprintf(f, "<text x=\"%.2f\" y=\"%.2f\" font-size=\"11\" text-anchor=\"end\">%g</text>\n", x0 - 4,
                Y + 4, fabs(t) < 1e-12 * ys ? 0.0 : t);
    }
    fprintf(f, "<text x=\"%.2f\" y=\"18\" font-size=\"13\" text-anchor=\"middle\">", (x0 + x1) / 2);
    put_text(f, p->title);
    fprintf(f, "</text>\n<text x=\"%.2f\" y=\"%.2f\" font-size=\"12\" text-anchor=\"middle\">", (x0 + x1) / 2,
            h - 12);
    put_text(f, p->xlabel);
    fprintf(f, "</text>\n<text x=\"%.2f\" y=\"%.2f\" font-size=\"12\" text-anchor=\"middle\" "
               "transform=\"rotate(-90 %.2f %.2f)\">",
            ox + 16, (y0 + y1) / 2, ox + 16, (y0 + y1) / 2);
    put_text(f, p->ylabel);
    fputs("</text>\n", f);
    fprintf(f, "<clipPath id=\"c%d\"><rect x=\"%.2f\" y=\"%.2f\" width=\"%.2f\" height=\"%.2f\"/></clipPath>\n",
            (int)ox, x0, y1, x1 - x0, y0 - y1);
    for (int s = 0; s < p->series_count; s++) {
        const persp_svg_series *se = &p->series[s];
        const char *col = palette[s % PERSP_SVG_MAX_SERIES];
        int open = 0;
        for (int i = 0; i < se->n; i++) {
            double x = se->x[i], y = se->y[i];
            if (!isfinite(x) || !isfinite(y)) {
                if (open) fputs("\"/>\n", f);
                open = 0;
                continue;
            }
            if (!open)
                fprintf(f, "<polyline clip-path=\"url(#c%d)\" fill=\"none\" stroke=\"%s\" stroke-width=\"1.6\" points=\"",
                        (int)ox, col);
            fprintf(f, "%s%.2f,%.2f", open ? " " : "", SX(x), SY(y));
            open = 1;
        }
        if (open) fputs("\"/>\n", f);
    }
    /* The legend over the curves on a white, slightly translucent box, so
     * that lines under it do not cross its text. */
    size_t longest = 0;
    for (int s = 0; s < p->series_count; s++)
        if (p->series[s].label && strlen(p->series[s].label) > longest) longest = strlen(p->series[s].label);
    if (p->series_count > 0)
        fprintf(f,
                "<rect x=\"%.2f\" y=\"%.2f\" width=\"%.2f\" height=\"%.2f\" fill=\"#fff\" "
                "fill-opacity=\"0.85\" stroke=\"#ccc\"/>\n",
                x0 + 4, y1 + 3, 34 + 6.2 * (double)longest, 15.0 * p->series_count + 4);
    for (int s = 0; s < p->series_count; s++) {
        const persp_svg_series *se = &p->series[s];
        const char *col = palette[s % PERSP_SVG_MAX_SERIES];
        double ly = y1 + 14 + 15 * s;
        fprintf(f, "<line x1=\"%.2f\" y1=\"%.2f\" x2=\"%.2f\" y2=\"%.2f\" stroke=\"%s\" stroke-width=\"2\"/>\n",
                x0 + 8, ly - 4, x0 + 28, ly - 4, col);
        fprintf(f, "<text x=\"%.2f\" y=\"%.2f\" font-size=\"11\">", x0 + 32, ly);
        put_text(f, se->label);
        fputs("</text>\n", f);
    }
#undef SX
#undef SY
    return 0;
}

int persp__svg_write(FILE *f, const persp_svg_panel *panels, int count, int panel_w, int panel_h)
{
    if (!f || count < 1 || panel_w < 100 || panel_h < 100) return -1;
    for (int i = 0; i < count; i++) {
        double lo, hi;
        fit_y(&panels[i], &lo, &hi);
        if (!(panels[i].xmax > panels[i].xmin) || !(hi > lo)) return -1; /* nothing half-written */
    }
    fprintf(f,
            "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%d\" height=\"%d\" viewBox=\"0 0 %d %d\" "
            "font-family=\"sans-serif\">\n<rect width=\"100%%\" height=\"100%%\" fill=\"#fff\"/>\n",
            panel_w * count, panel_h, panel_w * count, panel_h);
    for (int i = 0; i < count; i++)
        if (panel(f, &panels[i], (double)(i * panel_w), panel_w, panel_h)) return -1;
    fputs("</svg>\n", f);
    return ferror(f) ? -1 : 0;
}
