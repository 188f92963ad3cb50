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
    Verilated::commandArgs(argc, argv);
    if (argc < 2) {
        std::fprintf(stderr, "usage: tb_%s VECTORS [MIN_PIXELS]\n", name);
        return 2;
    }
    const long min_pixels = argc > 2 ? std::atol(argv[2]) : 1;
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
    dut->clk = 0, dut->rst = 1, dut->load = 0;
    dut->eval();
    dut->clk = 1, dut->eval();
    dut->clk = 0, dut->rst = 0, dut->eval();
    size_t next = 0, got = 0;
    long cycles = 0, latency = -1, first_load = -1, idle = 0;
    while (got < want.size()) {
        dut->load = 0;
        if (dut->ready && next < jobs.size()) {
            const job<DEG> &j = jobs[next++];
            dut->load = 1;
            load(*dut, j);
            dut->len = (uint8_t)j.len;
            if (first_load < 0) first_load = cycles;
        }
        dut->eval();
        dut->clk = 1, dut->eval();
        cycles++;
        if (dut->out_valid) {
            if (latency < 0) latency = cycles - 1 - first_load;
            const expect_px &e = want[got++];
            idle = 0;
            const int64_t t[2] = {tb::sext(dut->out_tu, TOW), tb::sext(dut->out_tv, TOW)};
            for (int c = 0; c < 2; c++)
                if (t[c] != e.t[c] && mismatches++ < 10)
                    std::printf("mismatch: line %ld: t%c %lld, expected %lld\n", e.line, "uv"[c], (long long)t[c],
                                (long long)e.t[c]);
        } else if (++idle > 100) {
            std::printf("mismatch: no output for 100 cycles with %zu pixels pending\n", want.size() - got);
            mismatches++;
            break;
        }
        dut->clk = 0, dut->eval();
    }
    std::printf("%s: %ld spans (%ld outside the format, %ld pixels; %ld of 1-2 pixels, %ld of 64), %zu pixels in "
                "the hardware\n",
                name, spans, outside, outside_pixels, short_spans, long_spans, want.size());
    std::printf("%s: latency %ld cycles, cycles %ld for %zu pixels: %.4f pixels per clock\n", name, latency, cycles, got,
                cycles ? (double)got / (double)cycles : 0.0);
    return tb::verdict(name, (long)got, mismatches, min_pixels);
}

}  // namespace tb_fd

#endif
