"""Sensitivity of the thesis model's regime to the inputs that decide it (issue 46 section 3).

Each sample is one point of eight inputs: the DC well's rest height and stiffness (maps/well.py: set by
``dc_rest`` and ``dc_stiffness``, the law's shape kept), the law's shape (`listing`'s cubic, `catalogue`,
listing C.14's `dynamics-script`), the AC sign, the flight damping c_air, the AC amplitude V, the relay
frequency and the start (the bar at rest at a fraction of the rest height, the listings' i = 0.1 A).  At it:

- the thesis-1dof model (preset matlab-listing) runs from that start over ``transient`` + ``record`` relay
  periods (one scalar run, :func:`maps.run_scene`); over the recorded window it gives ``gap``, the continuous
  distance to the thesis' regime (studies/sensitivity/measures.py: the share of relay periods without exactly one
  impact, the spread of the impacts' phases, the stroke beyond 10 mm, averaged; 0 exactly in the regime: the
  bar's motion repeats every relay period with one impact and a stroke of at most 10 mm), ``stroke_mm`` (x's
  range over the window) and ``in_regime`` (gap below 1e-3: the old study's 0/1 output, reported per law);
- the 2-DOF prototype (drift soil, the same law, well, AC sign, c_air, V and relay frequency, its own preset)
  gives ``rate_mm_s``, the progression rate over the second half of ``periods_2dof`` relay periods.

Categorical inputs: the law and the AC sign are uniform inputs on [0, 3) and [0, 2) mapped to their levels by
their integer part (levels in :data:`LAWS`, :data:`SIGNS`), so the Sobol and delta indices measure their whole
effect as one input each; the per-law table beside them gives each law's own means.  The stiffness is a factor
(2^-1 to 2^0.5) of the law's own stiffness at its rest in that scene, since the laws' own stiffnesses differ
twentyfold (15.4 N/m for the cubics, 305 N/m for `catalogue`); the catalogue law under the weight reaches at most
1.48 times its own.

Method: SALib's Saltelli sampling and Sobol estimator (total ST with bootstrap 95 % intervals, N base samples,
N (D + 2) runs); the moment-independent delta (Borgonovo, SALib) on the same samples where Sobol does not meet
the convergence test (:func:`converged`).  Nothing is tuned to agree with the thesis.
"""
from __future__ import annotations

import contextlib
import io
import json
import math
import time as _time
import warnings
from pathlib import Path

import numpy as np

from .measures import FEW_MM, regime_gap

NAME = "sensitivity"
SCENE, PRESET, SCENE_2DOF = "thesis-1dof", "matlab-listing", "prototype"
LAWS = ("listing", "catalogue", "dynamics-script")
SIGNS = ("physical", "listing")
I0 = 0.1                    # [A] the listings' start current (C.1)
#: input -> (low, high, unit, meaning and source)
INPUTS = {
    "log10_rest_mm": (0.0, math.log10(62.5), "log10 mm",
                      "rest height above the stop, AC off, 1-62.5 mm (62.5 mm: listing C.9 with y = 0.108 m; the "
                      "dc-well study finds the regime at 1-5 mm)"),
    "log2_stiffness": (-1.0, 0.5, "log2 of a factor", "well stiffness at the rest, 0.5-1.41 times the law's own"),
    "law": (0.0, 3.0, "level", "DC law's shape: [0,1) listing (cubic, C.9), [1,2) catalogue, [2,3) dynamics-script "
                               "(C.14)"),
    "ac_sign": (0.0, 2.0, "level", "AC force sign: [0,1) physical, [1,2) listing (the listings' reversed sign)"),
    "c_air": (0.0, 0.5, "N s m-1", "flight damping: none (the listings) to 0.5 (docs/model.md)"),
    "V": (25.0, 90.0, "V", "AC amplitude, the thesis' experiments' 25-90 V"),
    "relay_hz": (2.0, 10.0, "Hz", "relay frequency, the thesis' 2-10 Hz"),
    "start": (0.0, 1.0, "1", "start height as a fraction of the rest height (0: on the stop), at rest, i = 0.1 A"),
}
OUTPUTS = {"gap": "distance to the regime (0: in it) [1]", "stroke_mm": "stroke over the record [mm]",
           "rate_mm_s": "2-DOF progression rate, drift soil [mm/s]"}
