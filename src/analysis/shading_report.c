/* persp_shading_accuracy_report: the text report and SVG figures of
 * persp accuracy --shading (measurements in shading.c). */
#include "analysis/shading.h"

#include "analysis/analysis.h"
#include "analysis/claims.h"
#include "analysis/svg.h"
#include "core/internal.h"
#include "io/outfile.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* Depth ratios of the ΔI table and Fig. 4.3 (z2/z1; below 1 the mirror case). */
static const double delta_ratios[] = {0.2, 0.5, 1.25, 1.5, 2.0, 3.0, 5.0, 10.0};
#define DELTA_RATIOS (sizeof delta_ratios / sizeof delta_ratios[0])

/* The closed form of max Δ printed in [Romanyuk-PCF] §4.2, read literally: the
 * factors √(r − 1) cancel and it reduces to r − √r. */
static double printed_max(double r)
{
    return r - sqrt(r);
}

/* Maximum of |Δ| by dense sampling, independent of the derivation. */
static double delta_sampled_max(double r, double *at)
{
    double best = 0.0;
    *at = 0.0;
    for (int i = 0; i <= 100000; i++) {
        double u = i / 100000.0, d = fabs(persp__delta_factor(u, r));
        if (d > best) best = d, *at = u;
    }
    return best;
}

static const char *const kind_names[3] = {"quad", "pwquad", "cubic"};
static const persp_approx_kind kinds[3] = {PERSP_APPROX_QUAD, PERSP_APPROX_PWQUAD, PERSP_APPROX_CUBIC};

/* §4.3's stated maximum relative errors (percent), ħ = 2..5; < 0: none stated. */
static double claimed_bound(int kind, double hbar)
{
    const persp_claim *c = persp__claim(PERSP_CLAIM_TW_BOUNDS);
    int i = (int)hbar - 2;
    if (hbar != floor(hbar) || i < 0 || i >= PERSP_CLAIM_TW_HBARS) return -1.0;
    return kind == 1 ? c->series[i] : kind == 2 ? c->series[PERSP_CLAIM_TW_HBARS + i] : -1.0;
}

static void write_modes(FILE *f, const persp_shade_err *e, double hbar, int with_normals)
{
    for (int i = 0; i < PERSP_SHADE_MODES; i++) {
        const persp_shade_err *r = &e[i];
        if (hbar > 0.0)
            fprintf(f, "%6.2f  ", hbar);
        fprintf(f, "%-19s %9llu %8.2f %8.3f %7.2f%% %8.2f", persp_shading_name(r->mode),
                (unsigned long long)r->pixels, r->col_max, r->col_mean, 100.0 * r->col_over, r->own_max);
        if (with_normals && r->has_normals)
            fprintf(f, " %9.3f %9.4f %10.1e", r->ang_max, r->ang_mean, r->len_max);
        else if (with_normals)
            fprintf(f, " %9s %9s %10s", "-", "-", "-");
        fputc('\n', f);
    }
}

