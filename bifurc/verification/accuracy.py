"""Work-precision study: error against run time for the toolkit and the baselines.

The reference is the toolkit itself in extended precision: heyoka in long
double (x86 80-bit, machine epsilon 1.1e-19) at ``tol = 1e-19`` by default, or
real128 (epsilon 1.9e-34) at ``tol = 1e-28`` on request.  Long double suffices
for double-precision runs: their errors are >= ~1e-14 (round-off over ~1e3
steps), while the long-double reference is accurate to ~1e-16 or better; the
study measures this bound by running the reference a second time at a 100x
looser tolerance and records the difference (``reference_error_bound``).  Relay
switch instants are the same double numbers in every run (the problem is defined
with them), so they are not a source of difference.

Errors are measured at ``t_end``:

- final-state error: ``max_k |y_k - y_ref_k| / max(1, |y_ref_k|)`` (heyoka's
  mixed absolute/relative norm) over (x [m], v [m/s], i [A], z [A/s]);
- position error: ``|x - x_ref|`` [m];
- impact-time error: the largest difference of contact onset times [s] when the
  impact counts agree, NaN otherwise (a missed or added contact).
"""
from __future__ import annotations

import math
import time as _time

import numpy as np
import xarray as xr

from maps.engines.scalar import HybridRun
from maps.impacts import impact_table
from maps.parameters import ParameterError
from maps.provenance import cf_attrs, recorded
from maps.problem import problem

from ..storage.build import dataset
from . import baselines
from .ladders import DEFAULT_LADDERS

def _problem(scene, preset=None, params=None, x0=None, circuit=None, ac_sign=None, dc_law=None):
    pb = problem(scene, preset, params, x0, circuit=circuit, ac_sign=ac_sign, dc_law=dc_law)
    return pb.scene, dict(pb.values), pb.state_vector(), pb


def reference_solution(scene, t_end, preset=None, params=None, x0=None, precision="longdouble",
                       tol=None, circuit=None, ac_sign=None, dc_law=None) -> dict:
    """Final state (float128-like array), impact times and error bound of the extended-precision run.

    ``precision`` is ``"longdouble"`` (tol 1e-19) or ``"real128"`` (tol 1e-28, ~12 s to compile).
    """
    import heyoka as hy
    sc, values, y0, pb = _problem(scene, preset, params, x0, circuit, ac_sign, dc_law)
    if precision == "longdouble":
        fp, tol = np.longdouble, tol or 1e-19
    elif precision == "real128":
        fp, tol = hy.real128, tol or 1e-28
    else:
        raise ParameterError(f"reference precision {precision!r}; allowed: longdouble, real128")
    out = {}
    for label, t in (("ref", tol), ("loose", tol * 100)):
        y0x = np.array([fp(float(v)) for v in y0], dtype=fp)   # the same double start, exactly
        run = HybridRun(sc.system, values, y0x, tol=t, fp_type=fp, max_events=None)
        t0 = _time.perf_counter()
        run.advance(t_end)
        out[label] = (np.array([np.longdouble(str(v)) if fp is not np.longdouble else v for v in run.ta.state]),
                      impact_table(run)["t"], _time.perf_counter() - t0, run.compile_seconds)
    y_ref, t_imp, secs, comp = out["ref"]
    bound = final_state_error(out["loose"][0], y_ref)
    return {"y": y_ref, "impact_times": t_imp, "run_seconds": secs, "compile_seconds": comp,
            "precision": precision, "tol": tol, "error_bound": bound, "scene": sc, "params": values,
            "y0": y0, "problem": pb}


def final_state_error(y, y_ref) -> float:
    """``max_k |y_k - y_ref_k| / max(1, |y_ref_k|)`` in extended precision, returned as a float."""
    y = np.asarray(y, dtype=np.longdouble)
    y_ref = np.asarray(y_ref, dtype=np.longdouble)
    return float(np.max(np.abs(y - y_ref) / np.maximum(1, np.abs(y_ref))))


