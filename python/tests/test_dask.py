"""volsample.dask.pyramid: bit-identical to the whole-volume pyramid for any chunking."""

import numpy as np
import pytest

da = pytest.importorskip("dask.array")
import dask  # noqa: E402

import volsample
import volsample.dask as vd
from conftest import random_straight_u8

SHAPE = (21, 18, 27)  # odd and even sizes, none a multiple of 2^levels
LEVELS = 3
#: The chunkings the invariance test runs (z, y, x); the channel axis is never split.
CHUNKINGS = [
    (8, 8, 8),      # aligned to 2^3 already
    (5, 7, 11),     # odd sizes: rechunked up to multiples of 8
    (16, 18, 9),    # one chunk along y
    (21, 18, 27),   # one chunk in all
    (3, 4, 30),     # smaller than 2^levels
]


@pytest.fixture(scope="module")
def volumes():
    rng = np.random.default_rng(33)
    u8 = random_straight_u8(rng, SHAPE)
    f32 = u8.astype(np.float32) / np.float32(255)
    return {"uint8": u8, "float32": f32}


@pytest.mark.parametrize("chunks", CHUNKINGS, ids=lambda c: "x".join(map(str, c)))
@pytest.mark.parametrize("method,a", [("extinction", 0.25), ("extinction", 0.2),
                                      ("opacity", 0.125), ("opacity", 0.0)])
@pytest.mark.parametrize("dtype", ["uint8", "float32"])
def test_chunk_invariance_bit_identical(volumes, chunks, method, a, dtype):
    vol = volumes[dtype]
    whole = volsample.pyramid(vol, LEVELS, method=method, a=a)
    levels = vd.pyramid(da.from_array(vol, chunks=chunks + (4,)), LEVELS, method=method, filter=a)
    assert len(levels) == LEVELS + 1
    computed = dask.compute(*levels, scheduler="threads")
    for lvl, (got, want, g) in enumerate(zip(levels, whole, computed)):
        # Every chunk but the last a multiple of 2^(levels − ℓ) voxels; channels in one chunk.
        for c in got.chunks[:3]:
            assert all(x % 2 ** (LEVELS - lvl) == 0 for x in c[:-1]), got.chunks
        assert got.chunks[3] == (4,)
        assert g.dtype == np.float32 and g.shape == want.shape
        np.testing.assert_array_equal(g, want, err_msg=f"level {lvl}")
        assert g.tobytes() == want.tobytes()  # bit for bit, signed zeros included


def test_deeper_than_the_volume(volumes):
    vol = volumes["uint8"][:5, :3, :9]
    whole = volsample.pyramid(vol, 5)
    levels = vd.pyramid(da.from_array(vol, chunks=(2, 2, 4, 4)), 5)
    for got, want in zip(dask.compute(*levels), whole):
        np.testing.assert_array_equal(got, want)
    assert levels[-1].shape == (1, 1, 1, 4)


def test_bad_input_raises():
    x = da.zeros((8, 8, 8, 4), dtype=np.uint8, chunks=4)
    with pytest.raises(ValueError, match="levels"):
        vd.pyramid(x, -1)
    with pytest.raises(ValueError, match="filter"):
        vd.pyramid(x, 1, filter=0.7)
    with pytest.raises(ValueError, match="shape"):
        vd.pyramid(da.zeros((8, 8, 8, 3), dtype=np.uint8), 1)
    with pytest.raises(ValueError, match="uint8 or float32"):
        vd.pyramid(da.zeros((8, 8, 8, 4), dtype=np.float64), 1)
    with pytest.raises(ValueError, match="method"):
        vd.pyramid(x, 1, method="mean")
    # A bad voxel surfaces the core's message when computed.
    bad = np.zeros((4, 4, 4, 4), np.float32)
    bad[1, 2, 3, 3] = 1.5
    with pytest.raises(ValueError, match="out of range"):
        vd.pyramid(da.from_array(bad, chunks=2), 1)[1].compute()


def test_the_halo_matters(volumes):
    """The invariance test can fail: downsampling each chunk on its own (no halo, each chunk
    clamped at its own edges) differs from the whole volume at the chunk seams."""
    vol = volumes["float32"][:16, :16, :16]
    ext = volsample.to_extinction(vol)
    whole = volsample.downsample_level(ext, "extinction", 0.25)
    naive = da.from_array(ext, chunks=(8, 8, 8, 4)).map_blocks(
        lambda b: volsample.downsample_level(np.ascontiguousarray(b), "extinction", 0.25),
        chunks=((4, 4),) * 3 + ((4,),), dtype=np.float32).compute()
    assert not np.array_equal(naive, whole)
    # Away from the seams (coarse voxels 0-2 and 5-7 read no other chunk) they agree.
    inner = np.r_[0:3, 5:8]
    np.testing.assert_array_equal(naive[np.ix_(inner, inner, inner)],
                                  whole[np.ix_(inner, inner, inner)])


