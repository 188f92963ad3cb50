/* Context, allocator, status strings and error details. */
#include "core/internal.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/fmath.h"
#include "core/pool.h"

const char *persp_version(void) { return PERSP_VERSION_STRING; }

const char *persp_status_string(persp_status status)
{
    switch (status) {
    case PERSP_OK: return "ok";
    case PERSP_ERR_INVALID_ARGUMENT: return "invalid argument";
    case PERSP_ERR_OUT_OF_MEMORY: return "out of memory";
    case PERSP_ERR_IO: return "input/output error";
    case PERSP_ERR_FORMAT: return "malformed data";
    case PERSP_ERR_TOO_LARGE: return "too large";
    case PERSP_ERR_UNSUPPORTED: return "unsupported";
    case PERSP_ERR_NOT_FOUND: return "not found";
    case PERSP_ERR_UNAVAILABLE: return "not available in this build";
    }
    return "unknown status";
}

static void *default_alloc(void *user, size_t size)
{
    (void)user;
    return malloc(size);
}

static void default_free(void *user, void *ptr)
{
    (void)user;
    free(ptr);
}

static const char *const simd_names[] = {"auto",   "baseline", "avx2", "avx2-gather",
                                          "avx512", "avx512-gather"};
/* persp_simd order after AUTO. */
static const int simd_isa[] = {PERSP_ISA_BASE, PERSP_ISA_AVX2, PERSP_ISA_AVX2_GATHER,
                               PERSP_ISA_AVX512, PERSP_ISA_AVX512_GATHER};

persp_simd persp__simd_from_isa(int isa)
{
    for (size_t i = 0; i < sizeof simd_isa / sizeof *simd_isa; i++)
        if (simd_isa[i] == isa) return (persp_simd)(i + 1);
    return PERSP_SIMD_AUTO;
}

const char *persp_simd_name(persp_simd simd)
{
    return (unsigned)simd < sizeof simd_names / sizeof *simd_names ? simd_names[simd] : "?";
}

persp_status persp_simd_parse(const char *name, persp_simd *out)
{
    if (!name || !out) return PERSP_ERR_INVALID_ARGUMENT;
    for (size_t i = 0; i < sizeof simd_names / sizeof *simd_names; i++)
        if (strcmp(name, simd_names[i]) == 0) {
            *out = (persp_simd)i;
            return PERSP_OK;
        }
    return PERSP_ERR_NOT_FOUND;
}

persp_status persp_context_create(const persp_context_desc *desc, persp_context **out)
{
    if (!out) return PERSP_ERR_INVALID_ARGUMENT;
    *out = NULL;
    persp_allocator al = {default_alloc, default_free, NULL};
    int threads = 1;
    size_t max_memory = 0;
    int isa = -1; /* PERSP_SIMD_AUTO: chosen at the first frame (persp_context_simd) */
    if (desc) {
        if (desc->allocator) {
            if (!desc->allocator->alloc || !desc->allocator->free) return PERSP_ERR_INVALID_ARGUMENT;
            al = *desc->allocator;
        }
        if (desc->threads < 0 || desc->threads > 256) return PERSP_ERR_INVALID_ARGUMENT;
        if (desc->threads > 1) threads = desc->threads;
        max_memory = desc->max_memory;
        if ((unsigned)desc->simd > PERSP_SIMD_AVX512_GATHER) return PERSP_ERR_INVALID_ARGUMENT;
        if (desc->simd != PERSP_SIMD_AUTO) {
            isa = simd_isa[desc->simd - 1];
            if (!persp__isa_runs(isa)) return PERSP_ERR_UNSUPPORTED;
        }
    }
    if (max_memory && max_memory < sizeof(persp_context))
        return PERSP_ERR_OUT_OF_MEMORY; /* not even the context fits */
    persp_context *ctx = al.alloc(al.user, sizeof *ctx);
    if (!ctx) return PERSP_ERR_OUT_OF_MEMORY;
    memset(ctx, 0, sizeof *ctx);
    ctx->allocator = al;
    ctx->threads = threads;
    ctx->max_memory = max_memory;
    ctx->isa = ctx->shade_isa = isa;
    ctx->mem_used = ctx->mem_peak = sizeof *ctx;
    *out = ctx;
    return PERSP_OK;
}

void persp_context_destroy(persp_context *ctx)
{
    if (!ctx) return;
    persp__warn_release(ctx, 0);
    persp__pool_destroy(ctx);
    if (ctx->render_free) ctx->render_free(ctx);
    persp_allocator al = ctx->allocator;
    al.free(al.user, ctx);
}

persp_context *persp__context_child(persp_context *ctx)
{
    persp_context *c = persp__calloc(ctx, 1, sizeof *c);
    if (!c) return NULL;
    c->allocator = ctx->allocator;
    c->threads = 1;
    c->isa = ctx->isa;
    c->shade_isa = ctx->shade_isa;
    return c;
}

