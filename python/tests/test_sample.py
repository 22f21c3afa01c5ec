"""Sampling at positions: every mode and filter against scipy.ndimage.map_coordinates."""

import numpy as np
import pytest
from scipy.ndimage import map_coordinates

import volsample
from conftest import random_straight_u8
from tolerance import (BSPLINE_VS_SCIPY_ABS, EXTINCTION_SAMPLE_ABS, SAMPLE_VS_SCIPY_ABS)


def scipy_sample(channels, pos, order, prefilter=False):
    """map_coordinates per channel of a (z, y, x, k) f64 array at (x, y, z) positions."""
    coords = pos[:, ::-1].T.astype(np.float64)  # (z, y, x) rows
    return np.stack([map_coordinates(channels[..., k], coords, order=order, mode="nearest",
                                     prefilter=prefilter) for k in range(channels.shape[-1])], -1)


def positions(rng, shape, n=500, margin=0.0):
    z, y, x = shape
    lo = margin
    return np.stack([rng.uniform(lo, x - 1 - lo, n), rng.uniform(lo, y - 1 - lo, n),
                     rng.uniform(lo, z - 1 - lo, n)], -1).astype(np.float32)


def straight_f64(vol_u8):
    s = vol_u8.astype(np.float64) / 255.0
    return s[..., :3], s[..., 3:]


@pytest.mark.parametrize("dtype", ["u8", "f32"])
def test_opacity_weighted_trilinear_equals_map_coordinates_on_premultiplied(rng, dtype):
    shape = (7, 9, 11)
    vol = random_straight_u8(rng, shape)
    c, a = straight_f64(vol)
    arg = vol if dtype == "u8" else (vol.astype(np.float32) / np.float32(255.0))
    if dtype == "f32":
        c, a = arg[..., :3].astype(np.float64), arg[..., 3:].astype(np.float64)
    premul = np.concatenate([c * a, a], -1)
    pos = positions(rng, shape)
    got = volsample.sample(arg, pos, mode="opacity_weighted", filter="trilinear")
    want = scipy_sample(premul, pos.astype(np.float64), order=1)
    assert got.dtype == np.float32 and got.shape == (len(pos), 4)
    err = np.abs(got - want).max()
    assert err <= SAMPLE_VS_SCIPY_ABS, err
    # Both trilinear evaluation orders.
    tree = volsample.sample(arg, pos, mode="opacity_weighted", filter="trilinear_tree")
    assert np.abs(tree - want).max() <= SAMPLE_VS_SCIPY_ABS


def test_positions_outside_clamp_to_the_edge(rng):
    shape = (4, 5, 6)
    vol = random_straight_u8(rng, shape)
    c, a = straight_f64(vol)
    pos = rng.uniform(-3, 9, (300, 3)).astype(np.float32)
    got = volsample.sample(vol, pos)
    want = scipy_sample(np.concatenate([c * a, a], -1), pos.astype(np.float64), order=1)
    assert np.abs(got - want).max() <= SAMPLE_VS_SCIPY_ABS


def test_separate_interpolates_straight_color(rng):
    shape = (5, 6, 7)
    vol = random_straight_u8(rng, shape)
    c, a = straight_f64(vol)
    pos = positions(rng, shape)
    got = volsample.sample(vol, pos, mode="separate")
    alpha = scipy_sample(a, pos, order=1)
    color = scipy_sample(c, pos, order=1)
    want = np.concatenate([color * alpha, alpha], -1)
    assert np.abs(got - want).max() <= SAMPLE_VS_SCIPY_ABS
    # And it differs from opacity weighting where colors and opacities vary.
    ow = volsample.sample(vol, pos, mode="opacity_weighted")
    assert np.abs(got - ow).max() > 0.01


def test_preweighted_interpolates_stored_associated(rng):
    shape = (5, 6, 7)
    straight = random_straight_u8(rng, shape).astype(np.float32) / np.float32(255)
    assoc = volsample.to_associated(straight)
    np.testing.assert_array_equal(assoc[..., 3], straight[..., 3])
    np.testing.assert_array_equal(assoc[..., :3], straight[..., :3] * straight[..., 3:])
    pos = positions(rng, shape)
    got = volsample.sample(assoc, pos, mode="preweighted")
    want = scipy_sample(assoc.astype(np.float64), pos, order=1)
    assert np.abs(got - want).max() <= SAMPLE_VS_SCIPY_ABS


