"""Numerical stability suite: stiff, chattering, grazing and extreme cases, with errors reported.

Each case runs in double precision and again in extended precision (long double,
or real128 where marked); the verdict says whether the double result can be
trusted:

- ``ok``: the same events, and final state and event times within the bound the
  tolerance implies (``bound = max(1e3, steps) * tol`` relative: heyoka's tol is a
  local error per step, accumulated over the steps);
- ``ill-conditioned``: the runs diverge beyond that bound (the divergence is
  reported: a sensitive orbit, not a wrong integrator, when a shorter horizon agrees);
- ``escaped`` (with the time), ``numerical-failure`` (non-finite state, with time
  and state), ``event-cap`` (a runaway stopped by the per-run event cap).
"""
from __future__ import annotations

import math
import sys
import time as _time
from dataclasses import dataclass, field
from pathlib import Path

import heyoka as hy
import numpy as np
import xarray as xr

from maps.hybrid import Escaped, HybridRun, IntegrationFailure
from maps.impacts import impact_table
from maps.simulate import resolve

__all__ = ["Case", "CASES", "QUICK", "run_case", "run_suite", "write_report", "VERDICTS"]

VERDICTS = ("ok", "ill-conditioned", "escaped", "numerical-failure", "event-cap")
HIT = {"x": 0.005, "v": -3.0}  # 5 mm above the stop moving down against the ~33 N DC pull: hits at ~2.6 m/s


@dataclass(frozen=True)
class Case:
    """One named case: a scene run for ``t_end`` seconds, and what it checks."""

    name: str
    group: str
    scene: str
    t_end: float
    params: dict = field(default_factory=dict)
    preset: str | None = None
    x0: dict = field(default_factory=dict)
    flags: dict = field(default_factory=dict)
    tol: float = 1e-12
    options: dict = field(default_factory=dict)   # circuit, ac_sign, energy
    extended: str = "longdouble"                  # or "real128"
    expect: str = "ok"
    max_events: int = 20_000
    note: str = ""                                # why the expected verdict is what it is


def _stiff(k, c):
    return Case(f"stiff-k{k:.0e}-c{c:g}", "stiff stop", "thesis-1dof", 0.02,
                dict(V=90.0, relay_hz=9.0, k=k, c=c), "matlab-listing", HIT,
                options=dict(circuit="kvl", energy=True))


CASES = [
    *[_stiff(k, c) for k in (1e5, 1e6, 1e8, 1e10) for c in (0.0, 10.0, 1e3)],
    Case("chatter-stick", "chattering", "ac-stop", 1.0, dict(V=0.0, k=1e6, c=20.0), x0={"x": 1e-3}),
    Case("stuck-unstick", "chattering", "ac-stop", 0.05, dict(V=200.0), x0={"x": 0.0}, flags={"stuck_bar": 1.0},
         options=dict(ac_sign="listing")),
    Case("stuck-held", "chattering", "ac-stop", 0.2, dict(V=200.0), x0={"x": 0.0}, flags={"stuck_bar": 1.0}),
    Case("graze-dc-only", "grazing", "dc-only", 1.0, x0={"x": 0.0}, expect="ill-conditioned",
         note="an exact graze: from rest on the stop the symmetric cubic potential returns the bar to the "
              "stop with zero speed, so whether each return is a contact at ~1e-6 m/s or a turning point "
              "1e-16 m above the stop is decided by rounding; the states agree to ~1e-15"),
    Case("graze-thesis-1um", "grazing", "thesis-1dof", 1.0, dict(V=90.0, relay_hz=9.0), "matlab-listing"),
    Case("relay-0.5Hz", "extreme", "thesis-1dof", 4.0, dict(V=90.0, relay_hz=0.5), "matlab-listing", HIT),
    Case("relay-100Hz", "extreme", "thesis-1dof", 0.5, dict(V=90.0, relay_hz=100.0), "matlab-listing", HIT),
    Case("V-300", "extreme", "thesis-1dof", 0.5, dict(V=300.0, relay_hz=9.0), "matlab-listing", HIT),
    Case("R-1ohm", "extreme", "thesis-1dof", 0.5, dict(V=90.0, relay_hz=9.0, R=1.0), "matlab-listing", HIT),
    Case("C-1e-6", "extreme", "thesis-1dof", 0.5, dict(V=90.0, relay_hz=9.0, C=1e-6), "matlab-listing", HIT),
    Case("C-1e-1", "extreme", "thesis-1dof", 0.5, dict(V=90.0, relay_hz=9.0, C=1e-1), "matlab-listing", HIT),
    Case("thrown-out", "extreme", "thesis-1dof", 1.0, dict(V=90.0, relay_hz=9.0), "matlab-listing",
         {"x": 0.0625, "v": 10.0}, expect="escaped"),
    Case("through-the-stop", "extreme", "ac-stop", 1.0, dict(V=0.0, k=1e2, c=0.0), x0={"x": 1e-3, "v": -5.0},
         expect="escaped"),
    Case("non-finite", "extreme", "dc-only", 1.0, dict(a3=-1e300), x0={"x": 0.1, "v": 0.0},
         expect="numerical-failure"),
    Case("precision-real128", "precision", "thesis-1dof", 0.3, dict(V=90.0, relay_hz=9.0), "matlab-listing", HIT,
         tol=1e-15, extended="real128"),
]
QUICK = ["stiff-k1e+05-c0", "stiff-k1e+08-c0", "stiff-k1e+10-c10", "chatter-stick", "stuck-unstick", "stuck-held",
         "graze-thesis-1um", "relay-100Hz", "thrown-out", "through-the-stop", "non-finite"]


