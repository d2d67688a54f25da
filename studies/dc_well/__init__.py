"""The DC well: where the bar rests decides whether the thesis model hammers a few millimetres (issue 46).

Two parts.

1. **The structural cause, measured.**  For every DC law (matlab-listing numbers, each law's own
   coefficients): the well's derived rest height, stiffness and range (maps/well.py, AC off, gravity
   included), beside DC-only runs from rest on the stop: the top of the undamped swing (it equals the
   well's range: flight is conservative, so the bar swings to the mirror level of the potential,
   whatever the DC strength), and where flight damping c_air = 0.5 N s/m parks the bar (the rest
   height).  With them, the figure docs/model.md quoted for thesis-text at 90 V (smallest gap from a
   1 mm start in 3 s) under the preset's law (`fit`) and under `listing`.
2. **The map.**  Rest height (set by ``dc_rest``, the law's shape kept: under `listing` it shifts
   d_dc) x relay frequency, for each case (V, c_air), dc_law `listing`, the physical AC sign, from the
   listings' start (x = 0, v = 0, i = 0.1 A, z = 0): the class in the bar's (mechanical) period, the
   impacts per relay period, and for every mechanical period-1 cell the stroke (x's range over the
   last 10 relay periods of a run as long as the sweep's).  The thesis' regime is mechanical
   period-1, one impact per relay period, a stroke of at most 10 mm (its LVDT reads +-5 mm).  Beside
   it, listing C.14's law (`dynamics-script`, rest on the stop, the listings' reversed AC sign, 25 V)
   over 2-10 Hz against the thesis' Fig 4.27 labels.

The map samples; it does not fit: nothing is tuned to agree with the thesis.  The quick form leaves
Lyapunov exponents out (an aperiodic value reads not-converged rather than chaotic: "not periodic within
the budget") and samples 7 rest heights x 9 integer relay frequencies for three cases; the full form
samples 1-62.5 mm (10 heights), 2-10 Hz in 0.5 Hz steps, four cases (25 and 90 V, c_air 0 and 0.5),
300 transient + 100 recorded relay periods, also without Lyapunov exponents (about 10 min on 2 cores).
At every cell in the thesis' regime (and at the issue's example, 5 mm, 5 Hz, 90 V, c_air 0.5) a
switch-on census (quick 8 starts, full 64) gives the share of switch-ons that end in that regime.
The orbits there are continued in d_dc (the rest height under `listing`) to the fold, period doubling or
grazing that bounds their stable window (quick: the first such cell of each case and the example).
"""
from __future__ import annotations

import math
import time as _time
from pathlib import Path

import numpy as np

NAME = "dc-well"
WRITES = "report.md, map_<case>[-quick].png and <case>_<rest>mm.nc"
SCENE = "thesis-1dof"
PRESET = "matlab-listing"
START = {"x": 0.0, "v": 0.0, "i": 0.1, "z": 0.0}          # the listings' start (C.1, with z = 0)
LAWS = ("listing", "fit", "measured", "catalogue", "dynamics-script")
#: (case, dc_law, AC sign, parameters): the map's cases
CASES = [
    ("listing-90V-cair0.5", "listing", "physical", {"V": 90.0, "c_air": 0.5}),
    ("listing-25V", "listing", "physical", {"V": 25.0}),
    ("listing-25V-cair0.5", "listing", "physical", {"V": 25.0, "c_air": 0.5}),
]
FULL_CASES = CASES + [("listing-90V", "listing", "physical", {"V": 90.0})]
C14 = ("c14-25V", "dynamics-script", "listing", {"V": 25.0})
QUICK = dict(cases=CASES, rests=(0.002, 0.003, 0.005, 0.0075, 0.010, 0.020, 0.0625),
             relays=tuple(float(w) for w in range(2, 11)), transient=150, record=50, lyapunov=False,
             c14_relays=tuple(float(w) for w in range(2, 11)), census_starts=8, census_periods=400,
             window_span=(0.0005, 0.02), window_points=40, windows_first_only=True)
FULL = dict(cases=FULL_CASES, rests=(0.001, 0.002, 0.003, 0.004, 0.005, 0.0075, 0.010, 0.015, 0.020, 0.0625),
            relays=tuple(np.round(np.arange(2.0, 10.01, 0.5), 10)), transient=300, record=100, lyapunov=False,
            c14_relays=tuple(float(w) for w in range(2, 11)), census_starts=64, census_periods=2000,
            window_span=(0.0005, 0.03), window_points=150, windows_first_only=False)
