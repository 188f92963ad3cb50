// Shared by tb_exact, tb_subdiv and tb_incremental, whose modules take
// exact's format (docs/HARDWARE.md, "exact"): the spans (`xspan` or
// `sspan`, with the end values) and pixels (`xpx`, `spx`) of `persp
// vectors`, and the comparison of a pixel's out-of-range flag and, in
// range, its t_u and t_v with persp's C model.
#ifndef PERSP_HW_TB_UV_H
#define PERSP_HW_TB_UV_H

#include "tb_common.h"

namespace tb {

constexpr int UV_EW = 41, UV_NW = 56, UV_TOW = 25;

struct uv_px {
    int ovf;
    int64_t t[2];
    long line;
};

// A span in the format: start values, steps (2G, 2A) and, for sspan, the
// values at its last pixel.
struct uv_job {
    int64_t E0, G2, N0[2], A2[2], E1, N1[2];
    int len;
    long line;
};

struct uv_vectors {
    std::vector<uv_job> jobs;
    std::vector<uv_px> px;
    long spans = 0, outside = 0, outside_pixels = 0, short_spans = 0, long_spans = 0, mismatches = 0;
};

// The spans and pixels of RECS. SPAN_KIND "xspan" (exact) or "sspan" (with
// the end values, whose steps the modules shift by up to 2^5: A2·32 must
// fit the register); PX_KIND "xpx" or "spx".
inline uv_vectors read_uv(const std::vector<record> &recs, const char *span_kind, const char *px_kind)
{
    uv_vectors v;
    const bool ends = std::string(span_kind) == "sspan";
    int64_t G = 0, A[2] = {0, 0};
    for (const record &r : recs) {
        if (r.kind == "xfmt") {
            G = r.i(2), A[0] = r.i(5), A[1] = r.i(8);
        } else if (r.kind == span_kind) {
            v.spans++;
            if (!r.i(3)) {
                v.outside++, v.outside_pixels += r.i(2);
                continue;
            }
            uv_job j{r.i(4), 2 * G, {r.i(5), r.i(6)}, {2 * A[0], 2 * A[1]}, 0, {0, 0}, (int)r.i(2), r.line};
            if (ends) j.E1 = r.i(7), j.N1[0] = r.i(8), j.N1[1] = r.i(9);
            bool fit = fits(j.E0, UV_EW) && fits(j.G2, UV_EW) && fits(j.E1, UV_EW) && j.len >= (ends ? 1 : 0) &&
                       j.len <= 127;
            for (int c = 0; c < 2; c++)
                fit = fit && fits(j.N0[c], UV_NW) && fits(j.N1[c], UV_NW) && fits(j.A2[c] * (ends ? 32 : 1), UV_NW);
            if (!fit) {
                std::printf("mismatch: line %ld: start value wider than its register\n", r.line);
                v.mismatches++;
            }
            v.short_spans += j.len <= 2, v.long_spans += j.len == 64;
            v.jobs.push_back(j);
        } else if (r.kind == px_kind) {
            v.px.push_back({(int)r.i(0), {r.i(1), r.i(2)}, r.line});
        }
    }
    return v;
}

// A span's start values and steps on exact's ports.
template <class DUT> void load_uv(DUT &d, const uv_job &j)
{
    d.E0 = port(j.E0, UV_EW), d.G2 = port(j.G2, UV_EW);
    d.Nu0 = port(j.N0[0], UV_NW), d.Nv0 = port(j.N0[1], UV_NW);
    d.Au2 = port(j.A2[0], UV_NW), d.Av2 = port(j.A2[1], UV_NW);
    d.len = (uint8_t)j.len;
}

// The same with the span's end values (subdiv, incremental).
template <class DUT> void load_uv_ends(DUT &d, const uv_job &j)
{
    load_uv(d, j);
    d.E1 = port(j.E1, UV_EW), d.Nu1 = port(j.N1[0], UV_NW), d.Nv1 = port(j.N1[1], UV_NW);
}

// One output against its expected pixel; WHO names the output in a
// mismatch ("" or "chain l: "). Counts the in-range pixels compared.
inline void check_uv(const uv_px &e, int ovf, uint64_t tu, uint64_t tv, const char *who, long &mismatches,
                     long &in_range)
{
    if (ovf != e.ovf) {
        if (mismatches++ < 10) std::printf("mismatch: line %ld: %sovf %d, expected %d\n", e.line, who, ovf, e.ovf);
        return;
    }
    if (e.ovf) return;
    in_range++;
    const int64_t t[2] = {sext(tu, UV_TOW), sext(tv, UV_TOW)};
    for (int c = 0; c < 2; c++)
        if (t[c] != e.t[c] && mismatches++ < 10)
            std::printf("mismatch: line %ld: %st%c %lld, expected %lld\n", e.line, who, "uv"[c], (long long)t[c],
                        (long long)e.t[c]);
}

}  // namespace tb

#endif
