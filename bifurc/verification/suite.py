"""Numerical stability suite: stiff, chattering, grazing and extreme cases, with errors reported.

Each case runs in double precision, again in double at a 1000 times tighter tolerance, and
again in extended precision (long double, or real128 where marked).  The verdict says whether
the double result can be trusted:

- ``ok``: the same events (contact, release, stick, unstick) in all three runs, and final
  state and event times within the bound the tolerance implies (``bound = max(1e3, steps) * tol``
  relative: heyoka's tol is a local error per step, accumulated over the steps);
- ``ill-conditioned``: the runs diverge beyond that bound.  The divergence is reported, with
  the same comparison over a short horizon: agreement there means a sensitive orbit (an
  error amplified by the dynamics), not a wrong integrator;
- ``escaped`` (with the time, compared with the extended run's), ``numerical-failure``
  (non-finite state, with time and state), ``event-cap`` (a runaway stopped by the per-run or
  per-relay-period event cap).
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

from maps.engines.scalar import HybridRun
from maps.hybrid import Escaped, EventCap, IntegrationFailure
from maps.impacts import free_flight_minima, impact_table
from maps.provenance import cf_attrs, recorded
from maps.problem import problem

from ..storage.build import dataset

VERDICTS = ("ok", "ill-conditioned", "escaped", "numerical-failure", "event-cap")
#: events whose count and times are compared between runs (observations such as "deepest" are not)
COMPARED_EVENTS = ("contact", "release", "stick", "unstick")
HIT = {"x": 0.005, "v": -3.0}  # 5 mm above the stop moving down against the ~33 N DC pull: hits at ~2.6 m/s
TOP = 0.125                     # thesis-1dof/dc-only: the DC well's far turning point above a rest on the stop [m]


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
    options: dict = field(default_factory=dict)   # structural options: circuit, ac_sign, energy, dc, stick_speed
    extended: str = "longdouble"                  # or "real128"
    expect: str = "ok"
    max_events: int = 20_000
    max_events_per_period: int | None = 2_000     # per relay period (scenes with a relay)
    note: str = ""                                # why the expected verdict is what it is


def _stiff(k, c):
    return Case(f"stiff-k{k:.0e}-c{c:g}", "stiff stop", "thesis-1dof", 0.02,
                dict(V=90.0, relay_hz=9.0, k=k, c=c), "matlab-listing", HIT,
                options=dict(circuit="kvl", energy=True))


_RELAY_PUSH = dict(V=90.0, relay_hz=5.0, k=1e8, c=1e3)  # no DC; listing-sign AC lifts the bar each ON half
CASES = [
    *[_stiff(k, c) for k in (1e5, 1e6, 1e8, 1e10) for c in (0.0, 10.0, 1e3)],
    Case("chatter-stick", "chattering", "ac-stop", 1.0, dict(V=0.0, k=1e6, c=20.0), x0={"x": 1e-3}),
    Case("chatter-relay", "chattering", "thesis-1dof", 1.0, _RELAY_PUSH, "matlab-listing", {"x": 1e-3},
         options=dict(dc=False, ac_sign="listing")),
    Case("chatter-no-stick", "chattering", "thesis-1dof", 1.0, _RELAY_PUSH, "matlab-listing", {"x": 1e-3},
         options=dict(dc=False, ac_sign="listing", stick_speed=0.0), max_events_per_period=30, expect="event-cap",
         note="the stick mode switched off (stick_speed = 0): the bar settles on the stop through an unbounded "
              "train of contact oscillations; the per-period cap turns it into a flagged result"),
    Case("stuck-unstick", "chattering", "ac-stop", 0.05, dict(V=200.0), x0={"x": 0.0}, flags={"stuck_bar": 1.0},
         options=dict(ac_sign="listing")),
    Case("stuck-held", "chattering", "ac-stop", 0.2, dict(V=200.0), x0={"x": 0.0}, flags={"stuck_bar": 1.0}),
    Case("stuck-2dof", "chattering", "thesis-2dof", 0.05, dict(V=0.0, dc_scale=0.04, F_static=-31.1),
         x0={"x1": 0.0}, flags={"stuck_bar": 1.0}),
    Case("prototype-stick", "chattering", "prototype", 1.0, dict(V=90.0)),
    Case("graze-dc-only", "grazing", "dc-only", 1.0, x0={"x": 0.0}, expect="ill-conditioned",
         note="an exact graze: from rest on the stop the symmetric cubic potential returns the bar to the "
              "stop with zero speed, so whether each return is a contact at ~1e-6 m/s or a turning point "
              "1e-16 m above the stop is decided by rounding, and one contact more or less changes the rest of the run"),
    Case("graze-miss-1nm", "grazing", "dc-only", 1.0, x0={"x": TOP - 1e-9}),
    Case("graze-hit-1nm", "grazing", "dc-only", 1.0, x0={"x": TOP + 1e-9}),
    Case("graze-miss-1um", "grazing", "dc-only", 1.0, x0={"x": TOP - 1e-6}),
    Case("graze-thesis", "grazing", "thesis-1dof", 1.0, dict(V=90.0, relay_hz=9.0), "matlab-listing"),
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
    Case("free-fall-out", "extreme", "ac-only", 1.0, dict(V=0.0), x0={"x": 0.0}, expect="escaped",
         note="no current, no stop: the bar falls freely 0.2 m past the AC centre, in sqrt(2 h / g)"),
    Case("non-finite", "extreme", "dc-only", 1.0, dict(a3=-1e300), x0={"x": 0.1, "v": 0.0},
         expect="numerical-failure"),
    Case("precision-real128", "precision", "thesis-1dof", 0.3, dict(V=90.0, relay_hz=9.0), "matlab-listing", HIT,
         tol=1e-15, extended="real128"),
    Case("precision-long-9Hz", "precision", "thesis-1dof", 30.0, dict(V=90.0, relay_hz=9.0), "matlab-listing",
         expect="ill-conditioned",
         note="270 relay periods of an orbit that reaches no attractor (free flight through the whole DC well, "
              "weak electrical damping): rounding differences grow to the size of the orbit after ~10 s; "
              "over 3 s double and extended precision agree to the tolerance"),
]
QUICK = ["stiff-k1e+05-c0", "stiff-k1e+08-c0", "stiff-k1e+10-c10", "chatter-stick", "chatter-relay",
         "chatter-no-stick", "stuck-unstick", "stuck-held", "stuck-2dof", "prototype-stick", "graze-miss-1nm", "graze-hit-1nm", "graze-thesis",
         "relay-100Hz", "thrown-out", "through-the-stop", "free-fall-out", "non-finite", "precision-long-9Hz"]


def case_scene(case: Case):
    """The case's scene (with its structural options) and validated parameter values."""
    pb = problem(case.scene, case.preset, case.params, **dict(case.options or {}))
    return pb.scene, pb.parameter_values()


