"""Mode 'post_classified' (the core's PostClassified) with a TransferFunction: the scalar is
interpolated, then classified, C̃ = α·C; checked against scipy's trilinear interpolation of the
scalar and numpy's np.interp of the control points, in f64."""

import numpy as np
import pytest

import volsample
from conftest import gil_free_ticks
from test_sample import positions, scipy_sample
from tolerance import CORRECTION_ABS, post_classified_abs, tf_eval_abs

# A ramp with a steep rise: s 0 → 60 → 100 → 255, slopes at most 0.9/40 per unit.
POINTS = [(0.0, 0.0, 0.0, 0.0, 0.0),
          (60.0, 1.0, 0.2, 0.0, 0.1),
          (100.0, 0.3, 0.9, 0.5, 1.0),
          (255.0, 0.0, 0.0, 1.0, 0.6)]
SLOPE = 0.9 / 40


def classify_f64(s, points=POINTS):
    """Straight (r, g, b, a) of the piecewise-linear function at s, ends held outside."""
    p = np.array(points, np.float64)
    return np.stack([np.interp(s, p[:, 0], p[:, k]) for k in range(1, 5)], -1)


def associated_f64(s):
    ca = classify_f64(s)
    return np.concatenate([ca[..., :3] * ca[..., 3:], ca[..., 3:]], -1)


def test_transfer_function_points_and_eval(rng):
    tf = volsample.TransferFunction(POINTS)
    assert len(tf) == 4
    np.testing.assert_array_equal(tf.points, np.array(POINTS, np.float32))
    s = rng.uniform(-20, 280, 1000).astype(np.float32)
    got = tf.eval(s)
    assert got.shape == (1000, 4) and got.dtype == np.float32
    assert np.abs(got - classify_f64(s.astype(np.float64))).max() <= tf_eval_abs(SLOPE, 280)
    # Outside the points the end values hold (the core's doc example: (0.5, 0.5) at 50).
    ramp = volsample.TransferFunction(np.array([[0, 0, 0, 0, 0], [100, 1, 1, 1, 1]], np.float32))
    assert ramp.eval(np.array([50, 1e9, -5], np.float32)).tolist() == [
        [0.5] * 4, [1.0] * 4, [0.0] * 4]


@pytest.mark.parametrize("dtype", [np.uint8, np.uint16, np.float32])
def test_trilinear_samples_classify_the_interpolated_scalar(rng, dtype):
    shape = (6, 7, 8)
    vol = rng.integers(0, 256, shape).astype(dtype)
    if dtype == np.float32:
        vol += rng.uniform(0, 1, shape).astype(np.float32)
    tf = volsample.TransferFunction(POINTS)
    pos = positions(rng, shape, n=600)
    got = volsample.sample(vol, pos, mode="post_classified", tf=tf)
    s = scipy_sample(vol.astype(np.float64)[..., None], pos, order=1)[:, 0]
    want = associated_f64(s)
    assert got.shape == (600, 4) and got.dtype == np.float32
    err = np.abs(got - want).max()
    assert err <= post_classified_abs(SLOPE, 256), err
    # Classifying after interpolating differs from interpolating classified voxels (the
    # steep rise is where the two part): this data reaches it.
    pre = volsample.sample(volsample.TransferFunction(POINTS).eval(
        vol.astype(np.float32).ravel()).reshape(shape + (4,)), pos, mode="opacity_weighted")
    assert np.abs(got - pre).max() > 0.05


def test_step_applies_opacity_correction(rng):
    shape = (4, 5, 6)
    vol = rng.integers(0, 256, shape).astype(np.uint8)
    tf = volsample.TransferFunction(POINTS)
    pos = positions(rng, shape, n=200)
    s = scipy_sample(vol.astype(np.float64)[..., None], pos, order=1)[:, 0]
    ca = classify_f64(s)
    for step, d_ref in ((0.5, 1.0), (1.0, 0.25)):
        got = volsample.sample(vol, pos, mode="post_classified", tf=tf, step=step,
                               reference_distance=d_ref)
        r = step / d_ref
        a = 1 - (1 - ca[:, 3:]) ** r
        want = np.concatenate([ca[:, :3] * a, a], -1)
        bound = post_classified_abs(SLOPE, 256) * r + CORRECTION_ABS * max(1, r)
        assert np.abs(got - want).max() <= bound, step


