"""Sensitivity of the thesis model's hammering to its unknowns: one-at-a-time (tornado) and Sobol indices.

Base model: thesis-1dof with listing C.1's numbers (preset matlab-listing) under the `catalogue` DC law
(docs/model.md section 1: a pull credible at the stop), every cell from the scene's start.  Each sample
(one value of every input inside its documented range) gives five scalars:

- `share_p1`: the share of a (relay 2-10 Hz x V 25-90 V) grid whose mechanical states are period-1 with
  one impact per relay period (`period_mechanical` = 1, `impacts_per_period_mechanical` = 1, periodic);
- `energy_mJ`, `stroke_mm`: mean impact energy (m v^2 / 2 at the impact) and bar stroke (x range over the
  last relay period) on those cells (NaN where none); `stroke_min_mm`: the smallest stroke among them (the
  thesis' period-1 moved the bar a few millimetres: a stroke of at most 10 mm counts as that regime);
- `rate_mm_s`: the 2-DOF prototype's progression rate (drift soil, 6 Hz, 90 V read as `v_factor` x 90 V,
  dc_scale 1.44) over the second half of its run.

Method: SALib's Saltelli sampling and Sobol estimator (first-order S1 and total ST with 95 % confidence
intervals; N base samples, N (D + 2) runs), and one-at-a-time runs (each input at its low and high end,
the others at mid-range).  Nothing is tuned to agree with the thesis.
"""
from __future__ import annotations

import json
import math
import time as _time
from pathlib import Path

import numpy as np

NAME = "sensitivity"
SCENE, PRESET, LAW = "thesis-1dof", "matlab-listing", "catalogue"
RELAY, VOLTS = (2.0, 10.0), (25.0, 90.0)
#: input -> (low, high, unit, documented range's source)
INPUTS = {
    "F_dc_sat": (3.6, 7.4, "N", "catalogue law's plateau: from Table 4.1's last point (3.6 N at 29 mm: the pull "
                                "cannot be lower at the stop) to the catalogue's 7.4 N at 24 V"),
    "c_air": (0.0, 0.5, "N s m-1", "free-flight damping: none (the thesis' model) to 0.5 (docs/model.md 1b)"),
    "v_factor": (1.0, math.sqrt(2.0), "1", "AC amplitude convention: the volts read as amplitude (1) or RMS (sqrt 2)"),
    "dc_scale": (0.5625, 1.44, "1", "DC supply 15-24 V under the (V/20)^2 rule (sections 4.2-4.3, 5.2)"),
    "R": (25.0, 30.0, "ohm", "listing C.1 (25) to sections 4.5-4.6 (30)"),
    "C": (2.8e-4, 3.0e-4, "F", "listing C.1 (2.8e-4) to sections 4.5-4.6 (3e-4)"),
    "k": (1e5, 1e6, "N m-1", "listing C.1 (1e5) to C.14 (1e6)"),
    "c": (10.0, 500.0, "N s m-1", "listing C.1 (10) to C.14 (500)"),
    "P_max": (40.0, 120.0, "N", "2-DOF drift soil threshold (an assumption; README: 55-130 N put the rate in range)"),
}
QUICK = dict(inputs=("F_dc_sat", "c_air", "v_factor"), N=4, n=3, transient=40, record=20, periods_2dof=30)
FULL = dict(inputs=tuple(INPUTS), N=256, n=9, transient=200, record=60, periods_2dof=120)
#: the full form's samples at N = 8 (107 samples of the 2835): its wall time per sample measures the full form's
#: (benchmarks/sensitivity.py); not a form of the command
MEDIUM = dict(FULL, N=8)
OUTPUTS = {"share_p1": "share of cells P1-1 (mechanical)", "energy_mJ": "mean impact energy on them [mJ]",
           "stroke_mm": "mean stroke on them [mm]", "stroke_min_mm": "smallest stroke on them [mm]",
           "rate_mm_s": "2-DOF progression rate [mm/s]"}
#: the thesis' period-1 moved the bar a few millimetres (its sensor spanned +-5 mm): a P1-1 cell whose
#: stroke is at most FEW_MM is a candidate, thesis-like where its settled stroke lies in THESIS_STROKE [mm]
#: (below 1 mm the bar chatters at the stop: not the thesis' hammering)
FEW_MM = 10.0
THESIS_STROKE = (1.0, FEW_MM)
#: a thesis-like cell is confirmed on a record ten times the full form's (relay periods)
CONFIRM = dict(transient=2000, record=400)


