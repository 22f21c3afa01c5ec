"""render's options of the library's fast path: early termination (a_stop), the background,
back-to-front compositing and empty-space skipping."""

import numpy as np
import pytest

import volsample
from conftest import random_straight_u8

EPS = np.finfo(np.float32).eps  # 2^−23


def column(n, alpha=0.5):
    """A 1×1×n float32 column of straight white voxels of opacity ``alpha``."""
    v = np.zeros((n, 1, 1, 4), np.float32)
    v[...] = [1.0, 1.0, 1.0, alpha]
    return v


def sparse(rng, n=24):
    """Mostly air, with a few random blobs: something for skipping to skip."""
    v = np.zeros((n, n, n, 4), np.uint8)
    for _ in range(4):
        c = rng.integers(2, n - 6, 3)
        v[c[0]:c[0] + 4, c[1]:c[1] + 4, c[2]:c[2] + 4] = random_straight_u8(rng, (4, 4, 4))
    return v


def down_z(vol, **kw):
    cam = volsample.Camera.looking_down_z(vol.shape)
    return volsample.render(vol, cam, vol.shape[2], vol.shape[1], step=1.0, **kw)


def test_a_stop_stops_where_the_opacity_reaches_it():
    # Looking down z with step 1 = d′, each sample of an α = ½ column adds half the remaining
    # transparency: after k samples A = 1 − 2^−k (exact in float32), C̃ = A (white). A ray
    # stops after the first k with A ≥ a_stop, so the pixel is 1 − 2^−k for that k.
    vol = column(10)
    full = down_z(vol)[0, 0]
    assert full.tolist() == [1 - 2.0**-10] * 4
    for a_stop, k in ((0.9, 4), (0.5, 1), (0.99, 7), (0.999, 10)):
        got = down_z(vol, a_stop=a_stop)[0, 0]
        assert got.tolist() == [1 - 2.0**-k] * 4, a_stop


def test_a_stop_one_is_the_default_image(rng):
    vol = random_straight_u8(rng, (12, 12, 12))
    cam = volsample.Camera.perspective([5.5, 5.5, -20.0], [5.5, 5.5, 5.5], [0, -1, 0], 0.7)
    default = volsample.render(vol, cam, 24, 20)
    assert volsample.render(vol, cam, 24, 20, a_stop=1.0).tobytes() == default.tobytes()


def test_a_stop_099_is_within_001_of_no_stop(rng):
    # A ray that stops has A_k ≥ a_stop; what the rest of it would add is (1 − A_k)·R with
    # R an associated color (each channel ≤ 1), so each channel differs by at most
    # 1 − a_stop = 0.01 (plus float rounding: a few ε per sample, far below 1e-5 here).
    vol = random_straight_u8(rng, (16, 16, 16))
    cam = volsample.Camera.perspective([7.5, 7.5, -30.0], [7.5, 7.5, 7.5], [0, -1, 0], 0.6)
    full = volsample.render(vol, cam, 40, 30)
    stop = volsample.render(vol, cam, 40, 30, a_stop=0.99)
    diff = np.abs(full.astype(np.float64) - stop)
    assert diff.max() <= 0.01 + 1e-5
    assert (stop[..., 3] <= full[..., 3] + 1e-6).all()  # stopping only leaves opacity out
    assert (full[..., 3] > 0.99).sum() > 100  # many rays do reach the threshold ...
    assert not np.array_equal(full, stop)  # ... and stopping them changes their pixels


@pytest.mark.parametrize("order", ["front_to_back", "back_to_front"])
@pytest.mark.parametrize("skip", [False, True])
def test_a_transparent_volume_renders_to_the_background(order, skip):
    bg = [0.25, 0.125, 0.0, 0.5]
    vol = np.zeros((6, 5, 4, 4), np.uint8)
    vol[..., :3] = 200  # colored but fully transparent
    cam = volsample.Camera.perspective([1.5, 2.0, -10.0], [1.5, 2.0, 2.5], [0, -1, 0], 1.2)
    img = volsample.render(vol, cam, 9, 7, background=bg, order=order, skip=skip)
    assert (img == np.array(bg, np.float32)).all()  # hits and misses alike


def test_the_background_lies_behind_the_volume():
    # Over the background: pixel = acc + (1 − A)·bg, with acc = A = 1 − 2^−4 (4 samples of
    # α = ½, white) and bg = (0.5, 0, 0.25, 0.5): exact in float32.
    bg = np.array([0.5, 0.0, 0.25, 0.5])
    got = down_z(column(4), background=bg)[0, 0]
    a = 1 - 2.0**-4
    assert got.tolist() == (a + (1 - a) * bg).tolist()
    with pytest.raises(ValueError, match="background must be a finite associated color"):
        down_z(column(4), background=[0.6, 0, 0, 0.5])  # C̃ > α
    with pytest.raises(ValueError, match="background must be a finite associated color"):
        down_z(column(4), background=[0, 0, 0, 1.5])


