// tb_subdiv — hw/rtl/subdiv.v against `persp vectors --module subdiv` (or
// subdiv:8 for a model built with -GN=8; format in docs/HARDWARE.md,
// "Vectors"): every span the hardware runs is loaded as soon as the module
// is ready, and every pixel's out-of-range flag and, in range, its t_u and
// t_v are compared with persp's C model (persp__hw_subdiv_span). Latency
// (load to first output) and pixels per clock are measured here; the
// spans' lengths are counted so that the run shows its short (1, 2 pixels)
// and long (64) spans.
//
//   tb_subdiv VECTORS [MIN_PIXELS]
#include "Vsubdiv.h"
#include "tb_uv.h"

#include <memory>

int main(int argc, char **argv)
{
    const long min_pixels = tb::min_units("subdiv", "PIXELS", argc, argv);
    tb::uv_vectors v = tb::read_uv(tb::read_records(argv[1], nullptr), "sspan", "spx");
    auto dut = std::make_unique<Vsubdiv>();
    tb::reset(*dut);
    size_t next = 0, got = 0;
    long in_range = 0;
    const tb::timing t = tb::clock_run(
        *dut, v.px.size(), "pixels", v.mismatches,
        [&](Vsubdiv &d) {
            if (next == v.jobs.size()) return false;
            tb::load_uv_ends(d, v.jobs[next++]);
            return true;
        },
        [&](Vsubdiv &d) -> size_t {
            if (!d.out_valid) return 0;
            tb::check_uv(v.px[got++], d.out_ovf, d.out_tu, d.out_tv, "", v.mismatches, in_range);
            return 1;
        });
    std::printf("subdiv: %ld spans (%ld outside the format, %ld pixels; %ld of 1-2 pixels, %ld of 64), %zu pixels "
                "in the hardware, %ld in range\n",
                v.spans, v.outside, v.outside_pixels, v.short_spans, v.long_spans, v.px.size(), in_range);
    tb::print_timing("subdiv", t, got, "pixels");
    return tb::verdict("subdiv", (long)got, v.mismatches, min_pixels);
}