#: the quick form: N = 4 (40 samples), short runs; the full form: N = 256 (2560 samples); MEDIUM: the full form's
#: runs at N = 32 (320 samples): what was run for the committed report.md (the full form exceeds the shared budget)
QUICK = dict(N=4, transient=20, record=8, periods_2dof=20)
FULL = dict(N=256, transient=100, record=20, periods_2dof=60)
MEDIUM = dict(FULL, N=32)
IN_REGIME = 1e-3            # gap below this: in the regime
#: convergence test of the top three total indices: 95 % intervals narrower than this
WIDTH = 0.1
TOL = 1e-10


def problem_spec():
    names = list(INPUTS)
    return {"num_vars": len(names), "names": names, "bounds": [list(INPUTS[k][:2]) for k in names]}


def design(size) -> np.ndarray:
    """Saltelli's sample rows (N (D + 2), scrambled Sobol' sequence, seed 1)."""
    from SALib.sample import sobol as sobol_sample
    return sobol_sample.sample(problem_spec(), size["N"], calc_second_order=False, seed=1)


def level(value: float, levels: tuple) -> str:
    """The categorical level of a uniform input on [0, len(levels)): its integer part."""
    return levels[min(int(math.floor(value)), len(levels) - 1)]


def configure(sample: dict, scene: str) -> dict:
    """The model at one sample: {"dc_law", "ac_sign", "params", "x0"} for ``scene`` (the 1-DOF start: at rest at
    ``start`` times the rest height; the 2-DOF scene keeps its own start)."""
    import maps
    law, sign = level(sample["law"], LAWS), level(sample["ac_sign"], SIGNS)
    preset = PRESET if scene == SCENE else None
    own = maps.problem(scene, preset, dc_law=law).well()
    rest = 1e-3 * 10 ** sample["log10_rest_mm"]
    params = {"dc_rest": rest, "dc_stiffness": own["dc_stiffness"] * 2.0 ** sample["log2_stiffness"],
              "c_air": sample["c_air"], "V": sample["V"], "relay_hz": sample["relay_hz"]}
    x0 = {"x": sample["start"] * rest, "v": 0.0, "i": I0, "z": 0.0} if scene == SCENE else None
    return {"dc_law": law, "ac_sign": sign, "params": params, "x0": x0}


def evaluate(sample: dict, size: dict) -> dict:
    """The outputs of one sample (:data:`OUTPUTS`, ``in_regime`` and the gap's three parts)."""
    clock = _time.process_time()
    out = one_dof(sample, size)
    out["rate_mm_s"] = rate(sample, size)
    out["cpu_s"] = _time.process_time() - clock
    return out


def one_dof(sample: dict, size: dict) -> dict:
    """gap, its parts, stroke [mm] and in_regime of the 1-DOF run at ``sample`` (:func:`regime_gap`)."""
    import maps
    from maps.studykit import impact_table
    cfg = configure(sample, SCENE)
    pb = maps.problem(SCENE, PRESET, cfg["params"], x0=cfg["x0"], dc_law=cfg["dc_law"], ac_sign=cfg["ac_sign"])
    T = 1.0 / sample["relay_hz"]
    t0, n = size["transient"] * T, size["record"]
    times = np.linspace(t0, t0 + n * T, 100 * n + 1)
    ix = [s.name for s in pb.system.states].index("x")
    xs = []

    def on_segment(c_out, ta, tb):
        sel = times[(times >= ta) & (times <= tb)]
        if sel.size:
            xs.append(np.asarray(c_out(sel))[:, ix])

    run = maps.run_scene(pb, t0 + n * T, tol=TOL, on_segment=on_segment)
    ok = run.status == "ok"
    stroke = 1e3 * float(np.ptp(np.concatenate(xs))) if ok and xs else math.nan
    g = regime_gap(impact_table(run)["t"], T, t0, n, stroke) if ok else \
        {"gap": 1.0, "off_count": 1.0, "phase_spread": 1.0, "stroke_excess": 1.0}
    return dict(g, stroke_mm=stroke, in_regime=float(g["gap"] < IN_REGIME), status=run.status)


