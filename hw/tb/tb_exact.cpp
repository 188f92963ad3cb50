// tb_exact — hw/rtl/exact.v against `persp vectors --module exact` (format
// in docs/HARDWARE.md, "Vectors"): every span the hardware runs is loaded
// as soon as the module is ready, and every pixel's out-of-range flag and,
// in range, its t_u and t_v are compared with persp's C model
// (persp__hw_exact_pixel). Latency (load to first output) and pixels per
// clock are measured here, not assumed.
//
//   tb_exact VECTORS [MIN_PIXELS]
#include "Vexact.h"
#include "tb_uv.h"

#include <memory>

int main(int argc, char **argv)
{
    const long min_pixels = tb::min_units("exact", "PIXELS", argc, argv);
    tb::uv_vectors v = tb::read_uv(tb::read_records(argv[1], nullptr), "xspan", "xpx");
    auto dut = std::make_unique<Vexact>();
    tb::reset(*dut);
    size_t next = 0, got = 0;
    long in_range = 0;
    const tb::timing t = tb::clock_run(
        *dut, v.px.size(), "pixels", v.mismatches,
        [&](Vexact &d) {
            if (next == v.jobs.size()) return false;
            tb::load_uv(d, v.jobs[next++]);
            return true;
        },
        [&](Vexact &d) -> size_t {
            if (!d.out_valid) return 0;
            tb::check_uv(v.px[got++], d.out_ovf, d.out_tu, d.out_tv, "", v.mismatches, in_range);
            return 1;
        });
    std::printf("exact: %ld spans (%ld outside the format, %ld pixels), %zu pixels in the hardware, %ld in range\n",
                v.spans, v.outside, v.outside_pixels, v.px.size(), in_range);
    tb::print_timing("exact", t, got, "pixels");
    return tb::verdict("exact", (long)got, v.mismatches, min_pixels);
}
