"""Many parameter values at once: serial, a process ensemble, or a Dask cluster.

The unit of work is a *point function*: a picklable callable ``f(value) -> dict``
of numpy arrays/scalars for one parameter value.  :func:`map_values` evaluates
it over a grid, in chunks of contiguous values:

- ``workers=1`` and no ``scheduler``: a plain loop in this process;
- ``workers=N``: a ``ProcessPoolExecutor`` whose initializer compiles the
  scene's integrator once per worker process;
- ``scheduler="tcp://host:port"`` or a ``dask.distributed.Client``: chunks go to
  the Dask workers; each worker process compiles once (integrators are cached
  per process in :mod:`maps.hybrid`) and is warmed up front with ``client.run``.

Results come back per chunk to ``on_chunk(start, results)`` (stream them to
disk) and, unless ``collect=False``, as one list in grid order.

:class:`StroboscopicTask` is the point function of a stroboscopic sweep
(transient relay periods, then recorded states at t = n / W and contact
onsets); :func:`sweep_dataset` runs it over a grid into one Dataset (or a
netCDF file written chunk by chunk); :func:`add_error_estimate` re-runs a
sample of values at a 100x tighter tolerance and stores the largest
differences on the dataset.
"""
from __future__ import annotations

import math
import os
import time as _time
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING

import numpy as np

from maps.hybrid import Escaped, HybridRun, IntegrationFailure
from maps.parameters import ParameterError
from maps.provenance import cf_attrs, recorded
from maps.scenes import get_scene

if TYPE_CHECKING:  # xarray is imported where used: worker processes start faster
    import xarray as xr

__all__ = ["StroboscopicTask", "BatchStroboscopicTask", "map_values", "sweep_dataset", "add_error_estimate", "chunks_of",
           "STATUS_MEANINGS"]

#: status codes of one parameter value
STATUS_MEANINGS = ("ok", "escaped", "failed")


@dataclass(frozen=True)
class StroboscopicTask:
    """Point function of a stroboscopic sweep over parameter ``param``.

    For each value: start from ``x0`` at t = 0 (flags at their defaults), integrate
    ``transient`` relay periods, then record the state at the end of each of the next
    ``record`` relay periods (t = n / relay_hz [s]) and every contact onset in that window
    (time [s] and gap rate [m/s]).  ``max_impacts`` caps the stored onsets (the count is kept).
    """

    scene: object                  # scene name or Scene (picklable)
    param: str
    params: dict                   # validated base parameter values
    x0: dict = field(default_factory=dict)
    transient: int = 300
    record: int = 100
    tol: float = 1e-10
    max_impacts: int | None = None

    @property
    def impact_capacity(self) -> int:
        return self.max_impacts if self.max_impacts is not None else 16 * self.record

    def warm(self):
        """Compile (once per process) and return the reusable run for this task."""
        key = (self.scene if isinstance(self.scene, str) else self.scene.name,
               get_scene(self.scene).options, self.tol)
        run = _RUNS.get(key)
        if run is None:
            sc = get_scene(self.scene)
            run = HybridRun(sc.system, self.params, self._y0(), tol=self.tol, record_events=False,
                            max_events=None)
            _RUNS[key] = run
        return run

    def _y0(self):
        sc = get_scene(self.scene)
        return sc.system.state_vector(sc.initial_state(**self.x0))

    def __call__(self, value) -> dict:
        run = self.warm()
        clock = _time.perf_counter()
        params = dict(self.params, **{self.param: float(value)})
        run.params = run.system.validate(params)
        run.reset(0.0, self._y0())
        run.record_events = False
        n_states = len(run.system.states)
        points = np.full((self.record, n_states), np.nan)
        cap = self.impact_capacity
        t_imp = np.full(cap, np.nan)
        v_imp = np.full(cap, np.nan)
        status, n_imp = 0, 0
        W = run.params["relay_hz"]
        try:
            run.advance(self.transient / W)
            run.record_events = True
            for n in range(self.record):
                run.advance((self.transient + n + 1) / W)
                points[n] = run.ta.state
        except Escaped:
            status = 1
        except IntegrationFailure:
            status = 2
        gap = run.system.gap
        for ev in run.events:
            if ev.name == "contact":
                if n_imp < cap:
                    t_imp[n_imp] = ev.t
                    v_imp[n_imp] = gap(ev.y_minus, run.params)[1]
                n_imp += 1
        run.events = []
        return {"points": points, "impact_time": t_imp, "impact_velocity": v_imp,
                "n_impacts": n_imp, "status": status, "n_steps": run.n_steps,
                "n_events": run.n_events, "n_switches": run.n_switches,
                "seconds": _time.perf_counter() - clock, "pid": os.getpid()}


