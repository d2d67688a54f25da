"""The one grid driver: any per-point task over a list of parameter points, resumed and shown with progress.

A task is a picklable callable ``task(value)`` (``value``: a parameter value, or an index into the task's own list
of parameter points) with ``task.problem`` (to tell whether it can travel to worker processes),
``task.points_per_worker`` (its cost grain: the default workers keep at least this many points each),
``task.planned_periods`` (the progress bar's planned work per point) and optionally ``run_many`` and ``warm``
(:mod:`bifurc.run.executor`).  :func:`run_points` spreads the points over processes or Dask, streams each finished
chunk to the resume store (:class:`bifurc.run.parts.Parts`), shows progress (:mod:`bifurc.run.progress`) and turns
Ctrl-C into :class:`Interrupted` naming what was kept.  The diagram, the regime map and the census run on it.
"""
from __future__ import annotations

import time as _time
from contextlib import contextmanager

import numpy as np

from maps.parameters import validate_value

from ..labels.codes import Status
from .executor import default_workers, map_values
from .progress import progress_bar
from .settings import MODES


def run_points(job, values, mode, parts, workers, scheduler, chunk_size, progress, desc, pool=None, unit="values"):
    """Every point of the grid through ``job`` (a task called with each of ``values``: parameter values, or indices
    into its own list of points), resumed from and streamed to ``parts`` (:class:`bifurc.run.parts.Parts`, or None);
    independent points on ``pool`` (an open :class:`bifurc.run.executor.WorkerPool` warmed with ``job``, ``workers``
    processes) if given.

    Returns ({branch: [ValueResult per value]}, values resumed, wall seconds of this call,
    worker processes used (0: a Dask cluster's)); Ctrl-C raises :class:`Interrupted` naming what was
    kept (``unit``: what a point is, in that message).  The one grid driver: of :func:`bifurc.sweep`,
    :func:`bifurc.regime_map` (whose values are the flat indices of its cells) and :func:`bifurc.attractors` (whose
    values index its points)."""
    workers, chunk_size = execution(job, values.size, workers, scheduler, chunk_size)
    branches = MODES[mode]
    results = {b: [None] * values.size for b in branches}
    for (b, i), r in (parts.load() if parts else {}).items():
        results[b][i] = r
    resumed = sum(r is not None for b in branches for r in results[b])
    bar = progress_bar(values.size * len(branches) - resumed, job.planned_periods, progress, desc, unit)

    def keep(b, indices, chunk):
        with deferred_interrupt():   # a part saved and counted whole, or not at all
            if parts:
                parts.save(b, indices, chunk)
            for i, r in zip(indices, chunk):
                results[b][i] = r
        bar.done(chunk)

    clock = _time.perf_counter()
    try:
        if mode == "independent":
            _run_independent(job, values, results["independent"], keep, workers, scheduler, chunk_size, pool)
        else:
            _run_follow(job, values, results, keep)
    except KeyboardInterrupt:
        done = sum(r is not None for b in branches for r in results[b])
        if parts:       # a part saved by the collecting thread while the signal reached this one
            done = max(done, len(parts.load()))
        raise Interrupted(kept_message(parts, done, values.size * len(branches), unit)) from None
    finally:
        bar.close()
    return results, resumed, _time.perf_counter() - clock, workers


@contextmanager
def deferred_interrupt():
    """Ctrl-C (SIGINT) waits until the block ends, then acts as it would have: a KeyboardInterrupt
    inside xarray's netCDF writer leaves its global lock held and the next write waits for it forever.
    Only in the main thread (elsewhere: no change)."""
    import signal
    import threading
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    got = []
    old = signal.signal(signal.SIGINT, lambda *sig: got.append(sig))
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, old)
        if got and callable(old):
            old(*got[0])


def write_result(ds, path, parts) -> None:
    """Write a grid's Dataset to ``path`` (refused earlier unless overwrite: :func:`bifurc.storage.files.output_guard`)
    and remove its resume ``parts``, with Ctrl-C deferred so that both happen or neither."""
    from ..storage.files import write_netcdf
    with deferred_interrupt():
        write_netcdf(ds, path, overwrite=True)
        parts.remove()


class Interrupted(KeyboardInterrupt):
    """Ctrl-C or a kernel interrupt stopped a sweep; the message says what was kept."""


def kept_message(parts, done: int, total: int, unit: str = "values") -> str:
    """One line: what an interrupted grid kept (``done`` of ``total`` completed; ``parts``: its resume folder)."""
    if parts is None:
        return (f"interrupted after {done} of {total} {unit}; nothing kept (pass path= to keep completed {unit} "
                "on disk and resume)")
    if done == 0:
        return f"interrupted: nothing completed yet, nothing kept in {parts.dir}"
    return (f"interrupted: {done} of {total} {unit} kept in {parts.dir}; the same command (same arguments) "
            "resumes from them")


def travels(pb) -> bool:
    """True when the problem pickles, so worker processes can rebuild it (a scene by name, address
    or module-level builder; not a bare HybridSystem whose declaration holds closures)."""
    import pickle
    try:
        pickle.dumps(pb)
    except Exception:   # noqa: BLE001 - whatever pickle raises: it cannot travel
        return False
    return True


def execution(job, n_values, workers, scheduler, chunk_size):
    """(worker processes, values per task): 0 workers with a Dask ``scheduler`` (the cluster's);
    by default every available core (:func:`bifurc.run.executor.default_workers`), 1 for a problem
    that cannot travel to another process (a bare HybridSystem with closures: :func:`travels`).  In this process a task holds 8 batches of values."""
    if scheduler is not None:
        workers = 0
    elif workers is None:
        workers = default_workers(n_values, job.points_per_worker) if travels(job.problem) else 1
    else:
        workers = int(validate_value("workers", workers, 1, 1024))
    if chunk_size is None and workers == 1:
        chunk_size = 8 * job.batch_size if job.batch_size > 1 else 1
    if chunk_size is not None:
        chunk_size = int(validate_value("chunk_size", chunk_size, 1, 1e9))
    return workers, chunk_size


def _run_independent(job, values, results, keep, workers, scheduler, chunk_size, pool=None):
    """Every value not yet in ``results`` from the same start, on ``workers`` processes (``pool``: an
    open one) or a Dask cluster."""
    missing = [i for i in range(values.size) if results[i] is None]
    if not missing:
        return
    warm = None
    if workers > 1 or scheduler is not None:   # while the workers integrate
        import threading
        warm = threading.Thread(target=_warm_xarray, daemon=True)
        warm.start()
    map_values(job, values[missing], workers=max(1, workers), scheduler=scheduler, collect=False, chunk_size=chunk_size,
               on_chunk=lambda start, chunk: keep("independent", missing[start:start + len(chunk)], chunk), pool=pool)
    if warm is not None:
        warm.join()


def _run_follow(job, values, results, keep):
    """Up then down the grid, each value from the previous one's final state (after a failure: from x0)."""
    start = None
    for b, order in (("up", range(values.size)), ("down", range(values.size - 1, -1, -1))):
        for i in order:
            r = results[b][i]
            if r is None:
                r = job(values[i], start)
                keep(b, [i], [r])
            start = r.end_state if r.status == Status.OK else None


def _warm_xarray():
    """Import what building the Dataset needs (xarray probes its duck-array modules, dask among
    them: ~1.4 s) while the worker processes integrate, instead of after them."""
    import xarray as xr
    xr.Dataset({"a": ("d", np.zeros(1))})


