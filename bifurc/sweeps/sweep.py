"""One-parameter sweeps: stroboscopic orbits, classification and grazing per value.

``mode="independent"``: every value starts from the same initial state (values
run in parallel: ``workers`` processes, by default every available core, or a Dask
``scheduler``).  ``mode="follow"``: each value starts from the previous value's final
state, swept up then down (dimension ``branch``), to reveal coexisting attractors and
hysteresis ("continuation" is a deprecated alias).

With ``path`` every completed chunk of values is saved at once under ``<path>.parts/``
(:mod:`bifurc.run.parts`); an interrupted sweep loses nothing and a rerun with the same
arguments resumes.  The final Dataset is written atomically and the parts are removed.

The tail after the grid (grazing bisections, error estimate) runs on the sweep's worker
processes, still open and warm, while this process builds the Dataset (independent mode on a
process pool; here otherwise).

The pieces: :mod:`bifurc.sweeps.job` (one value), :mod:`bifurc.run.executor` (many values),
:mod:`bifurc.sweeps.grazing`, :mod:`bifurc.sweeps.errors`, :mod:`bifurc.sweeps.dataset`.
"""
from __future__ import annotations

import time as _time
from contextlib import nullcontext

import numpy as np

from maps.parameters import ParameterError
from maps.provenance import recorded

from .errors import ErrorEstimate
from ..run.executor import WorkerPool, result_of, submit_all
from ..run.guard import check_size
from ..run.inputs import analysis_inputs
from ..run.where import Run
from ..storage.files import output_guard
from .grazing import bracket_cost, grazing_brackets, locate_bracket
from ..labels.anytime import BUDGET
from .job import ValueJob
from .method import Diagram
from ..run.grid import MODES, Interrupted, execution, kept_message, run_points, write_result
from ..run.parts import Parts
from .parts import ValueCodec, manifest

@recorded("bifurc.sweep")
def sweep(problem="thesis-1dof", param: str = "relay_hz", values=None, method: Diagram | None = None, *,
          run: Run | None = None, **options):
    """A one-parameter bifurcation diagram: ``param`` swept over ``values``, each value integrated, recorded and
    labelled on evidence; returns an xarray Dataset (:mod:`bifurc.sweeps.dataset`).

    Parameters
    ----------
    problem : :class:`maps.Problem` or scene name
        What is integrated (a scene name, Scene or HybridSystem is resolved by :func:`maps.problem`).
    param : str
        The parameter swept (docs/model.md section 6), e.g. "relay_hz", "V", "k".
    values : array_like
        The grid, 1-D (ascending for ``mode="follow"``).
    method : :class:`bifurc.Diagram`, optional
        How each value is integrated and judged (transient, record, budget, period search, tolerance, ...).
    run : :class:`bifurc.Run`, optional
        Where it runs (workers, Dask scheduler, output ``path`` with resume parts, progress, time budget).
    **options
        Keyword convenience: any problem keyword (``preset``, ``params``, ``x0``, ``dc_law``, ...), any field of
        :class:`bifurc.Diagram` or of :class:`bifurc.Run`, by name; they change the given objects.

    Returns
    -------
    xarray.Dataset
        ``bifurc_kind`` "diagram": strobe points, impacts, class n:m with its evidence, exponent with its interval,
        located grazings and the numerical error estimate; written to ``run.path`` if given.

    Examples
    --------
    >>> import numpy as np, bifurc
    >>> pb = maps.problem("thesis-1dof", preset="matlab-listing", params={"V": 90})  # doctest: +SKIP
    >>> d = bifurc.sweep(pb, "relay_hz", np.linspace(2, 10, 41), bifurc.Diagram(record=100))  # doctest: +SKIP
    """
    pb, m, r = analysis_inputs(problem, Diagram, method, run, options)
    values = values_array(values, "values")
    check_size(values.size * len(MODES[m.mode]), m.transient, m.record, r.workers, m.budget, r.allow_large,
               trajectories=m.trajectories)
    with output_guard(r.path, r.overwrite):
        return _sweep(pb, param, values, m, r)


