"""Two-parameter regime maps: every cell of a (param, param2) grid classified as a diagram value.

The grid is flattened into value jobs that carry both parameter values (:class:`CellJob`: its
values are the flat cell indices, row-major with ``param2`` fastest), so a map runs on the
sweep's own machinery: :func:`bifurc.run.grid.run_points` hands chunks of cells to
:mod:`bifurc.run.executor` (local processes, or Dask with ``scheduler``), heyoka's batch lanes span
both parameters, and with ``path`` completed chunks go to one resume folder ``<path>.parts/``
(:mod:`bifurc.run.parts`).  Each cell is classified exactly as a one-parameter diagram value
(:mod:`bifurc.sweeps.job`, :mod:`bifurc.labels.classify`).

The Dataset has the dimensions ``param`` and ``param2`` (named after them) and one variable
per per-value row of :mod:`bifurc.storage.schema` (class, period, impacts per period, Lyapunov
exponent and its interval, clearance, status, ...), with CF attributes and provenance.
"""
from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np

from maps.parameters import ParameterError
from maps.provenance import recorded

from .errors import error_estimate
from ..run.guard import check_size
from ..run.inputs import analysis_inputs
from ..run.where import Run
from ..storage.files import output_guard
from .job import ValueJob
from ..run.parts import Parts
from .parts import ValueCodec, manifest
from .method import Diagram
from ..run.grid import run_points, write_result
from .sweep import values_array, value_job, run_stats, with_time_budget

@dataclass(frozen=True)
class CellJob(ValueJob):
    """A :class:`~bifurc.sweeps.job.ValueJob` whose value is a flat cell index ``k`` of the grid
    ``values`` x ``values2``: ``param = values[k // len(values2)]``, ``param2 = values2[k % len(values2)]``."""

    param2: str = ""
    values: tuple = ()
    values2: tuple = ()

    def cell(self, k) -> tuple:
        """(param value, param2 value) of flat cell index ``k``."""
        i, j = divmod(int(k), len(self.values2))
        return self.values[i], self.values2[j]

    def at(self, value) -> dict:
        v1, v2 = self.cell(value)
        return dict(self.params, **{self.param: float(v1), self.param2: float(v2)})


@recorded("bifurc.regime_map")
def regime_map(problem="thesis-1dof", param: str = "relay_hz", values=None, param2: str = "V", values2=None,
               method: Diagram | None = None, *, run: Run | None = None, **options):
    """Classify every cell of the grid ``values`` (of ``param``) x ``values2`` (of ``param2``);
    returns an xarray Dataset with dimensions (param, param2).

    Every cell starts from the same initial state and gets the evidence of a diagram value
    (:func:`bifurc.sweep` with ``mode="independent"``): class, period n and impacts per
    period m, Lyapunov exponent [1/strobe period] with its 95 % interval where not periodic,
    minimum clearance [m], status.

    Parameters
    ----------
    problem : :class:`maps.Problem` or scene name
        What is integrated.
    param, values, param2, values2 : str, array_like
        The two parameters and their 1-D grids (``param2`` varies fastest).
    method : :class:`bifurc.Diagram`, optional
        How each cell is integrated and judged (its ``mode`` must be "independent").
    run : :class:`bifurc.Run`, optional
        Where it runs; with ``path`` the cells are streamed to ``<path>.parts/`` chunk by chunk (a rerun resumes).
    **options
        Problem keywords, :class:`bifurc.Diagram` or :class:`bifurc.Run` fields by name.
    """
    pb, m, r = analysis_inputs(problem, Diagram, method, run, options)
    values = values_array(values if values is not None else [], "values")
    values2 = values_array(values2 if values2 is not None else [], "values2")
    if m.mode != "independent":
        raise ParameterError(f"mode = {m.mode!r}: a regime map's cells are independent (mode='independent')")
    check_size(values.size * values2.size, m.transient, m.record, r.workers, m.budget, r.allow_large, "cells",
               trajectories=m.trajectories)
    with output_guard(r.path, r.overwrite):
        return _regime_map(pb, param, values, param2, values2, m, r)


def _regime_map(pb, param, values, param2, values2, m: Diagram, r: Run):
    if not isinstance(param2, str) or param2 == param:
        raise ParameterError(f"param2 {param2!r}: must be a parameter name other than param ({param!r})")
    if values2.size == 0 or not np.all(np.isfinite(values2)):
        raise ParameterError("values2 must be a non-empty array of finite numbers")
    pb.parameter(param2)  # raises for an unknown name or a well input
    job = value_job(pb.with_values(**{param2: float(values2[0])}), param, values, m)
    pb = job.problem
    for v in values2:            # every value of param2 valid before anything runs
        pb.with_values(**{param: float(values[0]), param2: float(v)})
    job = CellJob(**{f.name: getattr(job, f.name) for f in fields(ValueJob)}, param2=param2,
                  values=tuple(float(v) for v in values), values2=tuple(float(v) for v in values2))
    job = with_time_budget(job, r.time_budget)
    path, error_sample = r.path, m.error_sample
    cells = np.arange(values.size * values2.size, dtype=float)
    parts = Parts(path, manifest(job, cells, "map"), ValueCodec()) if path else None
    results, resumed, seconds, workers = run_points(job, cells, "independent", parts, r.workers, r.scheduler,
                                                    r.chunk_size, r.progress, f"{pb.name} {param} x {param2}",
                                                    unit="cells")
    from . import dataset as storage  # xarray: imported where the Dataset is built
    ds = storage.map_dataset(results["independent"], job)
    run_stats(ds, job, seconds, resumed, workers)
    if error_sample:
        est = error_estimate(results, cells, job, "independent", error_sample)
        sampled = [job.cell(k) for k in est.pop("sample_values")]
        ds = storage.add_error_estimate(ds, sample_values=[a for a, _ in sampled], **est)
        ds.attrs["error_estimate_values2"] = np.asarray([b for _, b in sampled] or [np.nan], float)
    if path:
        write_result(ds, path, parts)
    return ds

