// tb_incremental — hw/rtl/incremental.v against `persp vectors --module
// incremental` (format in docs/HARDWARE.md, "Vectors"): every span the
// hardware runs is loaded as soon as the module is ready; the left chain's
// outputs are compared with the span's pixels 0, 1, ... and the right
// chain's with n - 1, n - 2, ... (out-of-range flag and, in range, t_u and
// t_v of persp's C model, persp__hw_incremental_span). Latency (load to
// first output) and pixels per clock (both chains) are measured here; the
// spans' lengths are counted so that the run shows its short (1, 2 pixels)
// and long (64) spans.
//
//   tb_incremental VECTORS [MIN_PIXELS]
#include "Vincremental.h"
#include "tb_uv.h"

#include <memory>

int main(int argc, char **argv)
{
    const long min_pixels = tb::min_units("incremental", "PIXELS", argc, argv);
    const tb::uv_vectors v = tb::read_uv(tb::read_records(argv[1], nullptr), "sspan", "spx");
    long mismatches = v.mismatches;
    // Left chain: pixels 0 .. ceil(n/2) - 1 of each span; right chain: n - 1
    // down to ceil(n/2).
    std::vector<tb::uv_px> want_l, want_r;
    size_t p = 0;
    for (const tb::uv_job &j : v.jobs) {
        const size_t n = (size_t)j.len, h = (n + 1) / 2;
        for (size_t k = 0; k < h; k++) want_l.push_back(v.px.at(p + k));
        for (size_t k = n; k-- > h;) want_r.push_back(v.px.at(p + k));
        p += n;
    }
    const size_t total = want_l.size() + want_r.size();

    auto dut = std::make_unique<Vincremental>();
    tb::reset(*dut);
    size_t next = 0, got_l = 0, got_r = 0;
    long in_range = 0;
    // One chain's output against its next expected pixel.
    auto check = [&](int valid, int ovf, uint32_t tu, uint32_t tv, const std::vector<tb::uv_px> &want, size_t &got,
                     const char *who) -> size_t {
        if (!valid) return 0;
        if (got == want.size()) {
            if (mismatches++ < 10) std::printf("mismatch: %soutput beyond the expected pixels\n", who);
            return 1;
        }
        tb::check_uv(want[got++], ovf, tu, tv, who, mismatches, in_range);
        return 1;
    };
    const tb::timing t = tb::clock_run(
        *dut, total, "pixels", mismatches,
        [&](Vincremental &d) {
            if (next == v.jobs.size()) return false;
            tb::load_uv_ends(d, v.jobs[next++]);
            return true;
        },
        [&](Vincremental &d) {
            return check(d.out_valid_l, d.out_ovf_l, d.out_tu_l, d.out_tv_l, want_l, got_l, "chain l: ") +
                   check(d.out_valid_r, d.out_ovf_r, d.out_tu_r, d.out_tv_r, want_r, got_r, "chain r: ");
        });
    std::printf("incremental: %ld spans (%ld outside the format, %ld pixels; %ld of 1-2 pixels, %ld of 64), %zu pixels "
                "in the hardware, %ld in range\n",
                v.spans, v.outside, v.outside_pixels, v.short_spans, v.long_spans, total, in_range);
    tb::print_timing("incremental", t, got_l + got_r, "pixels");
    return tb::verdict("incremental", (long)(got_l + got_r), mismatches, min_pixels);
}