def rate(sample: dict, size: dict) -> float:
    """The prototype's progression rate [mm/s] (drift soil) over the second half of its run; NaN where the run
    fails or escapes."""
    import maps
    cfg = configure(sample, SCENE_2DOF)
    h = maps.simulate(SCENE_2DOF, periods=size["periods_2dof"], dc_law=cfg["dc_law"], ac_sign=cfg["ac_sign"],
                      soil="drift", params=cfg["params"], dt=2e-3, tol=TOL)
    return 1e3 * float(h.progression_rate) if h.attrs.get("status", "ok") == "ok" else math.nan


class SampleJob:
    """job(i): the outputs of sample row i (picklable, for bifurc's executor)."""

    batch_size = 1

    def __init__(self, rows, size):
        self.rows, self.size = np.asarray(rows), dict(size)

    def __call__(self, i):
        return evaluate(dict(zip(INPUTS, map(float, self.rows[int(i)]))), self.size)


def run(out, quick=False, progress=True, overwrite=False, workers=None, scheduler=None, size=None) -> dict:
    """Run every sample into ``out`` (each result kept in ``out/samples.parts/``: a rerun, or a run after
    Ctrl-C, resumes), then write ``report.md`` and ``samples.json``; returns the analysis as a dict (with the
    form's size, the wall time and the samples run).  ``size``: another form's dict (e.g. MEDIUM)."""
    from bifurc.studykit import available_cores, map_values, write_text
    from tqdm.auto import tqdm
    size = size or (QUICK if quick else FULL)
    out = Path(out)
    parts = out / "samples.parts"
    parts.mkdir(parents=True, exist_ok=True)
    rows = design(size)
    key = json.dumps({"size": size, "inputs": {k: v[:2] for k, v in INPUTS.items()}, "design": 2}, sort_keys=True)
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
        map_values(SampleJob(rows, size), np.array(todo, dtype=float), workers=w, scheduler=scheduler, chunk_size=1,
                   on_chunk=take, collect=False)
    bar.close()
    seconds = _time.perf_counter() - clock
    wall = out / "wall.json"      # the wall time of every run into this folder (a resumed run adds its own)
    total = (json.loads(wall.read_text())["seconds"] if wall.is_file() else 0.0) + seconds
    wall.write_text(json.dumps({"seconds": total}))
    keys = list(OUTPUTS) + ["in_regime", "off_count", "phase_spread", "stroke_excess", "cpu_s"]
    Y = {o: np.array([done[i].get(o, math.nan) for i in range(len(rows))], dtype=float) for o in keys}
    result = analyse(rows, Y)
    result.update(size=dict(size), seconds=seconds, seconds_all_runs=total, n_samples=len(rows), n_run=len(todo),
                  outputs_per_sample=Y, per_law=per_law(rows, Y))
    write_text(out / "samples.json", json.dumps({"inputs": list(INPUTS), "rows": rows.tolist(),
                                                 "outputs": {o: Y[o].tolist() for o in Y}}), overwrite=True)
    write_text(out / "report.md", report(result, size, quick), overwrite=True)
    return result


def per_law(rows, Y) -> dict:
    """{law: {"n", "gap" (mean), "in_regime" (share), "min_gap", "rate" (median)}} over the samples."""
    j = list(INPUTS).index("law")
    laws = np.array([level(v, LAWS) for v in rows[:, j]])
    out = {}
    for law in LAWS:
        m = laws == law
        if not m.any():
            continue
        r = Y["rate_mm_s"][m]
        out[law] = {"n": int(m.sum()), "gap": float(np.mean(Y["gap"][m])), "min_gap": float(np.min(Y["gap"][m])),
                    "in_regime": float(np.mean(Y["in_regime"][m])),
                    "rate": float(np.nanmedian(r)) if np.isfinite(r).any() else math.nan}
    return out


