"""The diagram and regime-map Datasets: assembly from the schema table, CF attributes and provenance.

Dimensions: ``branch`` ("independent", or "up"/"down" in follow mode), the
swept parameter (named after it, e.g. ``relay_hz``), ``sample`` (recorded
stroboscopic points 0..record), ``step`` (recorded periods), ``impact``
(contacts in the recorded window, NaN-padded; ``n_impacts`` counts them) and
``grazing`` (located grazing values).  Every variable is a row of
:mod:`bifurc.storage.schema`; :func:`to_dataset` (kind "diagram") and :func:`map_dataset` (kind
"map") share the row stacking (:func:`_stack`), the grazing flag and the run attributes.
"""
from __future__ import annotations

import math
import platform

import heyoka as hy
import numpy as np
import xarray as xr

from maps.provenance import cf_attrs

from maps.progression import held_mode, progression_measures

from .._version import __version__
from ..labels.codes import Status
from ..storage.build import dataset
from ..storage.schema import (CELL_VARIABLES, GRAZING, GRAZING_FLAG, GRAZING_GAP, GRAZING_SPEED, PARAM, PROGRESSION,
                              SWEEP, SWEEP_COORDS, flag_variable, grazing_flag, state_variable)
from ..labels.classify import lyapunov_threshold
from .method import FORCING_PERIODS
from ..labels.anytime import ANYTIME_METHOD
from ..labels.lyapunov import INTERVAL_METHOD, METHODS

#: how the stored exponent interval is made
INTERVAL_METHOD_K = ("the wider of a 95 % Student-t prediction interval for another trajectory's mean exponent over the "
                     "same window (lyapunov_window) from the spread of lyapunov_trajectories tangent trajectories (the "
                     "value's own and perturbed copies of its state; lyapunov_spread) and their batch-means intervals "
                     f"({INTERVAL_METHOD})")

STATUS_MEANINGS = " ".join(s.label for s in Status)


def _stack(results, branches, var, sizes, par, get=None):
    """The variable ``var`` over (branch, value, ...) from ValueResults (None: not computed -> fill)."""
    out = var.empty(sizes, par)
    for bi, b in enumerate(branches):
        for i, r in enumerate(results[b]):
            if r is not None:
                out[bi, i] = getattr(r, var.name) if get is None else get(r)
    return var.finish(out)


def _put_grazing_flag(ds, dims) -> None:
    """The grazing flag from the per-value minima (schema.grazing_flag)."""
    ds[GRAZING_FLAG.name] = (dims, grazing_flag(ds.min_clearance, ds.min_impact_speed).values.astype(np.int8),
                             GRAZING_FLAG.attrs())


def _progression(results, branches, job, sizes, par, values, mode) -> dict:
    """The 2-DOF progression measures (schema.PROGRESSION) of every value over its recorded window,
    from its relay-period samples and contacts (maps.progression).  A follow sweep starts each
    value where the previous one ended: no time to depth from the start."""
    system = job.problem.system
    ix2 = system.state_names.index("x2")
    x2_start = job.x0["x2"]
    held_by = held_mode(system)
    out = {var: var.empty(sizes, par) for var in PROGRESSION}
    for bi, b in enumerate(branches):
        for i, r in enumerate(results[b]):
            if r is None:
                continue
            p = job.at(values[i])
            W, n = p["relay_hz"], min(r.record_used, job.record)     # the stored samples: the first record
            t = (r.transient_used + np.arange(n + 1)) / W
            held = 0.0 if held_by is None else r.held_time      # the time in the mode, from its flag changes
            m = progression_measures(t, r.points[:n + 1, ix2], x2_start=x2_start, relay_hz=W,
                                     impact_time=r.impact_time, impact_velocity=r.impact_velocity, m1=p["m1"], held=held)
            if mode != "independent":
                m["time_to_depth"] = np.nan
            if r.n_impacts > job.max_impacts:
                m["impact_energy_per_period"] = np.nan
            for var in PROGRESSION:
                out[var][bi, i] = m[var.name]
    return {var: var.finish(data) for var, data in out.items()}