@pytest.mark.parametrize("mode", ["opacity_weighted", "separate"])
def test_nearest_reads_the_nearest_voxel(rng, mode):
    shape = (5, 6, 7)
    vol = random_straight_u8(rng, shape)
    c, a = straight_f64(vol)
    pos = positions(rng, shape)
    # Keep away from the .5 ties, where rounding conventions may differ.
    frac = pos - np.floor(pos)
    pos = pos[np.all(np.abs(frac - 0.5) > 1e-3, axis=1)]
    got = volsample.sample(vol, pos, mode=mode, filter="nearest")
    want = scipy_sample(np.concatenate([c * a, a], -1), pos, order=0)
    assert np.abs(got - want).max() <= SAMPLE_VS_SCIPY_ABS


def test_bspline_opacity_weighted_equals_unfiltered_quadratic_spline(rng):
    shape = (8, 9, 10)
    vol = random_straight_u8(rng, shape)
    c, a = straight_f64(vol)
    pos = positions(rng, shape, margin=1.5)  # inside: scipy's spline edge handling differs
    got = volsample.sample(vol, pos, mode="opacity_weighted", filter="bspline")
    want = scipy_sample(np.concatenate([c * a, a], -1), pos, order=2, prefilter=False)
    assert np.abs(got - want).max() <= BSPLINE_VS_SCIPY_ABS


def test_extinction_sampling_integrates_the_step(rng):
    shape = (5, 6, 7)
    straight = random_straight_u8(rng, shape)
    ext = volsample.to_extinction(straight, reference_distance=1.0)
    pos = positions(rng, shape)
    for step in (0.25, 1.0, 2.0):
        got = volsample.sample(ext, pos, mode="extinction", step=step)
        ct = scipy_sample(ext.astype(np.float64), pos, order=1)
        tau = ct[:, 3:]
        alpha = -np.expm1(-tau * step)
        with np.errstate(invalid="ignore", divide="ignore"):
            color = np.where(tau > 0, ct[:, :3] / tau, 0.0) * alpha
        want = np.concatenate([color, alpha], -1)
        assert np.abs(got - want).max() <= EXTINCTION_SAMPLE_ABS, step


def test_opacity_weighted_step_applies_correction(rng):
    shape = (4, 4, 4)
    vol = random_straight_u8(rng, shape)
    pos = positions(rng, shape, n=50)
    base = volsample.sample(vol, pos)
    half = volsample.sample(vol, pos, step=0.5)
    np.testing.assert_allclose(half, volsample.correct_opacity(base, 0.5), rtol=0, atol=1e-6)


@pytest.mark.parametrize("frac_bits", [4, 8, 12])
@pytest.mark.parametrize("mode,filt", [("opacity_weighted", "trilinear"), ("separate", "trilinear"),
                                       ("opacity_weighted", "nearest"), ("preweighted", "trilinear")])
def test_integer_kernels_track_the_float_kernels(rng, frac_bits, mode, filt):
    shape = (5, 6, 7)
    vol = random_straight_u8(rng, shape)
    if mode == "preweighted":
        vol[..., :3] = np.minimum(vol[..., :3], vol[..., 3:])
    pos = positions(rng, shape, n=300)
    if filt == "nearest":
        frac = pos - np.floor(pos)
        # Away from the ties by more than the quantization step 2^-F.
        pos = pos[np.all(np.abs(frac - 0.5) > 2.0 ** -frac_bits, axis=1)]
    got = volsample.sample_int(vol, pos, mode=mode, filter=filt, frac_bits=frac_bits)
    assert got.dtype == np.uint16
    assert (got[:, :3] <= got[:, 3:]).all() and (got <= 65280).all()
    flt = volsample.sample(vol, pos, mode=mode, filter=filt)
    # The position quantized to 2^-F of a voxel moves a trilinear sample by at most
    # 3·2^-(F+1) of the largest channel step, plus the U8.8 roundings.
    err = np.abs(got / 65280.0 - flt).max()
    assert err <= 3 * 2.0 ** -(frac_bits + 1) + 2 / 65280, err
    # Deterministic and bit-exact: the same call gives the same bits.
    np.testing.assert_array_equal(got, volsample.sample_int(vol, pos, mode=mode, filter=filt,
                                                            frac_bits=frac_bits))
