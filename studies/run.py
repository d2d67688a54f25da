"""Run a named study: ``python -m studies.run thesis-1dof-relay [--quick] [-o DIR]``.

Writes per case ``DIR/<case>.nc`` (sweep dataset), ``DIR/<case>.png`` (diagram)
and ``DIR/<case>.md`` (classification report), and ``DIR/comparison.md``: the
toolkit's class next to the thesis' claims, one sentence per disagreement.
"""
from __future__ import annotations

import argparse
import importlib
import math
import sys
from pathlib import Path

STUDIES = {"thesis-1dof-relay": "studies.thesis_1dof_relay", "thesis-replay": "studies.thesis_replay"}


def load_study(name):
    if name not in STUDIES:
        from maps.parameters import ParameterError
        raise ParameterError(f"unknown study {name!r}; studies: {', '.join(STUDIES)}")
    return importlib.import_module(STUDIES[name])


def run_study(name, out, quick=False, progress=True, cases=None):
    """Run every case of a study into folder ``out``; returns {case: dataset}."""
    from bifurc.plot_diagram import plot_diagram
    from bifurc.report import classification_report
    from bifurc.sweep import sweep
    study = load_study(name)
    if hasattr(study, "run"):          # a study with its own runner (thesis-replay: report.md and figures)
        return study.run(out, quick=quick, progress=progress)
    size = study.QUICK if quick else study.FULL
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    results = {}
    for case, preset, overrides in study.CASES:
        if cases and case not in cases:
            continue
        ds = sweep(study.SCENE, study.PARAM, size["values"], preset=preset, params=overrides,
                   transient=size["transient"], record=size["record"], path=out / f"{case}.nc", progress=progress)
        ds.attrs["study"] = name
        ds.attrs["study_case"] = case
        plot_diagram(ds, out / f"{case}.png")
        (out / f"{case}.md").write_text(classification_report(ds, at=study.AT))
        results[case] = ds
    (out / "comparison.md").write_text(comparison(study, results, quick))
    return results


def _sentence(w, c, thesis_n, V, seconds):
    """One sentence on a disagreement with the thesis' period at relay frequency w [Hz]."""
    parts = []
    if c["n_impacts"] == 0 and c["label"] != "periodic":
        weak = V <= 30 and ": the AC pull (< 0.5 N) cannot overcome the ~37 N DC force at the stop" or ""
        parts.append(f"the bar does not reach the stop in the recorded periods{weak}")
    if c["label"] == "periodic":
        parts.append(f"the orbit is period-{c['period']}, not period-{thesis_n}")
    elif c["label"] == "chaotic":
        parts.append(f"the orbit is chaotic (largest Lyapunov exponent {c['lyapunov']:.2f} per relay period)")
    elif c["label"] == "quasi-periodic":
        parts.append("the orbit is quasi-periodic (Lyapunov exponent within the window's threshold of 0)")
    elif c["label"] == "not-converged":
        parts.append(f"no period is reached within the simulated span (recurrence {c['recurrence']:.2g} x tolerance)")
    else:
        parts.append(f"the run ended {c['label']}")
    if c["forcing_period"] != 1:
        q = c["forcing_period"]
        parts.append(f"the forcing itself repeats only every {q} relay periods (50/{w:g} is not an integer), so "
                     f"a strict period-1 orbit of the relay-period map is impossible" if q else
                     "the forcing is not periodic in relay periods")
    parts.append(f"the thesis simulated only {seconds:g} s = {seconds * w:g} relay periods"
                 if c["label"] != "periodic" else "")
    text = "; ".join(p for p in parts if p)
    return text[0].upper() + text[1:] + "."


def comparison(study, results, quick) -> str:
    from bifurc.report import class_at
    lines = [f"# {study.NAME}: toolkit against the thesis", "",
             (study.__doc__ or "").strip(), "",
             f"Size: {'quick' if quick else 'full'} ({len((study.QUICK if quick else study.FULL)['values'])} values, "
             f"{(study.QUICK if quick else study.FULL)['transient']} transient + "
             f"{(study.QUICK if quick else study.FULL)['record']} recorded relay periods per value).", ""]
    for case, ds in results.items():
        V = ds.attrs.get("param_V", math.nan)
        lines += [f"## {case} (V = {V:g} V, R = {ds.attrs.get('param_R'):g} ohm, C = {ds.attrs.get('param_C'):g} F, "
                  f"k = {ds.attrs.get('param_k'):g} N/m)", "",
                  "| relay [Hz] | toolkit | impacts in record | thesis numerical | thesis experiment | agrees with numerical |",
                  "|---|---|---|---|---|---|"]
        notes = []
        for w in study.AT:
            c = class_at(ds, w)
            tn, te = study.THESIS_NUMERICAL[w], study.THESIS_EXPERIMENT[w]
            ok = c["label"] == "periodic" and c["period"] == tn
            lines.append(f"| {w} | {c['text']} | {c['n_impacts']} | period-{tn} | period-{te} | {'yes' if ok else 'no'} |")
            if not ok:
                notes.append(f"- {w} Hz: " + _sentence(w, c, tn, V, study.THESIS_SIMULATED_SECONDS))
        lines += [""] + (notes or ["All classes agree with the thesis' numerical periods."]) + [""]
        lines += [f"Numerical error (tol/100): one map step {ds.attrs.get('error_map_step_rel', math.nan):.2g} relative; "
                  f"periodic values re-run whole: map points {ds.attrs.get('error_map_points_rel', math.nan):.2g} "
                  f"relative, contact times {ds.attrs.get('error_impact_time_s', math.nan):.2g} s; sweep "
                  f"{ds.attrs.get('sweep_seconds', math.nan):.0f} s.", ""]
    return "\n".join(lines)


def _written(name, out) -> str:
    if hasattr(load_study(name), "run"):
        return f"wrote {out}/report.md and its figures"
    return f"wrote {out}/comparison.md and one .nc/.png/.md per case"


def main(argv=None) -> int:
    p = argparse.ArgumentParser(prog="python -m studies.run", description=__doc__.splitlines()[0])
    p.add_argument("study", choices=sorted(STUDIES))
    p.add_argument("--quick", action="store_true", help="the reduced size (integer frequencies only, short runs)")
    p.add_argument("-o", "--output", default="out/study", help="output folder (default out/study)")
    p.add_argument("--case", action="append", default=None, help="run only this case (repeatable)")
    args = p.parse_args(argv)
    run_study(args.study, args.output, quick=args.quick, cases=args.case)
    print(_written(args.study, args.output))
    return 0


if __name__ == "__main__":
    sys.exit(main())