def problem_spec(size):
    names = list(size["inputs"])
    return {"num_vars": len(names), "names": names, "bounds": [list(INPUTS[k][:2]) for k in names]}


def design(size) -> tuple[np.ndarray, int]:
    """(samples, n_oat): the one-at-a-time rows (mid, then each input low and high), then Saltelli's."""
    from SALib.sample import sobol as sobol_sample
    spec = problem_spec(size)
    lo, hi = np.array(spec["bounds"]).T
    mid = (lo + hi) / 2
    oat = [mid]
    for j in range(len(mid)):
        for end in (lo[j], hi[j]):
            row = mid.copy()
            row[j] = end
            oat.append(row)
    sob = sobol_sample.sample(spec, size["N"], calc_second_order=False, seed=1)
    return np.vstack([np.array(oat), sob]), len(oat)


class SampleJob:
    """job(i): the outputs of sample row i (picklable, for bifurc's executor)."""

    batch_size = 1

    def __init__(self, rows, names, size):
        self.rows, self.names, self.size = np.asarray(rows), list(names), dict(size)

    def __call__(self, i):
        return evaluate(dict(zip(self.names, map(float, self.rows[int(i)]))), self.size)


def _values(sample: dict, keys) -> dict:
    return {k: sample[k] for k in keys if k in sample}


def evaluate(sample: dict, size: dict) -> dict:
    """The outputs of one sample (:data:`OUTPUTS`; inputs not in ``sample`` take the model's defaults)."""
    import maps
    vf = sample.get("v_factor", 1.0)
    cells, share = hammering_cells(sample, size)
    energies, strokes = [c["energy_mJ"] for c in cells], [c["stroke_mm"] for c in cells]
    p2 = dict(_values(sample, ("F_dc_sat", "c_air", "P_max")), V=90.0 * vf,
              relay_hz=6.0)
    p2["dc_scale"] = 1.44 * sample.get("dc_scale", 1.0)
    p2["dc_scale"] = min(p2["dc_scale"], 100.0)
    h2 = maps.simulate("prototype", periods=size["periods_2dof"], dc_law=LAW, soil="drift", params=p2)
    return {"share_p1": share, "energy_mJ": float(np.mean(energies)) if energies else math.nan,
            "stroke_mm": float(np.mean(strokes)) if strokes else math.nan,
            "stroke_min_mm": float(np.min(strokes)) if strokes else math.nan,
            "rate_mm_s": float(h2.progression_rate) * 1e3}


def hammering_cells(sample: dict, size: dict, **record) -> tuple:
    """([cell], share): the (relay, V) cells of the sample's map that hammer mechanical period-1 with one
    impact per relay period, each a dict of its relay [Hz], V [V], impact energy [mJ], stroke [mm] and the
    stroke run's impacts in its last period (:func:`stroke_and_impacts`; ``record``: transient=, record=, and
    relays=, volts= to override the form's)."""
    from bifurc.labels.codes import ClassCode
    from bifurc.sweeps.regime import regime_map
    n, vf = size["n"], sample.get("v_factor", 1.0)
    params = _values(sample, ("F_dc_sat", "c_air", "dc_scale", "R", "C", "k", "c"))
    params.setdefault("c_air", 0.0)
    relays, volts = np.asarray(record.pop("relays", np.linspace(*RELAY, n))), \
        np.asarray(record.pop("volts", np.linspace(*VOLTS, n) * vf))
    periods = dict(dict(transient=size["transient"], record=size["record"]), **record)
    ds = regime_map(SCENE, "relay_hz", relays, "V", volts, preset=PRESET, dc_law=LAW, params=params, workers=1,
                    progress=False, error_sample=0, lyapunov=False, **periods)
    hit = ((ds.period_mechanical == 1) & (ds.impacts_per_period_mechanical == 1)
           & (ds.class_code == ClassCode.PERIODIC)).values
    m = float(ds.attrs.get("param_m", 0.155))
    total = periods["transient"] + periods["record"]
    cells = []
    for i, j in zip(*np.nonzero(hit)):
        x_range, impacts = stroke_and_impacts(dict(params, relay_hz=float(relays[i]), V=float(volts[j])), total)
        cells.append({"relay_hz": float(relays[i]), "V": float(volts[j]),
                      "energy_mJ": 0.5 * m * float(ds.min_impact_speed.values[i, j]) ** 2 * 1e3,
                      "stroke_mm": x_range * 1e3, "stroke_run_impacts": impacts})
    return cells, float(hit.mean())