_RUNS: dict = {}


def _warm(task):
    """Process initializer: compile the task's integrator once in this process."""
    if task is not None and hasattr(task, "warm"):
        task.warm()
    return os.getpid()


def _run_chunk(task, values):
    if hasattr(task, "run_many"):
        return task.run_many(values)
    return [task(v) for v in values]


@dataclass(frozen=True)
class BatchStroboscopicTask(StroboscopicTask):
    """:class:`StroboscopicTask` on heyoka's batch integrator (:mod:`bifurc.batch`).

    ``batch_size`` SIMD lanes, each with its own parameter values, relay switch instants,
    flags and event handling; a lane is refilled as soon as its value is done.  Results
    equal the scalar path up to round-off (SIMD arithmetic, switch instants located as
    events, and by default no stops at observation-only guards such as the free-flight
    minimum), amplified by the dynamics over long horizons.
    """

    batch_size: int = 4
    observations: bool = False      # also stop at observation-only guards (free-flight minimum, ...)

    def _engine(self):
        from .batch import engine_for
        return engine_for(get_scene(self.scene).system, self.tol, self.batch_size, self.observations)

    def warm(self):
        return self._engine()

    def __call__(self, value) -> dict:
        return self.run_many([value])[0]

    def run_many(self, values) -> list:
        from .batch import LaneJob
        eng = self._engine()
        system = eng.system
        y0 = self._y0()
        jobs = []
        for v in values:
            params = system.validate(dict(self.params, **{self.param: float(v)}))
            jobs.append(LaneJob(params, y0, system.initial_flags(0.0, params), transient=self.transient,
                                record=self.record, log=True))
        out = []
        cap, n_states = self.impact_capacity, len(system.states)
        for job, r in zip(jobs, eng.run(jobs)):
            points = np.full((self.record, n_states), np.nan)
            ends = r.points[1:]
            if ends:
                points[:len(ends)] = ends
            t_imp, v_imp = np.full(cap, np.nan), np.full(cap, np.nan)
            onsets = [(t, y) for period in r.period_events + [r.tail_events] for name, t, y in period
                      if name == "contact"]
            for i, (t, y) in enumerate(onsets[:cap]):
                t_imp[i] = t
                v_imp[i] = system.gap(y, job.params)[1]
            out.append({"points": points, "impact_time": t_imp, "impact_velocity": v_imp,
                        "n_impacts": len(onsets), "status": STATUS_MEANINGS.index(r.status),
                        "n_steps": r.n_steps, "n_events": r.n_events, "n_switches": r.n_switches,
                        "seconds": r.seconds, "pid": os.getpid()})
        return out


def chunks_of(n: int, size: int):
    """``(start, stop)`` index ranges covering ``range(n)`` in pieces of ``size``."""
    return [(i, min(n, i + size)) for i in range(0, n, size)]


def _default_chunk(n, workers, multiple=1):
    size = max(1, min(64, math.ceil(n / (8 * max(1, workers)))))
    return math.ceil(size / multiple) * multiple