def test_nearest_classifies_the_nearest_voxel(rng):
    shape = (5, 6, 7)
    vol = rng.integers(0, 256, shape).astype(np.uint16)
    pos = positions(rng, shape)
    frac = pos - np.floor(pos)
    pos = pos[np.all(np.abs(frac - 0.5) > 1e-3, axis=1)]
    got = volsample.sample(vol, pos, mode="post_classified", filter="nearest",
                           tf=volsample.TransferFunction(POINTS))
    s = scipy_sample(vol.astype(np.float64)[..., None], pos, order=0)[:, 0]
    assert np.abs(got - associated_f64(s)).max() <= post_classified_abs(SLOPE, 256, taps=1)


def test_render_composites_the_classified_column(rng):
    # Looking down z with step 1 = d′: each pixel is the "over" of its column's voxels,
    # classified (trilinear reads the voxel itself at its centre).
    vol = rng.integers(0, 256, (5, 3, 4)).astype(np.uint8)
    tf = volsample.TransferFunction(POINTS)
    img = volsample.render(vol, volsample.Camera.looking_down_z(vol.shape), 4, 3, step=1.0,
                           mode="post_classified", tf=tf, threads=2)
    s = associated_f64(vol.astype(np.float64))
    for j in range(3):
        for i in range(4):
            c, a = np.zeros(3), 0.0
            for z in range(5):
                c += (1 - a) * s[z, j, i, :3]
                a += (1 - a) * s[z, j, i, 3]
            assert np.abs(img[j, i, :3] - c).max() < 1e-5 and abs(img[j, i, 3] - a) < 1e-5


def test_the_gil_is_released(rng):
    vol = rng.integers(0, 256, (32, 32, 32)).astype(np.uint16)
    tf = volsample.TransferFunction(POINTS)
    cam = volsample.Camera.looking_down_z(vol.shape)
    took, ticks = gil_free_ticks(lambda: volsample.render(
        vol, cam, 128, 128, mode="post_classified", tf=tf, step=0.05))
    assert took > 0.05, "render too short to tell"
    assert ticks >= 5, (ticks, took)


def test_bad_input():
    v = np.zeros((2, 2, 2), np.uint8)
    pos = np.zeros((1, 3), np.float32)
    tf = volsample.TransferFunction(POINTS)
    with pytest.raises(ValueError, match="needs tf"):
        volsample.sample(v, pos, mode="post_classified")
    with pytest.raises(ValueError, match="post_classified' only"):
        volsample.sample(np.zeros((2, 2, 2, 4), np.uint8), pos, tf=tf)
    with pytest.raises(ValueError, match="scalar volume"):
        volsample.sample(np.zeros((2, 2, 2, 4), np.uint8), pos, mode="post_classified", tf=tf)
    with pytest.raises(ValueError, match="scalar volume"):
        volsample.sample(np.zeros((2, 2, 2), np.float64), pos, mode="post_classified", tf=tf)
    f = np.zeros((2, 2, 2), np.float32)
    f[1, 0, 1] = np.inf
    with pytest.raises(ValueError, match="voxel 5 is NaN or infinite"):
        volsample.sample(f, pos, mode="post_classified", tf=tf)
    with pytest.raises(ValueError, match="zero width or height"):
        volsample.render(v, volsample.Camera.looking_down_z(v.shape), 0, 2,
                         mode="post_classified", tf=tf, threads=2)
    # The core's messages for bad control points.
    with pytest.raises(ValueError, match="strictly increasing"):
        volsample.TransferFunction([(1, 0, 0, 0, 0), (1, 1, 1, 1, 1)])
    with pytest.raises(ValueError, match=r"outside \[0, 1\]"):
        volsample.TransferFunction([(0, 0, 0, 0, 1.5)])
    with pytest.raises(ValueError, match="no points"):
        volsample.TransferFunction([])
    with pytest.raises(ValueError, match="capacity"):
        volsample.TransferFunction([(i, 0, 0, 0, 0) for i in range(257)])
    with pytest.raises(ValueError, match=r"\(s, r, g, b, a\)"):
        volsample.TransferFunction([(0, 0, 0, 0)])
