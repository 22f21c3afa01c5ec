"""Type stubs of the native module ``volsample._volsample`` (re-exported by ``volsample``)."""

import os
from typing import Any, Literal, Sequence

import numpy as np
import numpy.typing as npt

Mode = Literal["separate", "opacity_weighted", "preweighted", "extinction", "extinction_u8",
               "post_classified"]
IntModeName = Literal["separate", "opacity_weighted", "preweighted", "extinction"]
FilterName = Literal["nearest", "trilinear", "trilinear_tree", "bspline", "triquadratic_bspline"]
Method = Literal["opacity", "extinction"]
VolumeArray = npt.NDArray[np.uint8] | npt.NDArray[np.float32]
#: RGBA volumes ``(z, y, x, 4)`` or, for ``mode="post_classified"``, scalar volumes ``(z, y, x)``
#: of ``uint8``, ``uint16`` or ``float32``.
AnyVolume = VolumeArray | npt.NDArray[np.uint16]
#: The integer kernels' volumes: straight or associated ``uint8`` RGBA, or ``uint32``
#: ``ExtinctionFx`` voxels ``(D·C r, g, b, D)`` (see :func:`to_extinction_fx`).
IntVolume = npt.NDArray[np.uint8] | npt.NDArray[np.uint32]
#: Scalar volumes ``(z, y, x)`` of the classification and shading pre-passes.
ScalarVolume = npt.NDArray[np.uint8] | npt.NDArray[np.uint16] | npt.NDArray[np.float32]

class TransferFunction:
    """A piecewise-linear transfer function (the core's ``TransferFunction``): scalar ``s`` to
    straight color and opacity, linear between control points, the end values outside them.

    ``points``: rows ``(s, r, g, b, a)``, ``s`` strictly increasing, colors and opacities in
    ``[0, 1]`` (opacity for the reference distance), at most 256 rows. Raises ``ValueError``
    with the core's message otherwise.

    >>> import numpy as np
    >>> tf = TransferFunction([(0, 0, 0, 0, 0), (100, 1, 1, 1, 1)])
    >>> tf.eval(np.array([50, 1e9], np.float32)).tolist()
    [[0.5, 0.5, 0.5, 0.5], [1.0, 1.0, 1.0, 1.0]]
    """

    def __init__(self, points: Sequence[Sequence[float]] | npt.NDArray[np.floating]) -> None: ...
    @property
    def points(self) -> npt.NDArray[np.float32]:
        """The control points, ``(n, 5)`` ``float32`` rows ``(s, r, g, b, a)``."""
    def eval(self, s: npt.NDArray[np.float32]) -> npt.NDArray[np.float32]:
        """Straight ``(r, g, b, a)`` ``(n, 4)`` at the scalars ``s`` ``(n,)``, within
        ``3ε + 2ε·L·m`` (``L`` the segment's slope, ``m`` the largest magnitude among ``s``
        and the segment's ends)."""
    def __len__(self) -> int: ...

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

def sample(volume: AnyVolume, positions: npt.NDArray[np.float32], mode: Mode = ...,
           filter: FilterName = ..., step: float = 1.0, reference_distance: float = 1.0,
           tf: TransferFunction | None = None) -> npt.NDArray[np.float32]:
    """Samples ``volume`` ``(z, y, x, 4)`` at ``positions`` ``(n, 3)`` (x, y, z): returns
    ``(n, 4)`` associated ``(C̃r, C̃g, C̃b, α)`` of a segment of length ``step``.

    ``mode``: ``"opacity_weighted"`` (Wittenbrink) and ``"separate"`` read straight RGBA
    (uint8 or float32), ``"preweighted"`` associated RGBA, ``"extinction"`` float32
    ``(C^τ, τ)`` (see :func:`to_extinction`), ``"extinction_u8"`` straight uint8 RGBA read as
    extinction through a table of ``τ`` per opacity byte for ``reference_distance`` (bit for
    bit ``"extinction"`` on ``to_extinction(volume, reference_distance)``, a quarter of the
    memory), ``"post_classified"`` a scalar volume ``(z, y, x)`` (uint8, uint16 or float32)
    interpolated, then classified by ``tf`` (``C̃ = α·C``; at ``step = reference_distance``
    ``α`` and each ``C̃`` within ``3ε + L·taps·ε·s_max`` of the exact value, ``L`` the steepest
    slope of ``tf``, ``s_max`` the largest scalar, ``ε = 2^−23``). Opacity-based modes (all but
    the two extinction modes) are corrected from ``reference_distance`` to ``step``.

    >>> import numpy as np
    >>> vol = np.zeros((2, 2, 2, 4), np.uint8); vol[..., 3] = 255; vol[..., 0] = 255
    >>> sample(vol, np.array([[0.5, 0.5, 0.5]], np.float32)).tolist()
    [[1.0, 0.0, 0.0, 1.0]]
    >>> ramp = TransferFunction([(0, 0, 0, 0, 0), (100, 1, 1, 1, 1)])
    >>> scalars = np.array([[[0, 100]]], np.uint8)          # (z, y, x): s = 0 and 100
    >>> sample(scalars, np.array([[0.5, 0, 0]], np.float32), mode="post_classified",
    ...        tf=ramp).tolist()                              # s = 50: C = α = ½, C̃ = ¼
    [[0.25, 0.25, 0.25, 0.5]]
    >>> fog = np.full((2, 2, 2, 4), [200, 100, 50, 128], np.uint8)
    >>> s = sample(fog, np.array([[0.5, 0.5, 0.5]], np.float32), mode="extinction_u8")
    >>> round(float(s[0, 3]), 4)                              # one step d = d′: α = 128/255
    0.502
    """