def map_values(func, values, workers: int = 1, scheduler=None, chunk_size: int | None = None,
               on_chunk=None, collect: bool = True, mp_context: str = "spawn"):
    """Evaluate ``func(value)`` for every value; returns the results in grid order.

    ``scheduler``: a Dask scheduler address or ``dask.distributed.Client`` (then ``workers``
    is ignored).  ``on_chunk(start, results)`` is called as each chunk completes (any order).
    ``mp_context``: start method of the process pool ("spawn" is safe with heyoka's threads).
    """
    values = np.asarray(values, dtype=float).ravel()
    n = values.size
    if workers < 1:
        raise ParameterError(f"workers = {workers}: need at least 1")
    out = [None] * n if collect else None

    def take(start, results):
        if on_chunk is not None:
            on_chunk(start, results)
        if collect:
            out[start:start + len(results)] = results

    if scheduler is not None:
        _map_dask(func, values, scheduler, chunk_size, take)
    elif workers == 1:
        size = chunk_size or max(1, n)
        for a, b in chunks_of(n, size):
            take(a, _run_chunk(func, values[a:b]))
    else:
        import multiprocessing as mp
        size = chunk_size or _default_chunk(n, workers, getattr(func, "batch_size", 1))
        with ProcessPoolExecutor(max_workers=workers, mp_context=mp.get_context(mp_context),
                                 initializer=_warm, initargs=(func,)) as pool:
            pending = chunks_of(n, size)[::-1]
            running = {}
            while pending or running:      # at most 2 chunks per worker in flight: bounded memory
                while pending and len(running) < 2 * workers:
                    a, b = pending.pop()
                    running[pool.submit(_run_chunk, func, values[a:b])] = a
                finished, _ = wait(running, return_when=FIRST_COMPLETED)
                for fut in finished:
                    take(running.pop(fut), fut.result())
    return out


def _map_dask(func, values, scheduler, chunk_size, take):
    from dask.distributed import Client, as_completed as dask_completed
    own = not isinstance(scheduler, Client)
    client = Client(scheduler) if own else scheduler
    try:
        n_workers = max(1, len(client.scheduler_info().get("workers", {})))
        client.run(_warm, func)                         # compile once per worker, up front
        size = chunk_size or _default_chunk(values.size, n_workers, getattr(func, "batch_size", 1))
        starts = [a for a, _ in chunks_of(values.size, size)]
        futures = client.map(_run_chunk, [func] * len(starts),
                             [values[a:b] for a, b in chunks_of(values.size, size)], pure=False)
        index = {f.key: a for f, a in zip(futures, starts)}
        for fut in dask_completed(futures):
            take(index[fut.key], fut.result())
            fut.release()
    finally:
        if own:
            client.close()


# ----- datasets ----------------------------------------------------------------------

def _skeleton(task: StroboscopicTask, values) -> xr.Dataset:
    import xarray as xr
    sc = get_scene(task.scene)
    system = sc.system
    unit = system.parameter(task.param).unit
    nv, nr, ni = len(values), task.record, task.impact_capacity
    ds = xr.Dataset(coords={
        task.param: (task.param, np.asarray(values, float),
                     {"units": unit, "long_name": system.parameter(task.param).long_name}),
        "period": ("period", np.arange(task.transient + 1, task.transient + nr + 1),
                   {"units": "1", "long_name": "relay period index n (state at t = n / relay_hz)"}),
        "impact": ("impact", np.arange(ni), {"units": "1", "long_name": "contact number in the recorded window"}),
    })
    for st in system.states:
        ds[st.name] = ((task.param, "period"), np.full((nv, nr), np.nan),
                       {"units": st.unit, "long_name": f"{st.long_name} at the end of each relay period"})
    ds["impact_time"] = ((task.param, "impact"), np.full((nv, ni), np.nan),
                         {"units": "s", "long_name": "contact onset time"})
    ds["impact_velocity"] = ((task.param, "impact"), np.full((nv, ni), np.nan),
                             {"units": "m s-1", "long_name": "gap rate at contact onset (negative: toward the stop)"})
    ds["n_impacts"] = (task.param, np.zeros(nv, np.int32),
                       {"units": "1", "long_name": "contacts in the recorded window (may exceed the impact dimension)"})
    ds["status"] = (task.param, np.zeros(nv, np.int8),
                    {"units": "1", "long_name": "integration status", "flag_values": np.arange(3, dtype=np.int8),
                     "flag_meanings": " ".join(STATUS_MEANINGS)})
    ds["n_steps"] = (task.param, np.zeros(nv, np.int64), {"units": "1", "long_name": "Taylor steps"})
    ds["run_seconds"] = (task.param, np.zeros(nv), {"units": "s", "long_name": "wall time of this value"})
    ds.attrs.update({"scene": sc.name, "swept_parameter": task.param, "transient_periods": task.transient,
                     "recorded_periods": task.record, "tol": task.tol,
                     **cf_attrs(f"scene {sc.name}, {task.param} sweep (stroboscopic states)")})
    for k, v in task.params.items():
        if k != task.param:
            ds.attrs[f"param_{k}"] = v
            ds.attrs[f"param_{k}_units"] = system.parameter(k).unit
    return ds


