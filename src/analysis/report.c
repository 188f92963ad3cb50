/*
 * Writers for persp accuracy results: an aligned table with the metric
 * definitions, CSV, and JSON (through jansson, so the output is valid JSON
 * whatever the method names contain).
 */
#include "analysis/analysis.h"
#include "core/internal.h"
#include "io/json_text.h"
#include "io/text.h"

#include <errno.h>
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
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

static int has_control(const char *s, size_t len);

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

/* A CSV field (RFC 4180 §2): quoted, quotes doubled. */
static void csv_text(FILE *f, const char *s, int *ok)
{
    *ok &= fputc('"', f) != EOF;
    for (; *s; s++) {
        if (*s == '"') *ok &= fputc('"', f) != EOF;
        *ok &= fputc(*s, f) != EOF;
    }
    *ok &= fputc('"', f) != EOF;
}

static int write_csv(const persp_accuracy_result *res, FILE *f)
{
    int ok = fputs("method,case,hbar,pixels,spans,triangles,max_u,max_v,mean_u,mean_v,p99_u,p99_v,"
                   "texel_miss,relpt_u,relpt_v,relspan_u,relspan_v,rel_floor,div_px,mul_px,add_px,"
                   "cmp_px\n",
                   f) != EOF;
    for (size_t i = 0; i < res->count; i++) {
        const persp_accuracy_row *r = &res->rows[i];
        csv_text(f, r->method, &ok);
        ok &= fputc(',', f) != EOF;
        csv_text(f, r->case_name, &ok);
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
    /* A line break or other control character in a name would end a CSV
     * record or a table line early (RFC 4180 allows them quoted, but
     * spreadsheets and line tools do not): refused before anything is
     * written. */
    for (size_t i = 0; format != PERSP_REPORT_JSON && i < res->count; i++)
        if (has_control(res->rows[i].method, strlen(res->rows[i].method)) ||
            has_control(res->rows[i].case_name, strlen(res->rows[i].case_name)))
            return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT,
                               "accuracy: row %zu: the method or case name holds a control character",
                               i + 1);
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

/* A file is read back only if it is exactly what write_json writes: every
 * key present with its type, no other key, the fixed texts of this version.
 * A row missing a number would otherwise come back as NaN and be written
 * as null (an empty CSV cell), and a foreign key or setting would be
 * dropped silently, so the merged file would contradict its shards. */

static const char *const row_numbers[] = {"max_u",     "max_v",     "mean_u",   "mean_v",
                                          "p99_u",     "p99_v",     "texel_miss", "relpt_u",
                                          "relpt_v",   "relspan_u", "relspan_v"};
static const char *const row_counts[] = {"pixels", "spans", "triangles"};
static const char *const row_ops[] = {"div", "mul", "add", "cmp"};

/* The key of o not among keys[0..n), or NULL. */
static const char *unknown_key(json_t *o, const char *const *keys, size_t n)
{
    const char *key;
    json_t *v;
    json_object_foreach(o, key, v) {
        size_t k = 0;
        while (k < n && strcmp(keys[k], key)) k++;
        if (k == n) return key;
    }
    return NULL;
}

/* A number written by jnum: a JSON number, or null for NaN. 0 if neither
 * or absent. */
static int read_num(json_t *o, const char *key, double *out)
{
    json_t *v = json_object_get(o, key);
    if (json_is_null(v)) *out = NAN;
    else if (json_is_number(v)) *out = json_number_value(v);
    else return 0;
    return 1;
}

static int rint_u64(json_t *o, const char *key, uint64_t *out)
{
    json_t *v = json_object_get(o, key);
    if (!json_is_integer(v) || json_integer_value(v) < 0) return 0;
    *out = (uint64_t)json_integer_value(v);
    return 1;
}

/* 1 if s holds a control character (U+0000..U+001F, U+007F): a name with
 * one would break the lines of the CSV and of the table. */
static int has_control(const char *s, size_t len)
{
    for (size_t i = 0; i < len; i++)
        if ((unsigned char)s[i] < 0x20 || s[i] == 0x7f) return 1;
    return 0;
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

/* Fills r from the row object o; on failure says what is wrong in why. */
static int read_row(json_t *o, double rel_floor, persp_accuracy_row *r, char *why, size_t why_size)
{
    static const char *const keys[] = {
        "method", "case",   "hbar",     "pixels",     "spans",   "triangles", "max_u",
        "max_v",  "mean_u", "mean_v",   "p99_u",      "p99_v",   "texel_miss", "relpt_u",
        "relpt_v", "relspan_u", "relspan_v", "ops_per_pixel"};
    if (!json_is_object(o)) return snprintf(why, why_size, "is not an object"), 0;
    const char *extra = unknown_key(o, keys, sizeof keys / sizeof keys[0]);
    char q[PERSP_QUOTE_BYTES];
    if (extra) return snprintf(why, why_size, "has an unknown key '%s'", persp__quote(extra, strlen(extra), q, sizeof q)), 0;
    memset(r, 0, sizeof *r);
    const char *names[2] = {"method", "case"};
    char *dest[2] = {r->method, r->case_name};
    size_t cap[2] = {sizeof r->method, sizeof r->case_name};
    for (int k = 0; k < 2; k++) {
        json_t *v = json_object_get(o, names[k]);
        if (!json_is_string(v)) return snprintf(why, why_size, "has no string '%s'", names[k]), 0;
        size_t len = json_string_length(v);
        if (len == 0 || len >= cap[k])
            return snprintf(why, why_size, "'%s' is empty or longer than %zu bytes", names[k], cap[k] - 1), 0;
        if (has_control(json_string_value(v), len))
            return snprintf(why, why_size, "'%s' holds a control character", names[k]), 0;
        memcpy(dest[k], json_string_value(v), len + 1);
    }
    double h;
    if (!read_num(o, "hbar", &h) || (h == h && !(h > 0.0)))
        return snprintf(why, why_size, "'hbar' is missing or not a positive number or null"), 0;
    r->hbar = h == h ? h : 0.0;
    uint64_t *counts[] = {&r->pixels, &r->spans, &r->triangles};
    for (size_t k = 0; k < 3; k++)
        if (!rint_u64(o, row_counts[k], counts[k]))
            return snprintf(why, why_size, "'%s' is missing or not a count", row_counts[k]), 0;
    double *nums[] = {&r->max_u,      &r->max_v,   &r->mean_u,  &r->mean_v,
                      &r->p99_u,      &r->p99_v,   &r->texel_miss, &r->relpt_u,
                      &r->relpt_v,    &r->relspan_u, &r->relspan_v};
    for (size_t k = 0; k < sizeof nums / sizeof nums[0]; k++)
        if (!read_num(o, row_numbers[k], nums[k]))
            return snprintf(why, why_size, "'%s' is missing or not a number or null", row_numbers[k]), 0;
    r->rel_floor = rel_floor;
    json_t *ops = json_object_get(o, "ops_per_pixel");
    r->div_px = r->mul_px = r->add_px = r->cmp_px = NAN;
    if (json_is_object(ops)) {
        extra = unknown_key(ops, row_ops, 4);
        if (extra)
            return snprintf(why, why_size, "'ops_per_pixel' has an unknown key '%s'",
                            persp__quote(extra, strlen(extra), q, sizeof q)), 0;
        double *o4[] = {&r->div_px, &r->mul_px, &r->add_px, &r->cmp_px};
        for (size_t k = 0; k < 4; k++)
            if (!read_num(ops, row_ops[k], o4[k]))
                return snprintf(why, why_size, "'ops_per_pixel' has no number or null '%s'", row_ops[k]), 0;
        r->ops_measured = 1;
    } else if (!json_is_null(ops)) {
        return snprintf(why, why_size, "'ops_per_pixel' is missing or not an object or null"), 0;
    }
    return 1;
}

/* The value of setting key in a sweep text ("methods=... cases=... seed=..."),
 * as a pointer into it and its length; NULL if absent. */
static const char *sweep_setting(const char *sweep, const char *key, size_t *len)
{
    size_t kl = strlen(key);
    for (const char *p = sweep; *p;) {
        const char *end = strchr(p, ' ');
        if (!end) end = p + strlen(p);
        if ((size_t)(end - p) > kl && !strncmp(p, key, kl) && p[kl] == '=') {
            *len = (size_t)(end - p) - kl - 1;
            return p + kl + 1;
        }
        p = *end ? end + 1 : end;
    }
    return NULL;
}

/* The root's form and the texts persp writes beside the rows: an object
 * with an array "rows", a "rel_floor" in (0, 1) (*rel_floor), no other key
 * than persp writes, and this version's reference and definitions. */
static persp_status read_root_texts(persp_context *ctx, const char *path, json_t *root,
                                    double *rel_floor)
{
    static const char *const top[] = {"reference", "definitions", "rel_floor", "rows", "shard"};
    double fl = NAN;
    if (!json_is_object(root) || !json_is_array(json_object_get(root, "rows")) ||
        !read_num(root, "rel_floor", &fl) || !(fl > 0.0 && fl < 1.0))
        return persp__fail(ctx, PERSP_ERR_FORMAT, "%s: not a persp accuracy JSON report", path);
    const char *extra = unknown_key(root, top, sizeof top / sizeof top[0]);
    char q[PERSP_QUOTE_BYTES];
    if (extra)
        return persp__fail(ctx, PERSP_ERR_FORMAT, "%s: unknown key '%s' (not written by persp accuracy)",
                           path, persp__quote(extra, strlen(extra), q, sizeof q));
    /* The texts persp writes beside the rows are this version's: a file that
     * says otherwise came from another version or was edited, and a merge
     * would write this version's texts over its rows. */
    const char *ref = json_string_value(json_object_get(root, "reference"));
    if (!ref || strcmp(ref, reference_text))
        return persp__fail(ctx, PERSP_ERR_FORMAT,
                           "%s: setting 'reference' is missing or not this version's", path);
    json_t *defs = json_object_get(root, "definitions");
    int defs_ok = json_is_object(defs) &&
                  json_object_size(defs) == sizeof definitions / sizeof definitions[0];
    for (size_t k = 0; defs_ok && k < sizeof definitions / sizeof definitions[0]; k++) {
        const char *t = json_string_value(json_object_get(defs, definitions[k].key));
        defs_ok = t && !strcmp(t, definitions[k].text);
    }
    if (!defs_ok)
        return persp__fail(ctx, PERSP_ERR_FORMAT,
                           "%s: setting 'definitions' is missing or not this version's", path);
    *rel_floor = fl;
    return PERSP_OK;
}

/* The shard description sh of a file of n rows into res: its slice, the
 * sweep's row count and text, and each row's place in the sweep (every one
 * this shard's); the sweep's rel_floor must be the file's. */
static persp_status read_shard(persp_context *ctx, const char *path, json_t *sh, double rel_floor,
                               size_t n, persp_accuracy_result *res)
{
    static const char *const shard_keys[] = {"index", "count", "rows", "sweep", "row_index"};
    uint64_t k, c, total;
    json_t *idx = json_object_get(sh, "row_index"), *sw = json_object_get(sh, "sweep");
    const char *sweep = json_string_value(sw);
    if (!json_is_object(sh) || !rint_u64(sh, "index", &k) || !rint_u64(sh, "count", &c) ||
        !rint_u64(sh, "rows", &total) || c == 0 || c > 1000000 || k >= c || !sweep ||
        json_string_length(sw) >= sizeof res->sweep || has_control(sweep, json_string_length(sw)) ||
        !json_is_array(idx) || json_array_size(idx) != n)
        return persp__fail(ctx, PERSP_ERR_FORMAT, "%s: malformed shard description", path);
    const char *extra = unknown_key(sh, shard_keys, sizeof shard_keys / sizeof shard_keys[0]);
    if (extra) {
        char q[PERSP_QUOTE_BYTES];
        return persp__fail(ctx, PERSP_ERR_FORMAT, "%s: shard description has an unknown key '%s'", path,
                           persp__quote(extra, strlen(extra), q, sizeof q));
    }
    /* The floor the rows were measured with is a setting of the sweep;
     * the top-level one is what the merged file will say. */
    size_t fl = 0;
    const char *f = sweep_setting(sweep, "rel_floor", &fl);
    char num[64];
    if (!f || fl >= sizeof num || (memcpy(num, f, fl), num[fl] = '\0', strtod(num, NULL) != rel_floor))
        return persp__fail(ctx, PERSP_ERR_FORMAT,
                           "%s: setting 'rel_floor' %.17g differs from the sweep's (%.*s)", path,
                           rel_floor, (int)(f ? fl : 1), f ? f : "-");
    res->shard_index = (int)k;
    res->shard_count = (int)c;
    res->total = (size_t)total;
    snprintf(res->sweep, sizeof res->sweep, "%s", sweep);
    for (size_t i = 0; i < n; i++) {
        json_t *v = json_array_get(idx, i);
        if (!json_is_integer(v) || json_integer_value(v) < 0 || (uint64_t)json_integer_value(v) >= total ||
            (uint64_t)json_integer_value(v) % c != k)
            return persp__fail(ctx, PERSP_ERR_FORMAT, "%s: row index %zu is not this shard's", path, i + 1);
        res->index[i] = (size_t)json_integer_value(v);
    }
    return PERSP_OK;
}

/* The checks of persp_accuracy_read on the parsed root. */
static persp_status read_root(persp_context *ctx, const char *path, json_t *root,
                              persp_accuracy_result **out)
{
    double rel_floor = NAN;
    persp_status st = read_root_texts(ctx, path, root, &rel_floor);
    if (st != PERSP_OK) return st;
    json_t *rows = json_object_get(root, "rows"), *sh = json_object_get(root, "shard");
    size_t n = json_array_size(rows);
    persp_accuracy_result *res = result_alloc(ctx, n);
    if (!res) return persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "%s: out of memory", path);
    snprintf(res->source, sizeof res->source, "%s", path);
    res->total = n;
    char why[160];
    for (size_t i = 0; i < n && st == PERSP_OK; i++) {
        if (!read_row(json_array_get(rows, i), rel_floor, &res->rows[i], why, sizeof why))
            st = persp__fail(ctx, PERSP_ERR_FORMAT, "%s: row %zu is malformed: it %s", path, i + 1, why);
        res->index[i] = i;
    }
    res->count = n;
    if (st == PERSP_OK && sh) st = read_shard(ctx, path, sh, rel_floor, n, res);
    if (st != PERSP_OK) {
        persp_accuracy_destroy(res);
        return st;
    }
    *out = res;
    return PERSP_OK;
}

persp_status persp_accuracy_read(persp_context *ctx, const char *path, persp_accuracy_result **out)
{
    if (!ctx) return PERSP_ERR_INVALID_ARGUMENT;
    persp__clear_error(ctx);
    if (!path || !out) return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "accuracy: nothing to read");
    *out = NULL;
    /* The text and jansson's tree are held within the context's budget:
     * the tree's need is bounded from the text before parsing, as for a
     * scene (src/io/json_text.c), so a large file is refused, not swapped. */
    char *text = NULL;
    size_t size = 0;
    persp_status st = persp__read_file(ctx, path, &text, &size);
    if (st != PERSP_OK) return st;
    char what[PERSP_ERRMSG_BYTES / 2];
    snprintf(what, sizeof what, "%s: parsing the JSON", path);
    size_t parse_bytes = persp__json_parse_bound(text, size);
    if ((st = persp__mem_reserve(ctx, parse_bytes, what)) != PERSP_OK) {
        persp__free(ctx, text);
        return st;
    }
    json_error_t err;
    char qe[PERSP_QUOTE_BYTES * 2];
    json_t *root = json_loadb(text, size, JSON_REJECT_DUPLICATES, &err);
    if (!root && persp__json_parse_ran_out(text, size, &err))
        st = persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "%s: out of memory parsing the JSON", path);
    else if (root && !persp__json_tree_matches(ctx, text, size, root))
        st = persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "%s: out of memory parsing the JSON", path);
    else if (!root)
        st = persp__fail(ctx, PERSP_ERR_FORMAT, "%s:%d:%d: %s", path, err.line, err.column,
                         persp__quote(err.text, strlen(err.text), qe, sizeof qe));
    else
        st = read_root(ctx, path, root, out);
    json_decref(root);
    persp__mem_release(ctx, parse_bytes);
    persp__free(ctx, text);
    return st;
}

