"""The horizontal rig of thesis Chapters 3-4 (scene `thesis-2dof`): do the impacts advance it into the soil?

The thesis' 2-DOF rig lies horizontally: the static force F_static = 31.1 N (listing C.14) pushes the rig,
the bar is meant to hammer its stop at the relay's rate.  For each soil law (viscous, coulomb, drift) a grid of relay
frequency 5-10 Hz x AC amplitude 25-90 V (the thesis' experiments) is swept on the batch engine
(``bifurc.sweeps.sweep.sweep``; the scene's own values, preset matlab-listing, under its DC law `listing`
and under `catalogue`, the law credible at the stop (docs/model.md section 1); nothing tuned), and each
cell's progression rate over the recorded window is set beside the rate the static force alone gives
without any bar motion (closed forms: viscous F_static / soil_c; coulomb and drift 0, as F_static is
below soil_friction = 1000 N and P_max = 60 N), and beside the AC source off (V = 0: the DC well and the
relay alone).  Impacts advance the rig in a cell where the bar hits its stop (at least one
impact per ten relay periods) and the rig's rate exceeds the static force's by more than ``ADVANCE`` =
0.1 mm/s (a bar that swings without impacts also moves the rig a little through the solenoids' reactions:
that is not counted).
"""
from __future__ import annotations

import math
import time as _time
from pathlib import Path

import numpy as np

from .. import provenance

NAME = "thesis-2dof-rig"
#: what run() writes, as `bifurc study` reports it
WRITES = "report.md"
SCENE = "thesis-2dof"
LAWS = ("viscous", "coulomb", "drift")
DC_LAWS = ("listing", "catalogue")
#: [mm/s] a cell's rate above the static force's own by more than this: the impacts advance the rig
ADVANCE = 0.1
FULL = dict(freqs=(5.0, 6.0, 7.0, 8.0, 9.0, 10.0), volts=(0.0, 25.0, 40.0, 55.0, 70.0, 90.0), transient=100,
            record=100)
QUICK = dict(freqs=(5.0, 10.0), volts=(0.0, 25.0, 90.0), transient=20, record=20)
TOL = 1e-10


def static_rate(law, params) -> float:
    """The rig's rate [mm/s] under the static force alone, the bar at rest (closed forms; NaN: it accelerates)."""
    F = params["F_static"]
    if law == "viscous":
        return 1e3 * F / params["soil_c"]
    limit = params["soil_friction"] if law == "coulomb" else params["P_max"]
    return 0.0 if F <= limit else math.nan


def measure(size, progress=True) -> dict:
    """{(soil law, DC law): {"rate": (volts, freqs) [mm/s], "impacts": impacts per relay period, "class": codes,
    "status": codes, "static": mm/s}}."""
    from bifurc import sweep
    from maps import problem
    say = print if progress else (lambda *a, **k: None)
    out = {}
    for law, dc in ((law, dc) for law in LAWS for dc in DC_LAWS):
        clock = _time.perf_counter()
        values = dict(problem(SCENE, None, None, soil=law).values)
        rate, imp, cls, st = (np.full((len(size["volts"]), len(size["freqs"])), np.nan) for _ in range(4))
        for i, v in enumerate(size["volts"]):
            ds = sweep(SCENE, "relay_hz", np.asarray(size["freqs"], float), soil=law, dc_law=dc,
                       params={"V": float(v)},
                       transient=size["transient"], record=size["record"], tol=TOL, workers=1, progress=False,
                       lyapunov=False, grazing=False, error_sample=0).isel(branch=0)
            rate[i] = 1e3 * ds.progression_rate.values
            imp[i] = ds.n_impacts.values / np.maximum(ds.record_used.values, 1)
            cls[i], st[i] = ds.class_code.values, ds.status.values
        out[(law, dc)] = {"rate": rate, "impacts": imp, "class": cls, "status": st, "static": static_rate(law, values)}
        say(f"{law}, DC law {dc}: {rate.size} cells in {_time.perf_counter() - clock:.1f} s", flush=True)
    return out


def advanced(m, size) -> dict:
    """{(soil law, DC law): (cells with the AC on where the impacts advance the rig, cells with the AC on)}."""
    on = np.asarray(size["volts"]) > 0
    out = {}
    for law, r in m.items():
        rate = r["rate"][on]
        hit = np.isfinite(rate) & (rate - r["static"] > ADVANCE) & (r["impacts"][on] >= 0.1)
        out[law] = (int(hit.sum()), int(rate.size))
    return out