def sample_int(volume: IntVolume, positions: npt.NDArray[np.float32], mode: IntModeName = ...,
               filter: Literal["nearest", "trilinear"] = ..., step: float = 1.0,
               reference_distance: float = 1.0, frac_bits: int = 8,
               table_nodes: Literal[17, 65, 257, 1025, 4097] = 257) -> npt.NDArray[np.uint16]:
    """The bit-exact integer kernels (firmware, HDL; ``IntRayMarcher::sample``) at
    ``frac_bits`` ∈ 4..=12 fractional position bits: ``(n, 4)`` U8.8 associated samples,
    ``65280`` = opacity 1.

    ``mode``: ``"separate"`` and ``"opacity_weighted"`` read straight uint8, ``"preweighted"``
    associated uint8, ``"extinction"`` (``IntExtinction``) uint32 ``ExtinctionFx`` voxels
    (:func:`to_extinction_fx`) with ``φ`` and ``e^(−x)`` tables of ``table_nodes`` nodes:
    ``α`` within ``½ + 65280·h²/(8e) + 0.01`` LSB of ``1 − e^(−x)`` and ``C̃`` within ½ LSB
    more, ``h = 1/(N − 1)`` (0.56 and 1.06 LSB at 257 nodes).

    >>> import numpy as np
    >>> cap = np.array([[[[64 << 20, 0, 32 << 20, 64 << 20]]]], np.uint32)  # D = 64, magenta
    >>> sample_int(cap, np.zeros((1, 3), np.float32), mode="extinction").tolist()
    [[65280, 0, 32640, 65280]]
    """

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

def render(volume: AnyVolume, camera: Camera, width: int, height: int, mode: Mode = ...,
           filter: FilterName = ..., step: float = 0.5, reference_distance: float = 1.0,
           threads: int = 1, tf: TransferFunction | None = None, a_stop: float = 1.0,
           order: Literal["front_to_back", "back_to_front"] = "front_to_back",
           background: Sequence[float] | None = None,
           skip: bool = False) -> npt.NDArray[np.float32]:
    """Renders ``(height, width, 4)`` associated pixels front to back (the library's fast path,
    ``RayMarcher::render_rows_into``; ``threads`` bands of rows give the same image bit for
    bit). Every mode of :func:`sample`; ``mode="post_classified"`` reads a scalar volume and
    ``tf``. Raises ``MemoryError`` for an image that cannot be allocated.

    ``a_stop`` ∈ (0, 1]: a ray stops once its opacity reaches it (``1``, the default: never;
    each channel then differs from the unstopped pixel by at most ``1 − a_stop``).
    ``order="back_to_front"`` composites the same samples from the far end (no ``a_stop``).
    ``background``: an associated ``(C̃r, C̃g, C̃b, α)`` composited behind every ray (default
    transparent). ``skip``: empty-space skipping over bricks of 8³ voxels, the same image bit
    for bit (not for ``post_classified``).

    >>> import numpy as np
    >>> vol = np.zeros((4, 4, 4, 4), np.uint8); vol[1:3, 1:3, 1:3] = 255
    >>> img = render(vol, Camera.looking_down_z(vol.shape), 4, 4)
    >>> bool(img[1, 1, 3] > 0.99), float(img[0, 0, 3])
    (True, 0.0)
    >>> col = np.full((10, 1, 1, 4), [1.0, 1.0, 1.0, 0.5], np.float32)  # α = ½ per voxel
    >>> cam = Camera.looking_down_z(col.shape)
    >>> float(render(col, cam, 1, 1, step=1.0, a_stop=0.9)[0, 0, 3])    # 1 − 2^−4 ≥ 0.9
    0.9375
    >>> render(col[:4], cam, 1, 1, step=1.0, background=[0, 0, 0.5, 0.5])[0, 0].tolist()
    [0.9375, 0.9375, 0.96875, 0.96875]
    """

