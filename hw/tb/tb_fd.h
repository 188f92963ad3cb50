// The testbench of the forward-difference span modules (quadratic, cubic,
// bezier; docs/HARDWARE.md): every span in the format is loaded with its
// forward differences (d0..dDEG of u and v) as soon as the module is ready,
// and every pixel's t_u and t_v are compared with persp's C model
// (persp__hw_fd_pixel). Latency (load to first output) and pixels per clock
// are measured here, not assumed; the spans' lengths are counted so that
// the run shows its short (1, 2 pixels) and long (64) spans. Each
// tb_MODULE.cpp gives the model, its degree and how its ports are loaded.
#ifndef PERSP_HW_TB_FD_H
#define PERSP_HW_TB_FD_H

#include "tb_common.h"
#include "verilated.h"

#include <memory>

namespace tb_fd {

constexpr int DW = 50, TOW = 25;

struct expect_px {
    int64_t t[2];
    long line;
};

template <int DEG> struct job {
    int64_t d[2][DEG + 1];
    int len;
    long line;
};

template <class Model, int DEG> int run(const char *name, int argc, char **argv, void (*load)(Model &, const job<DEG> &))
{
    const long min_pixels = tb::min_units(name, "PIXELS", argc, argv);
    const std::vector<tb::record> recs = tb::read_records(argv[1], nullptr);
    std::vector<job<DEG>> jobs;
    std::vector<expect_px> want;
    long spans = 0, outside = 0, outside_pixels = 0, mismatches = 0, short_spans = 0, long_spans = 0;
    for (const tb::record &r : recs) {
        if (r.kind == "sspan") {
            spans++;
            if (!r.i(3)) {
                outside++, outside_pixels += r.i(2);
                continue;
            }
            job<DEG> j{};
            j.len = (int)r.i(2), j.line = r.line;
            for (int c = 0; c < 2; c++)
                for (int i = 0; i <= DEG; i++) {
                    j.d[c][i] = r.i(4 + (size_t)(c * (DEG + 1) + i));
                    if (!tb::fits(j.d[c][i], DW)) {
                        std::printf("mismatch: line %ld: d%d wider than its register\n", r.line, i);
                        mismatches++;
                    }
                }
            if (j.len < 1 || j.len > 127) {
                std::printf("mismatch: line %ld: span length %d\n", r.line, j.len);
                mismatches++;
            }
            short_spans += j.len <= 2, long_spans += j.len == 64;
            jobs.push_back(j);
        } else if (r.kind == "spx") {
            want.push_back({{r.i(1), r.i(2)}, r.line});
        }
    }

    auto dut = std::make_unique<Model>();
    tb::reset(*dut);
    size_t next = 0, got = 0;
    const tb::timing t = tb::clock_run(
        *dut, want.size(), "pixels", mismatches,
        [&](Model &d) {
            if (next == jobs.size()) return false;
            const job<DEG> &j = jobs[next++];
            load(d, j);
            d.len = (uint8_t)j.len;
            return true;
        },
        [&](Model &d) -> size_t {
            if (!d.out_valid) return 0;
            const expect_px &e = want[got++];
            const int64_t tv[2] = {tb::sext(d.out_tu, TOW), tb::sext(d.out_tv, TOW)};
            for (int c = 0; c < 2; c++)
                if (tv[c] != e.t[c] && mismatches++ < 10)
                    std::printf("mismatch: line %ld: t%c %lld, expected %lld\n", e.line, "uv"[c], (long long)tv[c],
                                (long long)e.t[c]);
            return 1;
        });
    std::printf("%s: %ld spans (%ld outside the format, %ld pixels; %ld of 1-2 pixels, %ld of 64), %zu pixels in "
                "the hardware\n",
                name, spans, outside, outside_pixels, short_spans, long_spans, want.size());
    tb::print_timing(name, t, got, "pixels");
    return tb::verdict(name, (long)got, mismatches, min_pixels);
}

}  // namespace tb_fd

#endif