def stroke(params: dict, periods: int, samples: int = 1000) -> float:
    """Bar stroke [m]: the range of x over the last of ``periods`` relay periods from the scene's start
    (:func:`stroke_and_impacts`)."""
    return stroke_and_impacts(params, periods, samples)[0]


def stroke_and_impacts(params: dict, periods: int, samples: int = 1000) -> tuple:
    """(stroke [m], impacts): the range of x over the last of ``periods`` relay periods from the scene's
    start, sampled ``samples`` times in it, and the impacts in that period.  A bare scalar run at tol 1e-10
    without stops at observation-only guards: about 40 times cheaper than ``maps.simulate``'s full time
    history at the same samples (benchmarks/sensitivity.py).  It is another trajectory than the map's (the
    batch engine's): where attractors coexist and the transient is long the two can land apart, which its
    impact count shows."""
    from maps.engines.scalar import HybridRun
    from maps.problem import problem
    pb = problem(SCENE, PRESET, params, dc_law=LAW)
    period = 1.0 / float(params["relay_hz"])
    times = np.linspace((periods - 1) * period, periods * period, samples + 1)
    ix = [s.name for s in pb.system.states].index("x")
    xs = []

    def on_segment(c_out, ta, tb):
        sel = times[(times >= ta) & (times <= tb)]
        if sel.size:
            xs.append(np.asarray(c_out(sel))[:, ix])

    run = HybridRun(pb.system, dict(pb.values), dict(pb.x0), tol=1e-10, observations=False)
    if pb.flags0 is not None:
        run.reset(0.0, pb.state_vector(), pb.system.initial_flags(0.0, pb.values, pb.flags0))
    run.advance(times[0])
    run.advance(times[-1], on_segment=on_segment)
    from maps.impacts import impact_table
    return (float(np.ptp(np.concatenate(xs))) if xs else math.nan,
            int(np.sum(impact_table(run)["t"] >= times[0])))


def run(out, quick=False, progress=True, overwrite=False, workers=None, scheduler=None, size=None) -> dict:
    """Run every sample into ``out`` (each result kept in ``out/samples.parts/``: a rerun resumes),
    then write ``report.md`` and ``samples.json``; returns the report's tables as a dict (with the
    form's size, the wall time and the samples run).  ``size``: another form's dict (e.g. MEDIUM)."""
    from bifurc.storage.files import write_text
    from bifurc.run.executor import available_cores, map_values
    from tqdm.auto import tqdm
    size = size or (QUICK if quick else FULL)
    out = Path(out)
    parts = out / "samples.parts"
    parts.mkdir(parents=True, exist_ok=True)
    rows, n_oat = design(size)
    names = list(size["inputs"])
    key = json.dumps({"size": size, "names": names}, sort_keys=True)
    done = {}
    for f in parts.glob("*.json"):
        rec = json.loads(f.read_text())
        if rec.get("key") == key:
            done[int(rec["i"])] = rec["out"]
    todo = [i for i in range(len(rows)) if i not in done]
    clock = _time.perf_counter()
    bar = tqdm(total=len(rows), initial=len(done), desc=NAME, disable=not progress)

    def take(start, results):
        for k, res in enumerate(results):
            i = todo[start + k]
            done[i] = res
            (parts / f"{i:06d}.json").write_text(json.dumps({"key": key, "i": i, "out": res}))
            bar.update(1)

    if todo:
        w = workers or min(available_cores(), len(todo))
        map_values(SampleJob(rows, names, size), np.array(todo, dtype=float), workers=w, scheduler=scheduler, chunk_size=1,
                   on_chunk=take, collect=False)
    bar.close()
    seconds = _time.perf_counter() - clock
    wall = out / "wall.json"      # the wall time of every run into this folder (a resumed run adds its own)
    total = (json.loads(wall.read_text())["seconds"] if wall.is_file() else 0.0) + seconds
    wall.write_text(json.dumps({"seconds": total}))
    Y = {o: np.array([done[i][o] for i in range(len(rows))]) for o in OUTPUTS}
    result = analyse(rows, n_oat, Y, size)
    result.update(size=dict(size), seconds=seconds, seconds_all_runs=total, n_samples=len(rows), n_run=len(todo),
                  outputs_per_sample=Y, thesis_like=thesis_like(rows, names, size, Y),
                  hit_ranges=hit_ranges(rows, names, Y))
    write_text(out / "samples.json", json.dumps({"inputs": names, "rows": rows.tolist(),
                                                 "outputs": {o: Y[o].tolist() for o in Y}}), overwrite=True)
    write_text(out / "report.md", report(result, size, quick, seconds, len(rows), len(todo)), overwrite=True)
    return result