def _typed_state(y0, fp_type):
    if fp_type is float:
        return y0
    if fp_type is np.longdouble:
        return np.array([np.longdouble(float(v)) for v in y0], dtype=np.longdouble)
    return np.array([hy.real128(float(v)) for v in y0], dtype=hy.real128)


def _run(case: Case, fp_type=float, tol=None, t_end=None) -> dict:
    """One integration of ``case``; failures are recorded, never raised."""
    sc, values = case_scene(case)
    y0 = _typed_state(sc.system.state_vector(sc.initial_state(**case.x0)), fp_type)
    run = HybridRun(sc.system, values, y0, tol=tol or case.tol, fp_type=fp_type, max_events=case.max_events,
                    max_events_per_period=case.max_events_per_period, flags=case.flags or None,
                    steps_by_mode=True)    # steps per contact (_mechanics)
    clock = _time.perf_counter()
    res = {"run": run, "status": "ok", "failure": "", "t_fail": math.nan, "y_fail": None}
    try:
        run.advance(case.t_end if t_end is None else t_end)
    except Escaped as exc:
        res.update(status="escaped", failure=str(exc), t_fail=exc.t)
    except EventCap as exc:
        res.update(status="event-cap", failure=str(exc), t_fail=exc.t, y_fail=exc.state)
    except IntegrationFailure as exc:
        res.update(status="numerical-failure", failure=str(exc), t_fail=exc.t, y_fail=exc.state)
    res["seconds"] = _time.perf_counter() - clock
    return res


def event_log(run) -> list:
    """``(name, t)`` of the compared events (contact, release, stick, unstick) of a run."""
    return [(ev.name, ev.t) for ev in run.events if ev.name in COMPARED_EVENTS]


