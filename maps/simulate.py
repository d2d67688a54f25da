"""Time histories of a scene as xarray Datasets."""
from __future__ import annotations

import time as _time
from typing import TYPE_CHECKING

import heyoka as hy
import numpy as np

from .engines.scalar import HybridRun
from .hybrid import Escaped, IntegrationFailure
from .impacts import impact_table
from .parameters import ParameterError, validate_value
from .provenance import cf_attrs, recorded
from .problem import KEYWORDS, model_attrs, problem as make_problem

if TYPE_CHECKING:  # xarray is imported where used: worker processes start faster
    import xarray as xr

def dc_law_attrs(options) -> dict:
    """Dataset attributes naming the DC-force law and its provenance (docs/model.md section 1)."""
    a = model_attrs(options)
    return {"dc_law": a["dc_law"], "dc_law_source": a["dc_law_source"]}


def soil_law_attrs(options) -> dict:
    """Dataset attributes naming the soil law of a 2-DOF scene, its provenance (docs/model.md section 2)
    and its compaction (the resistance's growth with depth, or "none")."""
    a = model_attrs(options)
    return {k: a[k] for k in ("soil", "soil_source", "soil_compaction")}


def run_scene(problem, t_end, *, tol=1e-12, on_segment=None, max_events=100_000, max_events_per_period=None,
              fp_type=float, **options):
    """Integrate a problem (or a scene with the keywords of :func:`maps.problem` as ``options``) to ``t_end`` [s]
    and return the :class:`~maps.engines.scalar.HybridRun`.

    Failures (non-finite state, escape, event cap: ``max_events`` per run,
    ``max_events_per_period`` per relay period) are recorded on the run as
    ``run.status`` / ``run.failure`` instead of raised.
    """
    pb = make_problem(problem, **options)
    t_end = validate_value("t_end", t_end, 0.0, 1e7, low_open=True, unit="s")
    y0 = dict(pb.x0)
    run = HybridRun(pb.system, dict(pb.values), y0, tol=tol, fp_type=fp_type, max_events=max_events,
                    max_events_per_period=max_events_per_period)
    if pb.flags0 is not None:
        run.reset(0.0, pb.state_vector(), pb.system.initial_flags(0.0, pb.values, pb.flags0))
    run.problem, run.scene, run.provenance, run.y0 = pb, pb.scene, dict(pb.provenance), y0
    run.status, run.failure = "ok", None
    t0 = _time.perf_counter()
    try:
        run.advance(t_end, on_segment=on_segment)
    except Escaped as exc:
        run.status, run.failure = "escaped", exc
    except IntegrationFailure as exc:
        run.status, run.failure = "failed", exc
    run.run_seconds = _time.perf_counter() - t0
    return run