def render_int(volume: IntVolume, camera: Camera, width: int, height: int,
               mode: IntModeName = ..., filter: Literal["nearest", "trilinear"] = ...,
               step: float = 0.5, reference_distance: float = 1.0, frac_bits: int = 8,
               table_nodes: Literal[17, 65, 257, 1025, 4097] = 257, a_stop: int = 65280,
               threads: int = 1, background: Sequence[int] | None = None,
               skip: bool = False) -> npt.NDArray[np.uint16]:
    """Renders ``(height, width, 4)`` U8.8 associated pixels with the integer pipeline
    (``IntRayMarcher::render_into``: positions quantized to ``frac_bits``, the integer kernel
    of ``mode`` as in :func:`sample_int`, table-driven opacity correction, integer front-to-back
    compositing, every rounding half up). A ray stops before a sample once its opacity reaches
    ``a_stop`` (``65280``: only when opaque, the same as never). ``threads`` bands of rows give
    the same image bit for bit. Per ray the compositing adds at most ``n/2`` (α) and ``n`` (C̃)
    LSB over ``n`` samples.

    ``background``: U8.8 associated ``(C̃r, C̃g, C̃b, α)``, ``C̃ ≤ α ≤ 65280``, composited
    behind every ray (also one that stopped early) with the same integer step:
    ``x + ⌊(65280 − A)·bg_x/65280 + ½⌋`` per channel (default transparent; an empty volume
    renders to exactly the background). ``skip``: empty-space skipping over bricks of 8³
    voxels (``with_skipping``), the same image bit for bit; not for ``mode="extinction"``.

    >>> import numpy as np
    >>> vol = np.zeros((4, 4, 4, 4), np.uint8); vol[1:3, 1:3, 1:3] = 255
    >>> img = render_int(vol, Camera.looking_down_z(vol.shape), 4, 4)
    >>> img[1, 1].tolist(), int(img[0, 0, 3])                 # opaque white core, clear air
    ([65280, 65280, 65280, 65280], 0)
    >>> img = render_int(vol, Camera.looking_down_z(vol.shape), 4, 4, skip=True,
    ...                  background=[0, 0, 32640, 32640])     # half-opaque blue behind
    >>> img[1, 1].tolist(), img[0, 0].tolist()
    ([65280, 65280, 65280, 65280], [0, 0, 32640, 32640])
    """

def to_extinction_fx(volume: VolumeArray) -> npt.NDArray[np.uint32]:
    """The fixed-point extinction voxels ``(D·C r, g, b, D)`` (``ExtinctionFx``, U7.20:
    ``raw/2^20``) of a straight uint8 or float32 volume: ``D = ⌊2^20·min(−ln(1 − α), 64) + ½⌋``,
    the optical depth of one reference distance, and ``D·C`` rounded half up (for uint8
    ``⌊(2·D·C + 255)/510⌋``).

    >>> import numpy as np
    >>> to_extinction_fx(np.array([[[[255, 0, 0, 255], [0, 0, 0, 0]]]], np.uint8)).tolist()
    [[[[67108864, 0, 0, 67108864], [0, 0, 0, 0]]]]
    """

def downsample_level_int(volume: npt.NDArray[np.uint8] | npt.NDArray[np.uint16]
                         | npt.NDArray[np.uint32], method: Method,
                         a: float = 0.25) -> npt.NDArray[np.uint8] | npt.NDArray[np.uint16] | npt.NDArray[np.uint32]:
    """One level of the bit-exact integer downsampling (each axis ``n ↦ ⌈n/2⌉``, the
    ``(a_q, b_q, b_q, a_q)`` filter with ``a_q = ⌊2^16·a + ½⌋/2^16``, clamp to edge), in the
    input's dtype. ``method="opacity"``: associated uint8 or U8.8 uint16 voxels,
    ``α′ = ᾱ(2 − ᾱ)``, ``C̃′ = C̄(2 − ᾱ)``, within ``½ + 2^−8`` LSB; ``method="extinction"``:
    uint32 ``ExtinctionFx`` voxels, ``D′ = 2·D̄`` saturated at 64, within ½ LSB.

    >>> import numpy as np
    >>> v = np.full((4, 4, 4, 4), [40, 20, 0, 128], np.uint8)
    >>> downsample_level_int(v, "opacity", a=0.2)[0, 0, 0].tolist()   # α: 1 − (1 − α)²
    [60, 30, 0, 192]
    >>> fx = np.full((2, 2, 2, 4), [1 << 20, 0, 0, 1 << 20], np.uint32)
    >>> downsample_level_int(fx, "extinction")[0, 0, 0].tolist()    # D per coarse voxel: 2
    [2097152, 0, 0, 2097152]
    """

