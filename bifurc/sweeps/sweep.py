"""One-parameter sweeps: stroboscopic orbits, classification and grazing per value.

``mode="independent"``: every value starts from the same initial state (values
run in parallel: ``workers`` processes, by default every available core, or a Dask
``scheduler``).  ``mode="follow"``: each value starts from the previous value's final
state, swept up then down (dimension ``branch``), to reveal coexisting attractors and
hysteresis ("continuation" is a deprecated alias).

With ``path`` every completed chunk of values is saved at once under ``<path>.parts/``
(:mod:`bifurc.sweeps.resume`); an interrupted sweep loses nothing and a rerun with the same
arguments resumes.  The final Dataset is written atomically and the parts are removed.

The tail after the grid (grazing bisections, error estimate) runs on the sweep's worker
processes, still open and warm, while this process builds the Dataset (independent mode on a
process pool; here otherwise).

The pieces: :mod:`bifurc.sweeps.job` (one value), :mod:`bifurc.sweeps.executor` (many values),
:mod:`bifurc.sweeps.grazing`, :mod:`bifurc.sweeps.errors`, :mod:`bifurc.sweeps.dataset`.
"""
from __future__ import annotations

import sys
import time as _time
import warnings
from contextlib import contextmanager, nullcontext

import numpy as np

from maps.hybrid import validate_tol
from maps.parameters import ParameterError, validate_value
from maps.problem import problem
from maps.provenance import recorded

from ..codes import Status
from .errors import ErrorEstimate
from .executor import WorkerPool, default_workers, map_values, result_of, submit_all
from ..storage.files import guarded_output, write_netcdf
from .grazing import GRAZING_GAP, GRAZING_SPEED, bracket_cost, grazing_brackets, locate_bracket
from .anytime import BUDGET
from .job import ValueJob
from .lyapunov import METHODS
from .resume import Parts, manifest

__all__ = ["sweep", "Interrupted", "MODES", "GRAZING_GAP", "GRAZING_SPEED"]

#: sweep modes and their branches
MODES = {"independent": ("independent",), "follow": ("up", "down")}


