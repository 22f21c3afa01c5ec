"""Rendering with a camera through the library's fast path."""


import numpy as np

import volsample
from conftest import gil_free_ticks, random_straight_u8
from tolerance import CORRECTION_ABS


def cube():
    v = np.zeros((4, 4, 4, 4), np.uint8)
    v[1:3, 1:3, 1:3] = 255
    return v


def test_opaque_core_as_in_the_core_doc():
    vol = cube()
    img = volsample.render(vol, volsample.Camera.looking_down_z(vol.shape), 4, 4, step=0.5)
    assert img.shape == (4, 4, 4) and img.dtype == np.float32
    assert img[1, 1, 3] > 0.99 and img[1, 1, 0] > 0.99  # through the core: white
    assert img[0, 0, 3] == 0.0  # through air at the corner


def test_orthographic_column_composites_its_samples(rng):
    # Looking down z with step 1 = d′: a pixel is the front-to-back "over" of the column's
    # samples at the voxel centres (no correction, trilinear reads the voxel itself).
    vol = random_straight_u8(rng, (5, 3, 4))
    img = volsample.render(vol, volsample.Camera.looking_down_z(vol.shape), 4, 3, step=1.0)
    s = vol.astype(np.float64) / 255
    for j in range(3):
        for i in range(4):
            c, a = np.zeros(3), 0.0
            for z in range(5):
                az = s[z, j, i, 3]
                c += (1 - a) * s[z, j, i, :3] * az
                a += (1 - a) * az
            assert np.abs(img[j, i, :3] - c).max() < 1e-5 and abs(img[j, i, 3] - a) < 1e-5


def test_threads_and_modes_give_the_same_image(rng):
    vol = random_straight_u8(rng, (16, 16, 16))
    cam = volsample.Camera.perspective([7.5, 7.5, -30.0], [7.5, 7.5, 7.5], [0, -1, 0], 0.6)
    one = volsample.render(vol, cam, 40, 30, threads=1)
    four = volsample.render(vol, cam, 40, 30, threads=4)
    assert one.tobytes() == four.tobytes()
    ext = volsample.to_extinction(vol)
    e = volsample.render(ext, cam, 40, 30, mode="extinction", filter="bspline")
    assert e.shape == (30, 40, 4) and np.isfinite(e).all()
    assert (e[..., :3] <= e[..., 3:] + 1e-6).all()


def test_the_gil_is_released(rng):
    # A second Python thread keeps running while a render is in the kernel.
    vol = random_straight_u8(rng, (32, 32, 32))
    cam = volsample.Camera.looking_down_z(vol.shape)
    took, ticks = gil_free_ticks(lambda: volsample.render(vol, cam, 128, 128, step=0.05))
    assert took > 0.05, "render too short to tell"
    assert ticks >= 5, (ticks, took)


def test_correct_opacity_formula(rng):
    a = rng.uniform(0, 1, 200)
    c = rng.uniform(0, 1, (200, 3)) * a[:, None]
    s = np.concatenate([c, a[:, None]], -1).astype(np.float32)
    for ratio in (0.25, 1.0, 3.0):
        got = volsample.correct_opacity(s, ratio)
        a64 = s[:, 3].astype(np.float64)
        ad = 1 - (1 - a64) ** ratio
        with np.errstate(invalid="ignore", divide="ignore"):
            cd = np.where(a64[:, None] > 0, s[:, :3] / a64[:, None], 0) * ad[:, None]
        assert np.abs(got[:, 3] - ad).max() <= CORRECTION_ABS * max(1, ratio)
        assert np.abs(got[:, :3] - cd).max() <= CORRECTION_ABS * max(1, ratio)