static persp_status write_svg(persp_context *ctx, const char *path)
{
    enum { NU = 201, NR = 191, NT = 769 };
    double u[NU], dy[DELTA_RATIOS][NU], r[NR], mx[NR], sp[NR], tv[NT], te[3][NT];
    char labels[DELTA_RATIOS][32];
    persp_svg_panel p[3];
    memset(p, 0, sizeof p);
    /* Fig. 4.3: Δ(u) for several z2/z1. */
    p[0].title = "Fig. 4.3: error factor of screen-linear Gouraud";
    p[0].xlabel = "u (screen parameter)";
    p[0].ylabel = "Delta(u) = (I_v - I_w)/(I_B - I_A)";
    p[0].xmin = 0.0, p[0].xmax = 1.0;
    for (int i = 0; i < NU; i++) u[i] = i / (double)(NU - 1);
    for (size_t k = 0; k < DELTA_RATIOS; k++) {
        for (int i = 0; i < NU; i++) dy[k][i] = persp__delta_factor(u[i], delta_ratios[k]);
        snprintf(labels[k], sizeof labels[k], "z2/z1 = %g", delta_ratios[k]);
        p[0].series[k] = (persp_svg_series){u, dy[k], NU, labels[k]};
    }
    p[0].series_count = (int)DELTA_RATIOS;
    /* Fig. 4.4: max |Δ| against z2/z1. */
    p[1].title = "Fig. 4.4: maximum of |Delta| against z2/z1";
    p[1].xlabel = "z2/z1";
    p[1].ylabel = "max |Delta|";
    p[1].xmin = 1.0, p[1].xmax = 20.0, p[1].ymin = 0.0, p[1].ymax = 1.0;
    for (int i = 0; i < NR; i++) {
        r[i] = 1.0 + 19.0 * i / (NR - 1);
        mx[i] = persp__delta_extremum(r[i], NULL);
        sp[i] = printed_max(r[i]);
    }
    p[1].series[0] = (persp_svg_series){r, mx, NR, "(sqrt r - 1)/(sqrt r + 1) (derived; = sampled max)"};
    p[1].series[1] = (persp_svg_series){r, sp, NR, "closed form as printed (= r - sqrt r)"};
    p[1].series_count = 2;
    /* Fig. 4.7 analogue: |p − t_w| for ħ = 3. */
    p[2].title = "t_w approximation error, hbar = Z_B/Z_A = 3";
    p[2].xlabel = "t_v";
    p[2].ylabel = "|p(t_v) - t_w(t_v)|";
    p[2].xmin = 0.0, p[2].xmax = 1.0;
    for (int k = 0; k < 3; k++) {
        double c0[4], c1[4];
        persp__tw_coeffs(kinds[k], 3.0, 0, c0);
        persp__tw_coeffs(kinds[k], 3.0, 1, c1);
        for (int i = 0; i < NT; i++) {
            double t = i / (double)(NT - 1);
            const double *c = kinds[k] == PERSP_APPROX_PWQUAD && t > 0.5 ? c1 : c0;
            tv[i] = t;
            te[k][i] = fabs(c[0] + t * (c[1] + t * (c[2] + t * c[3])) - persp__tw_exact(t, 3.0));
        }
        p[2].series[k] = (persp_svg_series){tv, te[k], NT, kind_names[k]};
    }
    p[2].series_count = 3;

    /* Written to a temporary name and renamed, so a failure leaves nothing. */
    persp_outfile o;
    persp_status st = persp__outfile_open(ctx, path, &o);
    if (st != PERSP_OK) return st;
    int bad = persp__svg_write(o.f, p, 3, 460, 380);
    return persp__outfile_close(
        ctx, &o, bad ? persp__fail(ctx, PERSP_ERR_IO, "%s: write failed", path) : PERSP_OK);
}

/* The desc's sizes and toggles in range; NULL, or the field that is not. */
static const char *shading_desc_problem(const persp_shading_accuracy_desc *desc)
{
    const char *bad = persp__analysis_size_problem(desc->triangles, desc->width, desc->height);
    if (!bad && (unsigned)desc->any_folder > PERSP_TOGGLE_OFF) bad = "any_folder";
    return bad;
}

/* The lit scene of section 2 (desc->scene, else the built-in one) and its
 * size (*w, *h: the desc's, else the scene's, else 640x480). */
static persp_status load_lit_scene(persp_context *ctx, const persp_shading_accuracy_desc *desc,
                                   persp_scene **scene, int *w, int *h)
{
    persp_scene_load_desc load;
    memset(&load, 0, sizeof load);
    if (desc->load) load = *desc->load;
    if (desc->any_folder != PERSP_TOGGLE_DEFAULT) load.any_folder = desc->any_folder;
    persp_status st = desc->scene ? persp_scene_load_ex(ctx, desc->scene, &load, scene)
                                  : persp__shading_test_scene(ctx, scene);
    if (st != PERSP_OK) return st;
    *w = desc->width, *h = desc->height;
    if (*w <= 0 || *h <= 0) persp_scene_default_size(*scene, w, h);
    if (*w <= 0 || *h <= 0) *w = 640, *h = 480;
    return PERSP_OK;
}

