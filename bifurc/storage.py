"""The sweep Dataset: layout, CF attributes, netCDF save and load.

Dimensions: ``branch`` ("independent", or "up"/"down" for continuation), the
swept parameter (named after it, e.g. ``relay_hz``), ``sample`` (recorded
stroboscopic points 0..record), ``step`` (recorded periods), ``impact``
(contacts in the recorded window, NaN-padded; ``n_impacts`` counts them) and
``grazing`` (located grazing values).
"""
from __future__ import annotations

import math
import platform

import heyoka as hy
import numpy as np
import xarray as xr

from .classify import CLASS_LABELS, FLAG_MEANINGS
from .storage_io import write_netcdf_atomic
from maps.presets import preset_attrs
from maps.simulate import dc_law_attrs

__all__ = ["to_dataset", "add_grazing", "add_error_estimate", "save", "load", "STATUS_MEANINGS"]

STATUS_MEANINGS = "ok escaped failed"


def _stack(results, branches, key, fill=np.nan, dtype=float):
    first = next((r[key] for b in branches for r in results[b] if r is not None), None)
    shape = np.shape(first) if first is not None else ()
    out = np.full((len(branches), len(results[branches[0]])) + shape, fill, dtype=dtype)
    for bi, b in enumerate(branches):
        for i, r in enumerate(results[b]):
            if r is not None:
                out[bi, i] = r[key]
    return out


#: per-value variables: (name, result key, per recorded step?, fill, dtype, units, long_name)
_PER_VALUE = [
    ("period", "class_period", False, -1, np.int16, "relay periods", "period n of the orbit (0: not periodic)"),
    ("impacts_per_period", "class_impacts_per_period", False, -1, np.int16, "1",
     "impacts per period m (-1: not periodic)"),
    ("recurrence", "class_recurrence", False, np.nan, float, "1",
     "max recurrence distance at the (candidate) period / (rtol*scale + atol)"),
    ("convergence_rate", "class_convergence_rate", False, np.nan, float, "1",
     "fitted per-period decay factor of the recurrence distance"),
    ("lyapunov", "lyapunov", False, np.nan, float, "1/relay period",
     "largest Lyapunov exponent of the map (NaN: not computed)"),
    ("forcing_period", "forcing_period_steps", False, 0, np.int32, "relay periods",
     "period of the forcing in relay periods (0: incommensurate)"),
    ("impacts_per_step", "impacts_per_step", True, -1, np.int32, "1",
     "contacts in each recorded relay period (-1: not reached)"),
    ("min_gap_per_step", "min_gap_per_step", True, np.nan, float, "m",
     "smallest gap to the stop in each recorded relay period (< 0: penetration)"),
    ("min_impact_speed_per_step", "min_impact_speed_per_step", True, np.nan, float, "m s-1",
     "slowest impact in each recorded relay period (inf: no impact)"),
    ("min_gap", "min_gap", False, np.nan, float, "m", "smallest gap to the stop over the record (< 0: penetration)"),
    ("min_flight_gap", "min_flight_gap", False, np.nan, float, "m",
     "lowest free-flight minimum of the gap over the record (inf: none; NaN: no period recorded)"),
    ("min_impact_speed", "min_impact_speed", False, np.nan, float, "m s-1",
     "slowest impact over the record (inf: no impact; NaN: no period recorded, see status)"),
]