class Light:
    """A directional light for :func:`shade` (the core's ``shade::Light``): ambient and diffuse
    (two-sided Lambert) terms, a shaded color ``C·min(1, k_a + k_d·|n·L|)`` with ``n`` the
    normalised scalar gradient (``|n·L| = 1`` where the gradient vanishes).

    ``direction`` ``(x, y, z)``: any finite non-zero vector (normalised by the core);
    ``ambient`` ``k_a ≥ 0``, ``diffuse`` ``k_d ≥ 0``. Raises ``ValueError`` with the core's
    message otherwise.

    >>> Light([0, 0, 2], ambient=0.25, diffuse=0.75).direction
    [0.0, 0.0, 2.0]
    """

    def __init__(self, direction: Sequence[float], ambient: float = 0.25,
                 diffuse: float = 0.75) -> None: ...
    @staticmethod
    def unlit() -> Light:
        """The identity light (``k_a = 1``, ``k_d = 0``): shading changes no color."""
    @property
    def direction(self) -> list[float]:
        """The direction as given."""
    @property
    def ambient(self) -> float: ...
    @property
    def diffuse(self) -> float: ...

def classify_transfer(scalars: ScalarVolume, tf: TransferFunction) -> npt.NDArray[np.float32]:
    """Pre-classification: every voxel of a scalar volume ``(z, y, x)`` through ``tf``, the
    straight ``(r, g, b, a)`` of ``tf.eval`` at its scalar (``classify::classify_transfer``), as
    a new straight ``float32`` volume ``(z, y, x, 4)`` to sample or render with the straight
    modes. The GIL is released.

    >>> import numpy as np
    >>> ramp = TransferFunction([(0, 0, 0, 0, 0), (100, 1, 1, 1, 1)])
    >>> classify_transfer(np.array([[[0, 50, 100]]], np.uint8), ramp)[0, 0].tolist()
    [[0.0, 0.0, 0.0, 0.0], [0.5, 0.5, 0.5, 0.5], [1.0, 1.0, 1.0, 1.0]]
    """

def classify_isosurface(scalars: ScalarVolume, isovalue: float, opacity: float = 1.0,
                        thickness: float = 1.0,
                        color: Sequence[float] = (1.0, 1.0, 1.0)) -> npt.NDArray[np.float32]:
    """Levoy's isosurface classification (``classify::classify_isosurface``): opacity
    ``opacity·(1 − |isovalue − f|/(thickness·|∇f|))`` where that ratio is at most 1 (``opacity``
    on the isovalue, 0 elsewhere), ``∇f`` as :func:`gradient`, and the straight ``color``
    everywhere: a new straight ``float32`` volume ``(z, y, x, 4)``. Each ``α`` within ``4ε``
    (``ε = 2^−23``) of the exact classification of the same scalars. ``opacity`` in ``[0, 1]``,
    ``thickness > 0`` (voxels), ``color`` in ``[0, 1]``.

    >>> import numpy as np
    >>> ramp = np.arange(5, dtype=np.float32).reshape(1, 1, 5)            # f = x, |∇f| = 1
    >>> classify_isosurface(ramp, 2.0, thickness=2.0)[0, 0, :, 3].tolist()
    [0.0, 0.5, 1.0, 0.5, 0.0]
    """

def gradient(scalars: ScalarVolume) -> npt.NDArray[np.float32]:
    """The gradient of a scalar volume ``(z, y, x)`` at every voxel (``classify::gradient``):
    ``(z, y, x, 3)`` ``float32`` ``(∂f/∂x, ∂f/∂y, ∂f/∂z)``, central differences
    ``(f[i+1] − f[i−1])/2`` inside, one-sided differences at the faces, 0 along an axis of
    length 1: the normals of :func:`classify_isosurface` and :func:`shade`.

    >>> import numpy as np
    >>> gradient(np.array([[[0, 1, 4]]], np.float32))[0, 0].tolist()
    [[1.0, 0.0, 0.0], [2.0, 0.0, 0.0], [3.0, 0.0, 0.0]]
    """

