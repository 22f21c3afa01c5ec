"""The OME-Zarr multiscale: written by volsample.dask.to_ome_zarr, read back by ome-zarr."""

import json
import os

import numpy as np
import pytest

da = pytest.importorskip("dask.array")
zarr = pytest.importorskip("zarr")

import volsample
import volsample.dask as vd
from conftest import random_straight_u8


@pytest.mark.parametrize("method", ["extinction", "opacity"])
def test_round_trip(tmp_path, rng, method):
    vol = random_straight_u8(rng, (20, 18, 26))
    levels = vd.pyramid(da.from_array(vol, chunks=(8, 8, 8, 4)), 2, method=method, filter=0.2,
                        reference_distance=0.5)
    path = str(tmp_path / "pyr.ome.zarr")
    vd.to_ome_zarr(levels, path, method=method, filter=0.2, reference_distance=0.5,
                   voxel_size=(2.0, 1.0, 1.0))
    with open(os.path.join(path, ".zattrs")) as f:
        attrs = json.load(f)
    ms = attrs["multiscales"][0]
    assert [ax["name"] for ax in ms["axes"]] == ["c", "z", "y", "x"]
    scales = [d["coordinateTransformations"][0]["scale"] for d in ms["datasets"]]
    assert scales == [[1, 2, 1, 1], [1, 4, 2, 2], [1, 8, 4, 4]]
    assert attrs["volsample"]["reference_distance"] == [0.5, 1.0, 2.0]
    assert attrs["volsample"]["method"] == method
    whole = volsample.pyramid(vol, 2, method=method, a=0.2, reference_distance=0.5)
    group = zarr.open_group(path, mode="r")
    for lvl, want in enumerate(whole):
        got = np.moveaxis(np.asarray(group[str(lvl)][...]), 0, -1)
        np.testing.assert_array_equal(got, want)


def test_readable_by_ome_zarr(tmp_path, rng):
    reader_mod = pytest.importorskip("ome_zarr.reader")
    from ome_zarr.io import parse_url

    vol = random_straight_u8(rng, (16, 16, 16))
    levels = vd.pyramid(da.from_array(vol, chunks=(8, 8, 8, 4)), 2)
    path = str(tmp_path / "pyr.ome.zarr")
    vd.to_ome_zarr(levels, path)
    nodes = list(reader_mod.Reader(parse_url(path))())
    assert nodes, "ome-zarr found no image"
    data = nodes[0].data
    assert len(data) == 3
    whole = volsample.pyramid(vol, 2)
    for lvl, arr in enumerate(data):
        np.testing.assert_array_equal(np.moveaxis(np.asarray(arr), 0, -1), whole[lvl])
    axes = nodes[0].metadata.get("axes")
    assert [a["name"] if isinstance(a, dict) else a for a in axes] == ["c", "z", "y", "x"]


def test_readable_by_ngff_zarr(tmp_path, rng):
    nz = pytest.importorskip("ngff_zarr")
    vol = random_straight_u8(rng, (20, 24, 28))
    levels = vd.pyramid(da.from_array(vol, chunks=(8, 8, 8, 4)), 2)
    path = str(tmp_path / "pyr.ome.zarr")
    vd.to_ome_zarr(levels, path, voxel_size=(2.0, 1.0, 1.0))
    ms = nz.from_ngff_zarr(path)
    assert len(ms.images) == 3
    assert [dict(im.scale) for im in ms.images] == [
        {"c": 1.0, "z": 2.0 * 2 ** l, "y": 2.0 ** l, "x": 2.0 ** l} for l in range(3)]
    whole = volsample.pyramid(vol, 2)
    for im, want in zip(ms.images, whole):
        assert tuple(im.dims) == ("c", "z", "y", "x")
        np.testing.assert_array_equal(np.moveaxis(np.asarray(im.data), 0, -1), want)


def test_int_round_trip(tmp_path, rng):
    fx = volsample.to_extinction_fx(random_straight_u8(rng, (20, 18, 26)))
    levels = vd.pyramid(da.from_array(fx, chunks=(8, 8, 8, 4)), 2, method="extinction_int")
    path = str(tmp_path / "pyr.ome.zarr")
    vd.to_ome_zarr(levels, path, method="extinction_int")
    with open(os.path.join(path, ".zattrs")) as f:
        attrs = json.load(f)
    assert attrs["volsample"]["method"] == "extinction_int"
    assert attrs["volsample"]["channels"][3].startswith("D ")
    group = zarr.open_group(path, mode="r")
    want = fx
    for lvl in range(3):
        got = np.moveaxis(np.asarray(group[str(lvl)][...]), 0, -1)
        assert got.dtype == np.uint32
        np.testing.assert_array_equal(got, want)
        want = volsample.downsample_level_int(want, "extinction")
