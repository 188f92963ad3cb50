// Shared by the Verilator testbenches of hw/tb: reading `persp vectors`
// files (docs/HARDWARE.md, "Vectors") and moving two's-complement values
// between C++ and Verilator's port words, which hold a W-bit signal in the
// low W bits of a 64-bit word with the rest zero.
#ifndef PERSP_HW_TB_COMMON_H
#define PERSP_HW_TB_COMMON_H

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

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