def converged(indices: dict, conf_key: str) -> tuple:
    """(bool, why): the top three indices' 95 % intervals (2 x the half-width ``conf_key``) narrower than
    :data:`WIDTH`, and none above 1 beyond its interval."""
    top = sorted(indices, key=lambda k: -indices[k]["value"])[:3]
    wide = [k for k in top if not 2 * indices[k][conf_key] < WIDTH]
    over = [k for k in indices if indices[k]["value"] - indices[k][conf_key] > 1]
    why = []
    if wide:
        why.append("intervals of " + ", ".join(f"{k} ({2 * indices[k][conf_key]:.2f})" for k in wide)
                   + f" not narrower than {WIDTH:g}")
    if over:
        why.append("above 1 beyond its interval: " + ", ".join(over))
    return not why, "; ".join(why)


def analyse(rows, Y) -> dict:
    """Per output: Sobol ST with 95 % intervals and its convergence; where it does not converge, delta."""
    from SALib.analyze import delta, sobol
    from scipy.stats import rankdata
    spec = problem_spec()
    out = {"sobol": {}, "delta": {}, "filled": {}}
    for o in OUTPUTS:
        y = Y[o].copy()
        finite = np.isfinite(y)
        out["filled"][o] = int((~finite).sum())
        if finite.sum() < 0.5 * y.size or np.nanstd(y) == 0:
            out["sobol"][o] = out["delta"][o] = None          # too few finite or all equal: no indices
            continue
        y[~finite] = np.nanmean(y)          # failed runs: the mean (stated in the report)
        si = sobol.analyze(spec, y, calc_second_order=False, seed=1, num_resamples=200)
        s = {n: {"value": float(si["ST"][j]), "conf": float(si["ST_conf"][j]), "S1": float(si["S1"][j])}
             for j, n in enumerate(spec["names"])}
        ok, why = converged(s, "conf")
        out["sobol"][o] = {"indices": s, "converged": ok, "why": why}
        if not ok:
            try:
                with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()), \
                        warnings.catch_warnings():          # SALib's bin and bias notices (stated in the report)
                    warnings.simplefilter("ignore")
                    d = delta.analyze(spec, rows, rankdata(y) / y.size, num_resamples=50, seed=1)
                key = next(k for k in ("delta_balanced", "delta_raw", "delta") if k in d)   # SALib's versions
                dd = {n: {"value": float(d[key][j]), "conf": float(d[key + "_conf"][j])}
                      for j, n in enumerate(spec["names"])}
                ok_d, why_d = converged(dd, "conf")
                out["delta"][o] = {"indices": dd, "converged": ok_d, "why": why_d}
            except (ValueError, np.linalg.LinAlgError) as exc:
                out["delta"][o] = {"indices": None, "converged": False, "why": f"delta failed: {exc}"}
    return out


def _f(v, fmt=".3g"):
    return "n/a" if v is None or (isinstance(v, float) and not math.isfinite(v)) else format(v, fmt)


