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


def gil_free_ticks(call):
    """Runs ``call()`` while a second Python thread ticks every millisecond; returns the
    call's duration and the ticks taken during it (many only if the call released the GIL)."""
    import threading
    import time

    ticks = []
    done = threading.Event()

    def ticker():
        while not done.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.001)

    t = threading.Thread(target=ticker)
    t.start()
    t0 = time.perf_counter()
    try:
        call()
        t1 = time.perf_counter()
    finally:  # a call that raises must not leave the ticker running (pytest would hang)
        done.set()
        t.join()
    return t1 - t0, len([x for x in ticks if t0 < x < t1])