@recorded("bifurc.sweep")
@guarded_output("path")
def sweep(scene="thesis-1dof", param="relay_hz", values=None, *, mode="independent", transient=300,
          record=100, max_record=None, preset=None, params=None, x0=None, tol=1e-10, max_period=100, rtol=1e-6,
          atol=1e-9, lyapunov=True, lyapunov_method="tangent", grazing=True, grazing_xtol=None, circuit=None,
          ac_sign=None, dc_law=None, soil=None, compaction=None, path=None,
          progress=True, workers=None, scheduler=None, error_sample=3, max_transient=None, batch_size=4,
          chunk_size=None, overwrite=False, budget=None, time_budget=None):
    """Sweep ``param`` over ``values``; returns an xarray Dataset (see bifurc.sweeps.dataset).

    Parameters
    ----------
    scene : a scene name, Scene, HybridSystem or :class:`maps.Problem` (what is integrated).
    preset, params, x0, circuit, ac_sign, dc_law, soil, compaction : as in :func:`maps.problem`
        (not with a Problem, except ``params`` and ``x0``).
    param : str
        Parameter name to sweep (docs/model.md section 6), e.g. "relay_hz", "V", "k".
    values : array
        The grid (ascending for follow mode).
    mode : "independent" or "follow" ("continuation": deprecated alias of "follow").
    transient, record : int
        Relay periods discarded, then recorded, per value.
    max_record : int
        A first record holding fewer than three forcing periods q (q <= max_period) is extended to
        3 q, at most ``max_record`` (default 3 x record); the stored samples are its first ``record``.
    budget : int
        Relay periods per value, transient included, an undecided value may be extended to (anytime
        classification, :mod:`bifurc.sweeps.anytime`; default 6000; ``max_transient`` raises it).
    time_budget : float
        Wall-clock seconds for the whole sweep (default None: no limit).  When they are spent no value
        is extended further: values still undecided are not-converged with that reason (a value's first
        transient and record always run).  The only option whose result depends on the machine.
    tol : float
        heyoka tolerance; ``error_sample`` values are re-run at tol/100 for the error estimate.
    max_period, rtol, atol : classification (bifurc.sweeps.classify): periods are multiples of the
        forcing period q up to ``max_period`` relay periods (default 100), two in the window.
    lyapunov : bool
        Compute the largest Lyapunov exponent where the orbit is not periodic.
    lyapunov_method : "tangent" (default) or "companion" (:data:`bifurc.sweeps.lyapunov.METHODS`).
    grazing : bool
        Locate grazing values where neighbours change between impacting and not, to ``grazing_xtol``.
    path : str
        netCDF output; completed values are kept in ``<path>.parts/`` for resuming.  An existing
        file is refused unless ``overwrite``; a second sweep into the same path at once is refused
        (``<path>.lock``, POSIX only; see :mod:`bifurc.storage.files`).
    workers : int
        Worker processes (default: every core, 16 values per worker at least; a problem that does not
        pickle runs here).
    scheduler : Dask scheduler address or Client (then ``workers`` is ignored).
    batch_size : int
        Values integrated together in heyoka's batch mode (SIMD lanes); 1: one value at a
        time.  Results agree to round-off, amplified by chaotic dynamics.
    chunk_size : int
        Values per task (default 8 x batch_size here, automatic on workers); with ``path``, an
        interruption loses at most the chunks in flight.
    """
    mode = _mode(mode)
    values = _grid(values, "values")
    job = _job(scene, param, values, transient, record, preset, params, x0, tol, max_period, rtol, atol,
               lyapunov, circuit, ac_sign, dc_law, max_transient, batch_size, max_record, soil, compaction,
               lyapunov_method, budget)
    job = with_time_budget(job, time_budget)
    parts = Parts(path, manifest(job, values, mode)) if path else None
    workers, chunk_size = _execution(job, values.size, workers, scheduler, chunk_size)
    pool = WorkerPool(job, workers) if mode == "independent" and workers > 1 else None
    with pool or nullcontext():     # open through the tail: its workers are warm
        results, resumed, seconds, workers = run_values(job, values, mode, parts, workers, scheduler, chunk_size,
                                                        progress, f"{job.problem.name} {param}", pool=pool)
        try:
            warm = pool if resumed < values.size else None   # every value resumed: no worker started, the tail runs here
            tail = _start_tail(results, values, job, MODES[mode][0], grazing, grazing_xtol, error_sample, warm)
            from . import dataset as storage  # xarray: imported where the Dataset is built (worker processes start faster)
            ds = storage.to_dataset(results, values, job, mode)
            run_stats(ds, job, seconds, resumed, workers)
            found, estimate = tail()
        except KeyboardInterrupt:   # every value done: the grazing bisections or the error estimate were running
            n = values.size * len(MODES[mode])
            raise Interrupted(kept_message(parts, n, n) + " (grazing and error estimate: run again)") from None
    return _finish(ds, found if grazing else None, estimate if error_sample else None, path, parts)


def _finish(ds, found, estimate, path, parts):
    """The sweep's Dataset with its located grazings and error estimate (None: not computed), written to
    ``path`` (the resume parts then removed)."""
    from . import dataset as storage
    if found is not None:
        ds = storage.add_grazing(ds, found)
    if estimate is not None:
        ds = storage.add_error_estimate(ds, **estimate)
    if path:
        with deferred_interrupt():
            write_netcdf(ds, path, overwrite=True)  # refused earlier unless overwrite (guarded_output)
            parts.remove()
    return ds


def _start_tail(results, values, job, branch, grazing, xtol, error_sample, pool):
    """Start the grazing bisections (if ``grazing``, to ``xtol``) and the error estimate's
    integrations (``error_sample`` values, 0: none) together, the longest first, on
    ``pool``'s workers (None: here, now).  Returns a function that waits for them and gives
    (located grazes for :func:`bifurc.sweeps.dataset.add_grazing`, keywords of
    :func:`bifurc.sweeps.dataset.add_error_estimate` or None)."""
    brackets = grazing_brackets(results, values, xtol) if grazing else []
    est = ErrorEstimate(results, values, job, branch, error_sample) if error_sample else None
    tasks = [(bracket_cost(job, br), locate_bracket, (job, br)) for br in brackets] + (est.tasks if est else [])
    futures = submit_all(tasks, pool)

    def finish():
        located = [(br.branch, result_of(f)) for br, f in zip(brackets, futures)]
        return ([(b, g) for b, g in located if g is not None],
                est.result(futures[len(brackets):]) if est else None)
    return finish