def _sweep(pb, param: str, values: np.ndarray, m: Diagram, r: Run):
    """The diagram of ``pb`` over ``values`` of ``param`` with the method ``m``, run as ``r`` says."""
    job = value_job(pb, param, values, m)
    job = with_time_budget(job, r.time_budget)
    parts = Parts(r.path, manifest(job, values, m.mode), ValueCodec()) if r.path else None
    workers, chunk_size = execution(job, values.size, r.workers, r.scheduler, r.chunk_size)
    pool = WorkerPool(job, workers) if m.mode == "independent" and workers > 1 else None
    with pool or nullcontext():     # open through the tail: its workers are warm
        results, resumed, seconds, workers = run_points(job, values, m.mode, parts, workers, r.scheduler, chunk_size,
                                                        r.progress, f"{job.problem.name} {param}", pool=pool)
        try:
            warm = pool if resumed < values.size else None   # every value resumed: no worker started, the tail runs here
            tail = _start_tail(results, values, job, MODES[m.mode][0], m.grazing, m.grazing_xtol, m.error_sample, warm)
            from . import dataset as storage  # xarray: imported where the Dataset is built (worker processes start faster)
            ds = storage.to_dataset(results, values, job, m.mode)
            run_stats(ds, job, seconds, resumed, workers)
            found, estimate = tail()
        except KeyboardInterrupt:   # every value done: the grazing bisections or the error estimate were running
            n = values.size * len(MODES[m.mode])
            raise Interrupted(kept_message(parts, n, n) + " (grazing and error estimate: run again)") from None
    return _finish(ds, found if m.grazing else None, estimate if m.error_sample else None, r.path, parts)


def _finish(ds, found, estimate, path, parts):
    """The sweep's Dataset with its located grazings and error estimate (None: not computed), written to
    ``path`` (the resume parts then removed)."""
    from . import dataset as storage
    if found is not None:
        ds = storage.add_grazing(ds, found)
    if estimate is not None:
        ds = storage.add_error_estimate(ds, **estimate)
    if path:
        write_result(ds, path, parts)
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


def run_stats(ds, job, seconds, resumed, workers) -> None:
    """Record how a grid ran in ``ds.attrs``: wall time of this call, computation time of every
    value (resumed ones included), values resumed, workers, SIMD lanes, this process's compile time."""
    ds.attrs["sweep_seconds"] = seconds     # wall time of this call's integrations
    ds.attrs["values_seconds"] = float(np.nansum(ds.run_seconds.values))  # resumed values included
    ds.attrs["resumed_values"] = resumed
    ds.attrs["workers"] = workers           # worker processes (0: a Dask cluster's)
    ds.attrs["batch_size"] = job.batch_size  # SIMD lanes (1: one value at a time); results agree to round-off
    ds.attrs["compile_seconds"] = job.warm().compile_seconds  # this process's scalar compile (workers compile their own)


def values_array(values, name: str) -> np.ndarray:
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


def value_job(pb, param: str, values: np.ndarray, m: Diagram) -> ValueJob:
    """The ValueJob of a diagram (or a map's first parameter), every value checked before anything runs."""
    if values.size == 0 or not np.all(np.isfinite(values)):
        raise ParameterError("values must be a non-empty array of finite numbers")
    pb.parameter(param)  # raises for an unknown name or a well input
    for v in values:  # every value must be valid before anything runs
        pb.with_values(**{param: v})
    return ValueJob(pb, param, m.transient, m.record, m.tol, m.max_period, m.rtol, m.atol, m.lyapunov,
                    max_transient=m.max_transient, batch_size=m.batch_size, max_record=m.max_record,
                    lyapunov_method=m.lyapunov_method, budget=BUDGET if m.budget is None else m.budget,
                    trajectories=m.trajectories)


def with_time_budget(job, seconds):
    """``job`` with the deadline ``seconds`` of wall-clock time from now (None: unchanged)."""
    if seconds is None:
        return job
    from dataclasses import replace
    return replace(job, deadline=_time.time() + seconds)


