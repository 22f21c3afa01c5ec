"""Bad input raises ValueError with the core's message."""

import numpy as np
import pytest

import volsample

POS = np.zeros((1, 3), np.float32)


def test_bad_shapes_and_dtypes():
    with pytest.raises(ValueError, match=r"\(z, y, x, 4\)"):
        volsample.sample(np.zeros((2, 2, 2, 3), np.uint8), POS)
    with pytest.raises(ValueError, match="uint8 or float32"):
        volsample.sample(np.zeros((2, 2, 2, 4), np.float64), POS)
    with pytest.raises(ValueError, match=r"\(n, 3\)"):
        volsample.sample(np.zeros((2, 2, 2, 4), np.uint8), np.zeros((2, 2), np.float32))


def test_names_are_checked():
    v = np.zeros((2, 2, 2, 4), np.uint8)
    with pytest.raises(ValueError, match="unknown mode"):
        volsample.sample(v, POS, mode="mean")
    with pytest.raises(ValueError, match="unknown filter"):
        volsample.sample(v, POS, filter="cubic")
    with pytest.raises(ValueError, match="unknown method"):
        volsample.pyramid(v, 1, method="mean")
    with pytest.raises(ValueError, match="frac_bits"):
        volsample.sample_int(v, POS, frac_bits=13)


def test_core_messages():
    v = np.zeros((2, 2, 2, 4), np.float32)
    v[0, 1, 1, 3] = 2.0
    with pytest.raises(ValueError, match="out of range") as e:
        volsample.sample(v, POS)
    assert "voxel" in str(e.value)
    v = np.zeros((2, 2, 2, 4), np.float32)
    v[0, 0, 0] = [0.5, 0, 0, 0.25]
    with pytest.raises(ValueError, match="color above its opacity"):
        volsample.sample(v, POS, mode="preweighted")
    v[0, 0, 0] = [np.nan, 0, 0, 0.25]
    with pytest.raises(ValueError, match="finite"):
        volsample.sample(v, POS)
    with pytest.raises(ValueError, match="step"):
        volsample.sample(np.zeros((2, 2, 2, 4), np.uint8), POS, step=0.0)
    with pytest.raises(ValueError, match="filter"):
        volsample.downsample_level(np.zeros((2, 2, 2, 4), np.float32), a=0.6)
    with pytest.raises(ValueError, match="reference distance"):
        volsample.to_extinction(np.zeros((2, 2, 2, 4), np.uint8), -1.0)
    with pytest.raises(ValueError):
        volsample.sample(np.zeros((0, 2, 2, 4), np.uint8), POS)
    with pytest.raises(ValueError, match="camera"):
        volsample.Camera.perspective([0, 0, 0], [0, 0, 0], [0, 1, 0], 1.0)
    with pytest.raises(ValueError, match="ratio"):
        volsample.correct_opacity(np.zeros((1, 4), np.float32), 0.0)
    with pytest.raises(ValueError, match="not a valid associated sample"):
        volsample.correct_opacity(np.array([[0.5, 0, 0, 0.25]], np.float32), 2.0)


def test_images_that_cannot_be_made():
    v = np.zeros((2, 2, 2, 4), np.uint8)
    cam = volsample.Camera.looking_down_z(v.shape)
    # A zero width split into row bands (it panicked in the band split).
    with pytest.raises(ValueError, match="zero width or height"):
        volsample.render(v, cam, 0, 4, threads=2)
    # Too many pixels to allocate: an exception, not an abort.
    with pytest.raises(MemoryError):
        volsample.render(v, cam, 2 ** 40, 2 ** 30)
    with pytest.raises(MemoryError):
        volsample.render(v, cam, 2 ** 31, 2 ** 31)
