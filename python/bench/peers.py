"""volsample's extinction pyramid next to the mean downsampling of ngff-zarr, ome-zarr-py and
tinybrain on the same RGBA8 volume: time, throughput per core, 1 → 2 workers, and the error a
renderer sees (each level rendered with the same camera and compared to the full-resolution
render).

    .venv/bin/pip install ./python -r python/requirements-test.txt ngff-zarr tinybrain
    .venv/bin/python python/bench/peers.py --size 256 --chunk 64 --levels 3

The volume: thin opaque coloured sheets (one voxel thick, the case where averaging opacity
loses it: Kraus §4's 2×2×2 example) and a soft ball, in faint coloured fog.

Rendering: ``volsample.render`` with one orthographic camera (oblique, so no sheet is seen
edge-on), step ½ fine voxel. Level ℓ is rendered in its own voxels (camera and step scaled by
2^-ℓ): volsample's extinction levels with mode ``extinction`` (τ per level voxel);
the mean-downsampled straight RGBA levels with ``opacity_weighted`` and their opacities taken
per *fine* voxel (``reference_distance = 2^-ℓ`` level voxels), the fairest reading of a mean of
straight opacities. The reference is level 0 (the RGBA8 input) rendered with
``opacity_weighted``. Error: RMS and maximum over the image's associated RGBA.
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np

import volsample
import volsample.dask as vd


def make_volume(n: int) -> np.ndarray:
    z, y, x = np.mgrid[0:n, 0:n, 0:n].astype(np.float32)
    vol = np.zeros((n, n, n, 4), np.uint8)
    # Faint fog.
    vol[..., :3] = (80, 120, 200)
    vol[..., 3] = 2
    # A soft ball.
    r = np.sqrt((x - 0.6 * n) ** 2 + (y - 0.45 * n) ** 2 + (z - 0.5 * n) ** 2)
    ball = r < 0.2 * n
    vol[ball] = (255, 230, 180, 40)
    # Thin sheets, one voxel thick, every n/8 voxels along z and along x (odd positions, so
    # a 2×2×2 box always mixes a sheet voxel with an empty one).
    for k in range(1, 8):
        p = (k * n) // 8 | 1
        vol[p, :, : n // 2] = (255, 60, 40, 200)
        vol[:, : n // 2, p] = (40, 220, 90, 180)
    return vol


def camera(n: int, level: int) -> volsample.Camera:
    s = 2.0 ** level
    eye_fine = np.array([n / 2 - 0.5 - 0.6 * n, n / 2 - 0.5 - 0.3 * n, n / 2 - 0.5 - n])
    d = np.array([0.6, 0.3, 1.0])
    eye = (eye_fine + 0.5) / s - 0.5
    return volsample.Camera.orthographic(eye.tolist(), d.tolist(), [0.0, -1.0, 0.0], 1.3 * n / s)


def render_level(vol: np.ndarray, kind: str, n: int, level: int, image: int, threads: int):
    s = 2.0 ** level
    cam = camera(n, level)
    step = 0.5 / s
    if kind == "extinction":
        return volsample.render(vol, cam, image, image, mode="extinction", step=step,
                                threads=threads)
    if kind == "straight":
        v = vol if vol.dtype == np.uint8 else np.clip(vol, 0, 1).astype(np.float32)
        return volsample.render(v, cam, image, image, mode="opacity_weighted", step=step,
                                reference_distance=1.0 / s, threads=threads)
    raise ValueError(kind)


def timed(fn, repeat=1):
    best = None
    out = None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        dt = time.perf_counter() - t0
        best = dt if best is None else min(best, dt)
    return best, out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--size", type=int, default=256)
    ap.add_argument("--chunk", type=int, default=64)
    ap.add_argument("--levels", type=int, default=3)
    ap.add_argument("--image", type=int, default=192)
    ap.add_argument("--repeat", type=int, default=1)
    args = ap.parse_args()
    import dask
    import dask.array as da

    n, L = args.size, args.levels
    vol = make_volume(n)
    arr = da.from_array(vol, chunks=(args.chunk,) * 3 + (4,))
    voxels = n ** 3
    print(f"input {n}^3 RGBA8 in {args.chunk}^3 chunks, {L} levels, {os.cpu_count()} CPUs here")

    rows = []  # (name, workers, seconds, levels (fine-voxel straight or extinction), kind)

    # volsample: the extinction pyramid on Dask, 1 and 2 threads (the kernels release the GIL).
    for w in (1, 2):
        t, levels = timed(lambda: dask.compute(*vd.pyramid(arr, L, method="extinction"),
                                               scheduler="threads", num_workers=w), args.repeat)
        rows.append(("volsample extinction (a=¼)", w, t, levels, "extinction"))
    for w in (1, 2):
        t, levels = timed(lambda: dask.compute(*vd.pyramid(arr, L, method="extinction", filter=0.0),
                                               scheduler="threads", num_workers=w), args.repeat)
        rows.append(("volsample extinction (a=0, box)", w, t, levels, "extinction"))

    # ngff-zarr: DASK_BIN_SHRINK (block mean), the whole multiscale computed.
    try:
        import ngff_zarr as nz

        def ngff():
            img = nz.to_ngff_image(arr, dims=["z", "y", "x", "c"])
            ms = nz.to_multiscales(img, scale_factors=[2 ** l for l in range(1, L + 1)],
                                   method=nz.Methods.DASK_BIN_SHRINK)
            return [np.asarray(x) for x in dask.compute(*[im.data for im in ms.images],
                                                        scheduler="threads", num_workers=w)]
        for w in (1, 2):
            t, levels = timed(ngff, args.repeat)
            levels = [np.asarray(x) for x in levels]
            if levels[0].shape[-1] != 4:  # ngff-zarr may reorder to (c, z, y, x)
                levels = [np.moveaxis(x, 0, -1) for x in levels]
            rows.append(("ngff-zarr dask_bin_shrink (mean)", w, t, levels, "straight"))
    except Exception as e:  # noqa: BLE001 - reported, not hidden
        print(f"ngff-zarr: {type(e).__name__}: {e}")

    # ome-zarr-py: its pyramid builder with local_mean, asked to halve z, y and x.
    try:
        from ome_zarr.scale import _build_pyramid

        czyx = da.moveaxis(arr, 3, 0)
        factors = [{"c": 1, "z": 2 ** l, "y": 2 ** l, "x": 2 ** l} for l in range(1, L + 1)]

        def omez():
            pyr = _build_pyramid(czyx, factors, dims=("c", "z", "y", "x"), method="local_mean")
            return [np.moveaxis(np.asarray(x), 0, -1)
                    for x in dask.compute(*pyr, scheduler="threads", num_workers=w)]
        for w in (1, 2):
            t, levels = timed(omez, args.repeat)
            rows.append(("ome-zarr-py local_mean", w, t, levels, "straight"))
    except Exception as e:  # noqa: BLE001
        print(f"ome-zarr-py: {type(e).__name__}: {e}")

    # tinybrain: averaging, numpy in memory, one thread ((x, y, z, c) order).
    try:
        import tinybrain

        xyzc = np.ascontiguousarray(np.transpose(vol, (2, 1, 0, 3)))
        t, mips = timed(lambda: tinybrain.downsample_with_averaging(xyzc, (2, 2, 2), num_mips=L),
                        args.repeat)
        levels = [vol] + [np.ascontiguousarray(np.transpose(m, (2, 1, 0, 3))) for m in mips]
        rows.append(("tinybrain downsample_with_averaging", 1, t, levels, "straight"))
    except Exception as e:  # noqa: BLE001
        print(f"tinybrain: {type(e).__name__}: {e}")

    ref = render_level(vol, "straight", n, 0, args.image, 2)
    print()
    hdr = "| method | workers | time (s) | Mvoxel/s per core | " + " | ".join(
        f"level {l} RMS / max" for l in range(1, L + 1)) + " |"
    print(hdr)
    print("|" + "---|" * (4 + L))
    for name, w, t, levels, kind in rows:
        errs = []
        for l in range(1, L + 1):
            lv = levels[l]
            if kind == "straight" and lv.dtype != np.uint8:
                lv = (lv / 255.0).astype(np.float32) if lv.max() > 1.5 else lv.astype(np.float32)
            img = render_level(lv, kind, n, l, args.image, 2)
            d = img.astype(np.float64) - ref
            errs.append(f"{np.sqrt((d ** 2).mean()):.4f} / {np.abs(d).max():.3f}")
        print(f"| {name} | {w} | {t:.2f} | {voxels / t / w / 1e6:.1f} | " + " | ".join(errs) + " |")
    print()
    print("shapes:", [tuple(x.shape) for x in rows[0][3]])


if __name__ == "__main__":
    main()
