// Shared by tb_tw_exact, tb_tw_quadratic, tb_tw_pwquad, tb_tw_cubic: reads
// `persp vectors --module tw_*` (docs/HARDWARE.md, "Vectors"), loads every
// span the hardware runs as soon as the module is ready and compares each
// pixel's t_w with persp's C model (persp__hw_tw_run). Latency (load to
// first output) and pixels per clock are measured, not assumed.
#ifndef PERSP_HW_TB_TW_H
#define PERSP_HW_TB_TW_H

#include "tb_common.h"
#include "verilated.h"

#include <memory>

namespace tb {

struct tw_span {
    int n, m;
    int64_t a[4], b[3];
};

// LOAD(dut, span) puts a span's start values on the module's ports.
template <class DUT, class LOAD>
int run_tw(const char *name, int argc, char **argv, LOAD load_ports)
{
    Verilated::commandArgs(argc, argv);
    if (argc < 2) {
        std::fprintf(stderr, "usage: tb_%s VECTORS [MIN_PIXELS]\n", name);
        return 2;
    }
    const long min_pixels = argc > 2 ? std::atol(argv[2]) : 1;
    const std::vector<record> recs = read_records(argv[1], nullptr);
    std::vector<tw_span> spans;
    std::vector<std::pair<int64_t, long>> want;
    long outside = 0, mismatches = 0;
    for (const record &r : recs) {
        if (r.kind == "twspan") {
            if (!r.i(3)) {
                outside++;
                continue;
            }
            spans.push_back({(int)r.i(2), (int)r.i(4), {r.i(5), r.i(6), r.i(7), r.i(8)}, {r.i(9), r.i(10), r.i(11)}});
        } else if (r.kind == "twpx") {
            want.push_back({r.i(0), r.line});
        }
    }
    auto dut = std::make_unique<DUT>();
    dut->clk = 0, dut->rst = 1, dut->load = 0;
    dut->eval();
    dut->clk = 1, dut->eval();
    dut->clk = 0, dut->rst = 0, dut->eval();
    size_t next = 0, got = 0;
    long cycles = 0, latency = -1, first_load = -1, idle = 0;
    while (got < want.size()) {
        dut->load = 0;
        if (dut->ready && next < spans.size()) {
            dut->load = 1;
            load_ports(*dut, spans[next++]);
            if (first_load < 0) first_load = cycles;
        }
        dut->eval();
        dut->clk = 1, dut->eval();
        cycles++;
        if (dut->out_valid) {
            if (latency < 0) latency = cycles - 1 - first_load;
            const auto &e = want[got++];
            idle = 0;
            if ((int64_t)dut->out_t != e.first && mismatches++ < 10)
                std::printf("mismatch: line %ld: t_w %lld, expected %lld\n", e.second, (long long)dut->out_t,
                            (long long)e.first);
        } else if (++idle > 100) {
            std::printf("mismatch: no output for 100 cycles with %zu pixels pending\n", want.size() - got);
            mismatches++;
            break;
        }
        dut->clk = 0, dut->eval();
    }
    std::printf("%s: %zu spans (%ld outside the format), %zu pixels\n", name, spans.size(), outside, want.size());
    std::printf("%s: latency %ld cycles, cycles %ld for %zu pixels: %.4f pixels per clock\n", name, latency, cycles,
                got, cycles ? (double)got / (double)cycles : 0.0);
    return verdict(name, (long)got, mismatches, min_pixels);
}

}  // namespace tb

#endif
