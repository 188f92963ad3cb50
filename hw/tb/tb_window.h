// Shared by tb_window_one and tb_window_two: reads `persp vectors --module
// window_*` (docs/HARDWARE.md, "Vectors"), loads every window as soon as
// the module is ready and compares each texel (x, y), in the module's
// order, with persp's C model (persp__hw_window_one / _two). Latency and
// texels per clock are measured, not assumed.
#ifndef PERSP_HW_TB_WINDOW_H
#define PERSP_HW_TB_WINDOW_H

#include "tb_common.h"
#include "verilated.h"

#include <memory>

namespace tb {

template <class DUT>
int run_window(const char *name, int argc, char **argv)
{
    constexpr int XW = 24;
    Verilated::commandArgs(argc, argv);
    if (argc < 2) {
        std::fprintf(stderr, "usage: tb_%s VECTORS [MIN_TEXELS]\n", name);
        return 2;
    }
    const long min_texels = argc > 2 ? std::atol(argv[2]) : 1;
    const std::vector<record> recs = read_records(argv[1], nullptr);
    std::vector<const record *> wins;
    std::vector<const record *> want;
    for (const record &r : recs) {
        if (r.kind == "win") wins.push_back(&r);
        else if (r.kind == "wt") want.push_back(&r);
    }
    auto dut = std::make_unique<DUT>();
    dut->clk = 0, dut->rst = 1, dut->load = 0;
    dut->eval();
    dut->clk = 1, dut->eval();
    dut->clk = 0, dut->rst = 0, dut->eval();
    size_t next = 0, got = 0;
    long cycles = 0, latency = -1, first_load = -1, idle = 0, mismatches = 0;
    while (got < want.size()) {
        dut->load = 0;
        if (dut->ready && next < wins.size()) {
            const record &w = *wins[next++];
            dut->load = 1;
            dut->x0 = (uint32_t)port(w.i(0), XW), dut->y0 = (uint32_t)port(w.i(1), XW);
            dut->xmaj = (uint8_t)w.i(2), dut->sxn = w.i(3) < 0, dut->syn = w.i(4) < 0;
            dut->dy = (uint16_t)w.i(5), dut->len = (uint8_t)w.i(6), dut->rows = (uint8_t)w.i(7);
            if (first_load < 0) first_load = cycles;
        }
        dut->eval();
        dut->clk = 1, dut->eval();
        cycles++;
        if (dut->out_valid) {
            if (latency < 0) latency = cycles - 1 - first_load;
            const record &e = *want[got++];
            idle = 0;
            const int64_t x = sext(dut->out_x, XW), y = sext(dut->out_y, XW);
            if ((x != e.i(0) || y != e.i(1)) && mismatches++ < 10)
                std::printf("mismatch: line %ld: texel (%lld, %lld), expected (%lld, %lld)\n", e.line, (long long)x,
                            (long long)y, (long long)e.i(0), (long long)e.i(1));
        } else if (++idle > 100) {
            std::printf("mismatch: no output for 100 cycles with %zu texels pending\n", want.size() - got);
            mismatches++;
            break;
        }
        dut->clk = 0, dut->eval();
    }
    std::printf("%s: %zu windows, %zu texels\n", name, wins.size(), want.size());
    std::printf("%s: latency %ld cycles, cycles %ld for %zu texels: %.4f pixels per clock\n", name, latency, cycles,
                got, cycles ? (double)got / (double)cycles : 0.0);
    return verdict(name, (long)got, mismatches, min_texels);
}

}  // namespace tb

#endif