def _fill(arrays: dict, state_names, start, results):
    for j, r in enumerate(results):
        i = start + j
        for s, name in enumerate(state_names):
            arrays[name][i] = r["points"][:, s]
        arrays["impact_time"][i] = r["impact_time"]
        arrays["impact_velocity"][i] = r["impact_velocity"]
        for k in ("n_impacts", "status", "n_steps"):
            arrays[k][i] = r[k]
        arrays["run_seconds"][i] = r["seconds"]


def _create_file(path, template: xr.Dataset, dim: str, values):
    """An empty netCDF file shaped like ``template`` with ``len(values)`` along ``dim``
    (NaN/zero fill, compressed), open for writing chunk by chunk."""
    import netCDF4
    nc = netCDF4.Dataset(path, "w")
    for d, size in template.sizes.items():
        nc.createDimension(d, len(values) if d == dim else size)
    for name, var in template.variables.items():
        fill = np.nan if var.dtype.kind == "f" else None
        v = nc.createVariable(name, var.dtype, var.dims, fill_value=fill, zlib=var.ndim > 1, complevel=1)
        v.setncatts({k: val for k, val in var.attrs.items()})
        if name == dim:
            v[:] = values
        elif name in template.coords:
            v[:] = var.values
        elif fill is None:
            v[:] = np.zeros(tuple(len(values) if d == dim else template.sizes[d] for d in var.dims), var.dtype)
    nc.setncatts(dict(template.attrs))
    return nc


@recorded("bifurc.parallel.sweep_dataset")
def sweep_dataset(task: StroboscopicTask, values, workers: int = 1, scheduler=None,
                  chunk_size: int | None = None, path=None, progress=None, overwrite=False) -> xr.Dataset:
    """Run ``task`` over ``values`` and return one Dataset (dims: parameter, period, impact).

    With ``path`` the netCDF file is created first and each chunk is written into it as it
    completes (memory stays bounded by a chunk); the file is then opened lazily. An existing file
    is refused unless ``overwrite``.
    """
    import xarray as xr
    if path is not None:
        from .files import refuse_existing
        refuse_existing(path, overwrite)
    values = np.asarray(values, dtype=float).ravel()
    ds = _skeleton(task, values if path is None else values[:1])   # on disk: metadata only
    names = list(get_scene(task.scene).system.state_names)
    fields = names + ["impact_time", "impact_velocity", "n_impacts", "status", "n_steps", "run_seconds"]
    t0 = _time.perf_counter()
    if path is None:
        arrays = {k: ds[k].values for k in fields}

        def on_chunk(start, results):
            _fill(arrays, names, start, results)
            if progress:
                progress(len(results))
    else:
        nc = _create_file(path, ds, task.param, values)

        def on_chunk(start, results):
            arrays = {k: np.empty((len(results),) + ds[k].shape[1:], ds[k].dtype) for k in fields}
            _fill(arrays, names, 0, results)
            for k in fields:
                nc.variables[k][start:start + len(results)] = arrays[k]
            nc.sync()
            if progress:
                progress(len(results))
    try:
        map_values(task, values, workers=workers, scheduler=scheduler, chunk_size=chunk_size,
                   on_chunk=on_chunk, collect=False)
    finally:
        if path is not None:
            nc.setncattr("wall_seconds", _time.perf_counter() - t0)
            nc.close()
    if path is not None:
        return xr.open_dataset(path)
    ds.attrs["wall_seconds"] = _time.perf_counter() - t0
    return ds