# --- the integer methods ---------------------------------------------------------------------

def whole_int(vol, levels, method, a):
    """The whole-volume integer pyramid: the input, then downsample_level_int level after level
    (what the core's build_chain_int computes)."""
    out = [vol]
    for _ in range(levels):
        out.append(volsample.downsample_level_int(out[-1], method, a=a))
    return out


@pytest.fixture(scope="module")
def int_volumes():
    rng = np.random.default_rng(34)
    straight = random_straight_u8(rng, SHAPE)
    assoc = np.minimum(straight, straight[..., 3:])  # associated bytes: C̃ ≤ α
    u88 = straight.astype(np.uint16) * 256 + rng.integers(0, 256, SHAPE + (4,), dtype=np.uint16)
    u88[..., 3] = np.minimum(u88[..., 3], 65280)
    u88 = np.minimum(u88, u88[..., 3:])
    fx = volsample.to_extinction_fx(straight)
    return {"uint8": assoc, "uint16": u88, "uint32": fx}


INT_CASES = [("opacity_int", "uint8", 0.2), ("opacity_int", "uint16", 0.125),
             ("extinction_int", "uint32", 0.25), ("extinction_int", "uint32", 0.2)]


@pytest.mark.parametrize("chunks", CHUNKINGS, ids=lambda c: "x".join(map(str, c)))
@pytest.mark.parametrize("method,dtype,a", INT_CASES)
def test_int_chunk_invariance_bit_identical(int_volumes, chunks, method, dtype, a):
    vol = int_volumes[dtype]
    whole = whole_int(vol, LEVELS, method.removesuffix("_int"), a)
    levels = vd.pyramid(da.from_array(vol, chunks=chunks + (4,)), LEVELS, method=method,
                        filter=a)
    assert len(levels) == LEVELS + 1
    computed = dask.compute(*levels, scheduler="threads")
    for lvl, (got, want, g) in enumerate(zip(levels, whole, computed)):
        for c in got.chunks[:3]:
            assert all(x % 2 ** (LEVELS - lvl) == 0 for x in c[:-1]), got.chunks
        assert got.dtype == vol.dtype and g.dtype == vol.dtype and g.shape == want.shape
        np.testing.assert_array_equal(g, want, err_msg=f"level {lvl}")
    assert computed[-1].any()  # not a trivially zero pyramid


def test_int_halo_matters(int_volumes):
    """Downsampling each chunk on its own (no halo) differs from the whole volume at the seams,
    so the invariance test above can fail."""
    fx = int_volumes["uint32"][:16, :16, :16]
    whole = volsample.downsample_level_int(fx, "extinction", 0.25)
    naive = da.from_array(fx, chunks=(8, 8, 8, 4)).map_blocks(
        lambda b: volsample.downsample_level_int(np.ascontiguousarray(b), "extinction", 0.25),
        chunks=((4, 4),) * 3 + ((4,),), dtype=np.uint32).compute()
    assert not np.array_equal(naive, whole)
    inner = np.r_[0:3, 5:8]
    np.testing.assert_array_equal(naive[np.ix_(inner, inner, inner)],
                                  whole[np.ix_(inner, inner, inner)])


def test_int_bad_input_raises():
    with pytest.raises(ValueError, match="'opacity_int' reads associated uint8 or U8.8 uint16"):
        vd.pyramid(da.zeros((8, 8, 8, 4), dtype=np.float32), 1, method="opacity_int")
    with pytest.raises(ValueError, match="to_extinction_fx"):
        vd.pyramid(da.zeros((8, 8, 8, 4), dtype=np.uint8), 1, method="extinction_int")
    with pytest.raises(ValueError, match="filter"):
        vd.pyramid(da.zeros((8, 8, 8, 4), dtype=np.uint32), 1, method="extinction_int",
                   filter=-0.1)
    with pytest.raises(ValueError, match="unknown method"):
        vd.pyramid(da.zeros((8, 8, 8, 4), dtype=np.uint8), 1, method="mean_int")
    # A bad voxel surfaces the core's message when computed.
    bad = np.zeros((4, 4, 4, 4), np.uint8)
    bad[1, 2, 3] = [9, 0, 0, 5]
    with pytest.raises(ValueError, match="color above its opacity"):
        vd.pyramid(da.from_array(bad, chunks=2), 1, method="opacity_int")[1].compute()
