/*
 * Writers for persp accuracy results: an aligned table with the metric
 * definitions, CSV, and JSON (through jansson, so the output is valid JSON
 * whatever the method names contain).
 */
#include "analysis/analysis.h"
#include "core/internal.h"

#include <errno.h>
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
    if (res->shard_count > 0) {
        /* Only in a shard's file: what persp_accuracy_merge needs to put the
         * rows back in place and to refuse shards of another sweep. */
        json_t *sh = json_object(), *idx = json_array();
        json_object_set_new(sh, "index", json_integer(res->shard_index));
        json_object_set_new(sh, "count", json_integer(res->shard_count));
        json_object_set_new(sh, "rows", json_integer((json_int_t)res->total));
        json_object_set_new(sh, "sweep", json_string(res->sweep));
        for (size_t i = 0; i < res->count; i++) json_array_append_new(idx, json_integer((json_int_t)res->index[i]));
        json_object_set_new(sh, "row_index", idx);
        json_object_set_new(root, "shard", sh);
    }
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

/* ------------------------------------------------------------ reading back */

static double rnum(json_t *o, const char *key)
{
    json_t *v = json_object_get(o, key);
    return json_is_number(v) ? json_number_value(v) : NAN;
}

static int rint_u64(json_t *o, const char *key, uint64_t *out)
{
    json_t *v = json_object_get(o, key);
    if (!json_is_integer(v) || json_integer_value(v) < 0) return 0;
    *out = (uint64_t)json_integer_value(v);
    return 1;
}

static persp_accuracy_result *result_alloc(persp_context *ctx, size_t n)
{
    persp_accuracy_result *res = persp__calloc(ctx, 1, sizeof *res);
    if (!res) return NULL;
    res->ctx = ctx;
    res->cap = n;
    res->rows = persp__calloc(ctx, n ? n : 1, sizeof *res->rows);
    res->index = persp__calloc(ctx, n ? n : 1, sizeof *res->index);
    if (!res->rows || !res->index) {
        persp_accuracy_destroy(res);
        return NULL;
    }
    return res;
}

static int read_row(json_t *o, double rel_floor, persp_accuracy_row *r)
{
    const char *method = json_string_value(json_object_get(o, "method"));
    const char *cname = json_string_value(json_object_get(o, "case"));
    if (!json_is_object(o) || !method || !cname || strlen(method) >= sizeof r->method ||
        strlen(cname) >= sizeof r->case_name)
        return 0;
    memset(r, 0, sizeof *r);
    snprintf(r->method, sizeof r->method, "%s", method);
    snprintf(r->case_name, sizeof r->case_name, "%s", cname);
    double h = rnum(o, "hbar");
    r->hbar = h == h ? h : 0.0;
    if (!rint_u64(o, "pixels", &r->pixels) || !rint_u64(o, "spans", &r->spans) ||
        !rint_u64(o, "triangles", &r->triangles))
        return 0;
    r->max_u = rnum(o, "max_u"), r->max_v = rnum(o, "max_v");
    r->mean_u = rnum(o, "mean_u"), r->mean_v = rnum(o, "mean_v");
    r->p99_u = rnum(o, "p99_u"), r->p99_v = rnum(o, "p99_v");
    r->texel_miss = rnum(o, "texel_miss");
    r->relpt_u = rnum(o, "relpt_u"), r->relpt_v = rnum(o, "relpt_v");
    r->relspan_u = rnum(o, "relspan_u"), r->relspan_v = rnum(o, "relspan_v");
    r->rel_floor = rel_floor;
    json_t *ops = json_object_get(o, "ops_per_pixel");
    r->ops_measured = json_is_object(ops);
    r->div_px = r->ops_measured ? rnum(ops, "div") : NAN;
    r->mul_px = r->ops_measured ? rnum(ops, "mul") : NAN;
    r->add_px = r->ops_measured ? rnum(ops, "add") : NAN;
    r->cmp_px = r->ops_measured ? rnum(ops, "cmp") : NAN;
    return 1;
}