THESIS_NUMERICAL = {2: 1, 3: 1, 4: 1, 5: 1, 6: 2, 7: 2, 8: 2, 9: 1, 10: 1}  # period per Fig 4.27
#: the census' period search [strobe periods]: the committed reports' (the census' default until issue 45 gave
#: every verb one default, 100)
CENSUS_MAX_PERIOD = 16
STROKE_MAX = 0.010        # [m] the thesis' LVDT range (+-5 mm)


# ----- part 1: the structural cause -----------------------------------------------------------------
def _dc_only(law, params, t_end, dt=1e-3):
    import maps
    return maps.simulate("dc-only", preset=PRESET, dc_law=law, params=params, x0={"x": 0.0, "v": 0.0},
                         t_end=t_end, dt=dt)


def structure() -> dict:
    """Per law: the derived well and the DC-only measures; the dc_scale runs; the 90 V gap figure."""
    import maps
    laws = {}
    for law in LAWS:
        pb = maps.problem("dc-only", preset=PRESET, dc_law=law)
        w = pb.well()
        swing = _dc_only(law, {}, 2.0, dt=1e-4)
        row = dict(w, x_max=float(swing.x.max()), x_min=float(swing.x.min()))
        if w["dc_rest"] > 0:
            park = _dc_only(law, {"c_air": 0.5}, 20.0, dt=1e-2)
            row["x_parked"] = float(park.x.values[-1])
        laws[law] = row
    scales = {s: float(_dc_only("listing", {"dc_scale": s}, 2.0, dt=1e-4).x.max()) for s in (0.1, 1.44)}
    stop = {s: _stop_force("listing", s) for s in (0.1, 1.44)}
    gaps = {}
    for law in ("fit", "listing"):
        ds = maps.simulate(SCENE, preset="thesis-text", dc_law=law, t_end=3.0, dt=1e-4, params={"V": 90.0})
        gaps[law] = (float(ds.x.min()), int(np.isfinite(ds.impact_time.values).sum()))
    return {"laws": laws, "scales": scales, "stop_force": stop, "gaps": gaps, "settling": settling()}


#: Fig 4.25 (section 4.5): AC only, 25 V, "steady state ... maximum displacement of -0.0446 m and minimum
#: displacement of -0.0464 m, oscillating at the centre of Solenoid 2"
FIG_4_25 = (-0.0464, -0.0446)
AC_ONLY_C_AIR = (0.0, 0.5, 5.0)              # with the weight: does any hold the bar in the AC coil?
AC_ONLY_C_AIR_NO_WEIGHT = (0.2, 0.25, 0.3, 0.4)


def settling() -> dict:
    """What c_air the settling of Fig 4.25 implies: ac-only (thesis-text, 25 V) from x = 0 over the
    listings' tf = 3 s: with the weight, when the bar leaves the model's domain; without it (Fig 4.25 sits
    on the AC centre, which the weight would pull it below), x's range over the last 0.3 s."""
    import maps
    out = {"weight": {}, "no_weight": {}}
    for c in AC_ONLY_C_AIR:
        ds = maps.simulate("ac-only", preset="thesis-text", params={"V": 25.0, "c_air": c}, t_end=3.0, dt=5e-4)
        out["weight"][c] = float(ds.t.values[-1])
    for c in AC_ONLY_C_AIR_NO_WEIGHT:
        ds = maps.simulate("ac-only", preset="thesis-text", params={"V": 25.0, "g": 0.0, "c_air": c}, t_end=3.0,
                           dt=5e-4)
        late = ds.x.values[ds.t.values > 2.7]
        out["no_weight"][c] = (float(late.min()), float(late.max()))
    return out


def _stop_force(law, scale):
    import maps
    pb = maps.problem("dc-only", preset=PRESET, dc_law=law, params={"dc_scale": scale})
    return pb.well()["dc_stop_force"]


# ----- part 2: the map ------------------------------------------------------------------------------------
def _stroke(law, sign, params, hz, periods):
    """x's (min, max) [m] over the last 10 relay periods of a run of ``periods`` relay periods."""
    import maps
    ds = maps.simulate(SCENE, preset=PRESET, dc_law=law, ac_sign=sign, params=dict(params, relay_hz=hz),
                       x0=START, periods=periods, dt=2e-4)
    late = ds.x.values[ds.t.values >= (periods - 10) / hz - 1e-12]
    return float(late.min()), float(late.max())


