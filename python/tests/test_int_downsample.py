"""downsample_level_int: one level of the integer downsampling (downsample::integer), against
an f64 model of the (a_q, b_q, b_q, a_q) filter with the tap quantized to Q0.16, and the Rust
docs' values."""

import numpy as np
import pytest

import volsample
from conftest import random_straight_u8
from test_downsample import FILTERS, filter_level_f64
from tolerance import INT_EXTINCTION_LEVEL_LSB, INT_OPACITY_LEVEL_LSB, ONE

MAX_DEPTH_RAW = 64 << 20


def a_q(a):
    """The tap the integer filter uses: ⌊2^16·a + ½⌋/2^16."""
    return np.floor(a * 65536 + 0.5) / 65536


@pytest.mark.parametrize("name", list(FILTERS))
def test_extinction_level_doubles_the_filtered_depth(rng, name):
    a = FILTERS[name]
    fx = volsample.to_extinction_fx(random_straight_u8(rng, (7, 6, 9)))
    fx[..., :3] //= 3  # still ≤ D, and not all at the cap
    fx = np.minimum(fx, 1 << 24)  # below the cap after doubling: no saturation here
    got = volsample.downsample_level_int(fx, "extinction", a=a)
    assert got.dtype == np.uint32 and got.shape == (4, 3, 5, 4)
    want = 2 * filter_level_f64(fx.astype(np.float64), a_q(a))
    assert np.abs(got - want).max() <= INT_EXTINCTION_LEVEL_LSB
    assert (got[..., :3] <= got[..., 3:]).all()


def test_extinction_level_constant_and_saturation():
    # A constant medium keeps its extinction per unit length: D doubles per coarse voxel
    # (twice as long), until the cap at 64.
    v = np.zeros((2, 2, 2, 4), np.uint32)
    v[...] = [4 << 20, 0, 1 << 20, 4 << 20]
    assert volsample.downsample_level_int(v, "extinction")[0, 0, 0].tolist() == [
        8 << 20, 0, 2 << 20, 8 << 20]
    v[...] = [MAX_DEPTH_RAW - 5, 0, 0, MAX_DEPTH_RAW - 5]
    assert volsample.downsample_level_int(v, "extinction")[0, 0, 0].tolist() == [
        MAX_DEPTH_RAW, 0, 0, MAX_DEPTH_RAW]


@pytest.mark.parametrize("name", list(FILTERS))
def test_opacity_level_u88_within_the_bound(rng, name):
    a = FILTERS[name]
    vol = random_straight_u8(rng, (7, 6, 9)).astype(np.uint16) * 256
    vol += rng.integers(0, 256, vol.shape, dtype=np.uint16)
    vol[..., 3] = np.minimum(vol[..., 3], ONE)
    vol[..., :3] = np.minimum(vol[..., :3], vol[..., 3:])
    got = volsample.downsample_level_int(vol, "opacity", a=a)
    assert got.dtype == np.uint16 and got.shape == (4, 3, 5, 4)
    f = filter_level_f64(vol.astype(np.float64) / ONE, a_q(a))
    gain = 2 - f[..., 3:]
    want = np.concatenate([f[..., :3] * gain, f[..., 3:] * gain], -1) * ONE
    assert np.abs(got - want).max() <= INT_OPACITY_LEVEL_LSB


def test_opacity_level_constants_and_u8_agreement(rng):
    # The core's doc: a constant volume v gives ⌊v(2·FULL − v)/FULL + ½⌋, here at U8.8 scale.
    v = [40 * 256, 20 * 256, 0, 128 * 256]
    base = np.zeros((4, 4, 4, 4), np.uint16)
    base[...] = v
    want = [(2 * x * (2 * ONE - v[3]) + ONE) // (2 * ONE) for x in v]
    assert want[3] == 49088  # 1 − (1 − α)² = 0.75195 at α = 128/255, in U8.8
    got = volsample.downsample_level_int(base, "opacity", a=0.2)
    assert (got == want).all()
    # On associated bytes it is downsample_level_u8.
    assoc = random_straight_u8(rng, (5, 6, 7))
    assoc[..., :3] = np.minimum(assoc[..., :3], assoc[..., 3:])
    np.testing.assert_array_equal(volsample.downsample_level_int(assoc, "opacity", a=0.2),
                                  volsample.downsample_level_u8(assoc, a=0.2))


def test_bad_input():
    with pytest.raises(ValueError, match="uint32 ExtinctionFx"):
        volsample.downsample_level_int(np.zeros((2, 2, 2, 4), np.uint8), "extinction")
    with pytest.raises(ValueError, match="associated uint8 or U8.8 uint16"):
        volsample.downsample_level_int(np.zeros((2, 2, 2, 4), np.uint32), "opacity")
    with pytest.raises(ValueError, match="filter weight"):
        volsample.downsample_level_int(np.zeros((2, 2, 2, 4), np.uint32), "extinction", a=0.6)
    with pytest.raises(ValueError, match="unknown method"):
        volsample.downsample_level_int(np.zeros((2, 2, 2, 4), np.uint8), "mean")
    bad = np.zeros((2, 2, 2, 4), np.uint16)
    bad[0, 1, 0] = [300, 0, 0, 200]
    with pytest.raises(ValueError, match=r"voxel 2: the integer sample breaks C <= A <= ONE"):
        volsample.downsample_level_int(bad, "opacity")
    bad = np.zeros((2, 2, 2, 4), np.uint32)
    bad[1, 1, 1] = [0, 0, 0, MAX_DEPTH_RAW + 1]
    with pytest.raises(ValueError, match="voxel 7 is out of range"):
        volsample.downsample_level_int(bad, "extinction")
    with pytest.raises(ValueError, match="color above its opacity"):
        volsample.downsample_level_int(np.full((2, 2, 2, 4), [9, 0, 0, 5], np.uint8), "opacity")