persp_status persp_accuracy_read(persp_context *ctx, const char *path, persp_accuracy_result **out)
{
    if (!ctx) return PERSP_ERR_INVALID_ARGUMENT;
    persp__clear_error(ctx);
    if (!path || !out) return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "accuracy: nothing to read");
    *out = NULL;
    json_error_t err;
    json_t *root = json_load_file(path, 0, &err);
    if (!root) {
        FILE *f = fopen(path, "rb");
        if (!f) return persp__fail(ctx, PERSP_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
        fclose(f);
        return persp__fail(ctx, PERSP_ERR_FORMAT, "%s:%d:%d: %s", path, err.line, err.column, err.text);
    }
    persp_status st = PERSP_OK;
    json_t *rows = json_object_get(root, "rows"), *sh = json_object_get(root, "shard");
    double rel_floor = rnum(root, "rel_floor");
    persp_accuracy_result *res = NULL;
    if (!json_is_array(rows) || !(rel_floor == rel_floor)) {
        st = persp__fail(ctx, PERSP_ERR_FORMAT, "%s: not a persp accuracy JSON report", path);
        goto done;
    }
    size_t n = json_array_size(rows);
    res = result_alloc(ctx, n);
    if (!res) {
        st = persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "accuracy: out of memory");
        goto done;
    }
    res->total = n;
    for (size_t i = 0; i < n; i++) {
        if (!read_row(json_array_get(rows, i), rel_floor, &res->rows[i])) {
            st = persp__fail(ctx, PERSP_ERR_FORMAT, "%s: row %zu is malformed", path, i + 1);
            goto done;
        }
        res->index[i] = i;
    }
    res->count = n;
    if (sh) {
        uint64_t k, c, total;
        json_t *idx = json_object_get(sh, "row_index");
        const char *sweep = json_string_value(json_object_get(sh, "sweep"));
        if (!rint_u64(sh, "index", &k) || !rint_u64(sh, "count", &c) || !rint_u64(sh, "rows", &total) ||
            c == 0 || c > 1000000 || k >= c || !sweep || !json_is_array(idx) ||
            json_array_size(idx) != n) {
            st = persp__fail(ctx, PERSP_ERR_FORMAT, "%s: malformed shard description", path);
            goto done;
        }
        res->shard_index = (int)k;
        res->shard_count = (int)c;
        res->total = (size_t)total;
        snprintf(res->sweep, sizeof res->sweep, "%s", sweep);
        for (size_t i = 0; i < n; i++) {
            json_t *v = json_array_get(idx, i);
            if (!json_is_integer(v) || json_integer_value(v) < 0 ||
                (uint64_t)json_integer_value(v) >= total ||
                (uint64_t)json_integer_value(v) % c != k) {
                st = persp__fail(ctx, PERSP_ERR_FORMAT, "%s: row index %zu is not this shard's", path,
                                 i + 1);
                goto done;
            }
            res->index[i] = (size_t)json_integer_value(v);
        }
    }
done:
    json_decref(root);
    if (st != PERSP_OK) {
        persp_accuracy_destroy(res);
        return st;
    }
    *out = res;
    return PERSP_OK;
}

persp_status persp_accuracy_merge(persp_context *ctx, const persp_accuracy_result *const *parts,
                                  size_t count, persp_accuracy_result **out)
{
    if (!ctx) return PERSP_ERR_INVALID_ARGUMENT;
    persp__clear_error(ctx);
    if (!parts || !count || !out) return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "merge: no shards");
    *out = NULL;
    const persp_accuracy_result *p0 = parts[0];
    if (!p0 || p0->shard_count <= 0)
        return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "merge: shard 1 is a whole run, not a shard");
    size_t shards = (size_t)p0->shard_count, total = p0->total;
    if (count != shards)
        return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "merge: %zu files for a sweep of %zu shards",
                           count, shards);
    for (size_t i = 0; i < count; i++) {
        const persp_accuracy_result *p = parts[i];
        if (!p || p->shard_count != p0->shard_count || p->total != total || strcmp(p->sweep, p0->sweep))
            return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT,
                               "merge: file %zu is not a shard of the same sweep as file 1", i + 1);
        for (size_t j = 0; j < i; j++)
            if (parts[j]->shard_index == p->shard_index)
                return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "merge: shard %d given twice",
                                   p->shard_index + 1);
    }
    /* Each row of the sweep comes from one shard, so the shards hold as many
     * rows as the sweep has at least: checked before the sweep's rows are
     * allocated, as a shard's "rows" is whatever number its file says. */
    size_t held = 0;
    for (size_t i = 0; i < count; i++)
        held += parts[i]->count;
    if (held < total)
        return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT,
                           "merge: rows are missing (the shards hold %zu of the sweep's %zu)", held,
                           total);
    persp_accuracy_result *res = result_alloc(ctx, total);
    unsigned char *seen = persp__calloc(ctx, total ? total : 1, 1);
    if (!res || !seen) {
        persp_accuracy_destroy(res);
        persp__free(ctx, seen);
        return persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "merge: out of memory");
    }
    persp_status st = PERSP_OK;
    for (size_t i = 0; i < count && st == PERSP_OK; i++)
        for (size_t r = 0; r < parts[i]->count; r++) {
            size_t at = parts[i]->index[r];
            if (at >= total || seen[at]) {
                st = persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "merge: row %zu given twice or out of range",
                                 at + 1);
                break;
            }
            seen[at] = 1;
            res->rows[at] = parts[i]->rows[r];
        }
    for (size_t r = 0; r < total && st == PERSP_OK; r++) {
        if (!seen[r]) st = persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "merge: row %zu is missing", r + 1);
        res->index[r] = r;
    }
    persp__free(ctx, seen);
    if (st != PERSP_OK) {
        persp_accuracy_destroy(res);
        return st;
    }
    res->count = res->total = total;
    *out = res;
    return PERSP_OK;
}
