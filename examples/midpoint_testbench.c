/*
 * midpoint_testbench — the shape of a testbench for a hardware design of
 * midpoint:int, the division-free interpolator of [Romanyuk-PCF] §4.5:
 * persp_midpoint_trace gives, for each span, the start values a design
 * loads and, for each pixel, the registers it must hold after the pixel
 * (lattice index n and the decision variable W of u and v). Here the
 * "design" is a plain C model of the per-pixel datapath written from
 * docs/METHODS.md; in a real flow step_pixel() would clock a simulated RTL
 * model (Verilator's C++ class, say) instead. Every register of every
 * pixel is compared and the first difference is printed.
 *
 *   midpoint_testbench [TRIANGLES [SEED]]
 *
 *   cc midpoint_testbench.c $(pkg-config --cflags --libs persp-analysis) -o midpoint_testbench
 */
#include <persp.h>
#include <persp_analysis.h>

#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>

/* The design's state for one coordinate: the registers of METHODS.md. */
typedef struct dut_coord {
    int64_t n, W, T, K;
} dut_coord;

typedef struct dut {
    int64_t E, G;
    dut_coord c[2];
} dut;

typedef struct bench {
    const persp_midpoint_format *f;
    unsigned long pixels, spans, mismatches;
} bench;

/* One pixel of the datapath: the step from the previous pixel (first:
 * none), then the lattice search. Returns 0 when the search would pass
 * the 32 steps after which midpoint:int re-seeds by a division, which
 * this design leaves to its divider (not modelled here). */
static int step_pixel(dut *d, int first)
{
    if (!first) {
        d->E += 2 * d->G;
        for (int j = 0; j < 2; j++) d->c[j].W += d->c[j].T - d->c[j].K;
    }
    for (int j = 0; j < 2; j++) {
        dut_coord *c = &d->c[j];
        int steps = 0;
        while (c->W <= 0 && steps < 32) c->n++, c->W += 2 * d->E, c->T += 4 * d->G, steps++;
        while (c->W > 2 * d->E && steps < 32) c->n--, c->W -= 2 * d->E, c->T -= 4 * d->G, steps++;
        if (!(c->W > 0 && c->W <= 2 * d->E)) return 0;
    }
    return 1;
}

/* The registers of coordinate j after pixel px, from persp's: n and W as
 * given, T = 2G·M with M = 2n + 2o (the invariant the steps keep). */
static void reload(dut *d, const persp_midpoint_format *f, int j, const persp_midpoint_pixel *px)
{
    d->c[j].n = px->n[j], d->c[j].W = px->W[j];
    d->c[j].T = 2 * f->G * (2 * px->n[j] + f->lattice2);
}

static void check_span(void *user, const persp_midpoint_span *s, const persp_midpoint_pixel *px)
{
    bench *b = user;
    b->spans++;
    dut d = {s->E0, b->f->G, {{0, 0, 0, 0}, {0, 0, 0, 0}}};
    for (int j = 0; j < 2; j++) d.c[j] = (dut_coord){s->n0[j], s->W0[j], s->T0[j], s->K[j]};
    for (int k = 0; k < s->int_pixels; k++) {
        /* A re-seeded pixel restarts from persp's registers, as a design
         * would after its divider answers. */
        if (!step_pixel(&d, k == 0) || px[k].reseed[0] || px[k].reseed[1]) {
            for (int j = 0; j < 2; j++) reload(&d, b->f, j, &px[k]);
            continue;
        }
        b->pixels++;
        for (int j = 0; j < 2; j++)
            if (d.c[j].n != px[k].n[j] || d.c[j].W != px[k].W[j]) {
                if (b->mismatches++ == 0)
                    printf("first mismatch: pixel (%d, %d) %c: design n %" PRId64 " W %" PRId64
                           ", persp n %" PRId64 " W %" PRId64 "\n",
                           s->x0 + k, s->y, "uv"[j], d.c[j].n, d.c[j].W, px[k].n[j], px[k].W[j]);
                reload(&d, b->f, j, &px[k]);
            }
    }
}

static double uniform(uint64_t *s, double lo, double hi)
{
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return lo + (hi - lo) * (double)(*s >> 11) / 9007199254740992.0;
}

int main(int argc, char **argv)
{
    const int triangles = argc > 1 ? atoi(argv[1]) : 50;
    uint64_t seed = argc > 2 ? strtoull(argv[2], NULL, 10) : 1;
    persp_context *ctx = NULL;
    if (persp_context_create(NULL, &ctx) != PERSP_OK) return 1;
    bench b = {NULL, 0, 0, 0};
    for (int t = 0; t < triangles; t++) {
        persp_method_vertex v[3];
        const double cx = uniform(&seed, 0, 640), cy = uniform(&seed, 0, 480), r = uniform(&seed, 5, 150);
        for (int k = 0; k < 3; k++)
            v[k] = (persp_method_vertex){cx + uniform(&seed, -r, r), cy + uniform(&seed, -r, r),
                                         uniform(&seed, 1, 8), (float)uniform(&seed, 0, 1),
                                         (float)uniform(&seed, 0, 1)};
        persp_midpoint_format f;
        b.f = &f;
        /* f is filled before the first span, as a design loads G, H, I, A,
         * B, C once per triangle. */
        persp_status st = persp_midpoint_trace(ctx, "midpoint:int", v, 640, 480, 256, 256, &f, check_span, &b);
        if (st != PERSP_OK) {
            fprintf(stderr, "midpoint_testbench: %s: %s\n", persp_status_string(st), persp_context_error(ctx));
            persp_context_destroy(ctx);
            return 1;
        }
    }
    printf("%d triangles, %lu spans, %lu pixels compared register by register, %lu mismatches\n", triangles,
           b.spans, b.pixels, b.mismatches);
    persp_context_destroy(ctx);
    return b.mismatches == 0 && b.pixels > 0 ? 0 : 1;
}