def _cells(ds, law, sign, params, rest, relays) -> list:
    from bifurc import class_at
    from bifurc.studykit import in_convention
    dm = in_convention(ds, "mechanical")
    out = []
    for hz in relays:
        c, full = class_at(dm, hz), class_at(ds, hz)
        cell = {"rest": rest, "relay": float(hz), "text": c["text"], "full": full["text"], "period": c["period"],
                "impacts": c["impacts"], "label": c["label"], "stroke": (math.nan, math.nan)}
        if c["label"] == "periodic" and c["period"] == 1:
            i = int(np.argmin(np.abs(ds.relay_hz.values - hz)))
            n = int(ds.periods_integrated.values[0, i])
            p = dict(params, **({"dc_rest": rest} if rest is not None else {}))
            cell["stroke"] = _stroke(law, sign, p, hz, n)
        out.append(cell)
    return out


def _hammers(cell) -> bool:
    lo, hi = cell["stroke"]
    return cell["label"] == "periodic" and cell["period"] == 1 and cell["impacts"] == 1 and hi - min(lo, 0.0) <= STROKE_MAX


def run(out, quick=False, progress=True, overwrite=False, workers=None) -> dict:
    from bifurc.studykit import write_netcdf, write_text
    from bifurc import sweep
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    size = QUICK if quick else FULL
    clock = _time.perf_counter()
    kw = dict(preset=PRESET, x0=START, transient=size["transient"], record=size["record"], lyapunov=size["lyapunov"],
              grazing=False, progress=progress, workers=workers)
    parts = {"structure": structure(), "maps": {}}
    sweeps = {}
    for case, law, sign, params in size["cases"]:
        cells = []
        for rest in size["rests"]:
            ds = sweep(SCENE, "relay_hz", np.array(size["relays"]), dc_law=law, ac_sign=sign,
                       params=dict(params, dc_rest=rest), **kw)
            ds.attrs.update(study=NAME, study_case=case)
            write_netcdf(ds, out / f"{case}_{1e3 * rest:g}mm.nc", overwrite=overwrite)
            cells += _cells(ds, law, sign, params, rest, size["relays"])
            sweeps[(case, rest)] = ds
        parts["maps"][case] = {"law": law, "sign": sign, "params": params, "cells": cells}
        _figure(case, parts["maps"][case], size, out / _png(case, quick), overwrite)
    parts["census"] = census(parts["maps"], size, workers)
    parts["windows"] = windows(parts["maps"], sweeps, size)
    case, law, sign, params = C14
    ds = sweep(SCENE, "relay_hz", np.array(size["c14_relays"]), dc_law=law, ac_sign=sign, params=params, **kw)
    write_netcdf(ds, out / f"{case}.nc", overwrite=overwrite)
    parts["c14"] = {"law": law, "sign": sign, "params": params,
                    "cells": _cells(ds, law, sign, params, None, size["c14_relays"]), "attrs": dict(ds.attrs)}
    parts["seconds"] = _time.perf_counter() - clock
    write_text(out / "report.md", report(parts, quick), overwrite=overwrite)
    return parts


def _png(case, quick) -> str:
    """The map figure's file name (the two forms' figures sit side by side in studies/dc_well/)."""
    return f"map_{case}{'-quick' if quick else ''}.png"


#: the issue's example cell (case, rest [m], relay [Hz]): censused whatever its class
EXAMPLE = ("listing-90V-cair0.5", 0.005, 5.0)


