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
    const long min_pixels = min_units(name, "PIXELS", argc, argv);
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
    reset(*dut);
    size_t next = 0, got = 0;
    const timing t = clock_run(
        *dut, want.size(), "pixels", mismatches,
        [&](DUT &d) {
            if (next == spans.size()) return false;
            load_ports(d, spans[next++]);
            return true;
        },
        [&](DUT &d) -> size_t {
            if (!d.out_valid) return 0;
            const auto &e = want[got++];
            if ((int64_t)d.out_t != e.first && mismatches++ < 10)
                std::printf("mismatch: line %ld: t_w %lld, expected %lld\n", e.second, (long long)d.out_t,
                            (long long)e.first);
            return 1;
        });
    std::printf("%s: %zu spans (%ld outside the format), %zu pixels\n", name, spans.size(), outside, want.size());
    print_timing(name, t, got, "pixels");
    return verdict(name, (long)got, mismatches, min_pixels);
}

}  // namespace tb

#endif
