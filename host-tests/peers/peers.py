"""Peers of the ray_march criterion bench (issue 9), on the same volume and sample positions.

Rebuilds the bench's 256^3 RGBA volume (voxel (x, y, z) = (x, y, z, 4 + (7x + 13y + 29z) mod
61), bytes read as n/255) as four float32 arrays, and the bench's sample positions: the
coherent rays (pixel (i, j) of a 128 x 128 grid starting at (16 + i + 1/4, 64 + j + 1/4, -1)
along (0.12, 0.08, 1) normalised, clipped to the box [-1/2, n - 1/2]^3, samples at k*d, d = 0.5,
computed in float32 as volsample does) and the 2^20 random positions (splitmix64 of the index).

Times scipy.ndimage.map_coordinates(order=1) on each channel (four calls per RGBA sample; no
compositing, which volsample's timing includes), writes the positions for the NanoVDB peer,
reads volsample's criterion medians back from target/criterion, and prints ns/sample and the
ratios. Usage: python peers.py CRITERION_DIR OUT_DIR [NANOVDB_RESULTS]
"""

import json
import os
import statistics
import sys
import time

import numpy as np
import scipy
from scipy import ndimage

N = 256
D = np.float32(0.5)


def volume(n):
    z, y, x = np.meshgrid(np.arange(n), np.arange(n), np.arange(n), indexing="ij")
    a = 4 + (7 * x + 13 * y + 29 * z) % 61
    chans = [x & 255, y & 255, z & 255, a]
    # n/255 correctly rounded to float32, as volsample's unorm8.
    return [(c.astype(np.float64) / 255.0).astype(np.float32) for c in chans]


def coherent_positions(n):
    w = n // 2
    x0, y0 = np.float32(n // 16), np.float32(n // 4)
    j, i = np.meshgrid(np.arange(w), np.arange(w), indexing="ij")
    ox = (x0 + i.astype(np.float32) + np.float32(0.25)).ravel()
    oy = (y0 + j.astype(np.float32) + np.float32(0.25)).ravel()
    oz = np.full_like(ox, -1.0)
    d = np.array([0.12, 0.08, 1.0], dtype=np.float32)
    d = d * (np.float32(1.0) / np.sqrt(np.sum(d * d, dtype=np.float32)))
    lo, hi = np.float32(-0.5), np.float32(n - 0.5)
    t0 = np.zeros_like(ox)
    t1 = np.full_like(ox, np.inf)
    for o, dk in ((ox, d[0]), (oy, d[1]), (oz, d[2])):
        inv = np.float32(1.0) / dk
        a, b = (lo - o) * inv, (hi - o) * inv
        t0 = np.maximum(t0, np.minimum(a, b))
        t1 = np.minimum(t1, np.maximum(a, b))
    k0 = np.ceil(t0 / D)
    k1 = np.ceil(t1 / D)
    counts = np.maximum(k1 - k0, 0).astype(np.int64)
    first = k0 * D
    ray = np.repeat(np.arange(ox.size), counts)
    j_in_ray = np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts)
    t = first[ray] + j_in_ray.astype(np.float32) * D
    pos = np.stack([ox[ray] + d[0] * t, oy[ray] + d[1] * t, oz[ray] + d[2] * t], axis=1)
    return pos.astype(np.float32)


