// Shared by the Verilator testbenches of hw/tb: reading `persp vectors`
// files (docs/HARDWARE.md, "Vectors"), moving two's-complement values
// between C++ and Verilator's port words, which hold a W-bit signal in the
// low W bits of a 64-bit word with the rest zero, and the clock loop that
// loads spans as the module is ready and measures latency and throughput.
#ifndef PERSP_HW_TB_COMMON_H
#define PERSP_HW_TB_COMMON_H

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "verilated.h"

namespace tb {

// A W-bit port word from a signed value (the value's low W bits).
inline uint64_t port(int64_t v, int w) { return w >= 64 ? (uint64_t)v : (uint64_t)v & ((1ull << w) - 1); }

// The signed value of a W-bit port word.
inline int64_t sext(uint64_t v, int w)
{
    return w >= 64 ? (int64_t)v : (int64_t)(v << (64 - w)) >> (64 - w);
}

// Whether v fits a W-bit two's-complement register.
inline bool fits(int64_t v, int w) { return sext(port(v, w), w) == v; }

// One record of a vectors file: its name, fields and line number.
struct record {
    std::string kind;
    std::vector<std::string> f;
    long line = 0;
    int64_t i(size_t k) const { return std::strtoll(f.at(k).c_str(), nullptr, 10); }
    uint64_t hex(size_t k) const { return std::strtoull(f.at(k).c_str(), nullptr, 16); }
};

// The records of FILE, '#' lines left out; exits on an unreadable file.
inline std::vector<record> read_records(const char *path, std::vector<std::string> *comments)
{
    std::ifstream in(path);
    if (!in) {
        std::fprintf(stderr, "tb: %s: cannot open\n", path);
        std::exit(2);
    }
    std::vector<record> out;
    std::string line;
    long no = 0;
    while (std::getline(in, line)) {
        no++;
        if (line.empty()) continue;
        if (line[0] == '#') {
            if (comments) comments->push_back(line);
            continue;
        }
        std::istringstream ss(line);
        record r;
        r.line = no;
        ss >> r.kind;
        std::string w;
        while (ss >> w) r.f.push_back(w);
        out.push_back(std::move(r));
    }
    return out;
}

// The command line every testbench takes, `tb_NAME VECTORS [MIN_UNITS]`:
// MIN_UNITS (default 1), or exit 2 with the usage.
inline long min_units(const char *name, const char *units, int argc, char **argv)
{
    Verilated::commandArgs(argc, argv);
    if (argc < 2) {
        std::fprintf(stderr, "usage: tb_%s VECTORS [MIN_%s]\n", name, units);
        std::exit(2);
    }
    return argc > 2 ? std::atol(argv[2]) : 1;
}

// A reset clock: every module resets synchronously and idles with load low.
template <class DUT> void reset(DUT &dut)
{
    dut.clk = 0, dut.rst = 1, dut.load = 0;
    dut.eval();
    dut.clk = 1, dut.eval();
    dut.clk = 0, dut.rst = 0, dut.eval();
}

// What a run measured: clocks, and load to first output (the latency).
struct timing {
    long cycles = 0, latency = -1;
};

// Clocks DUT until WANT outputs have come: before each rising edge, when the
// module is ready, LOAD(dut) puts the next job on its ports and says whether
// there was one (load is then raised); after the edge, OUTPUT(dut) checks
// and counts this clock's outputs. 100 clocks without one are a mismatch
// (the module hangs), and end the run.
template <class DUT, class LOAD, class OUTPUT>
timing clock_run(DUT &dut, size_t want, const char *units, long &mismatches, LOAD load, OUTPUT output)
{
    timing t;
    size_t got = 0;
    long first_load = -1, idle = 0;
    while (got < want) {
        dut.load = 0;
        if (dut.ready && load(dut)) {
            dut.load = 1;
            if (first_load < 0) first_load = t.cycles;
        }
        dut.eval();
        dut.clk = 1, dut.eval();
        t.cycles++;
        if (const size_t n = output(dut)) {
            if (t.latency < 0) t.latency = t.cycles - 1 - first_load;
            got += n, idle = 0;
        } else if (++idle > 100) {
            std::printf("mismatch: no output for 100 cycles with %zu %s pending\n", want - got, units);
            mismatches++;
            break;
        }
        dut.clk = 0, dut.eval();
    }
    return t;
}

// The line scripts/hw.sh reads the latency and the throughput from.
inline void print_timing(const char *name, const timing &t, size_t got, const char *units)
{
    std::printf("%s: latency %ld cycles, cycles %ld for %zu %s: %.4f pixels per clock\n", name, t.latency, t.cycles,
                got, units, t.cycles ? (double)got / (double)t.cycles : 0.0);
}

// The verdict every testbench ends with (scripts/hw.sh reads this line).
inline int verdict(const char *name, long pixels, long mismatches, long min_pixels)
{
    std::printf("%s: pixels %ld mismatches %ld\n", name, pixels, mismatches);
    if (mismatches) return 1;
    if (pixels < min_pixels) {
        std::printf("%s: FAIL: %ld pixels compared, fewer than the %ld asked\n", name, pixels, min_pixels);
        return 1;
    }
    return 0;
}

}  // namespace tb

#endif