void persp__context_child_free(persp_context *ctx, persp_context *child)
{
    if (!child) return;
    persp__mem_release(ctx, child->mem_used);
    if (child->render_free) child->render_free(child);
    persp__free(ctx, child);
}

const char *persp_context_error(const persp_context *ctx) { return ctx ? ctx->error : ""; }

void persp__clear_error(persp_context *ctx)
{
    if (!ctx) return;
    ctx->error[0] = '\0';
    ctx->mem_refused = 0;
}

/* Sizes in messages: bytes below 10 KiB, else KiB, MiB or GiB with one
 * decimal. */
static void format_bytes(char *buf, size_t n, size_t bytes)
{
    static const char *const unit[] = {"KiB", "MiB", "GiB", "TiB"};
    if (bytes < 10240) {
        snprintf(buf, n, "%zu bytes", bytes);
        return;
    }
    double v = (double)bytes / 1024.0;
    int u = 0;
    while (v >= 1024.0 && u < 3) v /= 1024.0, u++;
    snprintf(buf, n, "%.1f %s", v, unit[u]);
}

/* The budget's part of a detail: "needs X, over the memory budget of Y (Z
 * already in use)". */
static void budget_detail(const persp_context *ctx, size_t bytes, size_t in_use, char *buf, size_t n)
{
    char need[32], max[32], used[32];
    format_bytes(need, sizeof need, bytes);
    format_bytes(max, sizeof max, ctx->max_memory);
    format_bytes(used, sizeof used, in_use);
    snprintf(buf, n, "needs %s, over the memory budget of %s (%s already in use)", need, max, used);
}

static int budget_fits(const persp_context *ctx, size_t bytes)
{
    return !ctx->max_memory ||
           (ctx->mem_used <= ctx->max_memory && bytes <= ctx->max_memory - ctx->mem_used);
}

size_t persp__mem_available(const persp_context *ctx)
{
    if (!ctx || !ctx->max_memory) return (size_t)-1;
    return ctx->mem_used < ctx->max_memory ? ctx->max_memory - ctx->mem_used : 0;
}

persp_status persp__mem_reserve(persp_context *ctx, size_t bytes, const char *what)
{
    if (!ctx) return PERSP_OK;
    if (!budget_fits(ctx, bytes)) {
        char detail[160];
        budget_detail(ctx, bytes, ctx->mem_used, detail, sizeof detail);
        ctx->mem_refused = 0; /* this detail already names the budget */
        return persp__fail(ctx, PERSP_ERR_OUT_OF_MEMORY, "%s: %s", what ? what : "memory", detail);
    }
    ctx->mem_used += bytes;
    if (ctx->mem_used > ctx->mem_peak) ctx->mem_peak = ctx->mem_used;
    return PERSP_OK;
}

void persp__mem_release(persp_context *ctx, size_t bytes)
{
    if (ctx) ctx->mem_used = bytes < ctx->mem_used ? ctx->mem_used - bytes : 0;
}

void persp_context_set_warning_handler(persp_context *ctx, persp_warning_fn fn, void *user)
{
    if (!ctx) return;
    ctx->warn = fn;
    ctx->warn_user = fn ? user : NULL;
}

void persp_context_set_temp_file_handler(persp_context *ctx, persp_temp_file_fn fn, void *user)
{
    if (!ctx) return;
    ctx->temp_fn = fn;
    ctx->temp_user = fn ? user : NULL;
}

/* Details and warnings are one line each (persp.h): a file name, a method
 * spec, a JSON key or a decoder's message given by the input may carry a
 * line break. */
static void one_line(char *s)
{
    for (; *s; s++)
        if (*s == '\n' || *s == '\r') *s = ' ';
}

void persp__warn(persp_context *ctx, const char *fmt, ...)
{
    if (!ctx || !ctx->warn || !fmt) return;
    char line[PERSP_ERRMSG_BYTES];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    one_line(line);
    if (ctx->holding) {
        /* A warning between a refusal and its error keeps the refusal's
         * detail (persp__alloc clears it when it grants a block). */
        const size_t refused = ctx->mem_refused, refused_used = ctx->mem_refused_used;
        const size_t n = strlen(line) + 1;
        const int held = persp__grow(ctx, (void **)&ctx->held, &ctx->held_cap, ctx->held_len + n, 1) == PERSP_OK;
        ctx->mem_refused = refused, ctx->mem_refused_used = refused_used;
        if (held) {
            memcpy(ctx->held + ctx->held_len, line, n);
            ctx->held_len += n;
            return;
        }
        persp__warn_release(ctx, 1);
    }
    ctx->warn(ctx->warn_user, line);
}