def to_dataset(results, values, point, scene, table, mode) -> xr.Dataset:
    """Assemble per-value result dicts (see SweepPoint) into the sweep Dataset."""
    import bifurc
    branches = list(results)
    system = scene.system
    par = point.param
    p = system.parameter(par)
    dims = ("branch", par)
    ds = xr.Dataset(coords={
        "branch": ("branch", np.array(branches, dtype=str), {"long_name": "sweep branch", "units": "1"}),
        par: (par, np.asarray(values, float), {"units": p.unit, "long_name": p.long_name}),
        "sample": ("sample", np.arange(point.record + 1), {"units": "1", "long_name":
                   "stroboscopic sample k: t = (transient_used + k) / relay_hz"}),
        "step": ("step", np.arange(point.record), {"units": "1", "long_name": "recorded relay period"}),
        "impact": ("impact", np.arange(point.max_impacts), {"units": "1", "long_name": "contact in the record"}),
    })
    pts = _stack(results, branches, "points")
    for j, st in enumerate(system.states):
        ds[st.name] = (dims + ("sample",), pts[..., j], {"units": st.unit, "long_name": f"{st.long_name}, stroboscopic"})
    ds["class_code"] = (dims, _stack(results, branches, "class_code", -1, np.int8), {
        "units": "1", "long_name": "orbit class (-1: not computed)",
        "flag_values": np.arange(len(CLASS_LABELS), dtype=np.int8), "flag_meanings": FLAG_MEANINGS.replace("-", "_")})
    for name, key, step, fill, dtype, units, long_name in _PER_VALUE:
        ds[name] = (dims + (("step",) if step else ()), _stack(results, branches, key, fill, dtype),
                    {"units": units, "long_name": long_name})
    from .sweep import GRAZING_GAP, GRAZING_SPEED
    graze = ((ds.min_impact_speed < GRAZING_SPEED) | ((ds.min_gap >= 0) & (ds.min_gap < GRAZING_GAP)))
    ds["grazing_flag"] = graze.astype(np.int8).assign_attrs(
        units="1", long_name=f"orbit grazes: slowest impact < {GRAZING_SPEED} m/s or clearance < {GRAZING_GAP} m",
        flag_values=np.array([0, 1], np.int8), flag_meanings="clear grazing")
    for key, units, long_name in (
            ("impact_t", "s", "contact onset time"),
            ("impact_velocity", "m s-1", "gap rate at contact onset (< 0: toward the stop)"),
            ("impact_phase", "1", "relay phase of the contact onset, in [0, 1)"),
            ("impact_penetration", "m", "maximum penetration of the contact"),
            ("impact_duration", "s", "contact duration (NaN: padding, or still in contact at the record's end)")):
        ds[key] = (dims + ("impact",), _stack(results, branches, key), {"units": units, "long_name": long_name})
    ds["n_impacts"] = (dims, _stack(results, branches, "n_impacts", -1, np.int32), {
        "units": "1", "long_name": "contacts in the recorded window (may exceed the impact dimension)"})
    ds["status"] = (dims, _stack(results, branches, "status", -1, np.int8), {
        "units": "1", "long_name": "integration status (-1: not computed)", "flag_values": np.array([0, 1, 2], np.int8),
        "flag_meanings": STATUS_MEANINGS})
    ds["failure_time"] = (dims, _stack(results, branches, "failure_time"),
                          {"units": "s", "long_name": "time of escape or failure (NaN: none)"})
    ds["n_steps"] = (dims, _stack(results, branches, "n_steps", 0, np.int64), {"units": "1", "long_name": "Taylor steps"})
    ds["transient_used"] = (dims, _stack(results, branches, "transient_used", -1, np.int64), {
        "units": "relay periods", "long_name": "transient discarded before the record (extended where still converging)"})
    ds["run_seconds"] = (dims, _stack(results, branches, "seconds"), {"units": "s", "long_name": "wall time of the value"})
    o = scene.options
    circuit = (o.circuit if o.ac else "none") if o is not None else "none"
    ac_sign = (o.ac_sign if o.ac else "none") if o is not None else "none"
    ds.attrs.update({
        "title": f"{scene.name}: {par} sweep ({mode})", "scene": scene.name, "swept_parameter": par,
        "swept_parameter_units": p.unit, "mode": mode, "transient_periods": point.transient,
        "recorded_periods": point.record, "tol": point.tol, "max_period": point.max_period,
        "max_transient_periods": point.max_transient if point.max_transient is not None else point.transient,
        "classification_rtol": point.rtol, "classification_atol": point.atol,
        "lyapunov_steps": point.lyapunov_steps, "lyapunov_threshold": _lyap_thr(point.lyapunov_steps),
        "circuit": circuit, "ac_sign": ac_sign, **(dc_law_attrs(o) if o is not None else {"dc_law": "none"}),
        **preset_attrs(table),
        "initial_state": ", ".join(f"{k}={v:g}" for k, v in scene.initial_state(**point.x0).items()),
        "grazing_gap_threshold_m": _graze_gap(), "grazing_speed_threshold_m_s": _graze_speed(),
        "bifurc_version": bifurc.__version__, "heyoka_version": hy.__version__, "numpy_version": np.__version__,
        "xarray_version": xr.__version__, "python_version": platform.python_version(),
        "Conventions": "CF-1.10",
    })
    for k, (v, src) in table.items():
        if k != par:
            ds.attrs[f"param_{k}"] = v
            ds.attrs[f"param_{k}_units"] = system.parameter(k).unit
            ds.attrs[f"param_{k}_source"] = src
    return ds