def shade(volume: VolumeArray, scalars: ScalarVolume, light: Light) -> npt.NDArray[np.float32]:
    """Pre-shading (``shade::shade_in_place`` on a copy; ``volume`` is not modified): the
    straight colors of ``volume`` ``(z, y, x, 4)`` (uint8 ``n/255`` or float32) times
    ``min(1, k_a + k_d·|n·L|)``, ``n`` the normalised gradient of ``scalars`` (the same
    ``(z, y, x)``), clamped to ``[0, 1]``; opacities unchanged. A new straight ``float32``
    volume, each channel within ``k_d·7ε + 2u·min(1, k_a + k_d) + u`` of the exact value
    (``u = ε/2``).

    >>> import numpy as np
    >>> f = np.arange(3, dtype=np.float32).reshape(1, 1, 3)               # ∇f along x
    >>> rgba = np.full((1, 1, 3, 4), [1.0, 0.5, 0.0, 1.0], np.float32)
    >>> shade(rgba, f, Light([1, 0, 0], 0.25, 0.75))[0, 0, 0].tolist()    # n·L = 1: lit
    [1.0, 0.5, 0.0, 1.0]
    >>> shade(rgba, f, Light([0, 1, 0], 0.25, 0.75))[0, 0, 0].tolist()    # n ⊥ L: ambient
    [0.25, 0.125, 0.0, 1.0]
    """

VectorKernel = Literal[
    "opacity-weighted-nearest", "opacity-weighted-trilinear", "separate-nearest",
    "separate-trilinear", "preweighted-nearest", "preweighted-trilinear",
    "composite-front-to-back", "opacity-correction", "downsample-opacity-based",
    "extinction-weighted-nearest", "extinction-weighted-trilinear",
    "ray-march-opacity-weighted-nearest", "ray-march-opacity-weighted-trilinear"]

def vectors(kernel: VectorKernel, out: str | os.PathLike[str], count: int = 10_000,
            seed: int = 1, frac_bits: int = 8,
            table_size: Literal[5, 17, 65, 257, 1025, 4097] | None = None) -> dict[str, Any]:
    """Writes the HDL reference vectors of an integer kernel into ``out`` (created if
    missing), byte for byte what ``volsample vectors --kernel … --count … --seed …
    --frac-bits … [--table-size …] --out …`` writes (the same ``volsample_host::vectors``
    code): ``inputs.hex`` and ``expected.hex`` (one ``$readmemh`` word per line), the kernel's
    ``table_*.hex`` and ``manifest.json`` (every field's offset, width and meaning, the
    rounding rules, the generator). Returns the manifest as a dict.

    ``count`` vectors, corner cases first, then SplitMix64 draws from ``seed``;
    ``frac_bits`` (4..=12) the sampling kernels' fractional position bits; ``table_size``
    the ``φ``/``e^(−x)`` table entries of the ``extinction-weighted-*`` kernels (default 257).
    The GIL is released while generating. Raises ``ValueError`` with the library's message
    for a bad request, ``OSError`` when a file cannot be written.

    >>> import os, tempfile
    >>> out = os.path.join(tempfile.mkdtemp(), "ftb")
    >>> m = vectors("composite-front-to-back", out, count=100, seed=7)
    >>> m["count"], m["corner_cases"], m["inputs"]["word_bits"], m["expected"]["word_bits"]
    (100, 49, 128, 64)
    >>> [f["name"] for f in m["expected"]["fields"]]
    ['r', 'g', 'b', 'a']
    >>> sorted(os.listdir(out))
    ['expected.hex', 'inputs.hex', 'manifest.json']
    """

def read_vectors(dir: str | os.PathLike[str]) -> dict[str, Any]:
    """Reads a vector directory back (``volsample_host::vectors::read``: every word checked
    against the manifest's layout and count): ``manifest`` (the parsed ``manifest.json``),
    ``inputs`` and ``expected`` (``(count, fields)`` ``uint64`` arrays of field values, a two's
    complement field as its own ``width`` bits, as the word holds it), ``input_fields`` and
    ``expected_fields`` (the column names). Raises ``OSError`` for a missing file,
    ``ValueError`` for a malformed one.

    >>> import os, tempfile
    >>> out = os.path.join(tempfile.mkdtemp(), "ftb")
    >>> _ = vectors("composite-front-to-back", out, count=3)
    >>> v = read_vectors(out)
    >>> v["input_fields"][:4], v["inputs"].shape, v["expected"].dtype
    (['acc_r', 'acc_g', 'acc_b', 'acc_a'], (3, 8), dtype('uint64'))
    """