def census(maps_, size, workers) -> list:
    """The switch-on census (:func:`bifurc.attractors`, the scene's switch-on distribution: the bar at rest on
    the stop within 0.1 mm and 1 mm/s, the circuit at rest) at every cell in the thesis' regime and at
    :data:`EXAMPLE`: the share of starts that end on a mechanical period-1 one-impact attractor, and on any
    mechanical period-1 attractor with impacts, with 95 % Wilson intervals."""
    import maps
    from bifurc import attractors
    from scipy.stats import binomtest
    out = []
    for case, m in maps_.items():
        for c in m["cells"]:
            if not (_hammers(c) or (case, c["rest"], c["relay"]) == EXAMPLE):
                continue
            pb = maps.problem(SCENE, PRESET, dict(m["params"], dc_rest=c["rest"]), dc_law=m["law"], ac_sign=m["sign"])
            ds = attractors(pb, "relay_hz", [c["relay"]], starts="switch-on", n_starts=size["census_starts"],
                            budget=size["census_periods"], link=False, progress=False, workers=workers,
                            max_period=CENSUS_MAX_PERIOD)
            row = ds.isel({"relay_hz": 0})
            code = row.class_code.values
            pm, im = row.period_mechanical.values, row.impacts_per_period_mechanical.values
            counts = row.basin_count.values
            one = int(counts[(code == 0) & (pm == 1) & (im == 1)].sum())
            p1 = int(counts[(code == 0) & (pm == 1) & (im >= 1)].sum())
            n = size["census_starts"]
            ci = tuple(map(float, binomtest(one, n).proportion_ci(method="wilson")))      # 95 % Wilson score
            out.append({"case": case, "rest": c["rest"], "relay": c["relay"], "n": n, "p1_one": one, "p1": p1,
                        "p1_one_ci": ci, "attractors": int((row.present.values > 0).sum())})
    return out


def windows(maps_, sweeps, size) -> list:
    """The stable window in rest height of the orbits at the thesis-like cells (quick: the first of each case,
    and :data:`EXAMPLE`; full: every one): the orbit continued in d_dc (under `listing` the rest height itself)
    from the sweep's last state toward ``window_span``'s ends (:func:`bifurc.continue_orbit`, pseudo-arclength),
    and the run of stable points with the cell's period and impact count: its ends and what bounds each (a
    located fold, period doubling, Neimark-Sacker point or grazing, or "branch end" where the continuation
    stopped at ``window_points`` points or the span's end still stable)."""
    from bifurc import class_at, continue_orbit, sweep_point
    from bifurc.studykit import SPECIAL_KINDS
    from maps import ParameterError
    from bifurc import OrbitNotFound
    out = []
    for case, m in maps_.items():
        if m["law"] not in ("listing", "dynamics-script"):
            continue                       # d_dc is the rest height only where the law's rest is at xa = 0
        chosen = [c for c in m["cells"] if _hammers(c) or (case, c["rest"], c["relay"]) == EXAMPLE]
        if size["windows_first_only"]:
            chosen = [c for c in chosen if (case, c["rest"], c["relay"]) == EXAMPLE] + \
                [c for c in chosen if _hammers(c)][:1]
        for c in chosen:
            ds = sweeps[(case, c["rest"])]
            state, k = sweep_point(ds, c["relay"])
            full = class_at(ds, c["relay"])
            row = {"case": case, "rest": c["rest"], "relay": c["relay"], "period": full["period"],
                   "impacts": full["impacts"], "ends": []}
            for end in size["window_span"]:
                try:
                    br = continue_orbit(SCENE, "d_dc", (c["rest"], end), preset=PRESET, dc_law=m["law"],
                                        ac_sign=m["sign"], params=dict(m["params"], relay_hz=c["relay"]), start=state,
                                        k0=k, period=full["period"], max_points=size["window_points"], progress=False)
                except (OrbitNotFound, ParameterError) as exc:
                    row["ends"].append((math.nan, f"not continued: {getattr(exc, 'reason', str(exc))[:80]}"))
                    continue
                d, stab, imp = br.d_dc.values, br.stable.values, br.impacts_per_period.values
                i = 0
                while i + 1 < d.size and stab[i + 1] == 1 and imp[i + 1] == imp[0]:
                    i += 1
                bound = [j for j in range(br.sizes.get("special", 0)) if int(br.special_point.values[j]) == i]
                if bound:
                    j = bound[0]
                    row["ends"].append((float(br.special_value.values[j]),
                                        SPECIAL_KINDS[int(br.special_kind.values[j])].replace("_", " ")))
                elif i + 1 == d.size:
                    row["ends"].append((float(d[i]), "branch end, still stable"))
                else:
                    row["ends"].append((float(d[i]), f"last stable point (next {1e3 * float(d[i + 1]):.4g} mm: "
                                        + ("unstable" if stab[i + 1] != 1 else "impacts change") + ")"))
            out.append(row)
    return out


