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
#include "tb_common.h"
#include "verilated.h"

#include <memory>

namespace {

constexpr int EW = 41, NW = 56, TOW = 25;

struct expect_px {
    int ovf;
    int64_t t[2];
    long line;
};

struct job {
    int64_t E0, G2, N0[2], A2[2], E1, N1[2];
    int len;
    long line;
};

}  // namespace

int main(int argc, char **argv)
{
    Verilated::commandArgs(argc, argv);
    if (argc < 2) {
        std::fprintf(stderr, "usage: tb_incremental VECTORS [MIN_PIXELS]\n");
        return 2;
    }
    const long min_pixels = argc > 2 ? std::atol(argv[2]) : 1;
    const std::vector<tb::record> recs = tb::read_records(argv[1], nullptr);
    std::vector<job> jobs;
    std::vector<expect_px> want_l, want_r, span_px;
    int64_t G = 0, A[2] = {0, 0};
    long spans = 0, outside = 0, outside_pixels = 0, mismatches = 0, short_spans = 0, long_spans = 0;
    for (const tb::record &r : recs) {
        if (r.kind == "xfmt") {
            G = r.i(2), A[0] = r.i(5), A[1] = r.i(8);
        } else if (r.kind == "sspan") {
            spans++;
            if (!r.i(3)) {
                outside++, outside_pixels += r.i(2);
                continue;
            }
            job j{r.i(4), 2 * G, {r.i(5), r.i(6)}, {2 * A[0], 2 * A[1]}, r.i(7), {r.i(8), r.i(9)}, (int)r.i(2), r.line};
            if (!tb::fits(j.E0, EW) || !tb::fits(j.G2, EW) || !tb::fits(j.E1, EW) || j.len < 1 || j.len > 127) {
                std::printf("mismatch: line %ld: start value wider than its register\n", r.line);
                mismatches++;
            }
            for (int c = 0; c < 2; c++)
                if (!tb::fits(j.N0[c], NW) || !tb::fits(j.N1[c], NW) || !tb::fits(j.A2[c] * 32, NW)) {
                    std::printf("mismatch: line %ld: start value wider than its register\n", r.line);
                    mismatches++;
                }
            short_spans += j.len <= 2, long_spans += j.len == 64;
            jobs.push_back(j);
        } else if (r.kind == "spx") {
            span_px.push_back({(int)r.i(0), {r.i(1), r.i(2)}, r.line});
            if ((int)span_px.size() == jobs.back().len) {
                // Left chain: 0 .. ceil(n/2) - 1; right chain: n - 1 down to ceil(n/2).
                const size_t n = span_px.size(), h = (n + 1) / 2;
                for (size_t k = 0; k < h; k++) want_l.push_back(span_px[k]);
                for (size_t k = n; k-- > h;) want_r.push_back(span_px[k]);
                span_px.clear();
            }
        }
    }
    const size_t total = want_l.size() + want_r.size();

    auto dut = std::make_unique<Vincremental>();
    dut->clk = 0, dut->rst = 1, dut->load = 0;
    dut->eval();
    dut->clk = 1, dut->eval();
    dut->clk = 0, dut->rst = 0, dut->eval();
    size_t next = 0, got_l = 0, got_r = 0;
    long cycles = 0, latency = -1, first_load = -1, idle = 0, in_range = 0;
    // One chain's output against its next expected pixel.
    auto check = [&](int valid, int ovf, uint32_t tu, uint32_t tv, const std::vector<expect_px> &want, size_t &got,
                     char side) {
        if (!valid) return;
        if (got == want.size()) {
            if (mismatches++ < 10) std::printf("mismatch: chain %c: output beyond the expected pixels\n", side);
            return;
        }
        const expect_px &e = want[got++];
        if (ovf != e.ovf) {
            if (mismatches++ < 10)
                std::printf("mismatch: line %ld: chain %c: ovf %d, expected %d\n", e.line, side, ovf, e.ovf);
        } else if (!e.ovf) {
            in_range++;
            const int64_t t[2] = {tb::sext(tu, TOW), tb::sext(tv, TOW)};
            for (int c = 0; c < 2; c++)
                if (t[c] != e.t[c] && mismatches++ < 10)
                    std::printf("mismatch: line %ld: chain %c: t%c %lld, expected %lld\n", e.line, side, "uv"[c],
                                (long long)t[c], (long long)e.t[c]);
        }
    };
    while (got_l + got_r < total) {
        dut->load = 0;
        if (dut->ready && next < jobs.size()) {
            const job &j = jobs[next++];
            dut->load = 1;
            dut->E0 = tb::port(j.E0, EW), dut->G2 = tb::port(j.G2, EW), dut->E1 = tb::port(j.E1, EW);
            dut->Nu0 = tb::port(j.N0[0], NW), dut->Nv0 = tb::port(j.N0[1], NW);
            dut->Au2 = tb::port(j.A2[0], NW), dut->Av2 = tb::port(j.A2[1], NW);
            dut->Nu1 = tb::port(j.N1[0], NW), dut->Nv1 = tb::port(j.N1[1], NW);
            dut->len = (uint8_t)j.len;
            if (first_load < 0) first_load = cycles;
        }
        dut->eval();
        dut->clk = 1, dut->eval();
        cycles++;
        if (dut->out_valid_l || dut->out_valid_r) {
            if (latency < 0) latency = cycles - 1 - first_load;
            idle = 0;
            check(dut->out_valid_l, dut->out_ovf_l, dut->out_tu_l, dut->out_tv_l, want_l, got_l, 'l');
            check(dut->out_valid_r, dut->out_ovf_r, dut->out_tu_r, dut->out_tv_r, want_r, got_r, 'r');
        } else if (++idle > 100) {
            std::printf("mismatch: no output for 100 cycles with %zu pixels pending\n", total - got_l - got_r);
            mismatches++;
            break;
        }
        dut->clk = 0, dut->eval();
    }
    const size_t got = got_l + got_r;
    std::printf("incremental: %ld spans (%ld outside the format, %ld pixels; %ld of 1-2 pixels, %ld of 64), %zu pixels "
                "in the hardware, %ld in range\n",
                spans, outside, outside_pixels, short_spans, long_spans, total, in_range);
    std::printf("incremental: latency %ld cycles, cycles %ld for %zu pixels: %.4f pixels per clock\n", latency, cycles,
                got, cycles ? (double)got / (double)cycles : 0.0);
    return tb::verdict("incremental", (long)got, mismatches, min_pixels);
}