def thesis_like(rows, names, size, Y) -> list:
    """Each P1-1 cell with a stroke of at most :data:`FEW_MM`, found again by re-running its sample's map, and
    that cell re-run on a record ten times longer (:data:`CONFIRM`): [dict(sample, inputs, relay_hz, V, energy_mJ,
    stroke_mm, longer: the longer record's P1-1 cell or None, confirmed: P1-1 there with a stroke in
    :data:`THESIS_STROKE`)]."""
    out = []
    pick = np.nonzero((np.asarray(Y["share_p1"]) > 0) & (np.asarray(Y["stroke_min_mm"]) <= FEW_MM))[0]
    for i in pick:
        sample = dict(zip(names, map(float, rows[i])))
        for c in hammering_cells(sample, size)[0]:
            if c["stroke_mm"] <= FEW_MM:
                again = hammering_cells(sample, size, relays=[c["relay_hz"]], volts=[c["V"]], **CONFIRM)[0]
                longer = again[0] if again else None
                ok = (longer is not None and longer["stroke_run_impacts"] == 1
                      and THESIS_STROKE[0] <= longer["stroke_mm"] <= THESIS_STROKE[1])
                out.append(dict(c, sample=int(i), inputs=sample, longer=longer, confirmed=ok))
    return out


def hit_ranges(rows, names, Y) -> dict:
    """{input: (lowest, highest)} over the samples with a P1-1 cell (empty without one)."""
    hit = np.asarray(Y["share_p1"]) > 0
    return {k: (float(rows[hit, j].min()), float(rows[hit, j].max())) for j, k in enumerate(names)} if hit.any() else {}


def analyse(rows, n_oat, Y, size) -> dict:
    """Tornado (output at each input's low/high end) and Sobol S1/ST with 95 % intervals per output."""
    from SALib.analyze import sobol
    spec = problem_spec(size)
    out = {"tornado": {}, "sobol": {}, "base": {o: float(Y[o][0]) for o in Y}}
    for j, name in enumerate(spec["names"]):
        out["tornado"][name] = {o: (float(Y[o][1 + 2 * j]), float(Y[o][2 + 2 * j])) for o in Y}
    for o in Y:
        y = Y[o][n_oat:].copy()
        finite = np.isfinite(y)
        if finite.sum() < 0.5 * y.size or np.nanstd(y) == 0:
            out["sobol"][o] = None          # too few finite or all equal: no indices
            continue
        y[~finite] = np.nanmean(y)          # cells without hammering: the mean (stated in the report)
        si = sobol.analyze(spec, y, calc_second_order=False, seed=1)
        out["sobol"][o] = {name: {k: float(si[k][j]) for k in ("S1", "S1_conf", "ST", "ST_conf")}
                           for j, name in enumerate(spec["names"])}
    return out


def _f(v, fmt=".3g"):
    return "n/a" if v is None or (isinstance(v, float) and not math.isfinite(v)) else format(v, fmt)


