"""Type stubs of the native module ``volsample._volsample`` (re-exported by ``volsample``)."""

from typing import Literal, Sequence

import numpy as np
import numpy.typing as npt

Mode = Literal["separate", "opacity_weighted", "preweighted", "extinction"]
FilterName = Literal["nearest", "trilinear", "trilinear_tree", "bspline", "triquadratic_bspline"]
Method = Literal["opacity", "extinction"]
VolumeArray = npt.NDArray[np.uint8] | npt.NDArray[np.float32]

class Camera:
    """A camera for :func:`render`, in voxel units ``(x, y, z)``.

    >>> cam = Camera.perspective([8, 8, -40], [8, 8, 8], [0, -1, 0], 0.5)
    """

    @staticmethod
    def orthographic(eye: Sequence[float], dir: Sequence[float], up: Sequence[float],
                     extent: float) -> Camera:
        """Parallel rays along ``dir`` from an image plane centred at ``eye``; ``extent`` is the
        image's width in voxels. Raises ``ValueError`` for a degenerate camera."""
    @staticmethod
    def perspective(eye: Sequence[float], target: Sequence[float], up: Sequence[float],
                    fov_y: float) -> Camera:
        """A pinhole camera at ``eye`` looking at ``target``, vertical field of view ``fov_y``
        in radians. Raises ``ValueError`` for a degenerate camera."""
    @staticmethod
    def looking_down_z(shape: Sequence[int]) -> Camera:
        """Looks along +z at a volume of ``shape`` ``(z, y, x[, 4])``: in an ``x × y`` image
        pixel ``(i, j)`` looks down voxel column ``(i, j)``."""

def sample(volume: VolumeArray, positions: npt.NDArray[np.float32], mode: Mode = ...,
           filter: FilterName = ..., step: float = 1.0,
           reference_distance: float = 1.0) -> npt.NDArray[np.float32]:
    """Samples ``volume`` ``(z, y, x, 4)`` at ``positions`` ``(n, 3)`` (x, y, z): returns
    ``(n, 4)`` associated ``(C̃r, C̃g, C̃b, α)`` of a segment of length ``step``.

    ``mode``: ``"opacity_weighted"`` (Wittenbrink) and ``"separate"`` read straight RGBA
    (uint8 or float32), ``"preweighted"`` associated RGBA, ``"extinction"`` float32
    ``(C^τ, τ)`` (see :func:`to_extinction`). Opacity-based modes are corrected from
    ``reference_distance`` to ``step``.

    >>> import numpy as np
    >>> vol = np.zeros((2, 2, 2, 4), np.uint8); vol[..., 3] = 255; vol[..., 0] = 255
    >>> sample(vol, np.array([[0.5, 0.5, 0.5]], np.float32)).tolist()
    [[1.0, 0.0, 0.0, 1.0]]
    """

def sample_int(volume: npt.NDArray[np.uint8], positions: npt.NDArray[np.float32],
               mode: Literal["separate", "opacity_weighted", "preweighted"] = ...,
               filter: Literal["nearest", "trilinear"] = ..., step: float = 1.0,
               reference_distance: float = 1.0, frac_bits: int = 8) -> npt.NDArray[np.uint16]:
    """The bit-exact integer kernels (firmware, HDL) at ``frac_bits`` ∈ 4..=12 fractional
    position bits: ``(n, 4)`` U8.8 associated samples, ``65280`` = opacity 1."""

def correct_opacity(samples: npt.NDArray[np.float32], ratio: float) -> npt.NDArray[np.float32]:
    """Opacity correction of ``(n, 4)`` associated samples to ``ratio = d/d′``:
    ``α_d = 1 − (1 − α)^ratio``, ``C̃_d = C̃·α_d/α`` (within 8 ulp·max(1, ratio)).

    >>> import numpy as np
    >>> correct_opacity(np.array([[0.5, 0.5, 0.5, 0.5]], np.float32), 2.0).tolist()
    [[0.75, 0.75, 0.75, 0.75]]
    """

def to_associated(volume: VolumeArray) -> npt.NDArray[np.float32]:
    """Associated ``(C·α, α)`` float32 voxels of a straight volume."""

def to_extinction(volume: VolumeArray, reference_distance: float = 1.0) -> npt.NDArray[np.float32]:
    """Extinction ``(τ·C, τ)`` float32 voxels, ``τ = −ln(1 − α)/d′`` (optical depth capped at
    64), of a straight volume whose opacities hold for ``reference_distance`` voxels."""

def downsample_level(volume: npt.NDArray[np.float32], method: Method = "extinction",
                     a: float = 0.25) -> npt.NDArray[np.float32]:
    """One pyramid level (each axis ``n ↦ ⌈n/2⌉``) of method-format voxels with the 4-tap
    ``(a, ½ − a, ½ − a, a)`` filter, clamp to edge.

    >>> import numpy as np
    >>> v = np.zeros((2, 2, 2, 4), np.float32); v[:, :, 0] = 4.0   # Kraus's 2×2×2 example
    >>> downsample_level(v, "extinction", 0.25)[0, 0, 0].tolist()  # τ′ per coarse voxel
    [4.0, 4.0, 4.0, 4.0]
    """

def pyramid(volume: VolumeArray, levels: int, method: Method = "extinction", a: float = 0.25,
            reference_distance: float = 1.0) -> list[npt.NDArray[np.float32]]:
    """Level 0 of a straight volume in the method's format (:func:`to_extinction` or
    :func:`to_associated`) and ``levels`` coarser levels, each :func:`downsample_level` of the
    one before."""

def downsample_level_u8(volume: npt.NDArray[np.uint8], a: float = 0.25) -> npt.NDArray[np.uint8]:
    """One level of the bit-exact integer opacity-based downsampling of associated uint8
    voxels (``a`` quantized to Q0.16, round half up; every rounding named in the core)."""

def render(volume: VolumeArray, camera: Camera, width: int, height: int, mode: Mode = ...,
           filter: FilterName = ..., step: float = 0.5, reference_distance: float = 1.0,
           threads: int = 1) -> npt.NDArray[np.float32]:
    """Renders ``(height, width, 4)`` associated pixels front to back (the library's fast path,
    ``RayMarcher::render_into``; ``threads`` bands of rows give the same image bit for bit).

    >>> import numpy as np
    >>> vol = np.zeros((4, 4, 4, 4), np.uint8); vol[1:3, 1:3, 1:3] = 255
    >>> img = render(vol, Camera.looking_down_z(vol.shape), 4, 4)
    >>> bool(img[1, 1, 3] > 0.99), float(img[0, 0, 3])
    (True, 0.0)
    """