def toolkit_solution(sc, values, y0, t_end, tol, repeats=3, observations=True, min_seconds: float = 0.0) -> dict:
    """The toolkit in double precision (no dense output); run time is the best of ``repeats`` runs,
    more until they have taken ``min_seconds`` (as timeit's autorange: a burst of load on a shared
    machine then spoils a few of many runs, not all of five).  ``observations=False``: no stops at
    observation-only guards (a transient's run)."""
    run = HybridRun(sc.system, values, y0, tol=tol, max_events=None, observations=observations)

    def once():
        run.reset(0.0, y0)
        t0 = _time.perf_counter()
        run.advance(t_end)
        return _time.perf_counter() - t0, run
    best, _ = _best_time(once, repeats, min_seconds)
    return {"y": np.array(run.ta.state, dtype=float), "impact_times": impact_table(run)["t"],
            "run_seconds": best, "n_steps": run.n_steps, "compile_seconds": run.compile_seconds}


def _impact_error(t, t_ref):
    if t.size != t_ref.size:
        return math.nan
    return float(np.max(np.abs(t - t_ref))) if t.size else 0.0


@recorded("bifurc.verification.accuracy.work_precision")
def work_precision(scene="thesis-1dof", t_end=2.0, preset=None, params=None, x0=None,
                   ladders=None, methods=None, reference="longdouble", repeats=3,
                   max_seconds=30.0, progress=None, circuit=None, ac_sign=None, dc_law=None,
                   baseline_repeats: int = 1, min_seconds: float = 0.0) -> xr.Dataset:
    """Errors against run time for every method over its tolerance ladder.

    ``ladders`` maps a method to its tolerances (default :data:`DEFAULT_LADDERS`);
    ``methods`` selects among them.  A method stops climbing its ladder once a run takes
    longer than ``max_seconds``.  Run time: the best of ``repeats`` runs for the toolkit and
    of ``baseline_repeats`` for the baselines, each method repeating until its runs have taken
    ``min_seconds`` (a baseline rung stops once they have taken ``max_seconds``).  Returns a
    Dataset with dimension ``run``.
    """
    ladders = dict(DEFAULT_LADDERS if ladders is None else ladders)
    if methods is not None:
        unknown = set(methods) - set(DEFAULT_LADDERS)
        if unknown:
            raise ParameterError(f"unknown method {sorted(unknown)[0]!r}; methods: {', '.join(DEFAULT_LADDERS)}")
        ladders = {m: ladders.get(m, DEFAULT_LADDERS[m]) for m in methods}
    from maps.parameters import validate_value
    t_end = validate_value("t_end", t_end, 0.0, 1e4, low_open=True, unit="s")
    if any(not m.startswith("heyoka") for m in ladders):
        baselines.check_supported(_problem(scene, preset, params, x0, circuit, ac_sign, dc_law)[0])
    ref = reference_solution(scene, t_end, preset, params, x0, precision=reference, circuit=circuit,
                             ac_sign=ac_sign, dc_law=dc_law)
    sc, values, y0 = ref["scene"], ref["params"], ref["y0"]
    rows = []
    for method, ladder in ladders.items():
        for tol in ladder:
            if method.startswith("heyoka"):
                r = toolkit_solution(sc, values, y0, t_end, tol, repeats, observations=method == "heyoka",
                                     min_seconds=min_seconds)
                y, t_imp, secs = r["y"], r["impact_times"], r["run_seconds"]
            else:
                y, t_imp, secs = _baseline(method, values, y0, t_end, tol, sc.options.dc_law,
                                           baseline_repeats, max_seconds, min_seconds)
            rows.append(dict(method=method, tol=tol, run_seconds=secs,
                             final_state_error=final_state_error(y, ref["y"]),
                             position_error=float(abs(np.longdouble(y[0]) - ref["y"][0])),
                             impact_time_error=_impact_error(np.asarray(t_imp), np.asarray(ref["impact_times"], float)),
                             n_impacts=int(np.asarray(t_imp).size)))
            if progress:
                progress(rows[-1])
            if secs > max_seconds:
                break
    return _to_dataset(rows, ref, t_end)


def _best_time(once, repeats, min_seconds=0.0, max_seconds=math.inf):
    """(best time [s], last result) of ``once() -> (seconds, result)`` called ``repeats`` times
    (at least once), more until the calls have taken ``min_seconds``, fewer once they have taken
    ``max_seconds``."""
    best, spent, n = math.inf, 0.0, 0
    while n < max(1, int(repeats)) or spent < min_seconds:
        dt, result = once()
        best, spent, n = min(best, dt), spent + dt, n + 1
        if spent > max_seconds:
            break
    return best, result