def to_dataset(results, values, job, mode) -> xr.Dataset:
    """Assemble ``results`` {branch: [ValueResult or None per value]} into the sweep Dataset."""
    branches = list(results)
    system, scene_name = job.problem.system, job.problem.name
    par = job.param
    p = system.parameter(par)
    sizes = {"branch": len(branches), par: len(values), "sample": job.record + 1, "step": job.record,
             "impact": job.max_impacts}
    index = {"branch": np.array(branches, dtype=str)}
    coords = {c.name: (c.dims, index.get(c.name, np.arange(sizes[c.name])), c.attrs()) for c in SWEEP_COORDS}
    coords = {"branch": coords.pop("branch"), par: (par, np.asarray(values, float),
                                                  {"units": p.unit, "long_name": p.long_name}), **coords}
    ds = dataset("diagram", coords)
    new = {}                    # every variable, then one merge (one per variable cost 10 ms each)
    for j, st in enumerate(system.states):
        var = state_variable(st, ("branch", PARAM, "sample"), ", stroboscopic")
        new[st.name] = (var.dims_for(par), _stack(results, branches, var, sizes, par, lambda r: r.points[:, j]),
                        var.attrs())
    for j, name in enumerate(system.flag_names):     # the mode at each sample: a step restarts exactly there
        var = flag_variable(name, ("branch", PARAM, "sample"))
        new[var.name] = (var.dims_for(par), _stack(results, branches, var, sizes, par,
                                                   lambda r: r.point_flags[:, j]), var.attrs())
    for var in SWEEP:
        new[var.name] = (var.dims_for(par), _stack(results, branches, var, sizes, par), var.attrs())
    if "x2" in system.state_names and "relay_hz" in system.param_names:
        for var, data in _progression(results, branches, job, sizes, par, values, mode).items():
            new[var.name] = (var.dims_for(par), data, var.attrs())
    ds = ds.assign(new)
    _put_grazing_flag(ds, ("branch", par))
    ds.attrs.update({"title": f"{scene_name}: {par} sweep ({mode})", "scene": scene_name, "swept_parameter": par,
                     "swept_parameter_units": p.unit, "mode": mode,
                     **run_attrs(job, f"scene {scene_name}, {par} sweep ({mode})", skip=(par,))})
    return ds


def map_dataset(results, job) -> xr.Dataset:
    """The regime-map Dataset from the cells' ValueResults, flat and row-major over (param, param2)
    (None: not computed -> the row's fill); ``job`` is a :class:`bifurc.sweeps.regime.CellJob`."""
    system, name = job.problem.system, job.problem.name
    par, par2 = job.param, job.param2
    coords = {}
    for p_name, vals in ((par, job.values), (par2, job.values2)):
        p = system.parameter(p_name)
        coords[p_name] = (p_name, np.asarray(vals, float), {"units": p.unit, "long_name": p.long_name})
    ds = dataset("map", coords)
    cells = {"cells": list(results)}        # one "branch" of every cell: the diagram's stacking, then reshaped
    sizes = {"branch": 1, "cells": len(results)}
    for var in CELL_VARIABLES:
        flat = _stack(cells, ["cells"], var, sizes, "cells")[0]
        ds[var.name] = ((par, par2), flat.reshape(len(job.values), len(job.values2)), var.attrs())
    _put_grazing_flag(ds, (par, par2))
    p1, p2 = system.parameter(par), system.parameter(par2)
    ds.attrs.update({"title": f"{name}: regime map over {par} and {par2}", "scene": name,
                     "swept_parameter": par, "swept_parameter_units": p1.unit,
                     "swept_parameter2": par2, "swept_parameter2_units": p2.unit, "mode": "independent",
                     **run_attrs(job, f"scene {name}, regime map over {par} and {par2}", skip=(par, par2))})
    return ds


