"""volsample: opacity- and extinction-correct sampling, rendering and downsampling of RGBA
volumes, numpy in and out (the Rust crate ``volsample`` underneath, the GIL released in every
kernel call), and chunked pyramids on Dask in :mod:`volsample.dask`.

Volumes are C-ordered arrays of shape ``(z, y, x, 4)``, ``uint8`` (read as ``n/255``) or
``float32``; positions are ``(n, 3)`` ``float32`` arrays of ``(x, y, z)`` in voxel units, voxel
centres at integer coordinates. Errors are ``ValueError`` with the core's message.

>>> import numpy as np, volsample
>>> # Wittenbrink fig. 4: an opaque white voxel next to a transparent red one.
>>> vol = np.array([[[[255, 255, 255, 255], [255, 0, 0, 0]]]], dtype=np.uint8)
>>> mid = np.array([[0.5, 0.0, 0.0]], dtype=np.float32)
>>> volsample.sample(vol, mid, mode="opacity_weighted").tolist()  # stays white
[[0.5, 0.5, 0.5, 0.5]]
>>> volsample.sample(vol, mid, mode="separate").tolist()  # red bleeds in
[[0.5, 0.25, 0.25, 0.5]]
"""

from ._volsample import (
    Camera,
    Light,
    TransferFunction,
    classify_isosurface,
    classify_transfer,
    correct_opacity,
    downsample_level,
    downsample_level_int,
    downsample_level_u8,
    gradient,
    pyramid,
    read_vectors,
    render,
    render_int,
    sample,
    sample_int,
    shade,
    to_associated,
    to_extinction,
    to_extinction_fx,
    vectors,
)

__all__ = [
    "Camera",
    "Light",
    "TransferFunction",
    "classify_isosurface",
    "classify_transfer",
    "correct_opacity",
    "downsample_level",
    "downsample_level_int",
    "downsample_level_u8",
    "gradient",
    "pyramid",
    "read_vectors",
    "render",
    "render_int",
    "sample",
    "sample_int",
    "shade",
    "to_associated",
    "to_extinction",
    "to_extinction_fx",
    "vectors",
]
