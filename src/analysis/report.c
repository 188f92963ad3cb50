/*
 * Writers for persp accuracy results: an aligned table with the metric
 * definitions, CSV, and JSON (through jansson, so the output is valid JSON
 * whatever the method names contain).
 */
#include "analysis/analysis.h"
#include "core/internal.h"

#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

static const char reference_text[] =
    "u = (a*x + b*y + c) / (g*x + h*y + i), v likewise (Heckbert 1989 2.3.2), in double at the "
    "pixel centre";

static const struct {
    const char *key, *text;
} definitions[] = {
    {"max/mean/p99", "absolute error |method - exact| in texels of the case's texture "
                     "(paper-quad, random-triangles: 256x256); p99 = nearest-rank 99th percentile"},
    {"texel_miss", "share of pixels whose nearest texel (floor(s*size) in u and v) differs from "
                   "the exact one's"},
    {"relpt", "point-wise relative error: max |ds| / |s| over pixels with |s| >= rel_floor "
              "(s normalised, texture = [0,1])"},
    {"relspan", "span-relative error: max over spans of max|ds| / (max s - min s of the exact s "
                "on that span), spans whose range >= rel_floor"},
    {"ops/px", "the method's own operation counts (per triangle + per span + per pixel) divided "
               "by pixels; '-' where not measured"},
};

/* Numbers as the table prints them: 4 significant digits, '-' for NaN. */
static void fmt(char *buf, size_t size, double v)
{
    if (v != v)
        snprintf(buf, size, "-");
    else if (v == 0.0)
        snprintf(buf, size, "0");
    else
        snprintf(buf, size, "%.4g", v);
}

static void fmt_pct(char *buf, size_t size, double v)
{
    if (v != v)
        snprintf(buf, size, "-");
    else
        snprintf(buf, size, "%.3f", 100.0 * v);
}

enum { COLS = 19 };

static void row_cells(const persp_accuracy_row *r, char cell[COLS][72])
{
    snprintf(cell[0], 72, "%s", r->method);
    snprintf(cell[1], 72, "%s", r->case_name);
    if (r->hbar > 0.0)
        snprintf(cell[2], 72, "%g", r->hbar);
    else
        snprintf(cell[2], 72, "-");
    snprintf(cell[3], 72, "%llu", (unsigned long long)r->pixels);
    fmt(cell[4], 72, r->max_u);
    fmt(cell[5], 72, r->max_v);
    fmt(cell[6], 72, r->mean_u);
    fmt(cell[7], 72, r->mean_v);
    fmt(cell[8], 72, r->p99_u);
    fmt(cell[9], 72, r->p99_v);
    fmt_pct(cell[10], 72, r->texel_miss);
    fmt_pct(cell[11], 72, r->relpt_u);
    fmt_pct(cell[12], 72, r->relpt_v);
    fmt_pct(cell[13], 72, r->relspan_u);
    fmt_pct(cell[14], 72, r->relspan_v);
    fmt(cell[15], 72, r->div_px);
    fmt(cell[16], 72, r->mul_px);
    fmt(cell[17], 72, r->add_px);
    fmt(cell[18], 72, r->cmp_px);
}

static const char *const table_head[COLS] = {
    "method", "case", "hbar", "pixels", "max_u", "max_v", "mean_u", "mean_v", "p99_u", "p99_v",
    "miss%", "relpt_u%", "relpt_v%", "relspan_u%", "relspan_v%", "div/px", "mul/px", "add/px",
    "cmp/px"};

static int write_table(const persp_accuracy_result *res, FILE *f)
{
    int width[COLS];
    for (int c = 0; c < COLS; c++) width[c] = (int)strlen(table_head[c]);
    char cell[COLS][72];
    for (size_t i = 0; i < res->count; i++) {
        row_cells(&res->rows[i], cell);
        for (int c = 0; c < COLS; c++)
            if ((int)strlen(cell[c]) > width[c]) width[c] = (int)strlen(cell[c]);
    }
    int ok = 1;
    for (int c = 0; c < COLS; c++)
        ok &= fprintf(f, c < 2 ? "%-*s%s" : "%*s%s", width[c], table_head[c],
                      c + 1 < COLS ? "  " : "\n") > 0;
    for (size_t i = 0; i < res->count; i++) {
        row_cells(&res->rows[i], cell);
        for (int c = 0; c < COLS; c++)
            ok &= fprintf(f, c < 2 ? "%-*s%s" : "%*s%s", width[c], cell[c],
                          c + 1 < COLS ? "  " : "\n") > 0;
    }
    double floor_v = res->count ? res->rows[0].rel_floor : 0.01;
    ok &= fprintf(f, "\nreference: %s\n", reference_text) > 0;
    for (size_t k = 0; k < sizeof definitions / sizeof definitions[0]; k++)
        ok &= fprintf(f, "%s: %s\n", definitions[k].key, definitions[k].text) > 0;
    ok &= fprintf(f, "rel_floor = %g; miss, relpt, relspan in %%\n", floor_v) > 0;
    return ok;
}

static void csv_num(FILE *f, double v, int *ok)
{
    if (v == v)
        *ok &= fprintf(f, ",%.9g", v) > 0;
    else
        *ok &= fputc(',', f) != EOF;
}

