"""render_int's background and empty-space skipping (IntRayMarcher::with_background and
with_skipping): the background is composited behind each ray with the integer front-to-back
step (derived here from the compositing rule, every rounding half up); skipping changes no bit."""

import numpy as np
import pytest

import volsample
from conftest import random_straight_u8
from test_render_int import composite_int, ow_voxel_samples
from test_render_options import sparse
from tolerance import ONE


def over_int(acc, bg):
    """One more integer front-to-back step with ``acc`` in front of ``bg``:
    ``x ← x + ⌊(ONE − A)·bg_x/ONE + ½⌋`` per channel."""
    t = ONE - int(acc[3])
    return acc + (t * np.asarray(bg, np.int64) + ONE // 2) // ONE


# Every mode with and without skipping, but the integer extinction mode, which does not skip.
@pytest.mark.parametrize("mode,skip", [(m, s) for m in ("opacity_weighted", "separate",
                                                        "preweighted") for s in (False, True)]
                         + [("extinction", False)])
def test_an_empty_volume_renders_to_exactly_the_background(mode, skip):
    bg = [1000, 20000, 0, 30000]
    vol = np.zeros((6, 5, 4, 4), np.uint8)
    if mode != "preweighted":
        vol[..., :3] = 200  # colored but fully transparent (straight)
    if mode == "extinction":
        vol = volsample.to_extinction_fx(vol)  # D = 0, D·C = 0
    # Some rays hit the volume, some miss it: all are exactly the background.
    cam = volsample.Camera.perspective([1.5, 2.0, -10.0], [1.5, 2.0, 2.5], [0, -1, 0], 1.2)
    for frac_bits in (4, 8):
        img = volsample.render_int(vol, cam, 9, 7, mode=mode, background=bg, skip=skip,
                                   frac_bits=frac_bits, step=0.4)
        assert img.dtype == np.uint16
        assert (img == np.array(bg, np.uint16)).all()
    # Without a background: transparent.
    assert (volsample.render_int(vol, cam, 9, 7, mode=mode, skip=skip) == 0).all()


@pytest.mark.parametrize("a_stop", [ONE, ONE // 2])
@pytest.mark.parametrize("skip", [False, True])
def test_the_background_lies_behind_the_columns(rng, a_stop, skip):
    # Looking down z with step 1 = d′ (samples at voxel centres), each pixel is its column's
    # integer composite (stopping once A ≥ a_stop), then one more step over the background.
    vol = random_straight_u8(rng, (5, 3, 4))
    vol[..., 3] //= 3  # faint: most rays stay below opaque, so the background shows
    cam = volsample.Camera.looking_down_z(vol.shape)
    bg = [20000, 9000, 51000, 60000]
    img = volsample.render_int(vol, cam, 4, 3, step=1.0, a_stop=a_stop, background=bg,
                               skip=skip)
    s = ow_voxel_samples(vol)
    want = np.array([[over_int(composite_int(s[:, j, i], a_stop), bg) for i in range(4)]
                     for j in range(3)])
    np.testing.assert_array_equal(img, want)
    # The background did show through: the image differs from the one without it.
    plain = volsample.render_int(vol, cam, 4, 3, step=1.0, a_stop=a_stop)
    assert (img[..., 3] > plain[..., 3]).all()


MODES = [("opacity_weighted", lambda v: v), ("separate", lambda v: v),
         ("preweighted", lambda v: np.minimum(v, v[..., 3:]))]


@pytest.mark.parametrize("mode,convert", MODES)
@pytest.mark.parametrize("filt", ["nearest", "trilinear"])
@pytest.mark.parametrize("frac_bits", [4, 8, 12])
def test_skipping_changes_no_bit(rng, mode, convert, filt, frac_bits):
    vol = convert(sparse(rng))
    cam = volsample.Camera.perspective([11.5, 11.5, -40.0], [11.5, 11.5, 11.5], [0, -1, 0], 0.6)
    for kw in ({}, {"a_stop": 50000}, {"background": [100, 200, 300, 40000]},
               {"step": 0.3, "threads": 3}, {"step": 1.0}):
        kw = {"step": 0.5, **kw}
        plain = volsample.render_int(vol, cam, 32, 24, mode=mode, filter=filt,
                                     frac_bits=frac_bits, **kw)
        fast = volsample.render_int(vol, cam, 32, 24, mode=mode, filter=filt,
                                    frac_bits=frac_bits, skip=True, **kw)
        assert plain.tobytes() == fast.tobytes(), kw
        assert plain[..., 3].max() > 6000  # the rays do meet the blobs
        assert (plain[..., 3] == 0).sum() > 50 or "background" in kw  # and air


def test_bad_options():
    v = np.zeros((2, 2, 2, 4), np.uint8)
    cam = volsample.Camera.looking_down_z(v.shape)
    for bg in ([0, 0, 10, 5], [0, 0, 0, ONE + 1], [-1, 0, 0, 10], [0, 0, 0, 70000]):
        with pytest.raises(ValueError, match=r"background must be U8.8 associated .*"
                                             r"the integer sample breaks C <= A <= ONE"):
            volsample.render_int(v, cam, 2, 2, background=bg)
    with pytest.raises(ValueError, match="length 4"):
        volsample.render_int(v, cam, 2, 2, background=[0, 0, 0])
    fx = volsample.to_extinction_fx(v)
    with pytest.raises(ValueError, match="skip is not available for the integer mode 'extinction'"):
        volsample.render_int(fx, cam, 2, 2, mode="extinction", skip=True)
    # A valid background at the edge of the range is taken.
    img = volsample.render_int(v, cam, 2, 2, background=[ONE, ONE, ONE, ONE])
    assert (img == ONE).all()