/* How merge names part i in its messages: its file, or its position. */
static const char *part_name(const persp_accuracy_result *p, size_t i, char *buf, size_t size)
{
    if (p->source[0]) return p->source;
    snprintf(buf, size, "shard %zu", i + 1);
    return buf;
}

/* The first setting of sweep text b that differs from a's, as "key"
 * (value of b, value of a) in buf; "sweep" when the texts differ in form. */
static void sweep_difference(const char *a, const char *b, char *buf, size_t size)
{
    for (const char *p = b; *p;) {
        const char *end = strchr(p, ' '), *eq = strchr(p, '=');
        if (!end) end = p + strlen(p);
        if (!eq || eq > end) break;
        char key[32];
        size_t kl = (size_t)(eq - p), al = 0;
        if (kl >= sizeof key) break;
        memcpy(key, p, kl);
        key[kl] = '\0';
        const char *av = sweep_setting(a, key, &al);
        size_t bl = (size_t)(end - eq) - 1;
        if (!av || al != bl || memcmp(av, eq + 1, bl)) {
            snprintf(buf, size, "'%s' is %.*s, not %.*s", key, (int)PERSP_MIN(bl, 80), eq + 1,
                     (int)PERSP_MIN(av ? al : 1, 80), av ? av : "-");
            return;
        }
        p = *end ? end + 1 : end;
    }
    snprintf(buf, size, "the sweep is another");
}