def _lyap_thr(n):
    from .classify import lyapunov_threshold
    return lyapunov_threshold(n)


def _graze_gap():
    from .sweep import GRAZING_GAP
    return GRAZING_GAP


def _graze_speed():
    from .sweep import GRAZING_SPEED
    return GRAZING_SPEED


def add_grazing(ds: xr.Dataset, found) -> xr.Dataset:
    """Located grazing values [(branch, locate_grazing result), ...] on the ``grazing`` dimension."""
    par = ds.attrs["swept_parameter"]
    units = ds[par].attrs.get("units", "")
    n = len(found)
    ds = ds.assign_coords(grazing=("grazing", np.arange(n), {"units": "1", "long_name": "located grazing"}))
    ds["grazing_value"] = ("grazing", np.array([g["value"] for _, g in found], float),
                           {"units": units, "long_name": f"{par} at which the orbit grazes the stop (bisection)"})
    ds["grazing_xtol"] = ("grazing", np.array([g["xtol"] for _, g in found], float),
                          {"units": units, "long_name": "width of the final bisection bracket"})
    for key, long_name in (("impacts_below", "contacts in the record at the lower neighbour"),
                           ("impacts_above", "contacts in the record at the upper neighbour")):
        ds[f"grazing_{key}"] = ("grazing", np.array([g.get(key, -1) for _, g in found], np.int32),
                                {"units": "1", "long_name": long_name})
    ds["grazing_clearance"] = ("grazing", np.array([g.get("clearance", np.nan) for _, g in found], float), {
        "units": "m", "long_name": "clearance of the orbit at the bracket's end with fewer impacts"})
    ds["grazing_impact_speed"] = ("grazing", np.array([g.get("impact_speed", np.nan) for _, g in found], float), {
        "units": "m s-1", "long_name": "slowest impact at the bracket's end with more impacts"})
    ds["grazing_confirmed"] = ("grazing", np.array([bool(g.get("confirmed", False)) for _, g in found], np.int8), {
        "units": "1", "long_name": "the clearance shrank with the bracket (1: a graze; 0: the branch with "
        "fewer impacts ends otherwise, a jump)", "flag_values": np.array([0, 1], np.int8),
        "flag_meanings": "jump graze"})
    ds["grazing_branch"] = ("grazing", np.array([b for b, _ in found], dtype=str),
                            {"units": "1", "long_name": "sweep branch"})
    return ds


def add_error_estimate(ds, sample_values, point_err, time_err, counts_differ, seconds, tight_tol,
                       sensitive_err=math.nan, n_sensitive=0, step_err=math.nan) -> xr.Dataset:
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
        "error_estimate_method": "error_map_step_rel: one relay period from the same recorded states of the "
                                 "sampled values at tol and at tol/100, largest |difference| scaled by each "
                                 "state's largest magnitude (the error of every map point, any class); "
                                 "error_map_points_rel, error_impact_time_s: whole values re-run at tol/100 from "
                                 "the same start, over periodic values (global error); at chaotic, quasi-periodic "
                                 "or unconverged values that difference (error_map_points_rel_sensitive) reflects "
                                 "sensitivity, not accuracy",
    })
    return ds


def save(ds: xr.Dataset, path) -> None:
    """Write atomically to netCDF (a reader never sees a partial file)."""
    write_netcdf_atomic(ds, path)


#: attributes that are arrays: netCDF gives a one-element array back as a scalar
ARRAY_ATTRS = ("error_estimate_values",)


def load(path) -> xr.Dataset:
    """Open a sweep dataset fully into memory (the file is not kept open)."""
    with xr.open_dataset(path) as ds:
        ds = ds.load()
    for key in ARRAY_ATTRS:
        if key in ds.attrs:
            ds.attrs[key] = np.atleast_1d(ds.attrs[key])
    return ds