def _commit() -> str:
    import subprocess
    try:
        return subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=Path(__file__).parent, capture_output=True,
                              text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def report(result, size, quick, seconds, n_rows, n_run) -> str:
    import datetime
    from maps._version import __version__
    form = ("quick" if quick else "full" if size == FULL
            else f"medium (the full form's inputs and cells, N = {size['N']})")
    made_by = f"bifurc study {NAME}{' --quick' if quick else ''} -o DIR" if form in ("quick", "full") else \
        "python benchmarks/sensitivity.py"
    lines = [f"# {NAME}: what the thesis model's unknowns decide", "",
             f"Produced by `{made_by}` at commit {_commit()} on "
             f"{datetime.date.today().isoformat()}.", "", (__doc__ or "").strip(), "",
             f"Form: {form}: inputs {', '.join(size['inputs'])}; N = {size['N']}; "
             f"{size['n']} x {size['n']} cells per sample ({size['transient']} transient + {size['record']} "
             f"recorded relay periods); prototype {size['periods_2dof']} relay periods.  {n_rows} samples "
             f"({n_run} run now) in {seconds:.0f} s wall ({result.get('seconds_all_runs', seconds):.0f} s over every "
             f"run into its folder).  Toolkit {__version__}.", "",
             "## Inputs and their documented ranges", "", "| input | low | high | unit | source |", "|---|---|---|---|---|"]
    lines += [f"| {k} | {INPUTS[k][0]:g} | {INPUTS[k][1]:g} | {INPUTS[k][2]} | {INPUTS[k][3]} |" for k in size["inputs"]]
    lines += ["", "## One at a time (tornado): each output at the input's low / high end, others mid-range", "",
              "| input | " + " | ".join(OUTPUTS) + " |", "|---|" + "---|" * len(OUTPUTS)]
    lines += ["| (all mid) | " + " | ".join(_f(result["base"][o]) for o in OUTPUTS) + " |"]
    for k, row in result["tornado"].items():
        lines.append(f"| {k} | " + " | ".join(f"{_f(a)} / {_f(b)}" for a, b in (row[o] for o in OUTPUTS)) + " |")
    lines += ["", "## Sobol indices", "",
              "First-order S1 and total ST with 95 % confidence half-widths (SALib, Saltelli sampling).  Where an "
              "output is NaN for a sample (no hammering cell), it takes the outputs' mean; n/a: too few finite "
              "values or no variation.", "",
              "| output | input | S1 | S1 95 % | ST | ST 95 % |", "|---|---|---|---|---|---|"]
    for o in OUTPUTS:
        s = result["sobol"][o]
        if s is None:
            lines.append(f"| {o} | (all) | n/a | | n/a | |")
            continue
        lines += [f"| {o} | {k} | {_f(v['S1'], '.2f')} | ±{_f(v['S1_conf'], '.2f')} | {_f(v['ST'], '.2f')} | "
                  f"±{_f(v['ST_conf'], '.2f')} |" for k, v in s.items()]
    lines += ["", f"## Thesis-like cells: P1-1 with a stroke of at most {FEW_MM:g} mm", ""] + _thesis_like_lines(result)
    lines += ["", "## Finding", "", finding(result, size), ""]
    return "\n".join(lines)


def _thesis_like_lines(result) -> list:
    cells, size = result.get("thesis_like", []), result["size"]
    if not cells:
        return [f"None in the {len(result['outputs_per_sample']['share_p1'])} samples."]
    lines = [f"Each found again by re-running its sample's map, then re-run alone over {CONFIRM['transient']} + "
             f"{CONFIRM['record']} relay periods: thesis-like where it is still P1-1 there with a stroke of "
             f"{THESIS_STROKE[0]:g}-{THESIS_STROKE[1]:g} mm.  V is the amplitude applied (the volts read times "
             "v_factor).", "",
             "The stroke comes from a scalar run from the same start, the class and impact energy from the map's batch "
             "run: a cell is thesis-like only where the scalar run also strikes once in its last relay period (else "
             "the two runs settled on different attractors and the stroke is not the P1-1 orbit's).", "",
             "| sample | relay [Hz] | V [V] | stroke [mm] | impact energy [mJ] | longer record | scalar run's impacts in "
             f"its last period ({size['transient'] + size['record']}, {sum(CONFIRM.values())} periods) | inputs |", "|---|---|---|---|---|---|---|---|"]
    for c in cells:
        inputs = ", ".join(f"{k} {_f(v, '.4g')}" for k, v in c["inputs"].items())
        got = c["longer"]
        longer = ("not P1-1" if got is None else f"P1-1, stroke {_f(got['stroke_mm'])} mm, impact energy "
                  f"{_f(got['energy_mJ'])} mJ: {'thesis-like' if c['confirmed'] else 'not shown thesis-like'}")
        impacts = f"{c['stroke_run_impacts']}, " + ("n/a" if got is None else str(got["stroke_run_impacts"]))
        lines.append(f"| {c['sample']} | {c['relay_hz']:.4g} | {c['V']:.4g} | {_f(c['stroke_mm'])} | "
                     f"{_f(c['energy_mJ'])} | {longer} | {impacts} | {inputs} |")
    return lines


