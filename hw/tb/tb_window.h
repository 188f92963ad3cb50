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
    const long min_texels = min_units(name, "TEXELS", argc, argv);
    const std::vector<record> recs = read_records(argv[1], nullptr);
    std::vector<const record *> wins;
    std::vector<const record *> want;
    for (const record &r : recs) {
        if (r.kind == "win") wins.push_back(&r);
        else if (r.kind == "wt") want.push_back(&r);
    }
    auto dut = std::make_unique<DUT>();
    reset(*dut);
    size_t next = 0, got = 0;
    long mismatches = 0;
    const timing t = clock_run(
        *dut, want.size(), "texels", mismatches,
        [&](DUT &d) {
            if (next == wins.size()) return false;
            const record &w = *wins[next++];
            d.x0 = (uint32_t)port(w.i(0), XW), d.y0 = (uint32_t)port(w.i(1), XW);
            d.xmaj = (uint8_t)w.i(2), d.sxn = w.i(3) < 0, d.syn = w.i(4) < 0;
            d.dy = (uint16_t)w.i(5), d.len = (uint8_t)w.i(6), d.rows = (uint8_t)w.i(7);
            return true;
        },
        [&](DUT &d) -> size_t {
            if (!d.out_valid) return 0;
            const record &e = *want[got++];
            const int64_t x = sext(d.out_x, XW), y = sext(d.out_y, XW);
            if ((x != e.i(0) || y != e.i(1)) && mismatches++ < 10)
                std::printf("mismatch: line %ld: texel (%lld, %lld), expected (%lld, %lld)\n", e.line, (long long)x,
                            (long long)y, (long long)e.i(0), (long long)e.i(1));
            return 1;
        });
    std::printf("%s: %zu windows, %zu texels\n", name, wins.size(), want.size());
    print_timing(name, t, got, "texels");
    return verdict(name, (long)got, mismatches, min_texels);
}

}  // namespace tb

#endif
