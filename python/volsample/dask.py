"""Chunked RGBA pyramids on Dask, bit-identical to the whole-volume result, and their
OME-Zarr multiscale.

Each coarse voxel ``j`` of a level reads the fine voxels ``2j - 1 … 2j + 2`` of the level
before (clamped to the edge). :func:`pyramid` therefore

* rechunks the input so that every chunk but the last along an axis is a multiple of
  ``2**levels`` voxels (then every level's chunk boundaries fall on even voxels), with the
  channel axis in one chunk;
* builds each level with ``dask.array.map_overlap``: a halo of 2 voxels per side along every
  axis with more than one chunk (``boundary="nearest"``, the clamp to the edge), the core's
  ``downsample_level`` on the padded block, and the coarse voxels that belong to the block kept.

Inside a block the core computes every kept coarse voxel from the same fine values in the same
order as on the whole volume, so the result does not depend on the chunking, bit for bit
(``tests/test_dask.py`` checks several chunkings against :func:`volsample.pyramid`, and the
integer methods against :func:`volsample.downsample_level_int` applied level after level).

>>> import dask.array as da, numpy as np, volsample, volsample.dask
>>> vol = np.random.default_rng(1).integers(0, 256, (20, 24, 28, 4), dtype=np.uint8)
>>> levels = volsample.dask.pyramid(da.from_array(vol, chunks=(8, 8, 8, 4)), 2)
>>> [lv.shape for lv in levels]
[(20, 24, 28, 4), (10, 12, 14, 4), (5, 6, 7, 4)]
>>> whole = volsample.pyramid(vol, 2)
>>> all(np.array_equal(l.compute(), w) for l, w in zip(levels, whole))
True
"""

from __future__ import annotations

import math
from typing import Any, Sequence

import numpy as np

from . import _volsample

#: Halo per side, in voxels of the level being filtered: the 4-tap filter's reach past the
#: two fine voxels of a coarse voxel is one voxel, and one more aligns the padded block so that
#: its coarse voxel 1 is the block's first (the core's coarse voxel ``J`` of the padded block
#: reads padded voxels ``2J - 1 … 2J + 2``).
HALO = 2