/* The parts are shards of one sweep, each at most once: the same shard
 * count, sweep text and row count as the first, no shard index twice. */
static persp_status merge_check_parts(persp_context *ctx, const persp_accuracy_result *const *parts,
                                      size_t count)
{
    char n0[96], ni[96], diff[200];
    for (size_t i = 0; i < count; i++)
        if (!parts[i])
            return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "merge: shard %zu is NULL", i + 1);
    const persp_accuracy_result *p0 = parts[0];
    for (size_t i = 0; i < count; i++)
        if (parts[i]->shard_count <= 0)
            return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "merge: %s is a whole run, not a shard",
                               part_name(parts[i], i, ni, sizeof ni));
    size_t shards = (size_t)p0->shard_count, total = p0->total;
    for (size_t i = 1; i < count; i++) {
        const persp_accuracy_result *p = parts[i];
        const char *a = part_name(p0, 0, n0, sizeof n0), *b = part_name(p, i, ni, sizeof ni);
        if (p->shard_count != p0->shard_count)
            return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT,
                               "merge: %s is a shard of %d, %s of %d: not one sweep", b,
                               p->shard_count, a, p0->shard_count);
        if (strcmp(p->sweep, p0->sweep)) {
            sweep_difference(p0->sweep, p->sweep, diff, sizeof diff);
            return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT,
                               "merge: %s is not a shard of the same sweep as %s: setting %s", b, a,
                               diff);
        }
        if (p->total != total)
            return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT,
                               "merge: %s says the sweep has %zu rows, %s says %zu", b, p->total, a,
                               total);
    }
    for (size_t i = 0; i < count; i++)
        for (size_t j = 0; j < i; j++)
            if (parts[j]->shard_index == parts[i]->shard_index)
                return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "merge: shard %d of %zu given twice (%s, %s)",
                                   parts[i]->shard_index + 1, shards, part_name(parts[j], j, n0, sizeof n0),
                                   part_name(parts[i], i, ni, sizeof ni));
    return PERSP_OK;
}

