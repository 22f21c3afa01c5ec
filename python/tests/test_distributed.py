"""The chunked pyramid on dask.distributed.LocalCluster with 2 workers."""

import numpy as np
import pytest

da = pytest.importorskip("dask.array")
distributed = pytest.importorskip("distributed")

import volsample
import volsample.dask as vd
from conftest import random_straight_u8


def test_local_cluster_two_workers(tmp_path):
    rng = np.random.default_rng(7)
    vol = random_straight_u8(rng, (40, 36, 44))
    whole = volsample.pyramid(vol, 3, method="extinction", a=0.25)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        assert len(client.scheduler_info()["workers"]) == 2
        levels = vd.pyramid(da.from_array(vol, chunks=(16, 16, 16, 4)), 3)
        got = client.compute(levels, sync=True)
        for g, w in zip(got, whole):
            np.testing.assert_array_equal(g, w)
        # Both workers took part.
        counts = client.run(lambda dask_worker: len(dask_worker.data))
        assert len(counts) == 2
        # And the OME-Zarr writer runs on the cluster too.
        path = str(tmp_path / "cluster.ome.zarr")
        vd.to_ome_zarr(levels, path)
    import zarr
    g = zarr.open_group(path, mode="r")
    np.testing.assert_array_equal(np.moveaxis(np.asarray(g["3"][...]), 0, -1), whole[3])
