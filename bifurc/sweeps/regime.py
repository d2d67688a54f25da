"""Two-parameter regime maps: every cell of a (param, param2) grid classified as a diagram value.

The grid is flattened into value jobs that carry both parameter values (:class:`CellJob`: its
values are the flat cell indices, row-major with ``param2`` fastest), so a map runs on the
sweep's own machinery: :func:`bifurc.sweeps.sweep.run_values` hands chunks of cells to
:mod:`bifurc.sweeps.executor` (local processes, or Dask with ``scheduler``), heyoka's batch lanes span
both parameters, and with ``path`` completed chunks go to one resume folder ``<path>.parts/``
(:mod:`bifurc.sweeps.resume`).  Each cell is classified exactly as a one-parameter diagram value
(:mod:`bifurc.sweeps.job`, :mod:`bifurc.sweeps.classify`).

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
from ..storage.files import guarded_output
from .job import ValueJob
from .resume import Parts, manifest
from ..storage.schema import CELL_VARIABLES
from .sweep import _grid, _job, deferred_interrupt, run_stats, run_values, with_time_budget

__all__ = ["regime_map", "CellJob", "CELL_VARIABLES"]


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
@guarded_output("path")
def regime_map(scene="thesis-1dof", param="relay_hz", values=None, param2="V", values2=None, *, transient=300,
               record=100, preset=None, params=None, x0=None, tol=1e-10, max_period=100, rtol=1e-6, atol=1e-9,
               lyapunov=True, circuit=None, ac_sign=None, dc_law=None, soil=None, compaction=None, max_record=None,
               path=None, progress=True, workers=None, scheduler=None, error_sample=3, max_transient=None,
               batch_size=4, chunk_size=None, overwrite=False, budget=None, time_budget=None):
    """Classify every cell of the grid ``values`` (of ``param``) x ``values2`` (of ``param2``);
    returns an xarray Dataset with dimensions (param, param2).

    Every cell starts from the same initial state and gets the evidence of a diagram value
    (:func:`bifurc.sweeps.sweep.sweep`, ``mode="independent"``): class, period n and impacts per
    period m, Lyapunov exponent [1/relay period] with its 95 % interval where not periodic,
    minimum clearance [m], status.  Arguments as in :func:`bifurc.sweeps.sweep.sweep`; ``path``:
    netCDF output, streamed to ``<path>.parts/`` chunk by chunk (a rerun with the same
    arguments resumes); ``time_budget``: wall-clock seconds after which no cell is extended (as in
    :func:`~bifurc.sweeps.sweep.sweep`); ``workers``: local processes (default every available core);
    ``scheduler``: a Dask scheduler address or Client; ``error_sample``: cells re-run at tol/100.
    """
    values = _grid(values if values is not None else [], "values")
    values2 = _grid(values2 if values2 is not None else [], "values2")
    if not isinstance(param2, str) or param2 == param:
        raise ParameterError(f"param2 {param2!r}: must be a parameter name other than param ({param!r})")
    if values2.size == 0 or not np.all(np.isfinite(values2)):
        raise ParameterError("values2 must be a non-empty array of finite numbers")
    first = dict(params or {}, **{param2: float(values2[0])})
    job = _job(scene, param, values, transient, record, preset, first, x0, tol, max_period, rtol, atol,
               lyapunov, circuit, ac_sign, dc_law, max_transient, batch_size, max_record, soil, compaction,
               "tangent", budget)
    pb = job.problem
    pb.system.parameter(param2)  # raises for an unknown name
    for v in values2:            # every value of param2 valid before anything runs
        pb.with_values(**{param: float(values[0]), param2: float(v)})
    job = CellJob(**{f.name: getattr(job, f.name) for f in fields(ValueJob)}, param2=param2,
                  values=tuple(float(v) for v in values), values2=tuple(float(v) for v in values2))
    job = with_time_budget(job, time_budget)
    cells = np.arange(values.size * values2.size, dtype=float)
    parts = Parts(path, manifest(job, cells, "map")) if path else None
    results, resumed, seconds, workers = run_values(job, cells, "independent", parts, workers, scheduler, chunk_size,
                                                    progress, f"{pb.name} {param} x {param2}", unit="cells")
    from . import dataset as storage  # xarray: imported where the Dataset is built
    from ..storage.files import write_netcdf
    ds = storage.map_dataset(results["independent"], job)
    run_stats(ds, job, seconds, resumed, workers)
    if error_sample:
        est = error_estimate(results, cells, job, "independent", error_sample)
        sampled = [job.cell(k) for k in est.pop("sample_values")]
        ds = storage.add_error_estimate(ds, sample_values=[a for a, _ in sampled], **est)
        ds.attrs["error_estimate_values2"] = np.asarray([b for _, b in sampled] or [np.nan], float)
    if path:
        with deferred_interrupt():
            write_netcdf(ds, path, overwrite=True)  # refused earlier unless overwrite (guarded_output)
            parts.remove()
    return ds

