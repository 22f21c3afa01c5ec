// Verilator bench: vs_ow_ftb_pipe (pipelined OpacityWeighted trilinear sample + front-to-back
// step) against `volsample vectors`: the sample of vector i of `opacity-weighted-trilinear`
// (inputs.hex, expected.hex), composited behind the accumulator acc of vector i of
// `composite-front-to-back` (the low 64 bits of its inputs.hex: a valid U8.8 accumulator).
// The expected `out` is the manifest's step on the expected sample:
// out_x = acc_x + (T*s_x + 32640) div 65280, T = 65280 - acc_a.
// One vector enters per clock, with a bubble (in_valid = 0) every fifth clock; the outputs
// must come back in order with out_valid after the pipeline's latency.
//
// Usage: tb_ow_ftb_pipe F N OW_INPUTS OW_EXPECTED COMPOSITE_INPUTS. Prints every mismatch
// (the first 20 in full) and one final line starting with "PASS:" or "FAIL:"; exit status 1
// on failure.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "Vvs_ow_ftb_pipe.h"
#include "verilated.h"

using Word = std::vector<uint32_t>;  // little-endian 32-bit limbs

static std::vector<Word> read_hex(const char* path) {
    std::ifstream in(path);
    if (!in) {
        std::printf("FAIL: cannot read %s\n", path);
        std::exit(1);
    }
    std::vector<Word> words;
    std::string line;
    while (std::getline(in, line)) {
        if (line.empty()) continue;
        Word w((line.size() * 4 + 31) / 32, 0);
        for (size_t d = 0; d < line.size(); ++d) {
            const char c = line[line.size() - 1 - d];
            const uint32_t nib = (c >= 'a') ? c - 'a' + 10 : (c >= 'A') ? c - 'A' + 10 : c - '0';
            w[d / 8] |= nib << (4 * (d % 8));
        }
        words.push_back(w);
    }
    return words;
}

// Bits off..off+width-1 (width <= 64) of w.
static uint64_t bits(const Word& w, int off, int width) {
    uint64_t v = 0;
    for (int b = 0; b < width; ++b) {
        const int p = off + b;
        const uint64_t bit = (p / 32 < static_cast<int>(w.size())) ? (w[p / 32] >> (p % 32)) & 1 : 0;
        v |= bit << b;
    }
    return v;
}

static uint64_t front_to_back(uint64_t acc, uint64_t s) {
    const uint64_t t = 65280 - (acc >> 48);
    uint64_t out = 0;
    for (int k = 0; k < 4; ++k) {
        const uint64_t a = (acc >> (16 * k)) & 0xFFFF, x = (s >> (16 * k)) & 0xFFFF;
        out |= ((a + (t * x + 32640) / 65280) & 0xFFFF) << (16 * k);
    }
    return out;
}

int main(int argc, char** argv) {
    if (argc < 6) {
        std::printf("FAIL: usage: tb_ow_ftb_pipe F N OW_INPUTS OW_EXPECTED COMPOSITE_INPUTS\n");
        return 1;
    }
    const int f = std::atoi(argv[1]);
    const size_t n = std::strtoul(argv[2], nullptr, 10);
    const std::vector<Word> ins = read_hex(argv[3]), exp = read_hex(argv[4]), comp = read_hex(argv[5]);
    if (ins.size() < n || exp.size() < n || comp.size() < n) {
        std::printf("FAIL: vs_ow_ftb_pipe: fewer than %zu words in the vector files\n", n);
        return 1;
    }
    VerilatedContext ctx;
    Vvs_ow_ftb_pipe top(&ctx);
    auto tick = [&top]() {
        top.clk = 1;
        top.eval();
        const bool valid = top.out_valid;
        const uint64_t s = top.s, out = top.out;
        top.clk = 0;
        top.eval();
        return std::make_tuple(valid, s, out);
    };
    top.clk = 0;
    top.rst = 1;
    top.in_valid = 0;
    top.eval();
    tick();
    tick();
    top.rst = 0;
    size_t sent = 0, got = 0, errors = 0, cycles = 0, latency = 0;
    std::vector<size_t> sent_at(n);
    while (got < n && cycles < 2 * n + 100) {
        const bool bubble = cycles % 5 == 4;
        if (!bubble && sent < n) {
            const Word& w = ins[sent];
            for (int l = 0; l < 8; ++l) top.voxels[l] = w[l];
            top.fx = bits(w, 256, f);
            top.fy = bits(w, 256 + f, f);
            top.fz = bits(w, 256 + 2 * f, f);
            top.acc = bits(comp[sent], 0, 64);
            top.in_valid = 1;
            sent_at[sent] = cycles;
            ++sent;
        } else {
            top.in_valid = 0;
        }
        const auto [valid, s, out] = tick();
        ++cycles;
        if (valid) {
            latency = cycles - sent_at[got];
            const uint64_t want_s = bits(exp[got], 0, 64);
            const uint64_t want_out = front_to_back(bits(comp[got], 0, 64), want_s);
            if (s != want_s || out != want_out) {
                ++errors;
                if (errors <= 20)
                    std::printf("MISMATCH vector %zu: got s %016llx out %016llx expected s %016llx out %016llx\n",
                                got, (unsigned long long)s, (unsigned long long)out,
                                (unsigned long long)want_s, (unsigned long long)want_out);
            }
            ++got;
        }
    }
    top.final();
    if (got != n) {
        std::printf("FAIL: vs_ow_ftb_pipe F=%d: %zu of %zu vectors came out\n", f, got, n);
        return 1;
    }
    if (errors == 0) {
        std::printf("PASS: vs_ow_ftb_pipe F=%d: %zu vectors, 0 mismatches (latency %zu clocks, %zu clocks)\n",
                    f, n, latency, cycles);
        return 0;
    }
    std::printf("FAIL: vs_ow_ftb_pipe F=%d: %zu vectors, %zu mismatches\n", f, n, errors);
    return 1;
}