def _run(case: Case, fp_type, tol):
    sc, table = resolve(case.scene, case.params, case.preset, **case.options)
    values = {k: v for k, (v, _) in table.items()}
    y0 = sc.system.state_vector(sc.initial_state(**case.x0))
    if fp_type is not float:
        y0 = np.array([fp_type(float(v)) for v in y0], dtype=fp_type if fp_type is np.longdouble else object)
        if fp_type is not np.longdouble:
            y0 = np.array(list(y0), dtype=hy.real128)
    run = HybridRun(sc.system, values, y0, tol=tol, fp_type=fp_type, max_events=case.max_events,
                    flags=case.flags or None)
    clock = _time.perf_counter()
    status, failure, t_fail, y_fail = "ok", "", math.nan, None
    try:
        run.advance(case.t_end)
    except Escaped as exc:
        status, failure, t_fail = "escaped", str(exc), exc.t
    except IntegrationFailure as exc:
        status = "event-cap" if "events by" in str(exc) else "numerical-failure"
        failure, t_fail, y_fail = str(exc), exc.t, exc.state
    return run, status, failure, t_fail, y_fail, _time.perf_counter() - clock


def run_case(case: Case) -> dict:
    """Run ``case`` in double and extended precision; measured errors and a verdict."""
    run, status, failure, t_fail, y_fail, seconds = _run(case, float, case.tol)
    out = {"case": case.name, "group": case.group, "scene": case.scene, "t_end": case.t_end, "tol": case.tol,
           "status": status, "failure": failure, "failure_time": t_fail, "run_seconds": seconds,
           "compile_seconds": run.compile_seconds, "steps": run.n_steps, "events": run.n_events,
           "expected": case.expect, "note": case.note}
    imp = impact_table(run)
    out["contacts"] = imp["t"].size
    contact_steps = run.steps_where(contact=1) if "contact" in run.flags else 0
    out["steps_per_contact"] = contact_steps / imp["t"].size if imp["t"].size else math.nan
    out["max_penetration"] = float(np.max(imp["penetration"])) if imp["t"].size else math.nan
    p = run.params
    if imp["t"].size and "k" in p:
        v0 = abs(imp["velocity"][0])
        out["penetration_linear_estimate"] = v0 * math.sqrt(p["m"] / p["k"])
        out["penetration_ratio"] = float(imp["penetration"][0]) / out["penetration_linear_estimate"]
    else:
        out["penetration_linear_estimate"] = out["penetration_ratio"] = math.nan
    out["energy_balance_error"] = _energy_error(run, case) if case.options.get("energy") else math.nan
    stick = [t for (t, fl), (_, prev) in zip(run.flag_log[1:], run.flag_log[:-1])
             if fl.get("stuck_bar") == 1 and prev.get("stuck_bar") == 0]
    unstick = [ev.t for ev in run.events if ev.name == "unstick"]
    out["stick_time"] = stick[0] if stick else (0.0 if case.flags.get("stuck_bar") else math.nan)
    out["unstick_time"] = unstick[0] if unstick else math.nan
    if status != "ok":
        out.update(state_error=math.nan, event_time_error=math.nan, event_count_difference=0, bound=math.nan,
                   extended_seconds=math.nan)
        if y_fail is not None:
            out["failure"] += f"; state {np.array2string(np.asarray(y_fail, float), precision=4)}"
        out["verdict"] = status
        return out
    fp = np.longdouble if case.extended == "longdouble" else hy.real128
    ext_tol = 1e-19 if fp is np.longdouble else 1e-28
    ref, ref_status, *_rest, ref_seconds = _run(case, fp, ext_tol)
    ref_imp = impact_table(ref)
    y = np.array(run.ta.state, dtype=float)
    y_ref = np.array([float(v) for v in ref.ta.state])
    scale = np.maximum(1.0, np.abs(y_ref))
    out["state_error"] = float(np.max(np.abs(y - y_ref) / scale))
    out["event_count_difference"] = int(ref_imp["t"].size - imp["t"].size)
    out["event_time_error"] = (float(np.max(np.abs(imp["t"] - ref_imp["t"]))) if imp["t"].size else 0.0) \
        if out["event_count_difference"] == 0 else math.nan
    out["bound"] = max(1e3, run.n_steps) * case.tol
    out["extended_seconds"] = ref_seconds
    out["extended"] = case.extended
    good = (ref_status == "ok" and out["event_count_difference"] == 0 and out["state_error"] <= out["bound"]
            and (out["event_time_error"] <= out["bound"] * max(1.0, case.t_end)))
    out["verdict"] = "ok" if good else "ill-conditioned"
    return out


