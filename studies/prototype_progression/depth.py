"""The thesis' own progression measure: depth divided by the time to reach it, from the rig's start.

Tables 5.2-5.5 give 0.2 m divided by the time the rig took to progress 0.2 m into the soil (start-up
included), not a steady rate; Fig 5.22 follows one run to 0.9 m (745.9 s: 4.308 mm/s at first,
0.649 mm/s at the end, 1.207 mm/s overall).  Here the prototype runs from its start, one scalar-engine
run per condition, chunk by chunk until the deepest depth asked is reached or ``t_max`` passes; the
rig's position is sampled 20 times per relay period and a depth's first time is interpolated
linearly between those samples (at most 1/20 of a relay period, 8 ms at 6 Hz, late or early).
"""
from __future__ import annotations

import math

import numpy as np

#: Fig 5.22 (thesis section 5.4): 0.9 m in 745.9 s; initial and final average gradients [mm/s]
FIG_5_22 = dict(depth=0.9, seconds=745.9, overall=1.207, initial=4.308, final=0.649)


def depth_run(law, *, compaction=False, relay_hz=6.0, v_amplitude=127.28, f_static=31.1, depths=(0.2,),
              t_max=60.0, chunk=10.0, dc_law=None, tol=1e-10, per_period=20) -> dict:
    """Run the prototype (soil ``law``) from its start until it is ``max(depths)`` [m] into the soil or
    ``t_max`` [s] passed; returns {"times": first time [s] at each depth (NaN: not reached),
    "t", "depth": the samples [s, m], ``per_period`` per relay period, "status": "ok"/"escaped"/"failed"}."""
    from maps import Escaped, IntegrationFailure, run_scene
    params = {"relay_hz": float(relay_hz), "V": float(v_amplitude), "F_static": float(f_static)}
    period = 1.0 / float(relay_hz) / int(per_period)
    ts, xs = [], []
    state = {"next": 0.0}

    def on_segment(c_out, ta, tb):
        while state["next"] <= tb:
            if state["next"] >= ta:
                ts.append(state["next"])
                xs.append(float(np.asarray(c_out(state["next"]))[ix]))
            state["next"] += period

    from maps import problem
    pb = problem("prototype", None, params, soil=law, compaction=compaction or None, dc_law=dc_law)
    ix = list(pb.system.state_names).index("x2")
    x_start = float(pb.x0["x2"])
    run = run_scene(pb, period / 2, tol=tol, on_segment=on_segment)
    status, t = run.status, period / 2
    target = max(depths)
    while status == "ok" and t < t_max and not (xs and x_start - min(xs) >= target):
        t = min(t + chunk, t_max)
        try:
            run.advance(t, on_segment=on_segment)
        except Escaped:
            status = "escaped"
        except IntegrationFailure:
            status = "failed"
    tt, depth = np.asarray(ts), x_start - np.asarray(xs)
    return {"times": [first_time(tt, depth, d) for d in depths], "t": tt, "depth": depth, "status": status}


def first_time(t, depth, d) -> float:
    """First time [s] the samples ``depth`` [m] reach ``d`` [m], linear between samples (NaN: never)."""
    hit = np.flatnonzero(depth >= d)
    if not hit.size:
        return math.nan
    j = int(hit[0])
    if j == 0:
        return float(t[0])
    return float(t[j - 1] + (d - depth[j - 1]) / (depth[j] - depth[j - 1]) * (t[j] - t[j - 1]))


def thesis_rate(time_to_depth, depth=0.2) -> float:
    """The thesis' measure [mm/s]: ``depth`` [m] over the time to reach it [s] (NaN: not reached)."""
    return 1e3 * depth / time_to_depth if math.isfinite(time_to_depth) and time_to_depth > 0 else math.nan


def gradients(run, first=0.2, last=0.2, target=None) -> dict:
    """Fig 5.22's measures of a run to depth D (``target`` [m] where reached, else the deepest reached):
    the average gradient over the first ``first`` m, over the last ``last`` m (D - last to D) and overall
    (D over its time) [mm/s]."""
    t, d = run["t"], run["depth"]
    deepest = float(np.nanmax(d)) if d.size else math.nan
    if target is not None and deepest >= target:
        deepest = float(target)
    t_end = first_time(t, d, deepest) if math.isfinite(deepest) else math.nan
    t_first = first_time(t, d, first)
    t_from = first_time(t, d, deepest - last)
    return {"deepest_m": deepest, "seconds": t_end, "initial": thesis_rate(t_first, first),
            "final": 1e3 * last / (t_end - t_from) if t_end > t_from else math.nan,
            "overall": thesis_rate(t_end, deepest)}


#: (soil law, compaction) of the runs from the start
VARIANTS = (("viscous", False), ("coulomb", False), ("coulomb", True), ("drift", False), ("drift", True))


def _name(law, compaction) -> str:
    return f"{law}{' + compaction' if compaction else ''}"


