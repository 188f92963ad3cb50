// tb_midpoint_int — hw/rtl/midpoint_int.v against `persp vectors`
// (the default module; format in docs/METHODS.md, "Test vectors"). Two
// instances, u and v, each fed the spans of the integer path from its own
// queue (as with FIFOs between them and the texel fetch); every delivered
// pixel's n, W and re-seed flag is compared with persp's, and the pixel
// where persp leaves the integer path must be flagged out_oor by u or v.
//
//   tb_midpoint_int VECTORS [MIN_PIXELS]
//
// Prints `midpoint_int: pixels N mismatches M` (pixels: integer-path pixels
// compared, both coordinates), the cycle counts, the latency (load to a
// span's first pixel, the fewest over the spans) and the pixels per clock
// after it (each lane's outputs over the clocks from its first output to
// its last: 1 where no pixel stalls); exits 1 on a mismatch or on fewer
// than MIN_PIXELS pixels.
#include "Vmidpoint_int.h"
#include "tb_common.h"
#include "verilated.h"

#include <algorithm>
#include <deque>
#include <memory>

namespace {

// Register widths: the RTL's default parameters (docs/METHODS.md).
constexpr int EW = 43, N2W = 59, WW = 62, TW = 60, KW = 61, NW = 18;

struct expect_px {
    int64_t n, W;
    int reseed;
    long line;
};

// One span for one coordinate.
struct job {
    int o2;
    int64_t G, A, E0, N2, n0, W0, T0, K;
    int len;                   // pixels to ask for: int_pixels, + 1 where persp falls back
    bool fallback;             // persp leaves the integer path at pixel int_pixels
    std::vector<expect_px> px; // the int_pixels pixels persp computed
    long line;
    int got = 0;               // outputs received
    long loaded_at = 0;        // the clock edge that took the load
    bool oor_at_end = false;   // the fallback pixel was flagged out_oor
};

struct lane {
    std::unique_ptr<Vmidpoint_int> dut;
    std::vector<job> jobs;
    size_t next = 0;          // next job to load
    std::deque<size_t> live;  // loaded, outputs pending
    long busy = 0;            // cycles with a span loaded
};

long mismatches = 0;
long cycles = 0;       // clock edges so far
long latency = -1;     // the fewest edges from a load to its span's first pixel
long outputs = 0, first_out = -1, last_out = -1;  // delivered pixels (out_oor too), both lanes

void mismatch(const char *coord, long line, const char *what, int64_t got, int64_t want)
{
    if (mismatches++ < 10)
        std::printf("mismatch: line %ld %s: %s %lld, expected %lld\n", line, coord, what, (long long)got,
                    (long long)want);
}

void drive(lane &l)
{
    Vmidpoint_int &d = *l.dut;
    d.load = 0;
    if (d.ready && l.next < l.jobs.size()) {
        const job &j = l.jobs[l.next];
        d.load = 1;
        d.o2 = j.o2;
        d.G = tb::port(j.G, EW);
        d.A = tb::port(j.A, N2W);
        d.E0 = tb::port(j.E0, EW);
        d.N2_0 = tb::port(j.N2, N2W);
        d.n0 = (uint32_t)tb::port(j.n0, NW);
        d.W0 = tb::port(j.W0, WW);
        d.T0 = tb::port(j.T0, TW);
        d.K = tb::port(j.K, KW);
        d.len = (uint8_t)j.len;
        l.jobs[l.next].loaded_at = cycles + 1;
        l.live.push_back(l.next++);
    }
}

void collect(lane &l, const char *coord)
{
    Vmidpoint_int &d = *l.dut;
    if (!l.live.empty()) l.busy++;
    if (!d.out_valid) return;
    if (l.live.empty()) {
        mismatch(coord, 0, "output with no span loaded", 1, 0);
        return;
    }
    job &j = l.jobs[l.live.front()];
    outputs++;
    if (first_out < 0) first_out = cycles;
    last_out = cycles;
    const int k = j.got++;
    if (k == 0 && (latency < 0 || cycles - j.loaded_at < latency)) latency = cycles - j.loaded_at;
    const bool oor = d.out_oor;
    if (k < (int)j.px.size()) {
        const expect_px &e = j.px[(size_t)k];
        if (oor) mismatch(coord, e.line, "out_oor (integer path ended early)", 1, 0);
        else {
            const int64_t n = tb::sext(d.out_n, NW), W = tb::sext(d.out_W, WW);
            if (n != e.n) mismatch(coord, e.line, "n", n, e.n);
            if (W != e.W) mismatch(coord, e.line, "W", W, e.W);
            if ((int)d.out_reseed != e.reseed) mismatch(coord, e.line, "reseed", d.out_reseed, e.reseed);
        }
    } else {
        j.oor_at_end = oor;
    }
    if (oor || j.got == j.len) {
        if (j.got != j.len) mismatch(coord, j.line, "pixels delivered", j.got, j.len);
        l.live.pop_front();
    }
}

}  // namespace