def _energy_error(run, case):
    """|E(t) - E(0) - (W_src - E_R - E_c)| relative to the energy throughput (kvl, energy option)."""
    sc, table = resolve(case.scene, case.params, case.preset, **case.options)
    values = {k: v for k, (v, _) in table.items()}
    y0 = sc.system.state_vector(sc.initial_state(**case.x0))
    flags0 = sc.system.initial_flags(0.0, values)
    E0 = float(run.system.evaluate(["E_mech_el"], y0, values, flags0, 0.0)[0])
    y = np.array(run.ta.state, dtype=float)
    E1 = float(run.system.evaluate(["E_mech_el"], y, run.params, run.flags, run.t)[0])
    names = run.system.state_names
    W, ER, Ec = (y[names.index(n)] for n in ("W_src", "E_R", "E_c"))
    scale = abs(W) + ER + Ec + abs(E0) + abs(E1)
    return abs((E1 - E0) - (W - ER - Ec)) / scale


def run_suite(quick: bool = False, names=None, progress: bool = True) -> xr.Dataset:
    """Run the suite (``quick``: the reduced one) into a Dataset with one row per case."""
    cases = [c for c in CASES if (names is None or c.name in names) and (not quick or c.name in QUICK)]
    rows = []
    for i, case in enumerate(cases):
        if progress:
            print(f"[{i + 1}/{len(cases)}] {case.name} ...", file=sys.stderr, flush=True)
        rows.append(run_case(case))
    return _dataset(rows, quick)


_VARS = {  # name: (units, long_name)
    "t_end": ("s", "simulated time"), "tol": ("1", "heyoka tolerance (double run)"),
    "run_seconds": ("s", "wall time of the double run"), "extended_seconds": ("s", "wall time of the extended run"),
    "compile_seconds": ("s", "one-time compile cost of the double integrator"),
    "steps": ("1", "Taylor steps (double run)"), "events": ("1", "guard crossings (double run)"),
    "contacts": ("1", "contacts"), "steps_per_contact": ("1", "Taylor steps per contact"),
    "max_penetration": ("m", "maximum penetration into the stop"),
    "penetration_linear_estimate": ("m", "first contact: v_impact sqrt(m/k)"),
    "penetration_ratio": ("1", "first contact: penetration / linear estimate"),
    "energy_balance_error": ("1", "energy balance residual / energy throughput (kvl circuit)"),
    "state_error": ("1", "final state: max |double - extended| / max(1, |extended|)"),
    "event_time_error": ("s", "largest contact-time difference double vs extended (NaN: counts differ)"),
    "event_count_difference": ("1", "contacts (extended) - contacts (double)"),
    "bound": ("1", "error bound implied by the tolerance: max(1e3, steps) * tol"),
    "failure_time": ("s", "time of escape or failure (NaN: none)"),
    "stick_time": ("s", "first time the bar sticks on the stop (NaN: never)"),
    "unstick_time": ("s", "first time a stuck bar leaves the stop (NaN: never)"),
}


