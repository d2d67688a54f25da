"""The attractor census on a Dask cluster (issue 47 section 5) is the census run here: a LocalCluster of two worker
processes gives the local run's dataset, every variable equal (the starts, the outcomes, the polished orbits and
their multipliers, the matching); its workers attribute says it ran on a cluster (0)."""
from __future__ import annotations

import numpy as np
import pytest

import bifurc
from test_attractors import BOX, OSC

VALUES = [1.25, 1.3, 1.35]
KW = dict(params=OSC, box=BOX, n_starts=12, seed=4, progress=False, link=False)


def _assert_identical(a, b):
    assert set(a.data_vars) == set(b.data_vars) and set(a.coords) == set(b.coords)
    for k in list(a.data_vars) + list(a.coords):
        x, y = a[k].values, b[k].values
        assert x.shape == y.shape, k
        if x.dtype.kind == "f":
            assert np.array_equal(x, y, equal_nan=True), k
        else:
            assert np.array_equal(x, y), k
        assert a[k].attrs == b[k].attrs, k


@pytest.fixture(scope="module")
def cluster():
    distributed = pytest.importorskip("dask.distributed")
    with distributed.LocalCluster(n_workers=2, processes=True, threads_per_worker=1, dashboard_address=None) as c:
        yield c


def test_a_census_on_a_local_cluster_is_the_local_census(cluster):
    from dask.distributed import Client
    local = bifurc.attractors("impact-oscillator", "Omega", VALUES, workers=1, **KW)
    with Client(cluster) as client:
        remote = bifurc.attractors("impact-oscillator", "Omega", VALUES, run=bifurc.Run(scheduler=client,
                                                                                        progress=False),
                                   **{k: v for k, v in KW.items() if k != "progress"})
    by_address = bifurc.attractors("impact-oscillator", "Omega", VALUES, scheduler=cluster.scheduler_address, **KW)
    assert local.attrs["workers"] == 1 and remote.attrs["workers"] == 0 == by_address.attrs["workers"]   # 0: a cluster
    assert int(np.sum(local.present.values[:, :-5])) >= 4       # both orbits at 1.3 at least: a census worth comparing
    assert np.isfinite(local.multiplier_abs.values).any()
    _assert_identical(local, remote)
    _assert_identical(local, by_address)