def random_positions(count):
    def coord(k):
        with np.errstate(over="ignore"):
            z = (k + np.uint64(1)) * np.uint64(0x9E3779B97F4A7C15)
            z = (z ^ (z >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
            z = (z ^ (z >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
            z = z ^ (z >> np.uint64(31))
        return (z >> np.uint64(40)).astype(np.float32) * np.float32(255.0 / 16777216.0)

    i = np.arange(count, dtype=np.uint64)
    return np.stack([coord(3 * i), coord(3 * i + 1), coord(3 * i + 2)], axis=1)


def time_scipy(chans, pos, reps=3):
    # map_coordinates takes (axis0, axis1, axis2) = (z, y, x) coordinate rows.
    coords = np.ascontiguousarray(pos[:, ::-1].T.astype(np.float64))
    runs = []
    for _ in range(reps):
        t = time.perf_counter()
        for c in chans:
            ndimage.map_coordinates(c, coords, order=1, mode="nearest", prefilter=False,
                                    output=np.float32)
        runs.append((time.perf_counter() - t) * 1e9 / len(pos))
    return statistics.median(runs)


def volsample_ns(criterion_dir, name):
    base = os.path.join(criterion_dir, "ray_march", name, "new")
    try:
        with open(os.path.join(base, "estimates.json")) as f:
            median = json.load(f)["median"]["point_estimate"]
        with open(os.path.join(base, "benchmark.json")) as f:
            elems = json.load(f)["throughput"]["Elements"]
        return median / elems
    except (OSError, KeyError, TypeError):
        return None


def main():
    criterion_dir, out_dir = sys.argv[1], sys.argv[2]
    nano = {}
    if len(sys.argv) > 3 and os.path.exists(sys.argv[3]):
        for line in open(sys.argv[3]):
            path, ns, _count, _sink = line.split()
            nano[os.path.basename(path)] = float(ns)
    chans = volume(N)
    cases = [
        ("coherent", coherent_positions(N), "ow_f32_u8_256"),
        ("random", random_positions(1 << 20), "ow_f32_u8_256_random_access"),
    ]
    print(f"numpy {np.__version__}, scipy {scipy.__version__}")
    print(f"{'positions':<12} {'count':>9} {'volsample':>10} {'scipy':>9} {'scipy/vs':>9} "
          f"{'nanovdb':>9} {'nanovdb/vs':>10}")
    rows = []
    for label, pos, bench in cases:
        pos.tofile(os.path.join(out_dir, f"{label}.f32"))
        rows.append((label, pos, bench, time_scipy(chans, pos), nano.get(f"{label}.f32")))
    # The coherent rays four at a time (volsample's packet kernels, bit-identical per ray)
    # against the same peer timings.
    label, pos, _, ns_scipy, ns_nano = rows[0]
    rows.insert(1, (label + " x4", pos, "ow_f32_u8_256_packets", ns_scipy, ns_nano))
    # The bench's yardstick (not volsample): a hand-tuned SSE2 loop doing the same work on
    # the same rays, so the ratios show what a hand-written kernel gets on this machine.
    rows.insert(2, ("hand-tuned", pos, "yardstick_tuned_256", ns_scipy, ns_nano))
    # The same loop across rays (eight rays in AVX2 lanes where the CPU has them).
    rows.insert(3, ("tuned rays", pos, "yardstick_tuned_rays_256", ns_scipy, ns_nano))
    for label, pos, bench, ns_scipy, ns_nano in rows:
        ns_vs = volsample_ns(criterion_dir, bench)
        fmt = lambda x: "n/a" if x is None else f"{x:.2f}"
        ratio = lambda x: "n/a" if x is None or ns_vs is None else f"{x / ns_vs:.1f}x"
        print(f"{label:<12} {len(pos):>9} {fmt(ns_vs):>10} {fmt(ns_scipy):>9} "
              f"{ratio(ns_scipy):>9} {fmt(ns_nano):>9} {ratio(ns_nano):>10}")
    print("ns per RGBA sample; volsample includes front-to-back compositing (coherent) and "
          "the peers only interpolate (four channel lookups); 'coherent x4' is volsample's "
          "packet kernel (cast_rays: four rays at a time, eight in AVX2 lanes in a build with "
          "the feature avx2 for an AVX2 CPU) on the same rays; 'hand-tuned' is "
          "the bench's yardstick loop (not volsample) on the same rays, 'tuned rays' the "
          "same loop eight rays at a time in AVX2 lanes (one at a time without AVX2).")


if __name__ == "__main__":
    main()