def _figure(case, m, size, path, overwrite):
    import matplotlib.pyplot as plt

    from bifurc.studykit import check_figure_output
    check_figure_output(path, overwrite)
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for c in m["cells"]:
        x, y = c["relay"], 1e3 * c["rest"]
        if _hammers(c):
            style = dict(marker="*", color="tab:green", ms=14)
        elif c["label"] == "periodic" and c["period"] == 1:
            style = dict(marker="o", color="tab:olive", ms=9)
        elif c["label"] == "periodic":
            style = dict(marker="s", color="tab:blue", ms=7)
        else:
            style = dict(marker="x", color="tab:red", ms=7)
        ax.plot(x, y, ls="none", **style)
        if c["label"] == "periodic":
            ax.annotate(c["text"].replace("period-", "P").replace(" impacts", "i").replace(" impact", "i"), (x, y),
                        fontsize=6, xytext=(3, 3), textcoords="offset points")
    ax.set_yscale("log")
    rests = sorted({1e3 * c["rest"] for c in m["cells"]})
    ax.set_yticks(rests, [f"{r:g}" for r in rests])
    ax.minorticks_off()
    ax.set(xlabel="relay frequency [Hz]", ylabel="rest height above the stop [mm]",
           title=f"{case}: dc_law {m['law']}, AC sign {m['sign']} (star: P1, 1 impact, stroke <= 10 mm; "
                 f"circle: other P1; square: other periodic; x: not periodic)")
    ax.title.set_fontsize(8)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def report(parts, quick) -> str:
    from maps.studykit import git_commit
    s = parts["structure"]
    size = QUICK if quick else FULL
    L = [f"# {NAME}: where the bar rests decides whether the model hammers a few millimetres", "",
         (__doc__ or "").strip(), "",
         f"Form: {'quick' if quick else 'full'}; `bifurc study {NAME}{' --quick' if quick else ''}` at git "
         f"{git_commit() or 'unknown'}; {parts['seconds']:.0f} s.", "",
         "## 1. The structural cause (matlab-listing numbers; every row says its DC law)", "",
         "Derived: maps/well.py (`bifurc params` prints them, every dataset stores them). Simulated: `dc-only` from rest "
         "on the stop, 2 s undamped (x max), 20 s with c_air = 0.5 N s/m (x at the end).", "",
         "| dc_law | rest [mm] | stiffness [N/m] | depth [J] | range [mm] | force on the stop [N] | x max, undamped [mm] "
         "| parked, c_air 0.5 [mm] |", "|---|---|---|---|---|---|---|---|"]
    for law, r in s["laws"].items():
        park = f"{1e3 * r['x_parked']:.3f}" if "x_parked" in r else "on the stop"
        L.append(f"| {law} | {1e3 * r['dc_rest']:.3f} | {r['dc_stiffness']:.4g} | {r['dc_depth']:.4g} | "
                 f"{1e3 * r['dc_range']:.3f} | {r['dc_stop_force']:+.3f} | {1e3 * r['x_max']:.3f} | {park} |")
    L += ["", "Under `listing` the DC strength does not move the swing's top: "
          + "; ".join(f"dc_scale {k:g} ({s['stop_force'][k]:.1f} N at the stop): x max {1e3 * v:.3f} mm"
                      for k, v in s["scales"].items()) + ".", "",
          "thesis-text at 90 V from its 1 mm start, 3 s (the figure docs/model.md quoted as 0.63 mm): "
          + "; ".join(f"`{law}` smallest gap {1e3 * g:.3f} mm, {n} impacts" for law, (g, n) in s["gaps"].items())
          + ".", "",
          "Flight damping from the settling figures (`ac-only`, thesis-text, 25 V, from x = 0, the listings' "
          "tf = 3 s). Fig 4.25 ends oscillating -46.4..-44.6 mm about the AC centre (1.8 mm peak to peak). With the "
          "weight the bar leaves the model's domain at "
          + ", ".join(f"{t:.2f} s (c_air {c:g})" for c, t in s["settling"]["weight"].items())
          + ": no c_air keeps it in the coil, so the figure was not made with the weight acting. Without it, "
          "x's range over the last 0.3 s: "
          + "; ".join(f"c_air {c:g}: {1e3 * lo:.2f}..{1e3 * hi:.2f} mm ({1e3 * (hi - lo):.2f} p-p)"
                      for c, (lo, hi) in s["settling"]["no_weight"].items()) + ".", "",
          "## 2. The map: rest height x relay frequency", "",
          f"Sweeps of relay_hz ({size['transient']} transient + {size['record']} recorded relay periods, extended while "
          f"undecided{'; no Lyapunov exponents' if not size['lyapunov'] else ''}); class in the bar's period "
          "(mechanical), the full state's beside it where it differs; stroke: x's range over the last 10 relay periods "
          "of a run as long as the sweep's, for mechanical period-1 cells.", ""]
    for case, m in parts["maps"].items():
        L += [f"### {case}: dc_law {m['law']}, AC sign {m['sign']}, "
              + ", ".join(f"{k} = {v:g}" for k, v in m["params"].items()), "",
              f"![map]({_png(case, quick)})", "",
              "| rest [mm] | " + " | ".join(f"{w:g} Hz" for w in size["relays"]) + " |",
              "|---|" + "---|" * len(size["relays"])]
        for rest in size["rests"]:
            row = [c for c in m["cells"] if c["rest"] == rest]
            L.append(f"| {1e3 * rest:g} | " + " | ".join(_cell_text(c) for c in row) + " |")
        good = [c for c in m["cells"] if _hammers(c)]
        L += ["", "The thesis' regime (mechanical period-1, one impact per relay period, stroke <= 10 mm): "
              + (", ".join(f"{1e3 * c['rest']:g} mm at {c['relay']:g} Hz" for c in good) if good else "no cell")
              + ".", ""]
    if parts.get("census"):
        L += ["### Switch-on census of the thesis-like cells", "",
              "The scene's switch-on distribution (bar at rest on the stop within 0.1 mm and 1 mm/s, circuit at rest; "
              "not the listings' i = 0.1 A start of the map), `bifurc.attractors(..., starts=\"switch-on\")`, "
              f"{size['census_starts']} starts, up to {size['census_periods']} relay periods each; the share ending on "
              "a mechanical period-1 one-impact attractor (95 % Wilson interval) and on any mechanical period-1 "
              "attractor with impacts.", "",
              "| case | rest [mm] | relay [Hz] | P1, 1 impact | its 95 % interval | P1 with impacts | attractors |",
              "|---|---|---|---|---|---|---|"]
        for r in parts["census"]:
            lo, hi = r["p1_one_ci"]
            L.append(f"| {r['case']} | {1e3 * r['rest']:g} | {r['relay']:g} | {r['p1_one']} of {r['n']} | "
                     f"{lo:.2f}-{hi:.2f} | {r['p1']} of {r['n']} | {r['attractors']} |")
        L.append("")
    if parts.get("windows"):
        L += ["### Stable windows in rest height (continuation)", "",
              "The orbit at a thesis-like cell (and at the example cell) continued in d_dc, which under `listing` is "
              f"the rest height, toward {1e3 * size['window_span'][0]:g} and {1e3 * size['window_span'][1]:g} mm "
              f"(at most {size['window_points']} points each way): the stable run with the cell's period and impact "
              "count, and what bounds each end.", "",
              "| case | relay [Hz] | orbit (full state) | from rest [mm] | lower end [mm] | bounded by | upper end [mm] "
              "| bounded by |", "|---|---|---|---|---|---|---|---|"]
        for r in parts["windows"]:
            (lo, klo), (hi, khi) = r["ends"]
            L.append(f"| {r['case']} | {r['relay']:g} | period-{r['period']}, {r['impacts']} impacts | "
                     f"{1e3 * r['rest']:g} | {1e3 * lo:.4f} | {klo} | {1e3 * hi:.4f} | {khi} |")
        L.append("")
    c14 = parts["c14"]
    agree = [c for c in c14["cells"] if c["label"] == "periodic" and c["period"] == THESIS_NUMERICAL[int(c["relay"])]]
    L += [f"## 3. Listing C.14's law (`dynamics-script`, rest on the stop, AC sign {c14['sign']}, V = "
          f"{c14['params']['V']:g} V) against Fig 4.27", "",
          "| relay [Hz] | toolkit (mechanical) | full state | stroke [mm] | Fig 4.27 |", "|---|---|---|---|---|"]
    for c in c14["cells"]:
        st = "" if math.isnan(c["stroke"][1]) else f"{1e3 * c['stroke'][0]:.2f} .. {1e3 * c['stroke'][1]:.2f}"
        L.append(f"| {c['relay']:g} | {c['text']} | {'same' if c['full'] == c['text'] else c['full']} | {st} | "
                 f"period-{THESIS_NUMERICAL[int(c['relay'])]} |")
    names = ", ".join(f"{c['relay']:g} Hz" for c in agree) or "none"
    L += ["", f"Agrees with the thesis' numerical period at {len(agree)} of {len(c14['cells'])} frequencies "
          f"({names}). With the physical AC sign the bar stays on the "
          "stop (tests/test_dc_well.py).", ""]
    return "\n".join(L)


