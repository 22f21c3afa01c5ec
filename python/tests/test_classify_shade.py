"""The classification and shading pre-passes: classify_transfer, classify_isosurface, gradient
and shade with a Light, against f64 numpy models of the core's documented formulas (np.gradient
for the differences, np.interp for the transfer function, Levoy's opacity and the two-sided
Lambert factor written out), within the core's stated bounds."""

import numpy as np
import pytest

import volsample
from conftest import gil_free_ticks, random_straight_u8
from test_post_classified import POINTS, SLOPE, classify_f64
from tolerance import CLASSIFY_ISOSURFACE_ABS, EPS32, shade_abs, tf_eval_abs


def gradient_f64(s):
    """(∂f/∂x, ∂f/∂y, ∂f/∂z) per voxel of a (z, y, x) array: central differences inside,
    one-sided at the faces (np.gradient, edge_order 1), 0 along an axis of length 1."""
    s = s.astype(np.float64)
    out = np.zeros(s.shape + (3,))
    for k, axis in enumerate((2, 1, 0)):
        if s.shape[axis] >= 2:
            out[..., k] = np.gradient(s, axis=axis)
    return out


def isosurface_f64(s, fv, av, r):
    """Levoy's opacity: α_v(1 − |f_v − f|/(r·|∇f|)) where that ratio is at most 1, α_v on the
    isovalue, 0 elsewhere (and where the gradient vanishes off the isovalue)."""
    g = np.linalg.norm(gradient_f64(s), axis=-1)
    d = np.abs(fv - s.astype(np.float64))
    with np.errstate(divide="ignore", invalid="ignore"):
        q = d / (r * g)
    a = np.where((g > 0) & (q <= 1), av * (1 - q), 0.0)
    return np.where(d == 0, av, a)


def shade_f64(rgba, s, direction, ka, kd):
    """C·min(1, k_a + k_d·|n·L|), clamped to [0, 1], n the normalised gradient (|n·L| = 1
    where it vanishes); α unchanged."""
    g = gradient_f64(s)
    light = np.asarray(direction, np.float64)
    light /= np.linalg.norm(light)
    gn = np.linalg.norm(g, axis=-1)
    cos = np.where(gn > 0, np.abs(g @ light) / np.where(gn > 0, gn, 1.0), 1.0)
    k = np.minimum(1.0, ka + kd * np.minimum(cos, 1.0))
    out = rgba.astype(np.float64).copy()
    out[..., :3] = np.clip(out[..., :3] * k[..., None], 0.0, 1.0)
    return out


def ball(n=20, r=6.5):
    """A float32 distance field from the volume's centre (z, y, x)."""
    z, y, x = np.mgrid[:n, :n, :n].astype(np.float64) - (n - 1) / 2
    return np.sqrt(x * x + 1.3 * y * y + 0.7 * z * z).astype(np.float32) - r


# --- gradient --------------------------------------------------------------------------------

@pytest.mark.parametrize("dtype", [np.uint8, np.uint16, np.float32])
def test_gradient_is_central_differences(rng, dtype):
    # Integer-valued scalars: every difference and its half is exact in float32, so the
    # gradient equals np.gradient's bit for bit (x first).
    s = rng.integers(0, 256 if dtype == np.uint8 else 4000, (5, 6, 7)).astype(dtype)
    g = volsample.gradient(s)
    assert g.shape == (5, 6, 7, 3) and g.dtype == np.float32
    np.testing.assert_array_equal(g, gradient_f64(s).astype(np.float32))


def test_gradient_axes_of_length_one_and_real_values(rng):
    s = rng.normal(size=(1, 4, 3)).astype(np.float32)
    g = volsample.gradient(s)
    assert (g[..., 2] == 0).all()  # z has one voxel
    want = gradient_f64(s)
    # Each component within ε·m of the exact difference, m the largest differenced magnitude.
    assert np.abs(g - want).max() <= EPS32 * np.abs(s).max()
    assert np.abs(want[..., :2]).min() > 0  # not all trivially zero


# --- classify_transfer -----------------------------------------------------------------------

