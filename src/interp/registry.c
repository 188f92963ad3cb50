/* The method registry: every texture-coordinate method, in the order
 * `persp methods` lists them. */
#include "core/internal.h"
#include "interp/methods.h"

#include <string.h>

static const persp_method *const registry[] = {
    &persp__method_affine,
    &persp__method_exact,
    &persp__method_incremental,
    &persp__method_subdiv,
    &persp__method_subdiv_quad,
    &persp__method_quadratic,
    &persp__method_quadratic_shifted,
    &persp__method_quadratic_unnorm,
    &persp__method_quadratic_pw,
    &persp__method_cubic,
    &persp__method_biquadratic,
    &persp__method_bicubic,
    &persp__method_bezier,
    &persp__method_midpoint,
    &persp__method_constz,
    &persp__method_adaptive,
};

size_t persp__method_count(void) { return sizeof registry / sizeof registry[0]; }

const persp_method *persp__method_at(size_t i)
{
    return i < persp__method_count() ? registry[i] : NULL;
}

persp_status persp__method_resolve(persp_context *ctx, const char *spec, persp_method_sel *out)
{
    if (!spec || !out) return PERSP_ERR_INVALID_ARGUMENT;
    memset(out, 0, sizeof *out);
    char q[PERSP_QUOTE_BYTES];
    const char *colon = strchr(spec, ':');
    size_t len = colon ? (size_t)(colon - spec) : strlen(spec);
    for (size_t i = 0; i < persp__method_count(); i++) {
        const persp_method *m = registry[i];
        if (strlen(m->name) != len || strncmp(m->name, spec, len) != 0) continue;
        out->m = m;
        if (m->parse) {
            persp_status st = m->parse(colon ? colon + 1 : NULL, &out->params);
            if (st != PERSP_OK)
                return persp__fail(ctx, st, "method '%s': bad parameters (expected %s:%s)",
                                          persp__quote(spec, strlen(spec), q, sizeof q), m->name,
                                          m->params_help);
        } else if (colon) {
            return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT,
                                      "method '%s' takes no parameters", m->name);
        }
        return PERSP_OK;
    }
    return persp__fail(ctx, PERSP_ERR_NOT_FOUND,
                              "unknown method '%s' (persp_method_get lists them; `persp methods` prints them)",
                              persp__quote(spec, strlen(spec), q, sizeof q));
}

/* Public view of the registry. */
size_t persp_method_count(void) { return persp__method_count(); }

persp_status persp_method_get(size_t index, persp_method_info *out)
{
    const persp_method *m = persp__method_at(index);
    if (!out) return PERSP_ERR_INVALID_ARGUMENT;
    if (!m) return PERSP_ERR_NOT_FOUND;
    out->name = m->name;
    out->params = m->params_help;
    out->summary = m->summary;
    out->source = m->source;
    out->cost = m->cost;
    return PERSP_OK;
}

persp_status persp_method_check(const char *spec)
{
    persp_method_sel sel;
    return persp__method_resolve(NULL, spec, &sel);
}