def test_back_to_front_equals_front_to_back_within_rounding(rng):
    # The same "over" of the same samples in the other association order; every step rounds
    # each of its ≤ 3 operations (values ≤ 1) by ≤ ε/2, so the two differ by ≤ 3·n·ε for
    # n samples per ray (n ≤ diagonal/step + 2).
    vol = random_straight_u8(rng, (16, 16, 16))
    cam = volsample.Camera.perspective([7.5, 7.5, -30.0], [7.5, 7.5, 7.5], [0, -1, 0], 0.6)
    n = int(np.ceil(np.sqrt(3 * 16**2) / 0.5)) + 2
    for mode, v in (("opacity_weighted", vol), ("extinction", volsample.to_extinction(vol))):
        ftb = volsample.render(v, cam, 40, 30, mode=mode)
        btf = volsample.render(v, cam, 40, 30, mode=mode, order="back_to_front")
        assert np.abs(ftb.astype(np.float64) - btf).max() <= 3 * n * EPS, mode
        # Rounded in another order: some pixel differs in its last bits (the option is live).
        assert not np.array_equal(ftb, btf)


MODES = [("opacity_weighted", lambda v: v), ("separate", lambda v: v),
         ("preweighted", lambda v: (volsample.to_associated(v) * 255).round().astype(np.uint8)),
         ("extinction", lambda v: volsample.to_extinction(v)), ("extinction_u8", lambda v: v),
         ("opacity_weighted", lambda v: v.astype(np.float32) / 255)]


@pytest.mark.parametrize("mode,convert", MODES)
@pytest.mark.parametrize("filt", ["nearest", "trilinear", "bspline"])
def test_skipping_changes_no_bit(rng, mode, convert, filt):
    vol = convert(sparse(rng))
    cam = volsample.Camera.perspective([11.5, 11.5, -40.0], [11.5, 11.5, 11.5], [0, -1, 0], 0.6)
    for kw in ({}, {"a_stop": 0.9}, {"order": "back_to_front"},
               {"background": [0.1, 0.2, 0.3, 0.4], "step": 0.3}):
        kw = {"step": 0.5, **kw}
        plain = volsample.render(vol, cam, 32, 24, mode=mode, filter=filt, **kw)
        fast = volsample.render(vol, cam, 32, 24, mode=mode, filter=filt, skip=True, threads=2,
                                **kw)
        assert plain.tobytes() == fast.tobytes(), kw
        assert plain[..., 3].max() > 0.1  # the rays do meet the blobs


def test_post_classified_takes_the_options():
    ramp = volsample.TransferFunction([(0, 0, 0, 0, 0), (100, 1, 1, 1, 0.5)])
    scalars = np.full((10, 1, 1), 100, np.uint8)  # α = ½ per voxel, white: as column(10)
    cam = volsample.Camera.looking_down_z(scalars.shape)
    kw = dict(mode="post_classified", tf=ramp, step=1.0)
    assert volsample.render(scalars, cam, 1, 1, a_stop=0.9, **kw)[0, 0].tolist() == \
        [1 - 2.0**-4] * 4
    btf = volsample.render(scalars, cam, 1, 1, order="back_to_front", **kw)[0, 0]
    assert np.abs(btf - (1 - 2.0**-10)).max() <= 3 * 10 * EPS
    bg = volsample.render(np.zeros((3, 2, 2), np.uint8), volsample.Camera.looking_down_z(
        (3, 2, 2)), 2, 2, background=[0, 0, 0.5, 0.5], **kw)
    assert (bg == np.array([0, 0, 0.5, 0.5], np.float32)).all()
    with pytest.raises(ValueError, match="skip is not available for mode 'post_classified'"):
        volsample.render(scalars, cam, 1, 1, skip=True, **kw)


def test_bad_options_raise_value_error():
    vol = column(3)
    with pytest.raises(ValueError, match=r"early-termination threshold must lie in \(0, 1\]"):
        down_z(vol, a_stop=0.0)
    with pytest.raises(ValueError, match=r"early-termination threshold must lie in \(0, 1\]"):
        down_z(vol, a_stop=1.5)
    with pytest.raises(ValueError, match='unknown order "ftb"'):
        down_z(vol, order="ftb")
    with pytest.raises(ValueError, match="a_stop applies to order 'front_to_back' only"):
        down_z(vol, order="back_to_front", a_stop=0.9)