def report(m, size, quick, seconds) -> str:
    from bifurc import ClassCode
    lines = [f"# {NAME}: do the impacts advance the horizontal rig?{' -- quick form' if quick else ''}", "",
             (__doc__ or "").strip(), "", provenance(NAME, quick), "",
             f"Form: {'quick' if quick else 'full'}: relay {', '.join(f'{f:g}' for f in size['freqs'])} Hz x AC "
             f"{', '.join(f'{v:g}' for v in size['volts'])} V (amplitude); {size['transient']} transient + "
             f"{size['record']} recorded relay periods; tol {TOL:g}; wall time {seconds:.0f} s.", ""]
    adv = advanced(m, size)
    for (law, dc), r in m.items():
        lines += [f"## {law} soil, DC law {dc}: rate [mm/s] (impacts per relay period; class)", "",
                  f"Static force alone: {r['static']:.4g} mm/s.  Cells with the AC on where impacts advance the rig: "
                  f"{adv[(law, dc)][0]} of {adv[(law, dc)][1]}.", "",
                  "| V \\ relay [Hz] | " + " | ".join(f"{f:g}" for f in size["freqs"]) + " |",
                  "|---" * (1 + len(size["freqs"])) + "|"]
        for i, v in enumerate(size["volts"]):
            cells = []
            for j in range(len(size["freqs"])):
                label = ClassCode(int(r["class"][i, j])).label if np.isfinite(r["class"][i, j]) else "?"
                cells.append(f"{r['rate'][i, j]:.3g} ({r['impacts'][i, j]:.2g}; {label})")
            lines.append(f"| {v:g}{' (AC off)' if v == 0 else ''} | " + " | ".join(cells) + " |")
        lines += [""]
    lines += ["## Answer", ""]
    on = np.asarray(size["volts"]) > 0
    for key, r in m.items():
        n, of = adv[key]
        best = float(np.nanmax(r["rate"][on])) if np.isfinite(r["rate"][on]).any() else math.nan
        lines.append(f"- {key[0]} soil, DC law {key[1]}: {'yes' if n else 'no'}, in {n} of {of} cells (fastest "
                     f"{best:.3g} mm/s against {r['static']:.3g} mm/s from the static force alone; impacts per "
                     f"relay period up to "
                     f"{float(np.nanmax(r['impacts'][on])):.3g}).")
    return "\n".join(lines) + "\n"


def run(out, quick=False, progress=True, overwrite=False) -> dict:
    """The study into folder ``out`` (``report.md``); returns {"measured": ..., "size": ..., "seconds": ...}."""
    from bifurc.studykit import refuse_existing, write_text
    out = Path(out)
    refuse_existing(out / "report.md", overwrite, hint="use --force")
    out.mkdir(parents=True, exist_ok=True)
    size = QUICK if quick else FULL
    clock = _time.perf_counter()
    m = measure(size, progress=progress)
    seconds = _time.perf_counter() - clock
    write_text(out / "report.md", report(m, size, quick, seconds), overwrite=True)
    return {"measured": m, "size": size, "seconds": seconds}


def findings(results, quick) -> list:
    """Per soil law: the answer (yes/no), the cells where the impacts advance the rig (+-1), and the fastest
    rate with the AC on (+-10 %, at least 0.05 mm/s)."""
    from bifurc.studykit import Finding
    m, size = results["measured"], results["size"]
    adv = advanced(m, size)
    on = np.asarray(size["volts"]) > 0
    out = []
    for (law, dc), r in m.items():
        n, of = adv[(law, dc)]
        rate = r["rate"][on]
        best = float(np.nanmax(rate)) if np.isfinite(rate).any() else math.nan
        out += [Finding(f"{law}, {dc}: impacts advance the rig", "yes" if n else "no"),
                Finding(f"{law}, {dc}: cells advanced (of {of})", n, 1, "cells"),
                Finding(f"{law}, {dc}: fastest rate, AC on", round(best, 4), round(max(0.1 * abs(best), 0.05), 4),
                        "mm s-1")]
    return out