/* Section 1: every mode on seeded random lit triangles, per depth ratio. */
static persp_status write_random_section(persp_context *ctx, FILE *f, uint64_t seed, int tris)
{
    persp_shade_err e[PERSP_SHADE_MODES];
    fprintf(f, "1. Random lit triangles (seed %llu, %d per depth ratio hbar = z_far/z_near;\n"
               "   corridor projection 1024x768, spans cut at 64-pixel tiles as the renderer does)\n\n",
            (unsigned long long)seed, tris);
    fprintf(f, "  hbar  mode                   pixels  col max col mean  >1 lvl  own max   ang max  ang mean  ||N|-1| max\n");
    for (int g = 0; g < PERSP_HBAR_COUNT; g++) {
        persp_status st = persp__shading_random(ctx, seed, persp__hbar_groups[g], tris, e);
        if (st != PERSP_OK) return st;
        write_modes(f, e, persp__hbar_groups[g], 1);
    }
    fprintf(f,
            "\n  col max/mean: |colour - exact| in 8-bit levels, worst of R, G, B, where exact is\n"
            "  Blinn-Phong lit in double with the normal and eye position of the exact\n"
            "  perspective-correct barycentrics at the pixel centre (quantisation included:\n"
            "  a perfect method scores up to 0.5). >1 lvl: share of pixels more than one\n"
            "  level off. own max: gouraud modes against perspective-correct Gouraud in\n"
            "  double (the error of the interpolation alone), other modes = col max.\n"
            "  ang max/mean: angle in degrees between the normal a mode lights with and the\n"
            "  exact one. ||N|-1|: length error of that normal (after the mode's own\n"
            "  normalisation; none for phong-slerp).\n\n");
    return PERSP_OK;
}

/* Section 2: every mode's render of the lit scene against its phong-pc
 * render (name: how the scene is named in the heading). */
static persp_status write_scene_section(persp_context *ctx, FILE *f, const persp_scene *scene,
                                        const char *name, int w, int h)
{
    persp_shade_err e[PERSP_SHADE_MODES];
    persp_status st = persp__shading_scene_compare(ctx, scene, w, h, e);
    if (st != PERSP_OK) return st;
    fprintf(f, "2. Lit scene %s at %dx%d: each mode's render against the phong-pc render\n"
               "   (exact t_w per pixel), covered pixels\n\n",
            name, w, h);
    fprintf(f, "mode                   pixels  col max col mean  >1 lvl  own max\n");
    write_modes(f, e, 0.0, 0);
    return PERSP_OK;
}

/* Section 3: t_w against its polynomial approximations ([Romanyuk-PCF]
 * §4.3), with the paper's stated bounds. */
static void write_tw_section(FILE *f)
{
    fprintf(f, "\n3. t_w = t_v/(hbar - t_v(hbar - 1)) (4.7 corrected), hbar = Z_B/Z_A, against its\n"
               "   polynomial approximations (4.3), evaluated by the renderer's span code\n\n");
    fprintf(f, "  hbar  poly     abs max  8-bit lvl  rel max (0,1]  rel max [1/3,1]      claimed\n");
    static const double hb[] = {1.25, 1.5, 2.0, 3.0, 4.0, 5.0, 8.0, 0.5, 0.2};
    for (size_t i = 0; i < sizeof hb / sizeof hb[0]; i++)
        for (int k = 0; k < 3; k++) {
            persp_tw_error te;
            persp__tw_error(kinds[k], hb[i], &te);
            double claim = claimed_bound(k, hb[i]);
            fprintf(f, "%6.2f  %-7s %7.3f%%  %9.2f  %12.2f%%  %14.2f%%", hb[i], kind_names[k], 100.0 * te.abs_max,
                    255.0 * te.abs_max, 100.0 * te.rel_max, 100.0 * te.rel_third);
            if (claim >= 0.0) fprintf(f, "  <= %g%%", claim);
            fputc('\n', f);
        }
    fprintf(f, "\n  abs max: max |p - t_w| over t_v in [0,1] (t_w spans [0,1], so this is also the\n"
               "  error relative to the full range); 8-bit lvl: the same for an intensity range\n"
               "  of 255 levels. rel max: max |p - t_w|/t_w; as t_v -> 0 it tends to\n"
               "  |hbar p'(0) - 1| (the interpolants miss the slope 1/hbar of t_w at 0), which\n"
               "  dominates the cubic. claimed: the bound stated in [Romanyuk-PCF] §4.3; it\n"
               "  matches rel max over t_v in [1/3, 1] to within 0.4 points.\n\n");
}