def run_attrs(job, history, skip=()) -> dict:
    """The attributes every grid dataset carries: the job's settings, the problem's model options
    and parameters (except the gridded ones, ``skip``: :meth:`maps.Problem.attrs`), thresholds,
    versions and the CF history."""
    return {
        "transient_periods": job.transient,
        "recorded_periods": job.record, "max_record_periods": job.record_cap,
        "record_extension": f"a record holding fewer than {FORCING_PERIODS} forcing periods q (q <= max_period) is "
                            f"extended to {FORCING_PERIODS} q relay periods, at most max_record_periods; an undecided "
                            f"value is then extended (doubling its window) up to budget_periods, its non-stationary "
                            f"first halves discarded (transient_used); it is judged on that window (record_used)",
        "budget_periods": job.spent,
        **({"time_budget_deadline": _iso(job.deadline)} if getattr(job, "deadline", None) else {}),
        "classification_method": ANYTIME_METHOD,
        "tol": job.tol, "max_period": job.max_period,
        "max_transient_periods": job.max_transient if job.max_transient is not None else job.transient,
        "classification_rtol": job.rtol, "classification_atol": job.atol,
        "lyapunov_steps": job.exponent_steps, "lyapunov_threshold": lyapunov_threshold(job.exponent_steps),
        "lyapunov_threshold_rule": "2 ln(n)/n (at least 2e-3) for an n-step window (the finite-window bias on a "
                                   "sheared torus); a value's own threshold uses its window",
        "lyapunov_interval_method": INTERVAL_METHOD_K, "lyapunov_method": METHODS[job.lyapunov_method],
        "lyapunov_trajectories": job.trajectories,
        "initial_state": ", ".join(f"{k}={v:g}" for k, v in job.x0.items()),
        "grazing_gap_threshold_m": GRAZING_GAP, "grazing_speed_threshold_m_s": GRAZING_SPEED,
        "bifurc_version": __version__, "heyoka_version": hy.__version__, "numpy_version": np.__version__,
        "xarray_version": xr.__version__, "python_version": platform.python_version(),
        **cf_attrs(history), **job.problem.attrs(skip=skip),
    }


def add_grazing(ds: xr.Dataset, found) -> xr.Dataset:
    """Located grazing values [(branch, locate_grazing result), ...] on the ``grazing`` dimension."""
    par = ds.attrs["swept_parameter"]
    units = ds[par].attrs.get("units", "")
    columns = {"grazing": np.arange(len(found)), "grazing_branch": [b for b, _ in found]}
    for var in GRAZING:
        key = var.name.removeprefix("grazing_")
        data = columns.get(var.name)
        if data is None:
            data = [g.get(key, var.fill) for _, g in found]
        attrs = var.attrs(long_name=var.long_name.format(param=par), **({"units": units} if var.units == PARAM else {}))
        if var.name == "grazing":
            ds = ds.assign_coords(grazing=("grazing", data, attrs))
        else:
            ds[var.name] = (var.dims, np.array(data, dtype=var.dtype), attrs)
    return ds


def add_error_estimate(ds, sample_values, point_err, time_err, counts_differ, seconds, tight_tol,
                       sensitive_err=math.nan, n_sensitive=0, step_err=math.nan, not_robust=()) -> xr.Dataset:
    """Record the numerical error estimate next to the run time (NaN: nothing of that kind sampled)."""
    ds.attrs.update({
        "error_estimate_values": np.asarray(sample_values, float) if len(sample_values) else np.array([math.nan]),
        "error_estimate_tol": tight_tol,
        "error_map_step_rel": step_err,
        "error_map_points_rel": point_err,
        "error_impact_time_s": time_err,
        "error_impact_count_mismatches": int(counts_differ),
        "error_map_points_rel_sensitive": sensitive_err,
        "error_sensitive_values": int(n_sensitive),
        "error_estimate_seconds": seconds,
        "error_periodic_not_robust": ", ".join(f"{v:g}" for v in not_robust),
        "error_estimate_method": "error_map_step_rel: one relay period from the same recorded states of the "
                                 "sampled values at tol and at tol/100, largest |difference| scaled by each "
                                 "state's largest magnitude (the error of every map point, any class); "
                                 "error_map_points_rel, error_impact_time_s: whole values re-run at tol/100 from "
                                 "the same start, over periodic values (global error; NaN: none re-run); at "
                                 "chaotic, quasi-periodic or unconverged values that difference "
                                 "(error_map_points_rel_sensitive) reflects sensitivity, not accuracy; a periodic "
                                 "value whose re-run lands elsewhere (beyond 1e-3 at every phase: another attractor "
                                 "from the same start, after a transient that amplifies round-off) is listed in "
                                 "error_periodic_not_robust and counted with the sensitive ones",
    })
    return ds


def _iso(seconds: float) -> str:
    """A time.time() instant as ISO 8601 UTC text (the time budget's deadline)."""
    import datetime
    return datetime.datetime.fromtimestamp(seconds, datetime.timezone.utc).isoformat(timespec="seconds")