def _cell_text(c) -> str:
    t = c["text"].replace("period-", "P").replace(" impacts", " imp").replace(" impact", " imp")
    if c["full"] != c["text"]:
        t += f" (full {c['full'].replace('period-', 'P').split(',')[0]})"
    if not math.isnan(c["stroke"][1]):
        t += f", {1e3 * c['stroke'][0]:.1f}..{1e3 * c['stroke'][1]:.1f} mm"
    return ("**" + t + "**") if _hammers(c) else t


def findings(results, quick) -> list:
    from bifurc.studykit import Finding
    out = []
    s = results["structure"]
    for law, r in s["laws"].items():
        # tolerances above the report's 6 significant digits
        out.append(Finding(f"{law}: rest height (derived)", 1e3 * r["dc_rest"], 1e-3, "mm"))
        out.append(Finding(f"{law}: well stiffness (derived)", r["dc_stiffness"], max(1e-3, 1e-5 * r["dc_stiffness"]),
                           "N/m"))
        out.append(Finding(f"{law}: range, top of the swing from the stop (derived)", 1e3 * r["dc_range"], 1e-3, "mm"))
        out.append(Finding(f"{law}: DC-only from the stop, x max over 2 s", 1e3 * r["x_max"], 0.01, "mm"))
        if "x_parked" in r:
            out.append(Finding(f"{law}: DC-only, c_air 0.5, x after 20 s", 1e3 * r["x_parked"], 0.01, "mm"))
    for k, v in s["scales"].items():
        out.append(Finding(f"listing, dc_scale {k:g}: DC-only x max over 2 s", 1e3 * v, 0.01, "mm"))
    for law, (g, n) in s["gaps"].items():
        out.append(Finding(f"thesis-text 90 V, {law}: smallest gap in 3 s from 1 mm", 1e3 * g, 0.005, "mm"))
        out.append(Finding(f"thesis-text 90 V, {law}: impacts in 3 s", n, 0, ""))
    for c, t in results["structure"]["settling"]["weight"].items():
        out.append(Finding(f"ac-only 25 V with the weight, c_air {c:g}: time it leaves the domain", t, 0.01, "s"))
    for c, (lo, hi) in results["structure"]["settling"]["no_weight"].items():
        out.append(Finding(f"ac-only 25 V without the weight, c_air {c:g}: x range, last 0.3 s of 3 s",
                           1e3 * (hi - lo), 0.05, "mm"))
    for case, m in results["maps"].items():
        good = [c for c in m["cells"] if _hammers(c)]
        out.append(Finding(f"{case}: cells in the thesis' regime (P1, 1 impact, stroke <= 10 mm)",
                           "; ".join(f"{1e3 * c['rest']:g} mm {c['relay']:g} Hz" for c in good) or "none"))
        for c in m["cells"]:
            out.append(Finding(f"{case}: rest {1e3 * c['rest']:g} mm, {c['relay']:g} Hz (mechanical)", c["text"]))
    for r in results.get("census", []):
        out.append(Finding(f"switch-on census, {r['case']}, rest {1e3 * r['rest']:g} mm, {r['relay']:g} Hz: starts "
                           f"ending on mechanical P1 with 1 impact", r["p1_one"], 0, f"of {r['n']}"))
    for r in results.get("windows", []):
        for (v, kind), side in zip(r["ends"], ("lower", "upper")):
            out.append(Finding(f"window in rest height, {r['case']}, {1e3 * r['rest']:g} mm, {r['relay']:g} Hz: "
                               f"{side} end", 1e3 * v, 0.01, "mm"))
            out.append(Finding(f"window in rest height, {r['case']}, {1e3 * r['rest']:g} mm, {r['relay']:g} Hz: "
                               f"{side} end bounded by", kind.split(" (")[0]))
    for c in results["c14"]["cells"]:
        out.append(Finding(f"C.14 law, 25 V, listing sign: {c['relay']:g} Hz (mechanical)", c["text"]))
    return out