def measure(size, v_amplitude, f_static, say=print) -> dict:
    """{"to_depth": {(law, compaction, relay_hz): run}, "fig_5_22": {(law, compaction): gradients}}."""
    import time as _time
    out = {"to_depth": {}, "fig_5_22": {}}
    for law, comp in VARIANTS:
        clock = _time.perf_counter()
        for f in size["depth_freqs"]:
            out["to_depth"][(law, comp, f)] = depth_run(law, compaction=comp, relay_hz=f, v_amplitude=v_amplitude,
                                                        f_static=f_static, depths=(0.2,), t_max=size["depth_t_max"])
        say(f"{_name(law, comp)}: 0.2 m runs in {_time.perf_counter() - clock:.1f} s", flush=True)
    if size.get("fig_5_22_t_max"):
        for law, comp in (("drift", False), ("drift", True)):
            clock = _time.perf_counter()
            run = depth_run(law, compaction=comp, relay_hz=6.0, v_amplitude=v_amplitude, f_static=f_static,
                            depths=(FIG_5_22["depth"],), t_max=size["fig_5_22_t_max"], chunk=30.0)
            out["fig_5_22"][(law, comp)] = gradients(run, target=FIG_5_22["depth"])
            say(f"{_name(law, comp)}: the 0.9 m run in {_time.perf_counter() - clock:.1f} s", flush=True)
    return out


def report_lines(d, size, table55, steady) -> list[str]:
    """The report's sections on the thesis' measure; ``steady``: {(law, relay_hz): steady rate [mm/s]}."""
    fmt = (lambda x: "not reached" if not math.isfinite(x) else f"{x:.3g}")
    lines = ["## The thesis' measure: 0.2 m over the time to reach it (Table 5.5's conditions)", "",
             "One run from the rig's start per condition (AC 90 V RMS, actuator 10 V), up to "
             f"{size['depth_t_max']:g} s "
             "(src: studies/prototype_progression/depth.py); `0.2 m / t` [mm/s] beside the steady rate of the sweeps "
             "above (no compaction; the compaction runs have no steady rate: their resistance grows with depth).", "",
             "| relay [Hz] | thesis 0.2 m / t [mm/s] | " +
             " | ".join(f"{_name(law, c)}: 0.2 m / t (steady) [mm/s]" for law, c in VARIANTS) + " |",
             "|---" * (2 + len(VARIANTS)) + "|"]
    for f in size["depth_freqs"]:
        th = float(np.interp(f, table55["relay_Hz"], table55["rate_mm_per_s"]))
        cells = []
        for law, c in VARIANTS:
            run = d["to_depth"][(law, c, f)]
            got = fmt(thesis_rate(run["times"][0])) if run["status"] == "ok" else run["status"]
            if not math.isfinite(run["times"][0]) and run["status"] == "ok":
                got += f" ({1e3 * float(run['depth'][-1]):.3g} mm in {float(run['t'][-1]):.0f} s)"
            s = steady.get((law, f)) if not c else None
            cells.append(got + (f" ({fmt(s)})" if s is not None else ""))
        lines.append(f"| {f:g} | {th:.3g} | " + " | ".join(cells) + " |")
    lines += [""]
    if d["fig_5_22"]:
        lines += ["## The 0.9 m run of Fig 5.22 (6 Hz, AC 90 V RMS, actuator 10 V)", "",
                  f"Thesis: 0.9 m in {FIG_5_22['seconds']} s; first gradient {FIG_5_22['initial']} mm/s, last "
                  f"{FIG_5_22['final']} mm/s, overall {FIG_5_22['overall']} mm/s.  Model: gradients over the first "
                  "0.2 m and the last 0.2 m before 0.9 m (or before the deepest point reached), up to "
                  f"{size['fig_5_22_t_max']:g} s.  The compaction depth scale "
                  "is fitted to the thesis' first and last gradients (docs/model.md), so only the time and the "
                  "gradients' shape are a comparison.", "",
                  "| run | deepest [m] | time [s] | first 0.2 m [mm/s] | last 0.2 m [mm/s] | overall [mm/s] |",
                  "|---|---|---|---|---|---|",
                  f"| thesis | 0.9 | {FIG_5_22['seconds']} | {FIG_5_22['initial']} | {FIG_5_22['final']} | "
                  f"{FIG_5_22['overall']} |"]
        for (law, c), g in d["fig_5_22"].items():
            lines.append(f"| {_name(law, c)} | {g['deepest_m']:.3g} | {fmt(g['seconds'])} | {fmt(g['initial'])} | "
                         f"{fmt(g['final'])} | {fmt(g['overall'])} |")
        lines += [""]
    return lines


def findings(d) -> list:
    """0.2 m / t at every condition (+-10 %, or the depth reached [mm] +-10 % where 0.2 m is not) and the
    Fig 5.22 runs' deepest depth and overall gradient (+-10 %)."""
    from bifurc.studykit import Finding
    out = []
    for (law, c, f), run in d["to_depth"].items():
        r = thesis_rate(run["times"][0])
        if math.isfinite(r):
            out.append(Finding(f"0.2 m / t, {_name(law, c)}, {f:g} Hz", round(r, 4), round(0.1 * r, 4), "mm s-1"))
        else:
            mm = 1e3 * float(run["depth"][-1])
            out.append(Finding(f"depth reached (0.2 m not), {_name(law, c)}, {f:g} Hz", round(mm, 3),
                               round(max(0.1 * abs(mm), 0.05), 3), "mm"))
    for (law, c), g in d["fig_5_22"].items():
        out.append(Finding(f"Fig 5.22 run deepest, {_name(law, c)}", round(g["deepest_m"], 4),
                           round(0.1 * g["deepest_m"], 4), "m"))
        if math.isfinite(g["overall"]):
            out.append(Finding(f"Fig 5.22 run overall gradient, {_name(law, c)}", round(g["overall"], 4),
                               round(0.1 * g["overall"], 4), "mm s-1"))
    return out
