// NanoVDB peer for host-tests/benches/ray_march.rs (issue 9): the same 256^3 RGBA volume as
// four NanoVDB float grids (one per channel, values n/255), sampled with NanoVDB's trilinear
// sampler (SampleFromVoxels<..., 1, true>: order 1, cached stencil) at the positions peers.py
// wrote. Prints ns per RGBA sample (four channel lookups, no compositing) for each file.
// Built by run.sh from the header-only Debian package libnanovdb-dev.
#include <nanovdb/NanoVDB.h>
#include <nanovdb/util/GridBuilder.h>
#include <nanovdb/util/SampleFromVoxels.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <vector>

static float channel(int c, int x, int y, int z) {
    int v = c == 0 ? x : c == 1 ? y : c == 2 ? z : 4 + (7 * x + 13 * y + 29 * z) % 61;
    return float(v & 255) / 255.0f;
}

int main(int argc, char** argv) {
    const int n = 256;
    std::vector<nanovdb::GridHandle<>> handles;
    for (int c = 0; c < 4; ++c) {
        nanovdb::GridBuilder<float> builder(0.0f);
        builder([c](const nanovdb::Coord& ijk) { return channel(c, ijk[0], ijk[1], ijk[2]); },
                nanovdb::CoordBBox(nanovdb::Coord(0), nanovdb::Coord(n - 1)));
        handles.push_back(builder.getHandle<>());
    }
    for (int a = 1; a < argc; ++a) {
        std::ifstream f(argv[a], std::ios::binary | std::ios::ate);
        size_t bytes = f.tellg();
        f.seekg(0);
        std::vector<float> pos(bytes / 4);
        f.read(reinterpret_cast<char*>(pos.data()), bytes);
        size_t count = pos.size() / 3;
        std::vector<double> runs;
        double sink = 0;
        for (int rep = 0; rep < 5; ++rep) {
            auto t0 = std::chrono::steady_clock::now();
            for (int c = 0; c < 4; ++c) {
                auto* grid = handles[c].grid<float>();
                auto acc = grid->getAccessor();
                auto smp = nanovdb::createSampler<1, decltype(acc), true>(acc);
                float s = 0;
                for (size_t i = 0; i < count; ++i)
                    s += smp(nanovdb::Vec3f(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]));
                sink += s;
            }
            auto t1 = std::chrono::steady_clock::now();
            runs.push_back(std::chrono::duration<double, std::nano>(t1 - t0).count() / count);
        }
        std::sort(runs.begin(), runs.end());
        std::printf("%s %.3f %zu %g\n", argv[a], runs[runs.size() / 2], count, sink);
    }
    return 0;
}