int main(int argc, char **argv)
{
    const long min_pixels = tb::min_units("midpoint_int", "PIXELS", argc, argv);
    std::vector<std::string> comments;
    const std::vector<tb::record> recs = tb::read_records(argv[1], &comments);

    lane lanes[2];
    int in_format = 0, o2 = 1;
    int64_t G = 0, A[2] = {0, 0};
    long spans = 0, run_spans = 0, rejected = 0, dpx = 0, int_pixels = 0, reseeds = 0, fallbacks = 0;
    for (size_t r = 0; r < recs.size(); r++) {
        const tb::record &rec = recs[r];
        if (rec.kind == "fmt") {
            in_format = (int)rec.i(0), o2 = (int)rec.i(2), G = rec.i(3), A[0] = rec.i(6), A[1] = rec.i(9);
        } else if (rec.kind == "dpx") {
            dpx++;
        } else if (rec.kind == "span") {
            spans++;
            const int n = (int)rec.i(2), ip = (int)rec.i(3);
            const int64_t E0 = rec.i(4);
            // A span that set-up sent to the double path: no start values
            // (W0 > 0 after every successful start; docs/HARDWARE.md).
            const bool runnable = in_format && E0 > 0 && rec.i(7) > 0 && rec.i(12) > 0;
            if (!runnable) {
                rejected++;
                if (ip != 0) mismatch("uv", rec.line, "integer pixels of a span without start values", ip, 0);
                continue;
            }
            run_spans++;
            const bool fb = ip < n;
            fallbacks += fb;
            for (int c = 0; c < 2; c++) {
                job j;
                j.o2 = o2, j.G = G, j.A = A[c], j.E0 = E0;
                j.N2 = rec.i(5 + 5 * (size_t)c), j.n0 = rec.i(6 + 5 * (size_t)c);
                j.W0 = rec.i(7 + 5 * (size_t)c), j.T0 = rec.i(8 + 5 * (size_t)c), j.K = rec.i(9 + 5 * (size_t)c);
                j.len = ip + (fb ? 1 : 0), j.fallback = fb, j.line = rec.line;
                for (int k = 0; k < ip; k++) {
                    const tb::record &p = recs.at(r + 1 + (size_t)k);
                    if (p.kind != "px") {
                        std::fprintf(stderr, "tb: line %ld: expected px\n", p.line);
                        return 2;
                    }
                    j.px.push_back({p.i(4 * (size_t)c), p.i(1 + 4 * (size_t)c), (int)p.i(3 + 4 * (size_t)c), p.line});
                    reseeds += p.i(3 + 4 * (size_t)c);
                }
                // The format's widths are what the RTL holds (docs/METHODS.md).
                if (!tb::fits(j.E0, EW) || !tb::fits(j.N2, N2W) || !tb::fits(j.W0, WW) || !tb::fits(j.T0, TW) ||
                    !tb::fits(j.K, KW) || !tb::fits(j.G, EW) || !tb::fits(j.A, N2W - 1))
                    mismatch("uv", rec.line, "start value wider than its register", 0, 0);
                lanes[c].jobs.push_back(std::move(j));
            }
            int_pixels += ip;
        }
    }

    const char *names[2] = {"u", "v"};
    for (lane &l : lanes) {
        l.dut = std::make_unique<Vmidpoint_int>();
        tb::reset(*l.dut);
    }
    long idle = 0;
    for (;;) {
        bool pending = false;
        for (lane &l : lanes) pending |= l.next < l.jobs.size() || !l.live.empty();
        if (!pending) break;
        for (lane &l : lanes) drive(l), l.dut->eval();
        for (lane &l : lanes) l.dut->clk = 1, l.dut->eval();
        cycles++;
        bool any = false;
        for (int c = 0; c < 2; c++) {
            any |= lanes[c].dut->out_valid;
            collect(lanes[c], names[c]);
            lanes[c].dut->clk = 0, lanes[c].dut->eval();
        }
        // The longest silence: a re-seed (CAP + NLIM + a few cycles), or
        // the divider's pipeline (NLIM + 3).
        idle = any ? 0 : idle + 1;
        if (idle > 1000) {
            mismatch("uv", 0, "no output for 1000 cycles", 0, 1);
            break;
        }
    }
    // The pixel where persp leaves the integer path: u or v must say so.
    long fb_checked = 0;
    for (size_t s = 0; s < lanes[0].jobs.size(); s++) {
        const job &ju = lanes[0].jobs[s], &jv = lanes[1].jobs[s];
        if (!ju.fallback) continue;
        fb_checked++;
        if (!ju.oor_at_end && !jv.oor_at_end) mismatch("uv", ju.line, "fallback pixel not flagged out_oor", 0, 1);
    }
    std::printf("midpoint_int: %ld spans (%ld on the integer path, %ld sent to double by set-up), %ld dpx pixels "
                "outside the hardware, %ld re-seeds, %ld fallbacks checked\n",
                spans, run_spans, rejected, dpx, reseeds, fb_checked);
    std::printf("midpoint_int: cycles %ld (u busy %ld, v busy %ld) for %ld integer-path pixels: %.4f a clock, "
                "%.4f cycles per pixel per coordinate\n",
                cycles, lanes[0].busy, lanes[1].busy, int_pixels, cycles ? (double)int_pixels / (double)cycles : 0.0,
                int_pixels ? 0.5 * (double)(lanes[0].busy + lanes[1].busy) / (double)int_pixels : 0.0);
    std::printf("midpoint_int: latency %ld cycles (load to the span's first pixel)\n", latency);
    // Throughput after the latency: each lane's delivered pixels over the
    // clocks from the first output to the last (1 where nothing stalls).
    const long out_clocks = last_out < 0 ? 0 : last_out - first_out + 1;
    std::printf("midpoint_int: %ld pixels delivered in %ld clocks after the latency: %.4f pixels per clock\n",
                outputs / 2, out_clocks, out_clocks ? 0.5 * (double)outputs / (double)out_clocks : 0.0);
    return tb::verdict("midpoint_int", int_pixels, mismatches, min_pixels);
}
