"""Downsampling: the Rust tests' values and an independent numpy (f64) model of the filter."""

import numpy as np
import pytest

import volsample
from conftest import random_straight_u8
from tolerance import EPS32, extinction_level_abs, opacity_level_abs

FILTERS = {"box2": 0.0, "bspline": 0.125, "quadratic": 0.2, "box4": 0.25, "half": 0.5}


def filter_level_f64(v, a):
    """One level of the separable (a, b, b, a) filter in f64: coarse j reads fine 2j-1 … 2j+2,
    clamped to the edge, along x, y, z of a (z, y, x, k) array."""
    w = np.array([a, 0.5 - a, 0.5 - a, a])
    out = v
    for axis in (2, 1, 0):
        n = out.shape[axis]
        m = -(-n // 2)
        j = np.arange(m)
        taps = [np.clip(2 * j - 1 + i, 0, n - 1) for i in range(4)]
        out = sum(w[i] * np.take(out, taps[i], axis=axis) for i in range(4))
    return out


def opacity_model(assoc, a, levels):
    out = [assoc.astype(np.float64)]
    for _ in range(levels):
        f = filter_level_f64(out[-1], a)
        alpha = f[..., 3:]
        gain = 2 - alpha
        out.append(np.concatenate([f[..., :3] * gain, alpha * gain], -1))
    return out


def extinction_model(ext, a, levels):
    out = [ext.astype(np.float64)]
    for _ in range(levels):
        out.append(2 * filter_level_f64(out[-1], a))
    return out


def paper_volume(opacity_based):
    """Kraus's 2×2×2 example: the x = 0 layer at τ = 4 (α = 1 − e^(−4)), the x = 1 layer empty."""
    alpha = -np.expm1(np.float32(-4.0))
    v = np.zeros((2, 2, 2, 4), np.float32)
    v[:, :, 0, :] = alpha if opacity_based else 4.0
    return v


@pytest.mark.parametrize("name", list(FILTERS))
def test_paper_example_as_in_the_rust_tests(name):
    a = FILTERS[name]
    ext = volsample.downsample_level(paper_volume(False), method="extinction", a=a)
    assert ext.shape == (1, 1, 1, 4)
    assert ext[0, 0, 0, 3] == 4.0  # τ′ per coarse voxel
    assert abs(-np.expm1(-ext[0, 0, 0, 3]) - 0.98168) < 1e-5
    op = volsample.downsample_level(paper_volume(True), method="opacity", a=a)
    assert abs(op[0, 0, 0, 3] - 0.740758) < 1e-5  # opacity lost
    assert abs(op[0, 0, 0, 0] - 0.740758) < 1e-5


def test_constant_volume_stays_constant_as_in_the_core_doc():
    # build_chain's doc: C^τ = (0.5, 0.25, 0), τ = 0.5 on 6×5×3 gives (4, 2, 0, 4) at level 3.
    base = np.zeros((3, 5, 6, 4), np.float32)
    base[...] = [0.5, 0.25, 0.0, 0.5]
    lv = base
    for _ in range(3):
        lv = volsample.downsample_level(lv, method="extinction", a=0.2)
    assert lv.shape == (1, 1, 1, 4)
    assert lv[0, 0, 0].tolist() == [4.0, 2.0, 0.0, 4.0]


@pytest.mark.parametrize("name", list(FILTERS))
@pytest.mark.parametrize("shape", [(9, 7, 8), (5, 13, 3), (1, 4, 6)])
def test_opacity_pyramid_matches_numpy_model(rng, name, shape):
    a = FILTERS[name]
    vol = random_straight_u8(rng, shape)
    levels = volsample.pyramid(vol, 3, method="opacity", a=a)
    model = opacity_model(levels[0], a, 3)
    for lvl, (got, want) in enumerate(zip(levels, model)):
        assert got.shape == want.shape
        assert (got[..., :3] <= got[..., 3:]).all() and (got[..., 3] <= 1).all()
        err = np.abs(got - want).max()
        assert err <= opacity_level_abs(lvl), (lvl, err)


@pytest.mark.parametrize("name", list(FILTERS))
@pytest.mark.parametrize("shape", [(9, 7, 8), (5, 13, 3)])
def test_extinction_pyramid_matches_numpy_model(rng, name, shape):
    a = FILTERS[name]
    vol = random_straight_u8(rng, shape)
    vol[..., 3] = np.minimum(vol[..., 3], 250)  # keep τ moderate
    levels = volsample.pyramid(vol, 3, method="extinction", a=a)
    tau_max = float(levels[0][..., 3].max())
    # Level 0 is ExtinctionF32::from_straight: τ = −ln(1 − α), C^τ = τ·C.
    alpha = vol[..., 3:].astype(np.float64) / 255
    tau = -np.log1p(-alpha)
    np.testing.assert_allclose(levels[0][..., 3:], tau, rtol=4 * EPS32, atol=0)
    model = extinction_model(levels[0], a, 3)
    for lvl, (got, want) in enumerate(zip(levels, model)):
        err = np.abs(got - want).max()
        assert err <= extinction_level_abs(lvl, tau_max), (lvl, err)


def test_pyramid_is_repeated_downsample_level(rng):
    vol = random_straight_u8(rng, (6, 10, 7))
    levels = volsample.pyramid(vol, 4, method="extinction", a=0.2, reference_distance=0.5)
    np.testing.assert_array_equal(levels[0], volsample.to_extinction(vol, 0.5))
    for lo, hi in zip(levels, levels[1:]):
        np.testing.assert_array_equal(volsample.downsample_level(lo, "extinction", 0.2), hi)


def test_integer_opacity_level_as_in_the_core_doc():
    base = np.zeros((4, 4, 4, 4), np.uint8)
    base[...] = [40, 20, 0, 128]
    l1 = volsample.downsample_level_u8(base, a=0.2)
    assert l1.shape == (2, 2, 2, 4) and (l1 == [60, 30, 0, 192]).all()
    l2 = volsample.downsample_level_u8(l1, a=0.2)
    assert l2[0, 0, 0].tolist() == [75, 37, 0, 239]


def test_integer_level_within_half_an_lsb_plus_guard_of_the_model(rng):
    # The integer method against the f64 model with the quantized tap a_q = ⌊2^16·a + ½⌋/2^16:
    # within ½ + 2^−8 LSB (the integer module's doc).
    vol = random_straight_u8(rng, (7, 6, 9))
    vol[..., :3] = np.minimum(vol[..., :3], vol[..., 3:])
    for a in FILTERS.values():
        aq = np.floor(a * 65536 + 0.5) / 65536
        got = volsample.downsample_level_u8(vol, a=a).astype(np.float64)
        f = filter_level_f64(vol.astype(np.float64) / 255, aq)
        gain = 2 - f[..., 3:]
        want = np.concatenate([f[..., :3] * gain, f[..., 3:] * gain], -1) * 255
        assert np.abs(got - want).max() <= 0.5 + 2 ** -8, a