void persp__warn_hold(persp_context *ctx)
{
    if (ctx) ctx->holding = 1;
}

void persp__warn_release(persp_context *ctx, int deliver)
{
    if (!ctx) return;
    ctx->holding = 0;
    for (size_t at = 0; deliver && ctx->warn && at < ctx->held_len; at += strlen(ctx->held + at) + 1)
        ctx->warn(ctx->warn_user, ctx->held + at);
    persp__free(ctx, ctx->held);
    ctx->held = NULL;
    ctx->held_len = ctx->held_cap = 0;
}

persp_status persp__fail(persp_context *ctx, persp_status status, const char *fmt, ...)
{
    if (ctx && fmt) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(ctx->error, sizeof ctx->error, fmt, ap);
        va_end(ap);
        /* An allocation the budget refused: say so, whatever the caller
         * knew about it. */
        if (status == PERSP_ERR_OUT_OF_MEMORY && ctx->mem_refused) {
            char detail[160];
            budget_detail(ctx, ctx->mem_refused, ctx->mem_refused_used, detail, sizeof detail);
            size_t len = strlen(ctx->error);
            snprintf(ctx->error + len, sizeof ctx->error - len, " (%s)", detail);
            ctx->mem_refused = 0;
        }
        one_line(ctx->error);
    }
    return status;
}


void *persp__alloc(persp_context *ctx, size_t size)
{
    if (!ctx || size == 0 || size > (size_t)-1 - PERSP_BLOCK_HEADER) return NULL;
    if (ctx->frozen) {
        ctx->starved = 1;
        return NULL;
    }
    size_t total = size + PERSP_BLOCK_HEADER;
    ctx->mem_refused = 0; /* the detail speaks of the latest request only */
    if (!budget_fits(ctx, total)) {
        ctx->mem_refused = total;
        ctx->mem_refused_used = ctx->mem_used;
        return NULL;
    }
    unsigned char *p = ctx->allocator.alloc(ctx->allocator.user, total);
    if (!p) return NULL;
    memcpy(p, &total, sizeof total);
    ctx->mem_used += total;
    if (ctx->mem_used > ctx->mem_peak) ctx->mem_peak = ctx->mem_used;
    return p + PERSP_BLOCK_HEADER;
}

void persp__free(persp_context *ctx, void *ptr)
{
    if (!ctx || !ptr) return;
    unsigned char *p = (unsigned char *)ptr - PERSP_BLOCK_HEADER;
    size_t total;
    memcpy(&total, p, sizeof total);
    persp__mem_release(ctx, total);
    ctx->allocator.free(ctx->allocator.user, p);
}

void *persp__calloc(persp_context *ctx, size_t n, size_t size)
{
    size_t bytes;
    if (!persp__size_mul(n, size, &bytes) || bytes == 0) return NULL;
    void *p = persp__alloc(ctx, bytes);
    if (p) memset(p, 0, bytes);
    return p;
}

/* Capacity of an array's first allocation: small arrays then grow a few
 * times at most, and an empty one costs no allocation at all. */
#define GROW_FIRST 16

persp_status persp__grow(persp_context *ctx, void **ptr, size_t *cap, size_t need, size_t elem)
{
    if (need <= *cap) return PERSP_OK;
    size_t bytes;
    if (elem == 0 || !persp__size_mul(need, elem, &bytes)) return PERSP_ERR_TOO_LARGE;
    size_t ncap = *cap ? *cap : GROW_FIRST;
    while (ncap < need) ncap = ncap > (size_t)-1 / 2 ? need : ncap * 2;
    if (!persp__size_mul(ncap, elem, &bytes)) {
        ncap = need; /* doubling overflows where need itself does not */
        bytes = need * elem;
    }
    unsigned char *n = persp__alloc(ctx, bytes);
    if (!n) return PERSP_ERR_OUT_OF_MEMORY;
    size_t kept = *cap * elem;
    if (kept) memcpy(n, *ptr, kept);
    memset(n + kept, 0, bytes - kept);
    persp__free(ctx, *ptr);
    *ptr = n;
    *cap = ncap;
    return PERSP_OK;
}

persp_status persp__reserve(persp_context *ctx, void **ptr, size_t *cap, size_t need, size_t elem)
{
    if (need <= *cap) return PERSP_OK;
    size_t bytes;
    if (elem == 0 || !persp__size_mul(need, elem, &bytes)) return PERSP_ERR_TOO_LARGE;
    if (ctx->frozen) {
        ctx->starved = 1;
        return PERSP_ERR_OUT_OF_MEMORY;
    }
    persp__free(ctx, *ptr);
    *ptr = persp__calloc(ctx, need, elem);
    *cap = *ptr ? need : 0;
    return *ptr ? PERSP_OK : PERSP_ERR_OUT_OF_MEMORY;
}