@recorded("maps.simulate")
def simulate(problem="thesis-1dof", periods=None, *, t_end=None, dt=None, t_eval=None, tol=1e-12, transient=None,
             **options) -> xr.Dataset:
    """Time history of ``scene`` sampled on a grid from heyoka's dense output.

    Parameters
    ----------
    problem : str, Scene, HybridSystem or Problem
        A scene name (``maps.scene_names()``) or a :class:`~maps.problem.Problem` (then the
        keywords that define the model are not given).
    periods, t_end : float
        Duration in strobe periods (relay periods for the thesis model) or in seconds (exactly one of them).
    params : dict
        Parameter overrides by name (``bifurc params --scene S`` lists them; docs/model.md), e.g. ``{"V": 90}``.
    preset : str
        ``thesis-text``, ``matlab-listing`` or ``dynamics-listing``.
    x0 : dict
        Initial state components by name; the rest take the scene's defaults.
    tol : float
        heyoka's relative/absolute tolerance.
    dt, t_eval : float, array
        Sampling step [s] (default 2e-4 s) or explicit sample times; sampling
        never changes the trajectory.
    circuit, ac_sign : str
        Structural options ("thesis"/"kvl", "physical"/"listing").
    dc_law : str
        DC-force law: "listing" (listing C.9), "fit" (eqs 4.6-4.7) or "measured" (Table 4.1
        only, zero beyond |xa| = 29 mm); default: the preset's (docs/model.md section 1).
    soil : str
        2-DOF soil law: "viscous", "coulomb" or "drift" (docs/model.md section 2); default: the scene's.
    compaction : bool
        Coulomb and drift soils: the resistance grows with depth (``maps.model.COMPACTION``).
    transient : float
        2-DOF scenes: the progression measures (:mod:`maps.progression`) are taken after this
        time [s] (default: over the second half of the run).
    **options
        The problem's keywords (:func:`maps.problem`: ``params``, ``preset``, ``x0``, ``circuit``, ``ac_sign``,
        ``energy``, ``dc_law``, ``soil``, ``compaction``) and ``max_events_per_period``.

    Returns
    -------
    xarray.Dataset with ``time`` and ``impact`` dimensions.
    """
    max_events_per_period = options.pop("max_events_per_period", None)
    known = KEYWORDS + ("energy",)      # a time history can carry the energy audit's quadrature states
    unknown = [k for k in options if k not in known]
    if unknown:
        raise ParameterError(f"unknown option {unknown[0]!r}; valid: t_end, dt, t_eval, tol, transient, "
                             f"max_events_per_period, {', '.join(known)}")
    pb = make_problem(problem, **options)
    t_end = _duration(pb, periods, t_end)
    if t_eval is None:
        dt = validate_value("dt", 2e-4 if dt is None else dt, 0.0, t_end, low_open=True, unit="s")
        t_eval = np.arange(0.0, t_end + 0.5 * dt, dt)
        t_eval = t_eval[t_eval <= t_end]
    t_eval = np.asarray(t_eval, dtype=float)
    if t_eval.ndim != 1 or not np.all(np.isfinite(t_eval)) or np.any(np.diff(t_eval) < 0):
        raise ParameterError("t_eval must be a finite, non-decreasing 1-D array of times [s]")
    if t_eval.size and (t_eval[0] < 0 or t_eval[-1] > t_end):
        raise ParameterError(f"t_eval must lie in [0, t_end = {t_end:g}] s, got [{t_eval[0]:g}, {t_eval[-1]:g}]")
    n_states = len(pb.system.states)
    samples = np.full((t_eval.size, n_states), np.nan)

    def on_segment(c_out, ta, tb):
        lo, hi = np.searchsorted(t_eval, [ta, tb], side="left")
        hi = np.searchsorted(t_eval, tb, side="right")
        if hi > lo:
            samples[lo:hi] = c_out(t_eval[lo:hi])

    if transient is not None:
        transient = validate_value("transient", transient, 0.0, t_end, high_open=True, unit="s")
    run = run_scene(pb, t_end, tol=tol, on_segment=on_segment, max_events_per_period=max_events_per_period)
    return to_dataset(run, t_eval, samples, transient)


def _add_progression(ds, run, imp, transient):
    """The progression measures (:mod:`maps.progression`) as scalar variables, over the window
    from ``transient`` [s] (default: half the run reached) to the run's end."""
    from .progression import MEASURES, held_mode, held_time, progression_measures
    t, x2 = ds["t"].values, ds["x2"].values
    if t.size < 2:
        return
    t_b = float(t[-1])
    t_a = t_b / 2 if transient is None else min(float(transient), t_b)
    p = run.params
    m = progression_measures(t, x2, x2_start=float(run.y0["x2"]),
                             relay_hz=p.get("relay_hz"), impact_time=imp["t"], impact_velocity=imp["velocity"],
                             m1=p["m1"], held=held_time(run.flag_log, t_a, t_b, held_mode(run.system)),
                             window=(t_a, t_b))
    for name, value in m.items():
        units, long_name = MEASURES[name]
        ds[name] = ((), value, {"units": units, "long_name": long_name})
    ds.attrs["progression_window"] = np.array([t_a, t_b])


def _duration(pb, periods, t_end):
    if (periods is None) == (t_end is None):
        raise ParameterError("give exactly one of 'periods' (strobe periods) and 't_end' (seconds)")
    if periods is not None:
        if pb.system.strobe_period_of(pb.values) is None:
            raise ParameterError("'periods' counts strobe periods; this scene declares no clock: give 't_end' [s]")
        periods = validate_value("periods", periods, 0.0, 1e7, low_open=True)
        rate = pb.system.strobe_rate(pb.values)      # k / W exactly, as the relay's switch instants
        return periods / rate if rate is not None else periods * pb.strobe_period()
    return validate_value("t_end", t_end, 0.0, 1e7, low_open=True, unit="s")