def add_error_estimate(ds: xr.Dataset, task: StroboscopicTask, sample: int = 5, factor: float = 100.0,
                       workers: int = 1, scheduler=None) -> xr.Dataset:
    """Re-run ``sample`` evenly spaced values at ``tol / factor`` and store the largest differences.

    Adds ``error_sample`` (the re-run values), ``map_point_error`` (largest absolute difference of
    the recorded states, per state, over the sample) and ``impact_time_error`` [s] (largest
    difference of contact onset times; NaN where a contact count differs) and the attribute
    ``error_estimate_tol``.  Differences are measured only where both runs are ``ok``.
    """
    import xarray as xr
    values = ds[task.param].values
    idx = np.unique(np.linspace(0, values.size - 1, min(sample, values.size)).round().astype(int))
    tight = replace(task, tol=task.tol / factor)
    t0 = _time.perf_counter()
    results = map_values(tight, values[idx], workers=workers, scheduler=scheduler)
    seconds = _time.perf_counter() - t0
    names = list(get_scene(task.scene).system.state_names)
    point_err = np.full((idx.size, len(names)), np.nan)
    time_err = np.full(idx.size, np.nan)
    count_mismatch = np.zeros(idx.size, np.int8)
    for j, (i, r) in enumerate(zip(idx, results)):
        if r["status"] != 0 or int(ds["status"].values[i]) != 0:
            continue
        for s, name in enumerate(names):
            point_err[j, s] = np.nanmax(np.abs(ds[name].values[i] - r["points"][:, s]))
        if int(ds["n_impacts"].values[i]) == r["n_impacts"]:
            a, b = ds["impact_time"].values[i], r["impact_time"]
            time_err[j] = float(np.nanmax(np.abs(a - b))) if r["n_impacts"] else 0.0
        else:
            count_mismatch[j] = 1
    out = ds.copy()
    dim = f"{task.param}_error_sample"
    out = out.assign_coords({dim: (dim, values[idx], {"units": ds[task.param].attrs.get("units", ""),
                                                      "long_name": "values re-run at a tighter tolerance"})})
    for s, name in enumerate(names):
        out[f"{name}_map_error"] = (dim, point_err[:, s], {
            "units": ds[name].attrs.get("units", ""),
            "long_name": f"largest |difference| of recorded {name} against tol/{factor:g}"})
    out["impact_time_error"] = (dim, time_err, {"units": "s", "long_name":
                                                f"largest contact onset time difference against tol/{factor:g} "
                                                "(NaN: count differs or run failed)"})
    out["impact_count_mismatch"] = (dim, count_mismatch, {
        "units": "1", "long_name": "contact count differs at the tighter tolerance",
        "flag_values": np.array([0, 1], np.int8), "flag_meanings": "same differs"})
    out.attrs.update({"error_estimate_tol": task.tol / factor, "error_estimate_seconds": seconds,
                      "error_estimate_max_impact_time_error": float(np.nanmax(time_err)) if np.isfinite(time_err).any()
                      else float("nan"),
                      "error_estimate_impact_count_mismatches": int(count_mismatch.sum())})
    for s, name in enumerate(names):
        col = point_err[:, s]
        out.attrs[f"error_estimate_max_{name}"] = float(np.nanmax(col)) if np.isfinite(col).any() else float("nan")
    return out