def compare_runs(a, b) -> dict:
    """Differences of ``b`` from ``a``: final state (relative to max(1, |b|)), event count
    and largest event-time difference (NaN when the event sequences differ)."""
    ya = np.array([float(v) for v in a.ta.state])
    yb = np.array([float(v) for v in b.ta.state])
    la, lb = event_log(a), event_log(b)
    same = [n for n, _ in la] == [n for n, _ in lb]
    return {"state": float(np.max(np.abs(ya - yb) / np.maximum(1.0, np.abs(yb)))),
            "count": len(lb) - len(la),
            "time": (max((abs(ta - tb) for (_, ta), (_, tb) in zip(la, lb)), default=0.0) if same else math.nan)}


def _extended(case):
    return (np.longdouble, 1e-19) if case.extended == "longdouble" else (hy.real128, 1e-28)


def run_case(case: Case) -> dict:
    """Run ``case`` in double, tighter double and extended precision: errors and a verdict."""
    first = _run(case)
    run, status = first["run"], first["status"]
    out = {"case": case.name, "group": case.group, "scene": case.scene, "t_end": case.t_end, "tol": case.tol,
           "status": status, "failure": first["failure"], "failure_time": first["t_fail"],
           "run_seconds": first["seconds"], "compile_seconds": run.compile_seconds, "steps": run.n_steps,
           "events": run.n_events, "max_period_events": run.max_period_events, "expected": case.expect,
           "note": case.note, "extended": case.extended}
    out.update(_mechanics(run, case))
    nan = math.nan
    out.update(state_error=nan, event_time_error=nan, event_count_difference=0, tight_state_error=nan,
               tight_event_time_error=nan, tight_event_count_difference=0, bound=max(1e3, run.n_steps) * case.tol,
               extended_seconds=nan, short_horizon=nan, short_bound=nan, short_state_error=nan, short_event_time_error=nan,
               failure_time_difference=nan)
    if status in ("numerical-failure", "event-cap"):
        if first["y_fail"] is not None:
            out["failure"] += f"; state {np.array2string(np.asarray(first['y_fail'], float), precision=6)}"
        out["verdict"] = status
        return out
    fp, ext_tol = _extended(case)
    ref = _run(case, fp, ext_tol)
    out["extended_seconds"] = ref["seconds"]
    if status == "escaped":  # when does the extended run escape?
        out["failure_time_difference"] = abs(ref["t_fail"] - first["t_fail"]) if ref["status"] == "escaped" else nan
        out["verdict"] = status
        return out
    tight = _run(case, float, max(case.tol * 1e-3, 1e-16))
    d_ext, d_tight = compare_runs(run, ref["run"]), compare_runs(run, tight["run"])
    out.update(state_error=d_ext["state"], event_time_error=d_ext["time"], event_count_difference=d_ext["count"],
               tight_state_error=d_tight["state"], tight_event_time_error=d_tight["time"],
               tight_event_count_difference=d_tight["count"])
    bound = out["bound"]
    good = (ref["status"] == "ok" and tight["status"] == "ok" and d_ext["count"] == 0 and d_tight["count"] == 0
            and d_ext["state"] <= bound and d_ext["time"] <= bound * max(1.0, case.t_end)
            and d_tight["time"] <= bound * max(1.0, case.t_end))
    out["verdict"] = "ok" if good else "ill-conditioned"
    if not good:  # is the integrator wrong, or the orbit sensitive? the same comparison over a tenth
        horizon = case.t_end / 10
        short, short_ref = _run(case, t_end=horizon), _run(case, fp, ext_tol, t_end=horizon)
        d = compare_runs(short["run"], short_ref["run"])
        out.update(short_horizon=horizon, short_state_error=d["state"], short_event_time_error=d["time"],
                   short_bound=max(1e3, short["run"].n_steps) * case.tol)
    return out


