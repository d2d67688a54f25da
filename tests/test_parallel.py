"""Process ensemble, Dask and chunked streaming give the serial sweep; the error estimate."""
from dataclasses import replace

import numpy as np
import pytest

import maps
from bifurc.parallel import BatchStroboscopicTask, StroboscopicTask, add_error_estimate, sweep_dataset

STATES = ("x", "v", "i", "z")


@pytest.fixture(scope="module")
def task():
    sc = maps.get_scene("thesis-1dof")
    p = sc.parameters(preset="matlab-listing", V=90.0)
    return StroboscopicTask("thesis-1dof", "relay_hz", p, transient=20, record=6, tol=1e-10)


VALUES = np.linspace(2.0, 10.0, 10)


@pytest.fixture(scope="module")
def serial(task):
    return sweep_dataset(task, VALUES)


def _assert_same(a, b, tol=1e-12):
    for k in STATES + ("impact_time", "impact_velocity"):
        da, db = a[k].values, b[k].values
        assert np.array_equal(np.isnan(da), np.isnan(db)), k
        assert np.nanmax(np.abs(da - db) / np.maximum(1, np.abs(da))) <= tol, k
    assert np.array_equal(a["n_impacts"].values, b["n_impacts"].values)
    assert np.array_equal(a["status"].values, b["status"].values)


def test_recorded_points_are_the_state_at_whole_relay_periods(task, serial):
    """Independent path: a fresh run_scene to t = n / W gives the recorded map point."""
    for j in (0, 7):
        W = VALUES[j]
        for n in (0, 5):
            period = task.transient + n + 1
            run = maps.run_scene("thesis-1dof", period / W, params=dict(task.params, relay_hz=W), tol=task.tol)
            got = np.array([serial[s].values[j, n] for s in STATES])
            assert np.max(np.abs(got - run.y) / np.maximum(1, abs(run.y))) < 1e-12
            assert serial["period"].values[n] == period


def test_impacts_lie_in_the_recorded_window(task, serial):
    W = serial["relay_hz"].values[:, None]
    t = serial["impact_time"].values
    ok = np.isfinite(t)
    lo = np.broadcast_to(task.transient / W, t.shape)
    hi = np.broadcast_to((task.transient + task.record) / W, t.shape)
    assert np.all((t[ok] >= lo[ok]) & (t[ok] <= hi[ok]))
    assert np.all(serial["impact_velocity"].values[ok] < 0)
    assert np.array_equal(ok.sum(axis=1), np.minimum(serial["n_impacts"].values, t.shape[1]))


def test_process_ensemble_equals_serial(task, serial):
    par = sweep_dataset(task, VALUES, workers=2, chunk_size=2)
    _assert_same(serial, par)


def test_streamed_file_equals_in_memory(task, serial, tmp_path):
    streamed = sweep_dataset(task, VALUES, workers=2, chunk_size=3, path=tmp_path / "sweep.nc")
    _assert_same(serial, streamed)
    assert streamed["x"].attrs["units"] == "m" and streamed["status"].attrs["flag_meanings"] == "ok escaped failed"
    assert streamed.attrs["Conventions"] == "CF-1.10" and "bifurc" in streamed.attrs["source"]
    with pytest.raises(FileExistsError, match="overwrite=True"):  # refused before any work
        sweep_dataset(task, VALUES, path=tmp_path / "sweep.nc")


@pytest.fixture(scope="module")
def cluster():
    distributed = pytest.importorskip("dask.distributed")
    with distributed.LocalCluster(n_workers=2, processes=True, threads_per_worker=1,
                                  dashboard_address=None) as c:
        yield c


def test_dask_local_cluster_equals_serial(task, serial, cluster):
    from dask.distributed import Client
    with Client(cluster) as client:
        a = sweep_dataset(task, VALUES, scheduler=client, chunk_size=3)
    b = sweep_dataset(task, VALUES, scheduler=cluster.scheduler_address)
    _assert_same(serial, a)
    _assert_same(serial, b)


def test_sweep_on_processes_and_dask_equals_serial(cluster):
    """bifurc.sweep (orbits, classes, Lyapunov, error estimate) through map_values."""
    from bifurc.sweep import sweep
    kw = dict(preset="matlab-listing", params={"V": 90.0}, transient=15, record=8, progress=False,
              grazing=False, error_sample=0)
    values = np.linspace(2.0, 10.0, 6)
    a = sweep("thesis-1dof", "relay_hz", values, **kw)
    b = sweep("thesis-1dof", "relay_hz", values, workers=2, **kw)
    c = sweep("thesis-1dof", "relay_hz", values, scheduler=cluster.scheduler_address, **kw)
    for other in (b, c):
        for k in a.data_vars:
            if k == "run_seconds":
                continue
            x, y = a[k].values, other[k].values
            if x.dtype.kind == "f":
                fin = np.isfinite(x)
                assert np.array_equal(fin, np.isfinite(y)) and np.array_equal(x[~fin], y[~fin], equal_nan=True), k
                assert np.max(np.abs(x[fin] - y[fin]), initial=0.0) <= 1e-12 * max(1.0, np.max(np.abs(x[fin]), initial=0.0)), k
            else:
                assert np.array_equal(x, y), k


def test_error_estimate(task, serial):
    # same tolerance: the re-run is deterministic, every difference is exactly zero
    same = add_error_estimate(serial, task, sample=3, factor=1.0)
    assert same.attrs["error_estimate_max_x"] == 0.0
    assert same.attrs["error_estimate_max_impact_time_error"] == 0.0
    # 100x tighter: differences are finite, nonzero and stored with units
    est = add_error_estimate(serial, task, sample=3)
    assert est.attrs["error_estimate_tol"] == pytest.approx(task.tol / 100)
    assert est["x_map_error"].attrs["units"] == "m" and est.sizes["relay_hz_error_sample"] == 3
    assert 0 < est.attrs["error_estimate_max_x"] < 1e-2
    # a short horizon stays close to the tolerance (before sensitivity amplifies differences)
    short = replace(task, transient=1, record=2)
    ds = sweep_dataset(short, VALUES[:3])
    est = add_error_estimate(ds, short, sample=3)
    assert est.attrs["error_estimate_max_x"] < 10 * task.tol


def test_batch_mode_equals_scalar_to_the_tolerance(task):
    """SIMD lanes with their own relay frequencies, switches and events; 10 values = 3 batches."""
    short = replace(task, transient=2, record=3)
    batch = BatchStroboscopicTask(**{f: getattr(short, f) for f in short.__dataclass_fields__})
    a = sweep_dataset(short, VALUES)
    b = sweep_dataset(batch, VALUES)
    assert np.array_equal(a["n_impacts"].values, b["n_impacts"].values) and a["n_impacts"].values.sum() > 0
    assert np.array_equal(a["status"].values, b["status"].values)
    for k in STATES:
        scale = np.maximum(1, np.abs(a[k].values))
        # the two paths take different steps (no stops at observation guards in batch mode):
        # they differ by the integration error, a few tol over these 5 periods
        assert np.max(np.abs(a[k].values - b[k].values) / scale) < 100 * task.tol, k
    assert np.nanmax(np.abs(a["impact_time"].values - b["impact_time"].values)) < 100 * task.tol
    # steps: the same trajectories need nearly the same number of Taylor steps
    assert np.all(np.abs(b["n_steps"].values / a["n_steps"].values - 1) < 0.05)
    # batch mode in a process pool gives the in-process batch result bit for bit
    c = sweep_dataset(batch, VALUES, workers=2, chunk_size=4)
    _assert_same(b, c, tol=0.0)
