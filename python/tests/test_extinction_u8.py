"""Mode 'extinction_u8' (the core's ExtinctionWeightedU8): extinction sampling read straight
from uint8 RGBA through a table of τ per opacity byte."""

import numpy as np
import pytest

import volsample
from conftest import gil_free_ticks, random_straight_u8
from test_sample import positions, scipy_sample
from tolerance import EXTINCTION_SAMPLE_ABS


def extinction_f64(vol_u8, d_ref):
    """(C^τ, τ) in f64: τ = min(−ln(1 − α), 64)/d′, C^τ = τ·C, α = n/255."""
    s = vol_u8.astype(np.float64) / 255.0
    with np.errstate(divide="ignore"):
        tau = np.minimum(-np.log1p(-s[..., 3:]), 64.0) / d_ref
    return np.concatenate([tau * s[..., :3], tau], -1)


@pytest.mark.parametrize("d_ref", [1.0, 0.5])
def test_samples_integrate_the_step_against_f64(rng, d_ref):
    shape = (5, 6, 7)
    vol = random_straight_u8(rng, shape)
    ext = extinction_f64(vol, d_ref)
    pos = positions(rng, shape)
    for step in (0.25, 1.0, 2.0):
        got = volsample.sample(vol, pos, mode="extinction_u8", step=step, reference_distance=d_ref)
        ct = scipy_sample(ext, pos, order=1)
        tau = ct[:, 3:]
        alpha = -np.expm1(-tau * step)
        with np.errstate(invalid="ignore", divide="ignore"):
            color = np.where(tau > 0, ct[:, :3] / tau, 0.0) * alpha
        want = np.concatenate([color, alpha], -1)
        # τ up to 64/d′ makes the relative f32 errors of the sums absolute in α near 1.
        err = np.abs(got - want).max()
        assert err <= EXTINCTION_SAMPLE_ABS, (step, err)
    # The opacity of one step d = d′ through a uniform medium is the stored opacity.
    uniform = np.full((2, 2, 2, 4), [200, 100, 50, 128], np.uint8)
    s = volsample.sample(uniform, np.array([[0.5, 0.5, 0.5]], np.float32), mode="extinction_u8",
                         step=d_ref, reference_distance=d_ref)
    assert abs(s[0, 3] - 128 / 255) < 1e-6


@pytest.mark.parametrize("filt", ["nearest", "trilinear", "trilinear_tree", "bspline"])
def test_bit_identical_to_the_float32_extinction_volume(rng, filt):
    # The core's promise: τ per byte is exactly ExtinctionF32::from_straight's, so sampling the
    # bytes equals sampling to_extinction() of them, bit for bit.
    shape = (6, 5, 7)
    vol = random_straight_u8(rng, shape)
    pos = rng.uniform(-1, 8, (400, 3)).astype(np.float32)
    for d_ref, step in ((1.0, 1.0), (0.5, 0.3)):
        a = volsample.sample(vol, pos, mode="extinction_u8", filter=filt, step=step,
                             reference_distance=d_ref)
        b = volsample.sample(volsample.to_extinction(vol, d_ref), pos, mode="extinction",
                             filter=filt, step=step, reference_distance=d_ref)
        assert a.tobytes() == b.tobytes()


def test_render_equals_the_float32_extinction_render(rng):
    vol = random_straight_u8(rng, (12, 12, 12))
    cam = volsample.Camera.perspective([5.5, 5.5, -25.0], [5.5, 5.5, 5.5], [0, -1, 0], 0.6)
    a = volsample.render(vol, cam, 24, 20, mode="extinction_u8", reference_distance=0.5,
                         threads=2)
    b = volsample.render(volsample.to_extinction(vol, 0.5), cam, 24, 20, mode="extinction")
    assert a.tobytes() == b.tobytes()
    assert a[..., 3].max() > 0.5


def test_the_gil_is_released(rng):
    vol = random_straight_u8(rng, (32, 32, 32))
    cam = volsample.Camera.looking_down_z(vol.shape)
    took, ticks = gil_free_ticks(lambda: volsample.render(
        vol, cam, 256, 256, mode="extinction_u8", step=0.05))
    assert took > 0.05, "render too short to tell"
    assert ticks >= 5, (ticks, took)


def test_bad_input():
    pos = np.zeros((1, 3), np.float32)
    with pytest.raises(ValueError, match="extinction_u8.*uint8"):
        volsample.sample(np.zeros((2, 2, 2, 4), np.float32), pos, mode="extinction_u8")
    with pytest.raises(ValueError, match="reference distance"):
        volsample.sample(np.zeros((2, 2, 2, 4), np.uint8), pos, mode="extinction_u8",
                         reference_distance=0.0)
    with pytest.raises(ValueError, match="integer kernels offer the modes"):
        volsample.sample_int(np.zeros((2, 2, 2, 4), np.uint8), pos, mode="extinction_u8")