def _mechanics(run, case) -> dict:
    """Contacts, steps per contact, penetration, energy balance, sticking and clearance of one run."""
    imp = impact_table(run)
    n = imp["t"].size
    out = {"contacts": n}
    contact_steps = run.steps_where(contact=1) if "contact" in run.flags else 0
    out["steps_per_contact"] = contact_steps / n if n else math.nan
    out["max_penetration"] = float(np.max(imp["penetration"])) if n else math.nan
    p = run.params
    if n and "k" in p and "m" in p:
        out["impact_speed"] = abs(float(imp["velocity"][0]))
        out["penetration_linear_estimate"] = out["impact_speed"] * math.sqrt(p["m"] / p["k"])
        out["penetration_ratio"] = float(imp["penetration"][0]) / out["penetration_linear_estimate"]
    else:
        out["impact_speed"] = out["penetration_linear_estimate"] = out["penetration_ratio"] = math.nan
    out["energy_balance_error"] = _energy_error(run, case) if case.options.get("energy") else math.nan
    sticks = [ev.t for ev in run.events if ev.name == "stick"]
    unsticks = [ev.t for ev in run.events if ev.name == "unstick"]
    out["sticks"], out["unsticks"] = len(sticks), len(unsticks)
    out["stick_time"] = sticks[0] if sticks else (0.0 if case.flags.get("stuck_bar") else math.nan)
    out["unstick_time"] = unsticks[0] if unsticks else math.nan
    out["time_on_stop"] = _time_stuck(run) if "stuck_bar" in run.flags else math.nan
    mins = free_flight_minima(run)["gap"]
    out["min_clearance"] = float(np.min(mins)) if mins.size else math.nan
    return out


def _time_stuck(run) -> float:
    """Total time [s] with the flag stuck_bar set, from the run's flag log."""
    total, since = 0.0, None
    for t, flags in run.flag_log:
        if flags.get("stuck_bar") == 1 and since is None:
            since = t
        elif flags.get("stuck_bar") != 1 and since is not None:
            total, since = total + t - since, None
    return total + (run.t - since if since is not None else 0.0)


def _energy_error(run, case):
    """|E(t) - E(0) - (W_src - E_R - E_c)| relative to the energy throughput (kvl, energy option)."""
    sc, values = case_scene(case)
    y0 = sc.system.state_vector(sc.initial_state(**case.x0))
    E0 = float(run.system.evaluate(["E_mech_el"], y0, values, sc.system.initial_flags(0.0, values), 0.0)[0])
    y = np.array(run.ta.state, dtype=float)
    E1 = float(run.system.evaluate(["E_mech_el"], y, run.params, run.flags, run.t)[0])
    names = run.system.state_names
    W, ER, Ec = (y[names.index(n)] for n in ("W_src", "E_R", "E_c"))
    scale = abs(W) + ER + Ec + abs(E0) + abs(E1)
    return abs((E1 - E0) - (W - ER - Ec)) / scale


@recorded("bifurc.verification.suite.run_suite")
def run_suite(quick: bool = False, names=None, progress: bool = True) -> xr.Dataset:
    """Run the suite (``quick``: the reduced one; ``names``: only these cases) into a Dataset
    with one row per case.  Progress goes to stderr."""
    if names:
        unknown = sorted(set(names) - {c.name for c in CASES})
        if unknown:
            from maps.parameters import ParameterError
            raise ParameterError(f"unknown stability case {unknown[0]!r}; cases: {', '.join(c.name for c in CASES)}")
    cases = [c for c in CASES if (not names or c.name in names) and (not quick or c.name in QUICK)]
    rows = []
    clock = _time.perf_counter()
    for i, case in enumerate(cases):
        if progress:
            print(f"[{i + 1}/{len(cases)}] {case.name} ...", end="", file=sys.stderr, flush=True)
        rows.append(run_case(case))
        if progress:
            print(f" {rows[-1]['verdict']} ({_time.perf_counter() - clock:.1f} s)", file=sys.stderr, flush=True)
    return _dataset(rows, quick)