def _baseline(method, values, y0, t_end, tol, dc_law, repeats, max_seconds, min_seconds=0.0):
    """(final state, impact times, best run time [s]) of a baseline (:func:`_best_time`)."""
    def once():
        if method == "rk4-bisection":
            b = baselines.solve_rk4_bisection(values, y0, t_end, h=tol, dc_law=dc_law)
        else:
            b = baselines.solve_scipy(values, y0, t_end, method=method.split("-", 1)[1], tol=tol, dc_law=dc_law)
        return b.run_seconds, b
    best, b = _best_time(once, repeats, min_seconds, max_seconds)
    return b.y, b.impact_times, best


def _to_dataset(rows, ref, t_end) -> xr.Dataset:
    col = {k: np.array([r[k] for r in rows]) for k in rows[0]}
    ds = dataset("accuracy", {"run": ("run", np.arange(len(rows)), {"units": "1", "long_name": "run number"})})
    ds["method"] = ("run", col["method"].astype(str), {"long_name": "integration method"})
    ds["tol"] = ("run", col["tol"], {"units": "1", "long_name":
                                     "tolerance (rtol = atol; for rk4-bisection the step h in s)"})
    ds["run_seconds"] = ("run", col["run_seconds"], {"units": "s", "long_name": "integration wall time"})
    ds["final_state_error"] = ("run", col["final_state_error"], {
        "units": "1", "long_name": "final-state error max_k |y_k - y_ref_k| / max(1, |y_ref_k|)"})
    ds["position_error"] = ("run", col["position_error"], {"units": "m", "long_name": "final position error"})
    ds["impact_time_error"] = ("run", col["impact_time_error"], {
        "units": "s", "long_name": "largest contact onset time error (NaN: impact count differs)"})
    ds["n_impacts"] = ("run", col["n_impacts"], {"units": "1", "long_name": "number of contacts"})
    sc = ref["scene"]
    ds.attrs.update({
        "title": f"{sc.name}: work-precision study, error against run time", **ref["problem"].attrs(), "t_end": t_end, "reference_precision": ref["precision"],
        "reference_tol": float(ref["tol"]), "reference_error_bound": ref["error_bound"],
        "reference_n_impacts": int(ref["impact_times"].size),
        "reference_final_state": np.array(ref["y"], dtype=float),
        "reference_run_seconds": ref["run_seconds"], "initial_state": np.asarray(ref["y0"], float),
        **cf_attrs(f"scene {sc.name}, work-precision study"),
    })
    return ds


def plot_work_precision(ds: xr.Dataset, path=None, error="final_state_error", ax=None, overwrite=False):
    """Log-log error against run time, one line per method, into ``ax`` (default: a new figure);
    ``path``: also save it there (an existing file is refused unless ``overwrite``).
    Returns the Axes it drew on (``ax`` as given, or the new one)."""
    from ..storage.files import check_figure_output, save_figure
    if path is not None:
        check_figure_output(path, overwrite)
    own = ax is None
    if own:
        import matplotlib.pyplot as plt
        ax = plt.subplots(figsize=(7, 5))[1]
    fig = ax.figure
    floor = max(float(ds.attrs.get("reference_error_bound", 0.0)), 1e-18)
    for method in dict.fromkeys(ds["method"].values.tolist()):
        sel = ds.where(ds["method"] == method, drop=True)
        err = np.maximum(sel[error].values.astype(float), floor)
        ax.loglog(sel["run_seconds"].values, err, "o-", label=method)
        bad = sel["n_impacts"].values != ds.attrs["reference_n_impacts"]
        if bad.any():
            ax.loglog(sel["run_seconds"].values[bad], err[bad], "kx", ms=10)
    ax.axhline(floor, color="grey", lw=0.8, ls=":")
    ax.set_xlabel("run time [s]")
    ax.set_ylabel(ds[error].attrs.get("long_name", error))
    ax.set_title(f"{ds.attrs['scene']}, {ds.attrs['t_end']:g} s, V = {ds.attrs.get('param_V', float('nan')):g} V, "
                 f"relay {ds.attrs.get('param_relay_hz', float('nan')):g} Hz\n"
                 f"reference: {ds.attrs['reference_precision']} tol {ds.attrs['reference_tol']:g} "
                 f"(x: wrong impact count; dotted: reference bound)", fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    if own:
        fig.tight_layout()
    if path is not None:
        save_figure(fig, path, overwrite=overwrite, dpi=120, close=own)
    return ax