def to_dataset(run, t_eval, samples, transient=None) -> xr.Dataset:
    """Package a run and its samples: states, flags, impacts, parameters and provenance."""
    import xarray as xr
    system, sc = run.system, run.scene
    t_valid = run.t if run.status != "ok" else np.inf
    keep = t_eval <= t_valid
    t_eval, samples = t_eval[keep], samples[keep]
    ds = xr.Dataset(coords={"t": ("t", t_eval, {"units": "s", "long_name": "time",   # seconds, no epoch
                                                "comment": "elapsed time from the start of the integration"})})
    for j, st in enumerate(system.states):
        ds[st.name] = ("t", samples[:, j], {"units": st.unit, "long_name": st.long_name})
    times = np.array([t for t, _ in run.flag_log])
    idx = np.clip(np.searchsorted(times, t_eval, side="right") - 1, 0, None)
    for flag, long_name in (("P", "relay state (1: AC solenoid powered)"),
                            ("contact", "bar in contact with the stop")):
        if flag in system.flag_names:
            vals = np.array([fl[flag] for _, fl in run.flag_log], dtype=np.int8)[idx]
            ds[flag if flag != "P" else "relay"] = ("t", vals, {
                "units": "1", "long_name": long_name, "flag_values": np.array([0, 1], np.int8),
                "flag_meanings": "off on"})
    if "stuck" in system.flag_names:
        vals = np.array([fl["stuck"] for _, fl in run.flag_log], dtype=np.int8)[idx]
        ds["rig_stuck"] = ("t", vals, {"units": "1", "long_name": "rig stuck in the soil",
                                          "flag_values": np.array([0, 1], np.int8),
                                          "flag_meanings": "slipping stuck"})
    if "soil_pl" in system.flag_names:
        mode = np.array([fl["soil_el"] + 2 * fl["soil_pl"] for _, fl in run.flag_log], dtype=np.int8)[idx]
        ds["soil_mode"] = ("t", mode, {"units": "1", "long_name": "drift soil mode",
                                          "flag_values": np.array([0, 1, 2], np.int8),
                                          "flag_meanings": "clear elastic progression"})
    imp = impact_table(run)
    ds = ds.assign_coords(impact=("impact", np.arange(imp["t"].size),
                                  {"units": "1", "long_name": "contact number in time order"}))
    ds["impact_time"] = ("impact", imp["t"], {"units": "s", "long_name": "contact onset time"})
    ds["impact_velocity"] = ("impact", imp["velocity"],
                             {"units": "m s-1", "long_name": "bar velocity relative to the stop at contact onset"})
    ds["impact_penetration"] = ("impact", imp["penetration"],
                                {"units": "m", "long_name": "maximum penetration into the stop"})
    ds["impact_duration"] = ("impact", imp["duration"],
                             {"units": "s", "long_name": "contact duration (NaN: still in contact at the end)"})
    if "x2" in system.state_names:
        ds["progression"] = ds["x2"].isel(t=0) - ds["x2"]
        ds["progression"].attrs = {"units": "m", "long_name": "forward progression into the soil x2(0) - x2(t)"}
        _add_progression(ds, run, imp, transient)
    attrs = {
        **run.problem.attrs(), "scene_summary": sc.summary, "tol": run.tol, "heyoka_version": hy.__version__,
        "run_seconds": run.run_seconds, "compile_seconds": run.compile_seconds,
        "n_steps": run.n_steps, "n_events": run.n_events, "n_relay_switches": run.n_switches,
        "status": run.status, "t_end_reached": run.t,
        "title": f"{sc.name}: time history", **cf_attrs(f"scene {sc.name}, time history"),
        "bifurc_kind": "history",      # bifurc.storage.build.KIND_ATTR (maps never imports bifurc)
    }
    if run.failure is not None:
        attrs["failure"] = str(run.failure)
        attrs["failure_time"] = float(run.failure.t)
        attrs["failure_state"] = np.asarray(run.failure.state, dtype=float)
    ds.attrs.update(attrs)
    return ds