/* Section 4: the error factor Delta(u) of screen-linear Gouraud and its
 * extremum ([Romanyuk-PCF] §4.2, Fig. 4.3-4.4), derived, sampled and as
 * printed. */
static void write_delta_section(FILE *f)
{
    fprintf(f, "4. Delta I of screen-linear Gouraud (4.1): Delta(u) = u(1 - 1/(r + u(1 - r))), r = z2/z1\n\n");
    fprintf(f, "  z2/z1   u=0.1   u=0.3   u=0.5   u=0.7   u=0.9  extremum   at u  sampled max   8-bit lvl    as printed\n");
    for (size_t k = 0; k < DELTA_RATIOS; k++) {
        double rr = delta_ratios[k], at, at_s;
        fprintf(f, "%7.2f", rr);
        for (int i = 1; i <= 9; i += 2) fprintf(f, " %7.4f", persp__delta_factor(i / 10.0, rr));
        double ext = persp__delta_extremum(rr, &at), sm = delta_sampled_max(rr, &at_s);
        fprintf(f, "  %8.4f %6.4f  %11.4f  %10.1f  %12.4f\n", ext, at, sm, 255.0 * fabs(ext),
                printed_max(rr));
    }
    fprintf(f, "\n  extremum: (sqrt r - 1)/(sqrt r + 1) at u* = sqrt r/(1 + sqrt r) (derived from\n"
               "  Delta'(u) = 1 - r/(r + u(1 - r))^2); sampled max: max |Delta| over 100001 values\n"
               "  of u; 8-bit lvl: 255 |extremum|, the worst Gouraud error for I_B - I_A = 255.\n"
               "  as printed: the closed form printed in [Romanyuk-PCF] §4.2 read literally\n"
               "  (r - sqrt r).\n");
}

persp_status persp_shading_accuracy_report(persp_context *ctx, const persp_shading_accuracy_desc *desc,
                                           void *stream)
{
    if (!ctx) return PERSP_ERR_INVALID_ARGUMENT;
    persp__clear_error(ctx);
    if (!desc || !stream) return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT, "shading report: no desc or stream");
    /* Checked before anything runs (a billion triangles would run for hours). */
    const char *bad = shading_desc_problem(desc);
    if (bad)
        return persp__fail(ctx, PERSP_ERR_INVALID_ARGUMENT,
                           "shading report: persp_shading_accuracy_desc.%s is out of range", bad);
    FILE *f = stream;
    /* The scene is loaded first so that a bad file fails before any output. */
    persp_scene *scene = NULL;
    int w, h;
    persp_status st = load_lit_scene(ctx, desc, &scene, &w, &h);
    if (st != PERSP_OK) return st;
    fprintf(f, "Shading modes against the exact per-pixel reference ([Romanyuk-PCF] §4.2-4.3)\n\n");
    const uint64_t seed = desc->seed ? desc->seed : 1;
    const int tris = desc->triangles > 0 ? desc->triangles : 20;
    const char *name =
        desc->scene ? desc->scene : "(built-in: floor, coarse sphere, torus, long cylinder)";
    st = write_random_section(ctx, f, seed, tris);
    if (st == PERSP_OK) st = write_scene_section(ctx, f, scene, name, w, h);
    persp_scene_destroy(scene);
    if (st != PERSP_OK) return st;
    write_tw_section(f);
    write_delta_section(f);
    if (desc->svg_path) {
        st = write_svg(ctx, desc->svg_path);
        if (st != PERSP_OK) return st;
        fprintf(f, "\nFigures (Fig. 4.3, Fig. 4.4, t_w errors at hbar = 3) written to %s\n", desc->svg_path);
    }
    return ferror(f) ? persp__fail(ctx, PERSP_ERR_IO, "shading accuracy: writing the report failed")
                     : PERSP_OK;
}