@pytest.mark.parametrize("dtype", [np.uint8, np.uint16, np.float32])
def test_classify_transfer_is_the_transfer_function(rng, dtype):
    tf = volsample.TransferFunction(POINTS)
    s = rng.uniform(-20, 280, (6, 7, 8))
    s = s.astype(dtype) if dtype == np.float32 else np.clip(s, 0, 255).astype(dtype)
    out = volsample.classify_transfer(s, tf)
    assert out.shape == (6, 7, 8, 4) and out.dtype == np.float32
    want = classify_f64(s.astype(np.float64))
    assert np.abs(out - want).max() <= tf_eval_abs(SLOPE, 280)
    # Each voxel's (C, α) is the function's value at its scalar: tf.eval, bit for bit.
    np.testing.assert_array_equal(
        out.reshape(-1, 4), tf.eval(s.astype(np.float32).ravel()))
    # Straight, not premultiplied: a voxel at s = 60 is (1, 0.2, 0, 0.1).
    s[0, 0, 0] = 60
    assert volsample.classify_transfer(s, tf)[0, 0, 0].tolist() == pytest.approx(
        [1.0, 0.2, 0.0, 0.1], abs=1e-7)


# --- classify_isosurface ---------------------------------------------------------------------

def test_classify_isosurface_on_a_ramp_is_exact():
    # f = x, ∇f = (1, 0, 0) everywhere: α = α_v(1 − |2 − x|/2) for f_v = 2, r = 2.
    s = np.tile(np.arange(6, dtype=np.float32), (2, 3, 1))
    out = volsample.classify_isosurface(s, 2.0, opacity=0.8, thickness=2.0,
                                        color=[0.25, 0.5, 1.0])
    assert out.shape == (2, 3, 6, 4) and out.dtype == np.float32
    want_a = np.float32(0.8) * np.array([0.0, 0.5, 1.0, 0.5, 0.0, 0.0], np.float32)
    assert (out[..., 3] == want_a).all()
    assert (out[..., :3] == np.array([0.25, 0.5, 1.0], np.float32)).all()


@pytest.mark.parametrize("iso,opacity,thickness", [(0.0, 1.0, 1.0), (1.5, 0.6, 2.5),
                                                   (-3.0, 0.9, 0.5)])
def test_classify_isosurface_matches_levoy(iso, opacity, thickness):
    s = ball()
    out = volsample.classify_isosurface(s, iso, opacity=opacity, thickness=thickness)
    want = isosurface_f64(s, iso, opacity, thickness)
    assert np.abs(out[..., 3] - want).max() <= CLASSIFY_ISOSURFACE_ABS
    assert (want > 0.05).sum() > 50 and (want == 0).sum() > 50  # a shell, and air
    assert (out[..., :3] == 1.0).all()  # the default color, white


def test_classify_isosurface_integer_scalars(rng):
    s = rng.integers(0, 256, (7, 6, 5)).astype(np.uint8)
    out = volsample.classify_isosurface(s, 128.0, opacity=1.0, thickness=3.0)
    assert np.abs(out[..., 3] - isosurface_f64(s, 128.0, 1.0, 3.0)).max() <= \
        CLASSIFY_ISOSURFACE_ABS


# --- shade -----------------------------------------------------------------------------------

@pytest.mark.parametrize("direction,ka,kd", [([1.0, 0.0, 0.0], 0.25, 0.75),
                                             ([-0.5, 0.6, 1.0], 0.1, 0.6),
                                             ([0.0, 0.0, 3.0], 0.0, 1.5)])
def test_shade_is_the_lambert_factor(rng, direction, ka, kd):
    s = ball()
    rgba = random_straight_u8(rng, s.shape).astype(np.float32) / np.float32(255)
    before = rgba.copy()
    light = volsample.Light(direction, ambient=ka, diffuse=kd)
    out = volsample.shade(rgba, s, light)
    assert out.shape == rgba.shape and out.dtype == np.float32
    np.testing.assert_array_equal(rgba, before)  # the input is not modified
    assert out.tobytes() != rgba.tobytes()
    np.testing.assert_array_equal(out[..., 3], rgba[..., 3])  # opacity unchanged
    want = shade_f64(rgba, s, direction, ka, kd)
    assert np.abs(out - want).max() <= shade_abs(ka, kd)


def test_shade_uint8_reads_n_over_255(rng):
    s = rng.integers(0, 1000, (6, 5, 4)).astype(np.uint16)
    vol = random_straight_u8(rng, s.shape)
    out = volsample.shade(vol, s, volsample.Light([0.3, -1.0, 0.2], 0.2, 0.7))
    straight = vol.astype(np.float32) / np.float32(255)
    np.testing.assert_array_equal(out[..., 3], straight[..., 3])
    assert np.abs(out - shade_f64(straight, s, [0.3, -1.0, 0.2], 0.2, 0.7)).max() <= \
        shade_abs(0.2, 0.7)