_VARS = {  # name: (units, long_name)
    "t_end": ("s", "simulated time"), "tol": ("1", "heyoka tolerance (double run)"),
    "run_seconds": ("s", "wall time of the double run"), "extended_seconds": ("s", "wall time of the extended run"),
    "compile_seconds": ("s", "one-time compile cost of the double integrator"),
    "steps": ("1", "Taylor steps (double run)"), "events": ("1", "guard crossings and stick transitions (double run)"),
    "max_period_events": ("1", "most events in one relay period (double run)"),
    "contacts": ("1", "contacts"), "steps_per_contact": ("1", "Taylor steps in contact per contact"),
    "max_penetration": ("m", "maximum penetration into the stop"),
    "impact_speed": ("m s-1", "first contact: impact speed"),
    "penetration_linear_estimate": ("m", "first contact: v_impact sqrt(m/k)"),
    "penetration_ratio": ("1", "first contact: penetration / linear estimate"),
    "energy_balance_error": ("1", "energy balance residual / energy throughput (kvl circuit)"),
    "sticks": ("1", "times the bar sticks on the stop"), "unsticks": ("1", "times a stuck bar leaves the stop"),
    "stick_time": ("s", "first time the bar sticks on the stop (NaN: never)"),
    "unstick_time": ("s", "first time a stuck bar leaves the stop (NaN: never)"),
    "time_on_stop": ("s", "total time stuck on the stop"),
    "min_clearance": ("m", "smallest free-flight gap to the stop (NaN: no free-flight minimum)"),
    "state_error": ("1", "final state: max |double - extended| / max(1, |extended|)"),
    "event_time_error": ("s", "largest event-time difference double vs extended (NaN: event sequences differ)"),
    "event_count_difference": ("1", "events (extended) - events (double), contact/release/stick/unstick"),
    "tight_state_error": ("1", "final state: max |double - double at tol/1000| / max(1, |tight|)"),
    "tight_event_time_error": ("s", "largest event-time difference double vs tol/1000 (NaN: sequences differ)"),
    "tight_event_count_difference": ("1", "events (tol/1000) - events (tol)"),
    "bound": ("1", "error bound implied by the tolerance: max(1e3, steps) * tol"),
    "short_horizon": ("s", "horizon of the short comparison of an ill-conditioned case (NaN: not run)"),
    "short_state_error": ("1", "final state error double vs extended over the short horizon"),
    "short_bound": ("1", "error bound implied by the tolerance over the short horizon"),
    "short_event_time_error": ("s", "event-time error double vs extended over the short horizon"),
    "failure_time": ("s", "time of escape, failure or event cap (NaN: none)"),
    "failure_time_difference": ("s", "escape time: |double - extended| (NaN: not escaped)"),
}


def _flag_attrs(long_name):
    return {"units": "1", "long_name": long_name, "flag_values": np.arange(len(VERDICTS), dtype=np.int8),
            "flag_meanings": " ".join(v.replace("-", "_") for v in VERDICTS)}


def _dataset(rows, quick) -> xr.Dataset:
    ds = dataset("stability", {"case": ("case", [r["case"] for r in rows], {"long_name": "case name", "units": "1"})})
    for name, (units, long_name) in _VARS.items():
        ds[name] = ("case", np.array([r.get(name, math.nan) for r in rows], dtype=float),
                    {"units": units, "long_name": long_name})
    ds["verdict"] = ("case", np.array([VERDICTS.index(r["verdict"]) for r in rows], np.int8), _flag_attrs("verdict"))
    ds["expected"] = ("case", np.array([VERDICTS.index(r["expected"]) for r in rows], np.int8),
                      _flag_attrs("expected verdict"))
    for key, long_name in (("group", "case group"), ("scene", "scene"), ("extended", "extended floating-point type"),
                           ("failure", "failure message with time and state"), ("note", "why the expected verdict")):
        ds[key] = ("case", np.array([str(r.get(key, "")) for r in rows]), {"units": "1", "long_name": long_name})
    ds.attrs.update({"title": "bifurc numerical stability suite", "suite": "quick" if quick else "full",
                     "heyoka_version": hy.__version__, "bound_rule": "max(1e3, steps) * tol relative",
                     **cf_attrs("numerical stability suite")})
    return ds


def _g(x, p=".2g"):
    return "-" if not np.isfinite(float(x)) else format(float(x), p)