def _dataset(rows, quick) -> xr.Dataset:
    ds = xr.Dataset(coords={"case": ("case", [r["case"] for r in rows], {"long_name": "case name", "units": "1"})})
    for name, (units, long_name) in _VARS.items():
        ds[name] = ("case", np.array([r.get(name, math.nan) for r in rows], dtype=float),
                    {"units": units, "long_name": long_name})
    ds["verdict"] = ("case", np.array([VERDICTS.index(r["verdict"]) for r in rows], np.int8), {
        "units": "1", "long_name": "verdict", "flag_values": np.arange(len(VERDICTS), dtype=np.int8),
        "flag_meanings": " ".join(v.replace("-", "_") for v in VERDICTS)})
    ds["expected"] = ("case", np.array([VERDICTS.index(r["expected"]) for r in rows], np.int8), {
        "units": "1", "long_name": "expected verdict", "flag_values": np.arange(len(VERDICTS), dtype=np.int8),
        "flag_meanings": " ".join(v.replace("-", "_") for v in VERDICTS)})
    for key in ("group", "scene", "failure", "note"):
        ds[key] = ("case", np.array([str(r.get(key, "")) for r in rows]), {"units": "1", "long_name": key})
    ds.attrs.update({"title": "bifurc numerical stability suite", "suite": "quick" if quick else "full",
                     "heyoka_version": hy.__version__, "bound_rule": "max(1e3, steps) * tol relative",
                     "Conventions": "CF-1.10"})
    return ds


def _sentence(r) -> str:
    v = VERDICTS[int(r["verdict"])]
    if v == "ok":
        return ""
    if v == "escaped":
        return f"left the model's domain at t = {float(r['failure_time']):.6g} s ({r['failure'].values})."
    if v == "numerical-failure":
        return f"reported, not a crash: {r['failure'].values}."
    if v == "event-cap":
        return f"runaway stopped by the event cap at t = {float(r['failure_time']):.6g} s."
    why = []
    if int(r["event_count_difference"]):
        why.append(f"the extended run has {int(r['event_count_difference']):+d} contacts")
    if float(r["state_error"]) > float(r["bound"]):
        why.append(f"final states differ by {float(r['state_error']):.2g} > bound {float(r['bound']):.2g}")
    if not why:
        why.append(f"contact times differ by {float(r['event_time_error']):.2g} s")
    return "double and extended precision disagree: " + "; ".join(why) + \
        " (final states differ by {:.2g}).".format(float(r["state_error"]))


def write_report(ds: xr.Dataset, folder) -> Path:
    """Write ``stability.md`` and ``stability.nc`` into ``folder``."""
    from .storage_io import write_netcdf_atomic
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    write_netcdf_atomic(ds, folder / "stability.nc")
    lines = [f"# Numerical stability suite ({ds.attrs['suite']})", "", __doc__.split("\n\n", 1)[1].strip(), "",
             "| case | group | verdict (expected) | state error | bound | event-time error [s] | contacts (Δ ext) | "
             "steps | steps/contact | penetration / v sqrt(m/k) | energy balance | run [s] | extended [s] |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    f = lambda x, p=".2g": "-" if not np.isfinite(x) else format(float(x), p)  # noqa: E731
    notes = []
    for i in range(ds.sizes["case"]):
        r = ds.isel(case=i)
        v, e = VERDICTS[int(r.verdict)], VERDICTS[int(r.expected)]
        lines.append(f"| {str(r.case.values)} | {r.group.values} | {v} ({e}) | {f(r.state_error)} | {f(r.bound)} | "
                     f"{f(r.event_time_error)} | {int(r.contacts)} ({int(r.event_count_difference):+d}) | "
                     f"{int(r.steps)} | {f(r.steps_per_contact, '.1f')} | {f(r.penetration_ratio, '.4f')} | "
                     f"{f(r.energy_balance_error)} | {f(r.run_seconds, '.3f')} | {f(r.extended_seconds, '.2f')} |")
        s = _sentence(r)
        if s:
            notes.append(f"- **{str(r.case.values)}**: {s}" + (f" Expected: {r.note.values}." if str(r.note.values) else ""))
        if np.isfinite(r.stick_time) or np.isfinite(r.unstick_time):
            notes.append(f"- **{str(r.case.values)}**: bar stuck on the stop from t = {f(r.stick_time, '.6g')} s, "
                         f"leaves at t = {f(r.unstick_time, '.9g')} s.")
    (folder / "stability.md").write_text("\n".join(lines + [""] + notes) + "\n")
    return folder / "stability.md"
