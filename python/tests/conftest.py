import os
import sys

import numpy as np
import pytest

sys.path.insert(0, os.path.dirname(__file__))

SEED = int(os.environ.get("VOLSAMPLE_SEED", "33"))


@pytest.fixture
def rng():
    return np.random.default_rng(SEED)


def random_straight_u8(rng, shape):
    """Straight RGBA8 with a share of fully transparent and fully opaque voxels."""
    v = rng.integers(0, 256, shape + (4,), dtype=np.uint8)
    a = v[..., 3]
    a[rng.random(shape) < 0.2] = 0
    a[rng.random(shape) < 0.1] = 255
    return v