def test_unlit_and_flat_regions(rng):
    s = ball()
    rgba = random_straight_u8(rng, s.shape).astype(np.float32) / np.float32(255)
    # The identity light changes no bit.
    assert volsample.shade(rgba, s, volsample.Light.unlit()).tobytes() == rgba.tobytes()
    # A constant scalar field has no gradient: |n·L| = 1, the factor min(1, k_a + k_d).
    flat = np.zeros(s.shape, np.float32)
    out = volsample.shade(rgba, flat, volsample.Light([0, 1, 0], 0.2, 0.3))
    np.testing.assert_array_equal(out[..., :3], rgba[..., :3] * np.float32(0.5))


def test_light_attributes():
    light = volsample.Light([0, 0, 2], ambient=0.3, diffuse=0.6)
    assert light.direction == [0.0, 0.0, 2.0]
    assert light.ambient == pytest.approx(0.3) and light.diffuse == pytest.approx(0.6)
    assert "Light(" in repr(light)
    unlit = volsample.Light.unlit()
    assert (unlit.ambient, unlit.diffuse) == (1.0, 0.0)


def test_the_gil_is_released():
    # A second Python thread keeps running while the pre-passes are in the kernel (128³:
    # about 0.1–0.15 s each here).
    s = ball(128, 40.0)
    rgba = np.full(s.shape + (4,), 0.5, np.float32)
    light = volsample.Light([1, 1, 1])
    took, ticks = gil_free_ticks(lambda: volsample.shade(rgba, s, light))
    assert took > 0.05, "shade too short to tell"
    assert ticks >= 5, (ticks, took)
    took, ticks = gil_free_ticks(lambda: volsample.classify_isosurface(s, 0.0, thickness=2.0))
    assert took > 0.05, "classify_isosurface too short to tell"
    assert ticks >= 5, (ticks, took)


# --- bad input -------------------------------------------------------------------------------

def test_bad_input():
    tf = volsample.TransferFunction(POINTS)
    s = np.zeros((2, 3, 4), np.float32)
    for name, call in (("classify_transfer", lambda v: volsample.classify_transfer(v, tf)),
                       ("classify_isosurface", lambda v: volsample.classify_isosurface(v, 0.5)),
                       ("gradient", volsample.gradient)):
        with pytest.raises(ValueError, match=f"{name} reads a scalar volume"):
            call(s.astype(np.float64))
        with pytest.raises(ValueError, match=f"{name} reads a scalar volume"):
            call(np.zeros((2, 3, 4, 4), np.uint8))
        with pytest.raises(ValueError, match=f"{name} reads a scalar volume"):
            call(s.astype(np.int32))
        with pytest.raises(ValueError, match="volume dimension 2 is zero"):
            call(np.zeros((0, 3, 4), np.uint8))
        bad = s.copy()
        bad[0, 1, 2] = np.nan
        with pytest.raises(ValueError, match="voxel 6 is NaN or infinite"):
            call(bad)
    with pytest.raises(ValueError, match="isosurface classifier needs"):
        volsample.classify_isosurface(s, 0.5, opacity=1.5)
    with pytest.raises(ValueError, match="isosurface classifier needs"):
        volsample.classify_isosurface(s, 0.5, thickness=0.0)
    with pytest.raises(ValueError, match="isosurface classifier needs"):
        volsample.classify_isosurface(s, float("nan"))
    with pytest.raises(ValueError, match=r"color must be three values in \[0, 1\]"):
        volsample.classify_isosurface(s, 0.5, color=[1.5, 0, 0])
    with pytest.raises(ValueError, match="length 3"):
        volsample.classify_isosurface(s, 0.5, color=[1, 1])
    with pytest.raises(ValueError, match="light needs a finite non-zero direction"):
        volsample.Light([0, 0, 0])
    with pytest.raises(ValueError, match="light needs a finite non-zero direction"):
        volsample.Light([1, 0, 0], ambient=-0.1)
    with pytest.raises(ValueError, match="light needs a finite non-zero direction"):
        volsample.Light([1, float("inf"), 0])
    light = volsample.Light([1, 0, 0])
    vol = np.zeros((2, 3, 4, 4), np.float32)
    with pytest.raises(ValueError, match="must match"):
        volsample.shade(vol, np.zeros((4, 3, 2), np.float32), light)
    with pytest.raises(ValueError, match="shade reads a scalar volume"):
        volsample.shade(vol, s.astype(np.float64), light)
    with pytest.raises(ValueError, match=r"\(z, y, x, 4\) and dtype uint8 or float32"):
        volsample.shade(vol.astype(np.float64), s, light)
    bad = vol.copy()
    bad[0, 0, 1, 3] = 1.5
    with pytest.raises(ValueError, match="voxel 1 is out of range"):
        volsample.shade(bad, s, light)
    with pytest.raises(TypeError):
        volsample.shade(vol, s, "light")
