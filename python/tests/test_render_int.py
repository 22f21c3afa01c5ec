"""render_int: the integer ray marcher (IntRayMarcher), checked against an exact integer model
of its samples and of the integer front-to-back compositing (every rounding half up)."""

import numpy as np
import pytest

import volsample
from conftest import gil_free_ticks, random_straight_u8
from tolerance import ONE, extinction_int_a_lsb, extinction_int_c_lsb


def composite_int(samples, a_stop=ONE):
    """Integer front to back over a column of U8.8 samples (k, 4), as the core's compositing
    module states it: T = ONE − A, A += ⌊T·α/ONE + ½⌋, C += ⌊T·C̃/ONE + ½⌋, stopping before a
    sample once A ≥ a_stop."""
    acc = np.zeros(4, np.int64)
    for s in samples.astype(np.int64):
        if acc[3] >= a_stop:
            break
        t = ONE - acc[3]
        acc += (t * s + ONE // 2) // ONE
    return acc


def ow_voxel_samples(vol):
    """Opacity-weighted integer samples at voxel centres: α = 256·a, C̃ = ⌊C·α/255·256 + ½⌋
    of the bytes (the kernel's one rounding), so ⌊(512·c·a + 255)/510⌋."""
    v = vol.astype(np.int64)
    a = v[..., 3:]
    return np.concatenate([(512 * v[..., :3] * a + 255) // 510, 256 * a], -1)


@pytest.mark.parametrize("frac_bits", [4, 8, 12])
@pytest.mark.parametrize("filt", ["nearest", "trilinear"])
def test_columns_equal_the_integer_model(rng, frac_bits, filt):
    # Looking down z with step 1 = d′: the samples are at the voxel centres (no correction),
    # so each pixel is the integer composite of its column's voxels, bit for bit.
    vol = random_straight_u8(rng, (6, 3, 4))
    cam = volsample.Camera.looking_down_z(vol.shape)
    img = volsample.render_int(vol, cam, 4, 3, step=1.0, filter=filt, frac_bits=frac_bits)
    assert img.shape == (3, 4, 4) and img.dtype == np.uint16
    s = ow_voxel_samples(vol)
    want = np.array([[composite_int(s[:, j, i]) for i in range(4)] for j in range(3)])
    np.testing.assert_array_equal(img, want)
    # Preweighted: the stored associated bytes are the samples, 256·n.
    assoc = vol.copy()
    assoc[..., :3] = np.minimum(assoc[..., :3], assoc[..., 3:])
    img = volsample.render_int(assoc, cam, 4, 3, mode="preweighted", step=1.0, filter=filt)
    s = 256 * assoc.astype(np.int64)
    want = np.array([[composite_int(s[:, j, i]) for i in range(4)] for j in range(3)])
    np.testing.assert_array_equal(img, want)


def test_early_termination_stops_before_the_sample(rng):
    vol = random_straight_u8(rng, (8, 2, 2))
    vol[..., 3] = np.maximum(vol[..., 3], 100)
    cam = volsample.Camera.looking_down_z(vol.shape)
    s = ow_voxel_samples(vol)
    for a_stop in (ONE // 2, 50000, ONE):
        img = volsample.render_int(vol, cam, 2, 2, step=1.0, a_stop=a_stop)
        want = np.array([[composite_int(s[:, j, i], a_stop) for i in range(2)] for j in range(2)])
        np.testing.assert_array_equal(img, want)
    stopped = volsample.render_int(vol, cam, 2, 2, step=1.0, a_stop=ONE // 2)
    assert (stopped[..., 3] < volsample.render_int(vol, cam, 2, 2, step=1.0)[..., 3]).any()


def test_extinction_columns_within_the_kernel_and_compositing_bounds(rng):
    vol = random_straight_u8(rng, (6, 3, 4))
    fx = volsample.to_extinction_fx(vol)
    cam = volsample.Camera.looking_down_z(vol.shape)
    n = vol.shape[0]
    for nodes in (17, 257):
        img = volsample.render_int(fx, cam, 4, 3, mode="extinction", step=1.0, table_nodes=nodes)
        d = fx.astype(np.float64) / 2 ** 20
        alpha = -np.expm1(-d[..., 3:])
        with np.errstate(invalid="ignore", divide="ignore"):
            c = np.where(d[..., 3:] > 0, d[..., :3] / d[..., 3:], 0.0) * alpha
        s = np.concatenate([c, alpha], -1)
        for j in range(3):
            for i in range(4):
                acc, t = np.zeros(4), 1.0
                for z in range(n):
                    acc += t * s[z, j, i]
                    t *= 1 - s[z, j, i, 3]
                # Per sample the kernel's bound, which also moves every later transmittance,
                # plus the compositing's n/2 (A) and n (C) LSB.
                err = np.abs(img[j, i].astype(np.float64) - ONE * acc)
                a_lsb, c_lsb = extinction_int_a_lsb(nodes), extinction_int_c_lsb(nodes)
                assert err[3] <= n * a_lsb + n / 2, (nodes, err)
                assert err[:3].max() <= n * (a_lsb + c_lsb) + n, (nodes, err)


def test_threads_give_the_same_image_and_track_the_float_render(rng):
    vol = random_straight_u8(rng, (16, 16, 16))
    cam = volsample.Camera.perspective([7.5, 7.5, -30.0], [7.5, 7.5, 7.5], [0, -1, 0], 0.6)
    one = volsample.render_int(vol, cam, 40, 30, threads=1, frac_bits=12)
    three = volsample.render_int(vol, cam, 40, 30, threads=3, frac_bits=12)
    assert one.tobytes() == three.tobytes()
    flt = volsample.render(vol, cam, 40, 30)
    # 12 position bits, about 60 samples a ray: the integer image stays within 0.002 of the
    # float image (measured 0.00013 on seed 33, at most 0.00021 on seeds 1–3), far below what
    # a wrong channel or a missed correction would give.
    assert np.abs(one / ONE - flt).max() < 0.002
    assert flt[..., 3].max() > 0.5


@pytest.mark.parametrize("mode", ["opacity_weighted", "extinction"])
def test_the_gil_is_released(rng, mode):
    # A second Python thread keeps running while render_int is in the kernel.
    vol = random_straight_u8(rng, (32, 32, 32))
    if mode == "extinction":
        vol = volsample.to_extinction_fx(vol)
    cam = volsample.Camera.looking_down_z(vol.shape)
    size = 128 if mode == "opacity_weighted" else 256  # about 0.4 s each here
    took, ticks = gil_free_ticks(
        lambda: volsample.render_int(vol, cam, size, size, mode=mode, step=0.05))
    assert took > 0.05, "render too short to tell"
    assert ticks >= 5, (ticks, took)


def test_bad_input():
    v = np.zeros((2, 2, 2, 4), np.uint8)
    cam = volsample.Camera.looking_down_z(v.shape)
    with pytest.raises(ValueError, match="threshold"):
        volsample.render_int(v, cam, 2, 2, a_stop=0)
    with pytest.raises(ValueError, match="threshold"):
        volsample.render_int(v, cam, 2, 2, a_stop=70000)
    with pytest.raises(ValueError, match="threshold"):
        volsample.render_int(v, cam, 2, 2, a_stop=-1)
    with pytest.raises(ValueError, match="zero width or height"):
        volsample.render_int(v, cam, 2, 0, threads=2)
    with pytest.raises(ValueError, match="filters 'nearest' and 'trilinear'"):
        volsample.render_int(v, cam, 2, 2, filter="bspline")
    with pytest.raises(ValueError, match="frac_bits"):
        volsample.render_int(v, cam, 2, 2, frac_bits=3)
    with pytest.raises(ValueError, match="to_extinction_fx"):
        volsample.render_int(v, cam, 2, 2, mode="extinction")
    with pytest.raises(ValueError, match="read uint8"):
        volsample.render_int(v.astype(np.float32), cam, 2, 2)
    with pytest.raises(ValueError, match="too many samples"):
        volsample.render_int(v, cam, 2, 2, step=1e-9)
    with pytest.raises(MemoryError):
        volsample.render_int(v, cam, 2 ** 40, 2 ** 30)
