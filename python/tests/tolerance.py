"""The test suite's tolerance table: every bound a test holds, named, with where it comes from.

``EPS32 = 2**-23`` (the f32 machine epsilon); the core's doc comments state each kernel's bound.
"""

EPS32 = 2.0 ** -23

#: Trilinear (and the quadratic B-spline) sampling in f32 against scipy's f64
#: ``map_coordinates`` on premultiplied f64 arrays, per channel, absolute (channels are in
#: [0, 1]): 8 weights and 8 products, summed, plus the f32 rounding of C·α and of the
#: positions' fractions, stays below 16 ulp of 1.
SAMPLE_VS_SCIPY_ABS = 16 * EPS32

#: The same for the 27-tap triquadratic B-spline (27 products and sums).
BSPLINE_VS_SCIPY_ABS = 48 * EPS32

#: Extinction sampling (trilinear τ and C^τ, then α = 1 − e^(−τd) and C̃ = C^τ·α/τ by the
#: core's φ polynomial) against the f64 formula: the φ bound (2ε relative) plus the trilinear
#: sums' and the conversion's roundings.
EXTINCTION_SAMPLE_ABS = 64 * EPS32

#: Opacity correction (``opacity::correct``): within 8 ulp of the exact value times
#: max(1, ratio) (the core's doc), checked here against the f64 formula.
CORRECTION_ABS = 8 * EPS32


def opacity_level_abs(level: int) -> float:
    """Opacity-based level ``level`` against an f64 model: ``17ε·(2^ℓ − 1)`` (the core's doc)."""
    return 17 * EPS32 * (2 ** level - 1)


def extinction_level_abs(level: int, tau_max: float) -> float:
    """Extinction-based level ``level`` against an f64 model: ``7.5ε·ℓ·2^ℓ·τ_max`` (the core's
    doc), plus the f32 rounding of level 0's τ (relative 2ε, doubled per level)."""
    return 7.5 * EPS32 * level * 2 ** level * tau_max + 2 * EPS32 * 2 ** level * tau_max


def post_classified_abs(slope: float, s_max: float, taps: int = 8) -> float:
    """Post-classified sampling at ``d = d′`` against the f64 model: ``α`` and each ``C̃``
    within ``3ε + L·taps·ε·s_max``, ``L`` the transfer function's steepest slope and ``s_max``
    the largest scalar magnitude (the core's doc of ``PostClassified``)."""
    return (3 + slope * taps * s_max) * EPS32


def tf_eval_abs(slope: float, m: float) -> float:
    """``TransferFunction.eval``: within ``3ε + 2ε·L·m`` of the exact piecewise-linear value,
    ``m`` the largest magnitude among ``s`` and the segment's ends (the core's doc)."""
    return (3 + 2 * slope * m) * EPS32


#: U8.8 full scale: opacity 1.
ONE = 65280


def extinction_int_a_lsb(nodes: int) -> float:
    """Integer ``IntExtinction``: ``α`` within ``½ + ONE·h²/(8e) + 0.01`` U8.8 LSB of the exact
    ``1 − e^(−x)`` of the same stored voxels and weights, ``h = 1/(N − 1)`` (the core's doc)."""
    h = 1.0 / (nodes - 1)
    return 0.5 + ONE * h * h / (8 * 2.718281828459045) + 0.01


def extinction_int_c_lsb(nodes: int) -> float:
    """The same for each ``C̃``: ``1 + ONE·h²/(8e) + 0.01`` U8.8 LSB (the core's doc)."""
    return extinction_int_a_lsb(nodes) + 0.5


#: One level of the integer extinction-based downsampling: ``D′`` and each ``(D·C)′`` within
#: ½ U7.20 LSB of the exact method with the quantized taps (one rounding; the core's doc).
#: The f64 model's own rounding (sums below 2^31 with 53-bit products) adds below 1e-6.
INT_EXTINCTION_LEVEL_LSB = 0.5 + 1e-6

#: One level of the integer opacity-based downsampling: within ``½ + 2^−8`` storage LSB.
INT_OPACITY_LEVEL_LSB = 0.5 + 2 ** -8

#: Levoy's isosurface classification (``classify_isosurface``): each ``α`` within ``4ε`` of
#: the exact classification of the same f32 scalars, gradient included (the core's doc,
#: ``CLASSIFY_ISOSURFACE_ABS`` in its tests).
CLASSIFY_ISOSURFACE_ABS = 4 * EPS32


def shade_abs(ambient: float, diffuse: float) -> float:
    """``shade``: each shaded channel within ``k_d·7ε + 2u·min(1, k_a + k_d) + u`` of
    ``C·min(1, k_a + k_d·|n·L|)`` with the exact normal (``u = ε/2``; the core's doc of
    ``shade_in_place``)."""
    u = EPS32 / 2
    return diffuse * 7 * EPS32 + 2 * u * min(1.0, ambient + diffuse) + u
