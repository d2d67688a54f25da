"""Regime maps of the thesis 1-DOF model: where does it hammer periodically?

Planes (thesis-1dof, matlab-listing numbers, every cell from the scene's start):
(relay frequency 2-10 Hz, V 25-300 V) under each DC-force law (`listing`, `fit`, `measured`;
docs/model.md section 1), and (V 25-300 V, dc_scale 0-3) at 5 Hz under the `listing` law.  Each cell
is classified as a diagram value (`bifurc.regime_map`): periodic hammering is "period-1, 1 impact"
(one impact per relay period, the same every period) in the mechanical convention (the bar's position
and speed repeat every relay period; the thesis' period-1), whatever the coil current does: the full
state's count is given beside it.  Nothing is tuned to agree with anything.
"""
from __future__ import annotations

import math
import re
import time as _time
from collections import Counter
from pathlib import Path

import numpy as np

NAME = "regime-maps"
SCENE = "thesis-1dof"
PRESET = "matlab-listing"
RELAY = (2.0, 10.0)       # [Hz]
VOLTS = (25.0, 300.0)     # [V]
DC_SCALE = (0.0, 3.0)     # [1]
#: (case, first parameter and its range, second parameter and its range, DC law, fixed parameters)
CASES = [(f"relay-V-{law}", ("relay_hz", RELAY), ("V", VOLTS), law, {}) for law in ("listing", "fit", "measured")] + [
    ("V-dc_scale-5Hz", ("V", VOLTS), ("dc_scale", DC_SCALE), "listing", {"relay_hz": 5.0})]
_NUMBER = r"[-+]?\d+(\.\d+)?(e[-+]?\d+)?"
FULL = dict(n=41, n2=41, transient=300, record=100)
QUICK = dict(n=7, n2=7, transient=100, record=40)     # for the tests and `--quick`: under 2 minutes


def run(out, quick=False, progress=True, overwrite=False) -> dict:
    """Every map into folder ``out`` (refused before if occupied, see bifurc.commands.study.run_study):
    ``<case>.nc``, ``<case>.png`` and ``report.md``; returns {case: dataset}."""
    from bifurc.studykit import write_text
    from bifurc import plot_regime_map, regime_map
    out = Path(out)
    size = QUICK if quick else FULL
    clock = _time.perf_counter()
    results = {}
    for case, (p1, r1), (p2, r2), law, fixed in CASES:
        ds = regime_map(SCENE, p1, np.linspace(*r1, size["n"]), p2, np.linspace(*r2, size["n2"]), preset=PRESET,
                        dc_law=law, params=fixed, transient=size["transient"], record=size["record"],
                        path=out / f"{case}.nc", progress=progress, overwrite=True)
        ds.attrs["study"], ds.attrs["study_case"] = NAME, case
        plot_regime_map(ds, out / f"{case}.png", overwrite=True)
        results[case] = ds
    write_text(out / "report.md", report(results, quick, _time.perf_counter() - clock), overwrite=True)
    return results


def hammering(ds, period_of: str = "mechanical"):
    """Boolean (param, param2) mask of the cells that hammer periodically: period-1, 1 impact, in the
    convention ``period_of`` ("mechanical": the bar's; "full": the whole state's)."""
    from bifurc import ClassCode
    from bifurc.studykit import in_convention
    ds = in_convention(ds, period_of)
    return (ds.class_code == ClassCode.PERIODIC) & (ds.period == 1) & (ds.impacts_per_period == 1)


def _where(ds, mask) -> str:
    """Where ``mask`` holds: the range of the voltage axis at each value of the other parameter."""
    par, par2 = ds.attrs["swept_parameter"], ds.attrs["swept_parameter2"]
    volt, other = (par2, par) if par2 == "V" else (par, par2)
    m = mask.transpose(other, volt).values
    rows = []
    for i, w in enumerate(ds[other].values):
        vs = ds[volt].values[m[i]]
        if vs.size:
            unit = ds[other].attrs.get("units", "")
            rows.append(f"{other} = {w:.4g}{' ' + unit if unit not in ('', '1') else ''}: "
                        + (f"{vs.size} cells with {volt} from {vs.min():.4g} to {vs.max():.4g} V"
                           if vs.size > 1 else f"{volt} = {vs[0]:.4g} V"))
    return "; ".join(rows)


def _finding(ds) -> str:
    """The study's question for one map, answered from the cells."""
    from bifurc import ClassCode
    h = hammering(ds)
    n = int(h.sum())
    volt = "V"
    full = int(hammering(ds, "full").sum())
    if n:
        lowest = float(ds[volt].where(h).min())
        return (f"Periodic hammering (mechanical period-1, 1 impact per relay period) at {n} of {h.size} cells "
                f"({full} of them period-1 in the full state too); the lowest voltage that gives it on this grid "
                f"is {lowest:.4g} V. Where: {_where(ds, h)}.")
    from bifurc.studykit import in_convention
    dm = in_convention(ds, "mechanical")
    once = (dm.class_code == ClassCode.PERIODIC) & (dm.impacts_per_period == dm.period)
    text = ("No cell of this grid hammers periodically with one impact per relay period (mechanical period-1, "
            "1 impact).")
    if int(once.sum()):
        text += (f" {int(once.sum())} cell(s) are period-n with n impacts (one impact per relay period on "
                 f"average, repeating only every n periods): {_where(ds, once)}.")
    return text