def report(result, size, quick) -> str:
    from maps import __version__

    from .. import provenance
    form = "quick" if quick else "full" if size == FULL else f"reduced full (the full form's runs, N = {size['N']})"
    made_by = (provenance(NAME, quick) if form in ("quick", "full") else
               provenance(NAME, False).replace(f"bifurc study {NAME} -o DIR",
                                               f"python -c 'import studies.sensitivity as S; S.run(\"DIR\", "
                                               f"size=S.MEDIUM)'"))
    Y = result["outputs_per_sample"]
    lines = [f"# {NAME}: what decides the thesis model's regime", "", made_by, "", (__doc__ or "").strip(), "",
             f"Form: {form}: N = {size['N']}, {result['n_samples']} samples ({result['n_run']} run now) in "
             f"{result['seconds']:.0f} s wall ({result['seconds_all_runs']:.0f} s over every run into its folder); "
             f"1-DOF runs of {size['transient']} transient + {size['record']} recorded relay periods, prototype "
             f"{size['periods_2dof']} relay periods.  Toolkit {__version__}.  CPU per sample: mean "
             f"{np.nanmean(Y['cpu_s']):.1f} s (median {np.nanmedian(Y['cpu_s']):.1f} s), so the full form's "
             f"{FULL['N'] * (len(INPUTS) + 2)} samples would take about "
             f"{np.nanmean(Y['cpu_s']) * FULL['N'] * (len(INPUTS) + 2) / 2 / 3600:.1f} h on 2 idle cores at this "
             "form's run lengths (CPU time grows with the load's contention; the full form's runs are longer than "
             "the quick form's).", "",
             "## Inputs", "", "| input | low | high | unit | meaning and source |", "|---|---|---|---|---|"]
    lines += [f"| {k} | {v[0]:.4g} | {v[1]:.4g} | {v[2]} | {v[3]} |" for k, v in INPUTS.items()]
    lines += ["", "## Per law", "",
              f"Over the samples of each law (all other inputs as sampled); in the regime: gap below {IN_REGIME:g}.",
              "", "| law | samples | mean gap | smallest gap | share in the regime | median rate [mm/s] |",
              "|---|---|---|---|---|---|"]
    for law, r in result["per_law"].items():
        lines.append(f"| {law} | {r['n']} | {r['gap']:.3f} | {r['min_gap']:.3g} | {r['in_regime']:.3f} | "
                     f"{_f(r['rate'])} |")
    lines += ["", f"Over all samples: mean gap {np.mean(Y['gap']):.3f}, share in the regime "
              f"{np.mean(Y['in_regime']):.4f}, 1-DOF runs that escaped {int(np.sum(Y['gap'] == 1.0))}, prototype runs "
              f"without a rate (failed or escaped) {result['filled']['rate_mm_s']} (their rate set to the mean for the "
              "indices).", "", "## Total indices", "",
              f"Sobol ST with its bootstrap 95 % interval (+- half-width); converged: the top three intervals "
              f"narrower than {WIDTH:g} and no index above 1 beyond its interval.  Where Sobol does not converge, "
              "the moment-independent delta (Borgonovo; Plischke's bias-reduced estimator where SALib has it; 50 "
              "bootstrap resamples) from the same samples, on the output's ranks: delta compares the output's "
              "distribution with and without each input known, so it needs no variance decomposition (a few huge "
              "values, like the rate's, make the Sobol estimator's bootstrap intervals explode) and is unchanged by a "
              "monotone transform of the output, which the ranks are (they keep its kernel density estimate off "
              "the outliers).  Saltelli's rows are not independent draws, which delta assumes: its intervals here "
              "are indicative.", ""]
    for o, label in OUTPUTS.items():
        lines += [f"### {o}: {label}", ""]
        s, d = result["sobol"][o], result["delta"].get(o)
        if s is None:
            lines += ["No indices: too few finite values or no variation.", ""]
            continue
        lines += [f"Sobol: {'converged' if s['converged'] else 'not converged (' + s['why'] + ')'}." +
                  ("" if d is None else f"  Delta: {'converged' if d['converged'] else 'not converged (' + d['why'] + ')'}."),
                  "", "| input | ST | ST 95 % | S1 |" + (" delta | delta 95 % |" if d and d["indices"] else ""),
                  "|---|---|---|---|" + ("---|---|" if d and d["indices"] else "")]
        order = sorted(s["indices"], key=lambda k: -(d["indices"][k]["value"] if d and d["indices"] else
                                                      s["indices"][k]["value"]))
        for k in order:
            v = s["indices"][k]
            row = f"| {k} | {v['value']:.3f} | ±{v['conf']:.3f} | {v['S1']:.3f} |"
            if d and d["indices"]:
                row += f" {d['indices'][k]['value']:.3f} | ±{d['indices'][k]['conf']:.3f} |"
            lines.append(row)
        lines.append("")
    floor = inert_floor(result)
    if floor is not None:
        lines += [f"The rate does not depend on `start` (the prototype keeps its own start): its delta there, "
                  f"{floor[0]:.3f} ± {floor[1]:.3f}, is what an inert input reads on these samples, the floor below "
                  "which no delta ranks an input.", ""]
    lines += ["## Finding", "", finding(result), ""]
    return "\n".join(lines)