def _aligned_chunks(chunks: Sequence[int], n: int, multiple: int) -> tuple[int, ...]:
    """Chunks of an axis of ``n`` voxels: each but the last a multiple of ``multiple``, at least
    as large as the first given chunk rounded up."""
    c = max(1, chunks[0])
    c = -(-c // multiple) * multiple
    if c >= n:
        return (n,)
    out = [c] * (n // c)
    if n % c:
        out.append(n % c)
    return tuple(out)


def _merge_small_last(chunks: tuple[int, ...]) -> tuple[int, ...]:
    """Merges a last chunk smaller than the halo into the one before (the boundary between the
    two stays where it was in the previous level, so it stays even)."""
    if len(chunks) > 1 and chunks[-1] < HALO:
        return chunks[:-2] + (chunks[-2] + chunks[-1],)
    return chunks


#: The integer methods of :func:`pyramid` and the method of
#: :func:`volsample.downsample_level_int` each runs, with the dtypes it reads.
INT_METHODS = {
    "opacity_int": ("opacity", (np.uint8, np.uint16)),
    "extinction_int": ("extinction", (np.uint32,)),
}


def _level_kernel(block: np.ndarray, padded: tuple[bool, bool, bool], method: str, a: float,
                  out_shape: tuple[int, int, int]) -> np.ndarray:
    """The coarse voxels of one block: the core's level of the (padded) block, the ones that
    belong to the block kept."""
    if method in INT_METHODS:
        coarse = _volsample.downsample_level_int(np.ascontiguousarray(block),
                                                 INT_METHODS[method][0], a=a)
    else:
        coarse = _volsample.downsample_level(np.ascontiguousarray(block, dtype=np.float32),
                                             method=method, a=a)
    sl = tuple(slice(1, 1 + m) if p else slice(0, m) for p, m in zip(padded, out_shape))
    return coarse[sl + (slice(None),)]


def _downsample(arr: Any, method: str, a: float) -> Any:
    """One level of a dask array of method-format voxels ``(z, y, x, 4)``."""
    import dask.array as da

    arr = arr.rechunk(tuple(_merge_small_last(c) for c in arr.chunks[:3]) + ((4,),))
    multi = tuple(len(c) > 1 for c in arr.chunks[:3])
    depth = {i: (HALO if multi[i] else 0) for i in range(3)}
    depth[3] = 0
    out_chunks = tuple(tuple(-(-c // 2) for c in cs) for cs in arr.chunks[:3]) + ((4,),)

    def kernel(block: np.ndarray, block_info: dict | None = None) -> np.ndarray:
        # The block's own size along each axis (without the halo), from the chunk grid.
        loc = block_info[0]["chunk-location"] if block_info else (0, 0, 0, 0)
        own = tuple(arr.chunks[i][loc[i]] for i in range(3))
        out_shape = tuple(-(-n // 2) for n in own)
        return _level_kernel(block, multi, method, a, out_shape)

    return da.map_overlap(kernel, arr, depth=depth, boundary="nearest", trim=False,
                          chunks=out_chunks, dtype=arr.dtype,
                          meta=np.empty((0, 0, 0, 0), arr.dtype))


def _to_method_format(arr: Any, method: str, reference_distance: float) -> Any:
    """Level 0 in the method's voxel format, block by block (a per-voxel conversion)."""
    if method == "extinction":
        def conv(b: np.ndarray) -> np.ndarray:
            return _volsample.to_extinction(np.ascontiguousarray(b), reference_distance)
    elif method == "opacity":
        def conv(b: np.ndarray) -> np.ndarray:
            return _volsample.to_associated(np.ascontiguousarray(b))
    else:
        raise ValueError(f"unknown method {method!r}: expected 'opacity', 'extinction', "
                         "'opacity_int' or 'extinction_int'")
    return arr.map_blocks(conv, dtype=np.float32, meta=np.empty((0, 0, 0, 0), np.float32))


def pyramid(array: Any, levels: int, method: str = "extinction", filter: float = 0.25,
            reference_distance: float = 1.0) -> list[Any]:
    """Level 0 in the method's format and ``levels`` coarser levels of a straight RGBA volume.

    ``array`` is a ``dask.array`` (or anything ``dask.array.asarray`` accepts) of shape
    ``(z, y, x, 4)``, ``uint8`` (``n/255``) or ``float32`` straight color and opacity, the
    opacities holding for ``reference_distance`` voxels. ``method`` is ``"extinction"``
    (levels hold ``(C^τ, τ)``, ``τ`` per level voxel: Kraus §4) or ``"opacity"`` (levels hold
    ``(C̃, α)`` for the level's doubled reference distance). ``filter`` is the 4-tap filter's
    outer weight ``a`` in ``[0, ½]`` (0: 2×2×2 box, ⅛: B-spline, ⅕: quadratic, ¼: 4-tap box).

    Returns ``levels + 1`` lazy ``float32`` arrays; each equals, bit for bit,
    :func:`volsample.pyramid` of the whole volume, for any chunking of ``array``.

    The integer methods run the bit-exact integer downsampling
    (:func:`volsample.downsample_level_int`, ``a`` quantized to Q0.16) and read ``array`` in
    its integer format, which level 0 is (no conversion): ``"opacity_int"`` associated
    (premultiplied) ``uint8`` or U8.8 ``uint16`` RGBA (``65280`` = 1), ``"extinction_int"``
    ``uint32`` ``ExtinctionFx`` voxels ``(D·C r, g, b, D)`` in U7.20 (convert a straight volume
    block by block: ``arr.map_blocks(volsample.to_extinction_fx, dtype=np.uint32)``). Every
    level keeps the input's dtype and equals, bit for bit, ``downsample_level_int`` applied
    level after level to the whole volume, for any chunking (``reference_distance`` is not
    read: ``to_extinction_fx`` holds the depth of one reference distance).

    >>> import dask.array as da, numpy as np, volsample.dask
    >>> vol = da.zeros((16, 16, 16, 4), dtype=np.uint8, chunks=(8, 8, 8, 4))
    >>> [l.shape[:3] for l in volsample.dask.pyramid(vol, 3, method="opacity", filter=0.125)]
    [(16, 16, 16), (8, 8, 8), (4, 4, 4), (2, 2, 2)]
    """
    import dask.array as da

    if isinstance(levels, bool) or not isinstance(levels, int) or not 0 <= levels <= 24:
        raise ValueError("levels must be an integer in 0..=24")
    if not (isinstance(filter, (int, float)) and 0.0 <= filter <= 0.5):
        raise ValueError("filter (the outer weight a) must lie in [0, 0.5]")
    arr = da.asarray(array)
    if arr.ndim != 4 or arr.shape[3] != 4:
        raise ValueError("array must have shape (z, y, x, 4)")
    if method in INT_METHODS:
        core_method, dtypes = INT_METHODS[method]
        if arr.dtype not in dtypes:
            raise ValueError(
                "method 'opacity_int' reads associated uint8 or U8.8 uint16 voxels"
                if method == "opacity_int" else
                "method 'extinction_int' reads uint32 ExtinctionFx voxels "
                "(convert with volsample.to_extinction_fx)")
    elif arr.dtype not in (np.uint8, np.float32):
        raise ValueError("array must be uint8 or float32")
    if not (math.isfinite(reference_distance) and reference_distance > 0):
        raise ValueError("reference_distance must be finite and positive")
    mult = 2 ** levels
    chunks = tuple(_aligned_chunks(arr.chunks[i], arr.shape[i], mult) for i in range(3))
    arr = arr.rechunk(chunks + ((4,),))
    if method in INT_METHODS:
        out = [arr]
    else:
        out = [_to_method_format(arr, method, reference_distance)]
    for _ in range(levels):
        out.append(_downsample(out[-1], method, float(filter)))
    return out


def to_ome_zarr(levels: Sequence[Any], path: str, method: str = "extinction",
                filter: float = 0.25, reference_distance: float = 1.0,
                voxel_size: Sequence[float] = (1.0, 1.0, 1.0), name: str = "volsample",
                compute: bool = True) -> Any:
    """Writes a pyramid (as :func:`pyramid` returns it) as an OME-Zarr multiscale image
    (NGFF 0.4, zarr format 2) at ``path``.

    Arrays ``"0"``, ``"1"``, … hold the levels with axes ``(c, z, y, x)`` (NGFF puts the channel
    axis before the spatial ones); ``multiscales`` gives each level's scale
    ``voxel_size·2^ℓ`` and translation ``voxel_size·(2^ℓ − 1)/2`` (a coarse voxel's centre is the
    centre of the fine voxels it covers). The group's ``volsample`` attribute records the
    method, the filter, the channel meaning, and each level's reference distance: the distance,
    in level-0 voxels, for which its opacities hold (``opacity``) or per which its ``τ`` is
    given (``extinction``): ``reference_distance·2^ℓ``. The integer methods' levels are
    written in their integer dtype (``opacity_int``: ``C̃``, ``α`` in bytes or U8.8;
    ``extinction_int``: ``D·C``, ``D`` in U7.20).

    Returns what ``dask.array.store`` returns (``None``, or delayed objects when
    ``compute=False``).
    """
    import dask.array as da
    import zarr

    group = zarr.open_group(path, mode="w", zarr_format=2) if _zarr3() else zarr.open_group(path, mode="w")
    datasets = []
    sources, targets = [], []
    vs = [float(v) for v in voxel_size]
    for lvl, arr in enumerate(levels):
        arr = da.asarray(arr)
        czyx = da.moveaxis(arr, 3, 0).rechunk({0: 4})
        chunks = tuple(c[0] for c in czyx.chunks)
        if _zarr3():
            target = group.create_array(str(lvl), shape=czyx.shape, chunks=chunks, dtype=czyx.dtype)
        else:
            target = group.create_dataset(str(lvl), shape=czyx.shape, chunks=chunks, dtype=czyx.dtype)
        s = 2.0 ** lvl
        datasets.append({
            "path": str(lvl),
            "coordinateTransformations": [
                {"type": "scale", "scale": [1.0] + [v * s for v in vs]},
                {"type": "translation", "translation": [0.0] + [v * (s - 1) / 2 for v in vs]},
            ],
        })
        sources.append(czyx)
        targets.append(target)
    channels = {
        "extinction": ["C^tau r", "C^tau g", "C^tau b", "tau"],
        "extinction_int": ["D*C r", "D*C g", "D*C b", "D (U7.20: raw/2^20)"],
    }.get(method, ["C~ r", "C~ g", "C~ b", "alpha"])
    group.attrs["multiscales"] = [{
        "version": "0.4",
        "name": name,
        "axes": [
            {"name": "c", "type": "channel"},
            {"name": "z", "type": "space", "unit": "micrometer"},
            {"name": "y", "type": "space", "unit": "micrometer"},
            {"name": "x", "type": "space", "unit": "micrometer"},
        ],
        "datasets": datasets,
        "type": "volsample " + method + f" 4-tap a={filter}",
    }]
    group.attrs["volsample"] = {
        "method": method,
        "filter_a": float(filter),
        "channels": channels,
        "reference_distance": [float(reference_distance) * 2.0 ** l for l in range(len(levels))],
        "reference_distance_unit": "level-0 voxels",
    }
    return da.store(sources, targets, lock=False, compute=compute)


def _zarr3() -> bool:
    import zarr

    return int(zarr.__version__.split(".")[0]) >= 3