def run_values(job, values, mode, parts, workers, scheduler, chunk_size, progress, desc, pool=None, unit="values"):
    """Every value of the grid through ``job``, resumed from and streamed to ``parts``
    (:class:`bifurc.sweeps.resume.Parts`, or None); independent values on ``pool`` (an open
    :class:`bifurc.sweeps.executor.WorkerPool` warmed with ``job``, ``workers`` processes) if given.

    Returns ({branch: [ValueResult per value]}, values resumed, wall seconds of this call,
    worker processes used (0: a Dask cluster's)); Ctrl-C raises :class:`Interrupted` naming what was
    kept (``unit``: what a value is, in that message).  The grid driver of :func:`sweep` and
    :func:`bifurc.sweeps.regime.regime_map` (whose values are the flat indices of its cells)."""
    workers, chunk_size = _execution(job, values.size, workers, scheduler, chunk_size)
    branches = MODES[mode]
    results = {b: [None] * values.size for b in branches}
    for (b, i), r in (parts.load() if parts else {}).items():
        results[b][i] = r
    resumed = sum(r is not None for b in branches for r in results[b])
    bar = _progress(values.size * len(branches) - resumed, job.transient + job.record, progress, desc, unit)

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


def run_stats(ds, job, seconds, resumed, workers) -> None:
    """Record how a grid ran in ``ds.attrs``: wall time of this call, computation time of every
    value (resumed ones included), values resumed, workers, SIMD lanes, this process's compile time."""
    ds.attrs["sweep_seconds"] = seconds     # wall time of this call's integrations
    ds.attrs["values_seconds"] = float(np.nansum(ds.run_seconds.values))  # resumed values included
    ds.attrs["resumed_values"] = resumed
    ds.attrs["workers"] = workers           # worker processes (0: a Dask cluster's)
    ds.attrs["batch_size"] = job.batch_size  # SIMD lanes (1: one value at a time); results agree to round-off
    ds.attrs["compile_seconds"] = job.warm().compile_seconds  # this process's scalar compile (workers compile their own)


def _grid(values, name: str) -> np.ndarray:
    """A 1-D array of numbers, or one line naming ``name`` (no silent flattening of a 2-D grid)."""
    try:
        if isinstance(values, str) or any(isinstance(v, (str, bytes)) for v in np.ravel(np.asarray(values, object))):
            raise ValueError("text")
        out = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise ParameterError(f"{name} must be numbers (a 1-D array or list), got {values!r:.60}") from None
    if out.ndim > 1:
        raise ParameterError(f"{name} must be a 1-D array of numbers, got shape {out.shape}")
    return out.ravel()


def _whole(name: str, value, low, high) -> int:
    """A whole number of periods in [low, high], or one line naming ``name`` (10.5 is refused, not truncated)."""
    v = validate_value(name, value, low, high)
    if v != int(v):
        raise ParameterError(f"{name} = {value!r}: a whole number of periods is needed")
    return int(v)


def _mode(mode: str) -> str:
    """The sweep mode, checked ("continuation": the deprecated name of "follow")."""
    if mode == "continuation":
        warnings.warn('sweep mode "continuation" is now called "follow"', DeprecationWarning, stacklevel=3)
        mode = "follow"
    if mode not in MODES:
        raise ParameterError(f"mode {mode!r}; allowed: {', '.join(MODES)}")
    return mode