def inert_floor(result):
    """(delta, half-width) of ``start`` for the rate (an input the prototype's run does not read), or None."""
    d = result["delta"].get("rate_mm_s")
    if not d or not d["indices"]:
        return None
    v = d["indices"]["start"]
    return v["value"], v["conf"]


def ranking(result, o) -> tuple:
    """(measure, [inputs, most influential first], converged) of output ``o``: Sobol ST where it converged,
    else delta."""
    s, d = result["sobol"][o], result["delta"].get(o)
    if s is None:
        return "none", [], False
    use, name = (s, "Sobol ST") if s["converged"] or not (d and d["indices"]) else (d, "delta")
    idx = use["indices"]
    return name, sorted(idx, key=lambda k: -idx[k]["value"]), use["converged"]


def leaders(result, o) -> list:
    """The inputs of output ``o`` the samples cannot order below the most influential one: those whose index
    interval (value + its 95 % half-width) reaches the leader's lower bound, the leader first, by value."""
    name, order, _ = ranking(result, o)
    if not order:
        return []
    idx = (result["sobol"][o] if name == "Sobol ST" else result["delta"][o])["indices"]
    half = lambda k: float(np.nan_to_num(idx[k]["conf"]))  # noqa: E731 - no interval: the value alone
    floor = idx[order[0]]["value"] - half(order[0])
    return [k for k in order if idx[k]["value"] + half(k) >= floor]


def finding(result) -> str:
    parts = []
    for o in OUTPUTS:
        name, order, ok = ranking(result, o)
        if not order:
            parts.append(f"{o}: no indices.")
            continue
        idx = (result["sobol"][o] if name == "Sobol ST" else result["delta"][o])["indices"]
        say = lambda k: f"{k} {idx[k]['value']:.3f} ± {float(np.nan_to_num(idx[k]['conf'])):.3f}"  # noqa: E731
        lead, how = leaders(result, o), f"by {name} ({'converged' if ok else 'not converged'})"
        if len(lead) == 1:
            nxt = f"; the next, {say(order[1])}" if len(order) > 1 else ""
            parts.append(f"{o}: {how} {say(lead[0])} leads, above every other input's interval{nxt}.")
        else:
            parts.append(f"{o}: {how} the samples cannot order the leading {len(lead)}, their intervals reaching "
                         f"the leader's: {', '.join(say(k) for k in lead)}.")
    best = min(result["per_law"].items(), key=lambda kv: kv[1]["gap"])
    parts.append(f"The law nearest the regime on average: {best[0]} (mean gap {best[1]['gap']:.3f}).")
    return "  ".join(parts)


def findings(results, quick) -> list:
    """What the report states: the mean gap and the share in the regime (+-0.02 and +-1 sample), per law the mean
    gap (+-0.03), the leading inputs of each output by the measure used (:func:`leaders`: those the samples cannot
    order below the most influential one; exact)."""
    from bifurc.studykit import Finding
    Y = results["outputs_per_sample"]
    n = len(Y["gap"])
    out = [Finding("mean gap over samples", round(float(np.mean(Y["gap"])), 4), 0.02, "1"),
           Finding("share of samples in the regime", round(float(np.mean(Y["in_regime"])), 4), round(1.0 / n, 4), "1")]
    for law, r in results["per_law"].items():
        out.append(Finding(f"mean gap, {law}", round(r["gap"], 4), 0.03, "1"))
    for o in OUTPUTS:
        name, order, ok = ranking(results, o)
        out.append(Finding(f"leading inputs of {o} ({name})", ", ".join(leaders(results, o)) or "none"))
    return out