def finding(result, size) -> str:
    """What decides the period-1 regime, as found (from the tornado and Sobol tables)."""
    s = result["sobol"].get("share_p1")
    swing = {k: abs(v["share_p1"][1] - v["share_p1"][0]) for k, v in result["tornado"].items()}
    top = max(swing, key=swing.get)
    text = (f"Share of P1-1 cells at mid-range: {_f(result['base']['share_p1'])}.  "
            + (f"Largest one-at-a-time swing of that share: {top} ({_f(swing[top])})." if swing[top] > 0 else
               "No input moves that share one at a time."))
    if s is not None:
        st = max(s, key=lambda k: s[k]["ST"])
        text += (f"  Largest total Sobol index: {st} (ST {_f(s[st]['ST'], '.2f')} ± {_f(s[st]['ST_conf'], '.2f')}); "
                 "intervals this wide (small N) rank the inputs only where they do not overlap.")
    else:
        text += "  The share does not vary over the samples: no Sobol index for it."
    few, n_hit, smallest = _few_mm(result)
    text += (f"  Samples with a P1-1 cell: {n_hit} of {len(result['outputs_per_sample']['share_p1'])}; with one whose "
             f"stroke is at most {FEW_MM:g} mm (the thesis' few-mm period-1 at 25-90 V): {few}"
             + (f" (smallest stroke on any P1-1 cell: {_f(smallest)} mm)" if n_hit else "")
             + f"; thesis-like after the checks of the section above: "
               f"{sum(c['confirmed'] for c in result.get('thesis_like', []))}.")
    narrow = [f"{k} within {_f(a)}-{_f(b)} (documented {_f(INPUTS[k][0])}-{_f(INPUTS[k][1])})"
              for k, (a, b) in result.get("hit_ranges", {}).items() if b - a < 0.5 * (INPUTS[k][1] - INPUTS[k][0])]
    if narrow:
        text += "  Every sample with a P1-1 cell has " + "; ".join(narrow) + "."
    return text


def _few_mm(result) -> tuple:
    """(samples with a P1-1 cell of stroke <= FEW_MM, samples with a P1-1 cell, smallest such stroke [mm])."""
    Y = result["outputs_per_sample"]
    share, smin = np.asarray(Y["share_p1"], dtype=float), np.asarray(Y["stroke_min_mm"], dtype=float)
    hit = share > 0
    smallest = float(np.nanmin(smin[hit])) if hit.any() and np.isfinite(smin[hit]).any() else math.nan
    return int(np.sum(hit & (smin <= FEW_MM))), int(hit.sum()), smallest


def findings(results, quick) -> list:
    """What the report states: the share of P1-1 cells at mid-range and over all samples (+-1 cell of
    one sample's grid), the mid-range progression rate (+-0.05 mm/s) and the input of the largest
    one-at-a-time swing of each output (exact; "none" where no output moves)."""
    from bifurc.findings import Finding
    size = results.get("size", QUICK if quick else FULL)
    cell = 1.0 / size["n"] ** 2
    Y = results["outputs_per_sample"]
    few, n_hit, _ = _few_mm(results)
    out = [Finding("share_p1 at mid-range", round(results["base"]["share_p1"], 6), cell, "1"),
           Finding("share_p1 mean over samples", round(float(np.mean(Y["share_p1"])), 6), cell, "1"),
           Finding("samples with a P1-1 cell", n_hit, 1, "samples"),
           Finding(f"samples with a P1-1 cell of stroke at most {FEW_MM:g} mm", few, 1, "samples"),
           Finding(f"thesis-like cells (P1-1, stroke {THESIS_STROKE[0]:g}-{THESIS_STROKE[1]:g} mm on the longer record)",
                   sum(c["confirmed"] for c in results.get("thesis_like", [])), 0, "cells"),
           Finding("rate_mm_s at mid-range", round(results["base"]["rate_mm_s"], 4), 0.05, "mm s-1")]
    for o in ("share_p1", "rate_mm_s"):
        swing = {k: abs(v[o][1] - v[o][0]) for k, v in results["tornado"].items() if np.all(np.isfinite(v[o]))}
        top = max(swing, key=swing.get) if swing and max(swing.values()) > 0 else "none"
        out.append(Finding(f"largest one-at-a-time swing of {o}", top))
    return out

