"""The integer extinction kernel (IntExtinction over ExtinctionFx voxels, φ and e^(−x) from
ExtinctionTables of N nodes): to_extinction_fx against its integer formulas, sample_int against
an f64 model of the exact step integral at the quantized position."""

import numpy as np
import pytest

import volsample
from conftest import random_straight_u8
from test_sample import positions, scipy_sample
from tolerance import ONE, extinction_int_a_lsb, extinction_int_c_lsb

UNIT = 2.0 ** 20  # U7.20
MAX_DEPTH_RAW = 64 << 20


def test_to_extinction_fx_every_opacity_byte():
    a = np.arange(256)
    c = (a * 7 + 3) % 256
    vol = np.stack([c, 255 - c, c // 3, a], -1).astype(np.uint8).reshape(1, 16, 16, 4)
    fx = volsample.to_extinction_fx(vol).reshape(256, 4).astype(np.int64)
    assert volsample.to_extinction_fx(vol).dtype == np.uint32
    with np.errstate(divide="ignore"):
        depth = np.minimum(-np.log1p(-a / 255.0), 64.0)
    # D = ⌊2^20·D + ½⌋: within ½ LSB of the exact depth (f64 log1p to a few ulp).
    assert np.abs(fx[:, 3] - UNIT * depth).max() <= 0.5 + 1e-6
    # D·C = ⌊D·C/255 + ½⌋ of the stored D, in exact integers: ⌊(2·D·C + 255)/510⌋.
    col = np.stack([c, 255 - c, c // 3], -1).astype(np.int64)
    np.testing.assert_array_equal(fx[:, :3], (2 * fx[:, 3:] * col + 255) // 510)
    # The Rust tests' ends: opaque caps at 64, transparent is zero.
    assert fx[255, 3] == MAX_DEPTH_RAW and fx[0].tolist() == [0, 0, 0, 0]


def test_to_extinction_fx_from_float32(rng):
    vol = rng.uniform(0, 1, (3, 4, 5, 4)).astype(np.float32)
    fx = volsample.to_extinction_fx(vol).astype(np.float64)
    a = vol[..., 3].astype(np.float64)
    assert np.abs(fx[..., 3] - UNIT * -np.log1p(-a)).max() <= 0.5 + 1e-6
    # D·C = ⌊D·C + ½⌋, the f64 product exact (D < 2^27, C with 24 bits).
    np.testing.assert_array_equal(fx[..., :3], np.floor(fx[..., 3:] * vol[..., :3] + 0.5))


def quantize(pos, shape, frac_bits):
    """IntRayMarcher::quantize: clamp into [0, n − 1] per axis, then round half up to F bits."""
    hi = np.array(shape[::-1], np.float64) - 1
    p = np.clip(pos.astype(np.float64), 0, hi)
    return np.floor(p * 2 ** frac_bits + 0.5) / 2 ** frac_bits


def model(fx, pos, ratio, order=1):
    """The exact step integral of the stored voxels: D̄ and (D·C)‾ interpolated in f64,
    x = D̄·r, α = 1 − e^(−x), C̃ = (D·C)‾/D̄·α, in U8.8 LSB."""
    s = scipy_sample(fx.astype(np.float64) / UNIT, pos, order=order)
    x = s[:, 3:] * ratio
    alpha = -np.expm1(-x)
    with np.errstate(invalid="ignore", divide="ignore"):
        c = np.where(s[:, 3:] > 0, s[:, :3] / s[:, 3:], 0.0) * alpha
    return np.concatenate([c, alpha], -1) * ONE


@pytest.mark.parametrize("nodes", [17, 257, 4097])
@pytest.mark.parametrize("frac_bits", [4, 8, 12])
def test_samples_within_the_kernel_bound(rng, nodes, frac_bits):
    shape = (5, 6, 7)
    fx = volsample.to_extinction_fx(random_straight_u8(rng, shape))
    pos = np.concatenate([positions(rng, shape, n=300),
                          rng.uniform(-2, 9, (100, 3)).astype(np.float32)])
    q = quantize(pos, shape, frac_bits)
    for step, d_ref in ((1.0, 1.0), (0.5, 1.0), (0.3, 0.25), (2.0, 1.0)):
        got = volsample.sample_int(fx, pos, mode="extinction", step=step, reference_distance=d_ref,
                                   frac_bits=frac_bits, table_nodes=nodes)
        assert got.dtype == np.uint16 and got.shape == (len(pos), 4)
        assert (got[:, :3] <= got[:, 3:]).all() and (got <= ONE).all()
        want = model(fx, q, np.float32(step) / np.float32(d_ref))
        err_a = np.abs(got[:, 3] - want[:, 3]).max()
        err_c = np.abs(got[:, :3] - want[:, :3]).max()
        assert err_a <= extinction_int_a_lsb(nodes), (step, err_a)
        assert err_c <= extinction_int_c_lsb(nodes), (step, err_c)


def test_nearest_and_the_rust_tests_values():
    # Kraus's example through one step d = d′: D = 4, red; α = 1 − e^(−4).
    one = np.array([[[[4 << 20, 0, 0, 4 << 20]]]], np.uint32)
    pos = np.zeros((1, 3), np.float32)
    s = volsample.sample_int(one, pos, mode="extinction", filter="nearest")
    assert abs(s[0, 3] - ONE * -np.expm1(-4.0)) <= extinction_int_a_lsb(257)
    assert s[0, :3].tolist() == [s[0, 3], 0, 0]
    # At the cap, any position and ratio: exactly opaque, the straight color kept exactly.
    cap = np.zeros((2, 2, 2, 4), np.uint32)
    cap[...] = [MAX_DEPTH_RAW, 0, MAX_DEPTH_RAW // 2, MAX_DEPTH_RAW]
    p = np.array([[0.5, 0.5, 0.5], [0.999, 0.001, 0.5]], np.float32)
    for step in (1.0, 1e6):
        s = volsample.sample_int(cap, p, mode="extinction", step=step, frac_bits=12)
        assert s.tolist() == [[ONE, 0, ONE // 2, ONE]] * 2
    # Empty space is exactly transparent.
    z = volsample.sample_int(np.zeros((2, 2, 2, 4), np.uint32), p, mode="extinction", step=100.0)
    assert (z == 0).all()


def test_nearest_reads_the_nearest_voxel(rng):
    shape = (4, 5, 6)
    fx = volsample.to_extinction_fx(random_straight_u8(rng, shape))
    pos = positions(rng, shape)
    frac = pos - np.floor(pos)
    pos = pos[np.all(np.abs(frac - 0.5) > 2.0 ** -8, axis=1)]
    got = volsample.sample_int(fx, pos, mode="extinction", filter="nearest", step=0.7)
    want = model(fx, pos, np.float32(0.7), order=0)
    assert np.abs(got[:, 3] - want[:, 3]).max() <= extinction_int_a_lsb(257)
    assert np.abs(got[:, :3] - want[:, :3]).max() <= extinction_int_c_lsb(257)


def test_bad_input():
    pos = np.zeros((1, 3), np.float32)
    with pytest.raises(ValueError, match="to_extinction_fx"):
        volsample.sample_int(np.zeros((2, 2, 2, 4), np.uint8), pos, mode="extinction")
    with pytest.raises(ValueError, match="table_nodes"):
        volsample.sample_int(np.zeros((2, 2, 2, 4), np.uint32), pos, mode="extinction",
                             table_nodes=100)
    bad = np.zeros((2, 2, 2, 4), np.uint32)
    bad[0, 0, 1] = [5, 0, 0, 4]
    with pytest.raises(ValueError, match="voxel 1 has an associated color above its opacity"):
        volsample.sample_int(bad, pos, mode="extinction")
    bad[0, 0, 1] = [0, 0, 0, MAX_DEPTH_RAW + 1]
    with pytest.raises(ValueError, match="voxel 1 is out of range"):
        volsample.sample_int(bad, pos, mode="extinction")
    with pytest.raises(ValueError, match="sampling step"):
        volsample.sample_int(np.zeros((2, 2, 2, 4), np.uint32), pos, mode="extinction", step=-1.0)
    with pytest.raises(ValueError, match="out of range"):
        volsample.to_extinction_fx(np.full((1, 1, 1, 4), 2.0, np.float32))