def _job(scene, param, values, transient, record, preset, params, x0, tol, max_period, rtol, atol, lyapunov,
         circuit, ac_sign, dc_law, max_transient, batch_size, max_record=None, soil=None, compaction=None,
         lyapunov_method="tangent", budget=None):
    """The ValueJob of a sweep, every argument checked before anything runs (``scene``: a scene or a
    :class:`maps.Problem`; the other model keywords as :func:`maps.problem`)."""
    tol = validate_tol(tol)
    if values.size == 0 or not np.all(np.isfinite(values)):
        raise ParameterError("values must be a non-empty array of finite numbers")
    pb = problem(scene, preset, params, x0, circuit=circuit, ac_sign=ac_sign, dc_law=dc_law, soil=soil,
                 compaction=compaction)
    pb.system.parameter(param)  # raises for an unknown name
    for v in values:  # every value must be valid before anything runs
        pb.with_values(**{param: v})
    transient = _whole("transient", transient, 0, 1e7)
    record = _whole("record", record, 3, 1e7)
    if max_record is not None:
        max_record = int(validate_value("max_record", max_record, record, 1e7))
    if max_transient is not None:
        max_transient = int(validate_value("max_transient", max_transient, transient, 1e8))
    batch_size = int(validate_value("batch_size", batch_size, 1, 64))
    if lyapunov_method not in METHODS:
        raise ParameterError(f"lyapunov_method {lyapunov_method!r}; allowed: {', '.join(METHODS)}")
    budget = BUDGET if budget is None else int(validate_value("budget", budget, transient + record, 1e9))
    return ValueJob(pb, param, transient, record, float(tol), max_period, rtol, atol, lyapunov,
                    max_transient=max_transient, batch_size=batch_size, max_record=max_record,
                    lyapunov_method=lyapunov_method, budget=budget)


def with_time_budget(job, seconds):
    """``job`` with the deadline ``seconds`` of wall-clock time from now (None: unchanged)."""
    if seconds is None:
        return job
    from dataclasses import replace
    return replace(job, deadline=_time.time() + validate_value("time_budget", seconds, 1e-3, 1e9))


def travels(pb) -> bool:
    """True when the problem pickles, so worker processes can rebuild it (a scene by name, address
    or module-level builder; not a bare HybridSystem whose declaration holds closures)."""
    import pickle
    try:
        pickle.dumps(pb)
    except Exception:   # noqa: BLE001 - whatever pickle raises: it cannot travel
        return False
    return True


def _execution(job, n_values, workers, scheduler, chunk_size):
    """(worker processes, values per task): 0 workers with a Dask ``scheduler`` (the cluster's);
    by default every available core (:func:`bifurc.sweeps.executor.default_workers`), 1 for a problem
    that cannot travel to another process (a bare HybridSystem with closures: :func:`travels`).  In this process a task holds 8 batches of values."""
    if scheduler is not None:
        workers = 0
    elif workers is None:
        workers = default_workers(n_values) if travels(job.problem) else 1
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


class _NoBar:
    def done(self, chunk):
        pass

    def close(self):
        pass


class _PeriodBar:
    """Progress in relay periods integrated (copies included).  The total is the planned work: each
    value's first transient and record at the start, then what the values done used plus, for each
    value to come, the mean they used (never less than its first transient and record); the values
    done are shown beside it."""

    def __init__(self, bar, values: int, planned: int, unit: str):
        self.bar, self.values, self.planned, self.unit = bar, values, planned, unit
        self.count = self.used = 0

    def done(self, chunk):
        used = sum(max(int(getattr(r, "periods_integrated", 0)), 0) or self.planned for r in chunk)
        self.count += len(chunk)
        self.used += used
        self.bar.total = self.used + (self.values - self.count) * max(self.planned, self.used / self.count)
        self.bar.set_postfix_str(f"{self.count}/{self.values} {self.unit}", refresh=False)
        self.bar.update(used)

    def close(self):
        self.bar.close()


def _progress(values, planned, progress, desc, unit="values"):
    """A bar over ``values`` values of ``planned`` relay periods each (planned work), or one that shows nothing."""
    if not progress or values == 0:
        return _NoBar()
    try:                            # a widget in Jupyter (tqdm.auto needs ipywidgets for it), text elsewhere
        import ipywidgets  # noqa: F401
        from tqdm.auto import tqdm
    except ImportError:             # without ipywidgets tqdm.auto would warn and print text anyway
        from tqdm import tqdm
    bar = tqdm(total=values * planned, desc=desc, unit="period", unit_scale=True, file=sys.stderr, smoothing=0.1)
    return _PeriodBar(bar, values, planned, unit)