static int write_csv(const persp_accuracy_result *res, FILE *f)
{
    int ok = fputs("method,case,hbar,pixels,spans,triangles,max_u,max_v,mean_u,mean_v,p99_u,p99_v,"
                   "texel_miss,relpt_u,relpt_v,relspan_u,relspan_v,rel_floor,div_px,mul_px,add_px,"
                   "cmp_px\n",
                   f) != EOF;
    for (size_t i = 0; i < res->count; i++) {
        const persp_accuracy_row *r = &res->rows[i];
        /* Method specs never contain quotes or commas except in parameters,
         * which are quoted to keep the column count. */
        ok &= fprintf(f, "\"%s\",\"%s\"", r->method, r->case_name) > 0;
        csv_num(f, r->hbar > 0.0 ? r->hbar : NAN, &ok);
        ok &= fprintf(f, ",%llu,%llu,%llu", (unsigned long long)r->pixels,
                      (unsigned long long)r->spans, (unsigned long long)r->triangles) > 0;
        const double v[] = {r->max_u,     r->max_v,     r->mean_u,    r->mean_v,    r->p99_u,
                            r->p99_v,     r->texel_miss, r->relpt_u,  r->relpt_v,   r->relspan_u,
                            r->relspan_v, r->rel_floor, r->div_px,    r->mul_px,    r->add_px,
                            r->cmp_px};
        for (size_t k = 0; k < sizeof v / sizeof v[0]; k++) csv_num(f, v[k], &ok);
        ok &= fputc('\n', f) != EOF;
    }
    return ok;
}

static json_t *jnum(double v) { return v == v && isfinite(v) ? json_real(v) : json_null(); }

static int write_json(const persp_accuracy_result *res, FILE *f)
{
    json_t *root = json_object(), *rows = json_array(), *defs = json_object();
    if (!root || !rows || !defs) {
        json_decref(root), json_decref(rows), json_decref(defs);
        return 0;
    }
    json_object_set_new(root, "reference", json_string(reference_text));
    for (size_t k = 0; k < sizeof definitions / sizeof definitions[0]; k++)
        json_object_set_new(defs, definitions[k].key, json_string(definitions[k].text));
    json_object_set_new(root, "definitions", defs);
    json_object_set_new(root, "rel_floor", jnum(res->count ? res->rows[0].rel_floor : 0.01));
    for (size_t i = 0; i < res->count; i++) {
        const persp_accuracy_row *r = &res->rows[i];
        json_t *o = json_object();
        if (!o) break;
        json_object_set_new(o, "method", json_string(r->method));
        json_object_set_new(o, "case", json_string(r->case_name));
        json_object_set_new(o, "hbar", r->hbar > 0.0 ? json_real(r->hbar) : json_null());
        json_object_set_new(o, "pixels", json_integer((json_int_t)r->pixels));
        json_object_set_new(o, "spans", json_integer((json_int_t)r->spans));
        json_object_set_new(o, "triangles", json_integer((json_int_t)r->triangles));
        json_object_set_new(o, "max_u", jnum(r->max_u));
        json_object_set_new(o, "max_v", jnum(r->max_v));
        json_object_set_new(o, "mean_u", jnum(r->mean_u));
        json_object_set_new(o, "mean_v", jnum(r->mean_v));
        json_object_set_new(o, "p99_u", jnum(r->p99_u));
        json_object_set_new(o, "p99_v", jnum(r->p99_v));
        json_object_set_new(o, "texel_miss", jnum(r->texel_miss));
        json_object_set_new(o, "relpt_u", jnum(r->relpt_u));
        json_object_set_new(o, "relpt_v", jnum(r->relpt_v));
        json_object_set_new(o, "relspan_u", jnum(r->relspan_u));
        json_object_set_new(o, "relspan_v", jnum(r->relspan_v));
        json_t *ops = json_object();
        json_object_set_new(ops, "div", jnum(r->div_px));
        json_object_set_new(ops, "mul", jnum(r->mul_px));
        json_object_set_new(ops, "add", jnum(r->add_px));
        json_object_set_new(ops, "cmp", jnum(r->cmp_px));
        json_object_set_new(o, "ops_per_pixel", r->ops_measured ? ops : json_null());
        if (!r->ops_measured) json_decref(ops);
        json_array_append_new(rows, o);
    }
    json_object_set_new(root, "rows", rows);
    int ok = json_dumpf(root, f, JSON_INDENT(2) | JSON_PRESERVE_ORDER) == 0;
    ok &= fputc('\n', f) != EOF;
    json_decref(root);
    return ok;
}

persp_status persp_accuracy_write(persp_context *ctx, const persp_accuracy_result *res,
                                  persp_report_format format, void *stream)
{
    if (ctx) persp__clear_error(ctx);
    if (!res || !stream) return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "accuracy: nothing to write");
    FILE *f = stream;
    int ok;
    switch (format) {
    case PERSP_REPORT_TABLE: ok = write_table(res, f); break;
    case PERSP_REPORT_CSV: ok = write_csv(res, f); break;
    case PERSP_REPORT_JSON: ok = write_json(res, f); break;
    default: return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "accuracy: unknown format");
    }
    if (!ok || fflush(f) != 0) return persp__fail(ctx, PERSP_ERR_IO, "accuracy: write failed");
    return PERSP_OK;
}