def sentence(r) -> str:
    """One sentence explaining a non-ok verdict of one row of the suite's Dataset."""
    v = VERDICTS[int(r["verdict"])]
    if v == "ok":
        return ""
    if v == "escaped":
        diff = float(r["failure_time_difference"])
        return (f"left the model's domain at t = {float(r['failure_time']):.9g} s ({r['failure'].values}); "
                f"the extended-precision run escapes {_g(diff)} s apart.")
    if v == "numerical-failure":
        return f"reported, not a crash: {r['failure'].values}."
    if v == "event-cap":
        return (f"runaway stopped by the event cap at t = {float(r['failure_time']):.6g} s "
                f"({r['failure'].values}).")
    why = []
    for prefix, who in (("", "extended precision"), ("tight_", "a 1000x tighter tolerance")):
        n = int(r[prefix + "event_count_difference"])
        if n:
            why.append(f"{who} has {n:+d} events")
    if float(r["state_error"]) > float(r["bound"]):
        why.append(f"final states differ from extended precision by {_g(r['state_error'])} > bound {_g(r['bound'])}")
    if not why:
        why.append(f"event times differ by {_g(r['event_time_error'])} s")
    text = "double and reference runs disagree: " + "; ".join(why) + "."
    if np.isfinite(float(r["short_horizon"])):
        ok = float(r["short_state_error"]) <= float(r["short_bound"])
        text += (f" Over the first {float(r['short_horizon']):.3g} s they agree to {_g(r['short_state_error'])} "
                 f"(bound {_g(r['short_bound'])}; event times {_g(r['short_event_time_error'])} s): "
                 + ("a sensitive orbit amplifying rounding, not an integration error." if ok
                    else "they disagree there too."))
    return text


def _stick_sentence(r) -> str:
    n, m = int(r.sticks), int(r.unsticks)
    parts = [f"the bar sticks on the stop {n} time{'s' if n != 1 else ''} (first at t = {_g(r.stick_time, '.9g')} s)"
             if n else "the bar starts stuck on the stop"]
    parts.append(f"leaves it {m} time{'s' if m != 1 else ''} (first at t = {_g(r.unstick_time, '.9g')} s)"
                 if m else "never leaves it")
    return " and ".join(parts) + f"; {_g(r.time_on_stop, '.4g')} s on the stop in all."


def write_report(ds: xr.Dataset, folder, overwrite: bool = False) -> Path:
    """Write ``stability.md`` and ``stability.nc`` into ``folder`` (existing ones refused unless ``overwrite``)."""
    from ..storage.files import refuse_existing, write_netcdf
    folder = Path(folder)
    for name in ("stability.nc", "stability.md"):
        refuse_existing(folder / name, overwrite)
    write_netcdf(ds, folder / "stability.nc", overwrite=overwrite)
    lines = [f"# Numerical stability suite ({ds.attrs['suite']})", "", __doc__.split("\n\n", 1)[1].strip(), ""]
    notes = []
    for group in dict.fromkeys(str(g) for g in ds.group.values):
        sub = ds.isel(case=np.flatnonzero(ds.group.values == group))
        lines += [f"## {group}", "",
                  "| case | verdict (expected) | state error (ext / tight) | bound | event-time error [s] | "
                  "events Δ (ext / tight) | contacts | steps | steps/contact | events/period max | "
                  "penetration / v√(m/k) | energy balance | stuck [s] | run [s] | extended [s] |",
                  "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
        for i in range(sub.sizes["case"]):
            r = sub.isel(case=i)
            v, e = VERDICTS[int(r.verdict)], VERDICTS[int(r.expected)]
            lines.append(
                f"| {str(r.case.values)} | {v} ({e}) | {_g(r.state_error)} / {_g(r.tight_state_error)} | "
                f"{_g(r.bound)} | {_g(r.event_time_error)} | {int(r.event_count_difference):+d} / "
                f"{int(r.tight_event_count_difference):+d} | {int(r.contacts)} | {int(r.steps)} | "
                f"{_g(r.steps_per_contact, '.1f')} | {int(r.max_period_events)} | {_g(r.penetration_ratio, '.4f')} | "
                f"{_g(r.energy_balance_error)} | {_g(r.time_on_stop, '.4g')} | {_g(r.run_seconds, '.3f')} | "
                f"{_g(r.extended_seconds, '.2f')} |")
            s = sentence(r)
            name = str(r.case.values)
            if s:
                notes.append(f"- **{name}** ({v}): {s}" + (f" Expected: {r.note.values}." if str(r.note.values) else ""))
            if int(r.sticks) or int(r.unsticks):
                notes.append(f"- **{name}**: " + _stick_sentence(r))
        lines.append("")
    (folder / "stability.md").write_text("\n".join(lines + ["## Notes", ""] + notes) + "\n")
    return folder / "stability.md"