/* The failure naming the shards missing from count distinct parts of a
 * sweep of shards (count < shards): named, as a re-run takes them by
 * number. */
static persp_status merge_name_missing(persp_context *ctx, const persp_accuracy_result *const *parts,
                                       size_t count, size_t shards)
{
    unsigned char *have = persp__calloc(ctx, shards, 1);
    if (!have) return persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "merge: out of memory");
    for (size_t i = 0; i < count; i++) have[parts[i]->shard_index] = 1;
    char list[PERSP_ERRMSG_BYTES / 2];
    size_t len = 0, missing = shards - count, listed = 0;
    list[0] = '\0';
    /* Runs as "a-b", the form of sbatch --array and of a re-run's list. */
    for (size_t k = 0; k < shards && len + 48 < sizeof list; k++) {
        if (have[k]) continue;
        size_t end = k;
        while (end + 1 < shards && !have[end + 1]) end++;
        int w = end > k ? snprintf(list + len, sizeof list - len, "%s%zu-%zu", listed ? "," : "", k + 1, end + 1)
                        : snprintf(list + len, sizeof list - len, "%s%zu", listed ? "," : "", k + 1);
        if (w > 0) len += (size_t)w;
        listed += end - k + 1;
        k = end;
    }
    persp__free(ctx, have);
    return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "merge: missing shard%s %s%s of %zu (%zu file%s given)",
                       missing == 1 ? "" : "s", list, listed < missing ? ",..." : "", shards, count,
                       count == 1 ? "" : "s");
}

/* The sweep's total rows, each from the one part that holds it, in the
 * sweep's order; a row given twice, out of range or missing is refused. */
static persp_status merge_rows(persp_context *ctx, const persp_accuracy_result *const *parts,
                               size_t count, size_t total, persp_accuracy_result **out)
{
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

persp_status persp_accuracy_merge(persp_context *ctx, const persp_accuracy_result *const *parts,
                                  size_t count, persp_accuracy_result **out)
{
    if (!ctx) return PERSP_ERR_INVALID_ARGUMENT;
    persp__clear_error(ctx);
    if (!parts || !count || !out) return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "merge: no shards");
    *out = NULL;
    persp_status st = merge_check_parts(ctx, parts, count);
    if (st != PERSP_OK) return st;
    /* Every shard is in at most once (checked above), so count < shards
     * means some are missing. */
    size_t shards = (size_t)parts[0]->shard_count;
    if (count < shards) return merge_name_missing(ctx, parts, count, shards);
    return merge_rows(ctx, parts, count, parts[0]->total, out);
}