#: periodic n:m on fewer cells than this share one row of the report's table
RARE = 3


def _counts(ds):
    """(regime, cells) rows: every n:m on at least RARE cells (and period-1, 1 impact always), the
    rarer ones in one row, then the other classes."""
    from bifurc.studykit import in_convention, regime_categories
    index, cats = regime_categories(in_convention(ds, "mechanical"), colours=None)   # every n:m its own category
    rows = [(text, int((index == i).sum())) for i, (text, _) in enumerate(cats)]
    keep = lambda t, n: not t.startswith("period-") or n >= RARE or t == "period-1, 1 impact"  # noqa: E731
    rare = [(t, n) for t, n in rows if not keep(t, n)]
    out = [(t, n) for t, n in rows if keep(t, n) and t.startswith("period-")]
    if rare:
        out.append((f"other periodic n:m, each on fewer than {RARE} cells ({len(rare)} kinds)", sum(n for _, n in rare)))
    return out + [(t, n) for t, n in rows if not t.startswith("period-")]


def report(results, quick, seconds) -> str:
    from bifurc import ClassCode
    size = QUICK if quick else FULL
    lines = [f"# {NAME}: where the thesis model hammers periodically", "", (__doc__ or "").strip(), "",
             f"Size: {'quick' if quick else 'full'}: {size['n']} x {size['n2']} cells per map, "
             f"{size['transient']} transient + {size['record']} recorded relay periods per cell; "
             f"{len(results)} maps in {seconds:.0f} s.", ""]
    for case, ds in results.items():
        a = ds.attrs
        fixed = ", ".join(f"{k} = {a[f'param_{k}']:g} {a[f'param_{k}_units']}" for k in ("relay_hz",)
                          if f"param_{k}" in a)
        lines += [f"## {case}: {a['swept_parameter']} x {a['swept_parameter2']}, dc_law {a['dc_law']}"
                  + (f", {fixed}" if fixed else ""), "", f"![{case}]({case}.png)", "", _finding(ds), "",
                  "| regime (mechanical period) | cells |", "|---|---|"]
        lines += [f"| {text} | {n} |" for text, n in _counts(ds)]
        nc = ds.class_code == ClassCode.NOT_CONVERGED
        if int(nc.sum()):
            reasons = Counter(re.sub(_NUMBER, "#", str(r)) or "no reason stored" for r in ds.class_reason.values[nc.values])
            lines += ["", f"Not converged within the budget ({a['transient_periods']} + {a['recorded_periods']} "
                          f"relay periods first, extended up to {a.get('budget_periods', '?')} while undecided; "
                          f"{int(nc.sum())} cells; the label claims no more), by stored reason (# : a number "
                          "that varies per cell, see `class_reason` in the .nc):", ""]
            lines += [f"- {k} cell{'s' if k > 1 else ''}: {r}" for r, k in reasons.most_common()]
        err = a.get("error_map_step_rel", math.nan)
        lines += ["", f"Numerical error (tol/100): one map step {err:.2g} relative; map computed in "
                      f"{a['values_seconds']:.0f} s of cell time ({a['sweep_seconds']:.0f} s wall, "
                      f"{a['workers']} worker processes).", ""]
    return "\n".join(lines)


def findings(results, quick) -> list:
    """What the report states, per map: the cells that hammer (mechanical period-1, 1 impact; +-1 cell),
    those that are period-1 in the full state too (+-1), the chaotic and not-converged cells (+-2 and 5 %
    of the map: chaotic labels near the threshold may move with round-off), the lowest hammering voltage
    (+- one grid step; NaN: none)."""
    from bifurc import ClassCode
    from bifurc.studykit import Finding
    out = []
    for case, ds in results.items():
        h = hammering(ds)
        size = int(h.size)
        volts = ds["V"].values
        step = float(np.diff(volts).max()) if volts.size > 1 else 0.0
        lowest = float(ds["V"].where(h).min()) if int(h.sum()) else math.nan
        loose = 2 + 0.05 * size
        out += [Finding(f"{case}: hammering cells (mechanical period-1, 1 impact)", int(h.sum()), 1, "cells"),
                Finding(f"{case}: of them period-1 in the full state", int(hammering(ds, "full").sum()), 1, "cells"),
                Finding(f"{case}: chaotic cells", int((ds.class_code == ClassCode.CHAOTIC).sum()), loose, "cells"),
                Finding(f"{case}: not-converged cells", int((ds.class_code == ClassCode.NOT_CONVERGED).sum()), loose,
                        "cells"),
                Finding(f"{case}: lowest hammering voltage", lowest, step, "V")]
    return out
