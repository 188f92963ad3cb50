/*
 * A small SVG line-plot writer for the analysis reports (no packaged C
 * library does this; docs/DESIGN.md, "Dependencies"). One document holds one or more panels side by side;
 * each panel has linear axes with "nice" ticks (1, 2, 5 × 10^k), labels,
 * a title, a legend and up to PERSP_SVG_MAX_SERIES polylines.
 */
#ifndef PERSP_ANALYSIS_SVG_H
#define PERSP_ANALYSIS_SVG_H

#include <stdio.h>

#define PERSP_SVG_MAX_SERIES 12

typedef struct persp_svg_series {
    const double *x, *y; /* n points; non-finite y values break the line */
    int n;
    const char *label;
} persp_svg_series;

typedef struct persp_svg_panel {
    const char *title, *xlabel, *ylabel;
    double xmin, xmax, ymin, ymax; /* axis ranges; ymin == ymax: fitted to the data */
    persp_svg_series series[PERSP_SVG_MAX_SERIES];
    int series_count;
} persp_svg_panel;

/* Writes a complete SVG document with count panels in one row, each
 * panel_w × panel_h pixels. Returns 0 on success, -1 if writing failed or an
 * axis range is empty. */
int persp__svg_write(FILE *f, const persp_svg_panel *panels, int count, int panel_w, int panel_h);

#endif
