"""Run a named study: ``python -m bifurc.studies.run thesis-1dof-relay [--quick] [-o DIR]``.

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

STUDIES = {"thesis-1dof-relay": "bifurc.studies.thesis_1dof_relay", "thesis-replay": "bifurc.studies.thesis_replay",
           "thesis-orbits": "bifurc.studies.thesis_orbits", "regime-maps": "bifurc.studies.regime_maps",
           "prototype-progression": "bifurc.studies.prototype_progression"}


def load_study(name):
    if name not in STUDIES:
        from maps.parameters import ParameterError
        raise ParameterError(f"unknown study {name!r}; studies: {', '.join(STUDIES)}")
    return importlib.import_module(STUDIES[name])


def run_study(name, out, quick=False, progress=True, cases=None, overwrite=False, hint="pass overwrite=True"):
    """Run every case of a study into folder ``out``; returns {case: dataset}.

    A folder holding anything but interrupted sweeps (``*.parts``, which resume) is refused
    unless ``overwrite`` (then its files are replaced); ``hint`` completes the refusal.
    """
    from bifurc.storage.files import write_text
    from bifurc.plots.diagram import plot_diagram
    from bifurc.report import classification_report
    from bifurc.sweeps.sweep import sweep
    study = load_study(name)
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise NotADirectoryError(f"{out} is a file, not a folder")
    held = sorted(p.name for p in out.iterdir() if not p.name.endswith(".parts")) if out.is_dir() else []
    if held and not overwrite:
        raise FileExistsError(f"{out} is not empty ({len(held)} entries, e.g. {held[0]}); {hint} to write into it")
    if hasattr(study, "run"):          # a study with its own runner (report.md and figures)
        return study.run(out, quick=quick, progress=progress, overwrite=overwrite)
    size = study.QUICK if quick else study.FULL
    out.mkdir(parents=True, exist_ok=True)
    results = {}
    for case, preset, overrides in study.CASES:
        if cases and case not in cases:
            continue
        ds = sweep(study.SCENE, study.PARAM, size["values"], preset=preset, params=overrides,
                   transient=size["transient"], record=size["record"], path=out / f"{case}.nc", progress=progress,
                   overwrite=overwrite)
        ds.attrs["study"] = name
        ds.attrs["study_case"] = case
        plot_diagram(ds, out / f"{case}.png", overwrite=overwrite)
        write_text(out / f"{case}.md", classification_report(ds, at=study.AT), overwrite=overwrite)
        results[case] = ds
    write_text(out / "comparison.md", comparison(study, results, quick), overwrite=overwrite)
    return results


def _sentence(w, c, thesis_n, r, f_well):
    """One sentence on a disagreement with the thesis' period at relay frequency w [Hz], its causes
    measured: the 3 s run from the same start (studies.thesis_replay.measure) beside the sweep's class."""
    from bifurc.studies.thesis_replay import T_THESIS, _budget
    parts = []
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
    if c["n_impacts"] == 0 and c["label"] != "periodic":
        parts.append("the bar does not reach the stop in the recorded periods")
    fx = r["fft_peak_3s_hz"]
    well = (math.isfinite(f_well) and math.isfinite(fx) and abs(fx - f_well) <= 1.0 / T_THESIS + 1e-9
            and abs(fx - w) > 1.0 / T_THESIS + 1e-9)
    parts.append(f"x's spectrum over 3 s peaks at {fx:.2f} Hz" + (f", the DC well's own frequency ({f_well:.2f} Hz)"
                                                                  if well else "") + f", the relay is {w:g} Hz")
    parts.append(f"x spans {r['x_min_mm']:.1f} to {r['x_max_mm']:.1f} mm; {_budget(r)}")
    parts.append(f"a {T_THESIS:g} s run from the same start supports {r['label_3s']}")
    text = "; ".join(p for p in parts if p)
    return text[0].upper() + text[1:] + "."


def _measured(study, ds, case_preset, w):
    """The replay's measured columns for a sweep case at relay w [Hz]: its own preset, law, V, AC sign
    and start, 3 s only (studies.thesis_replay.measure)."""
    from bifurc.studies.thesis_replay import measure
    o = {k: ds.attrs.get(k) for k in ("dc_law", "ac_sign", "circuit")}
    return measure(float(w), float(ds.attrs["param_V"]), o["dc_law"], preset=case_preset, ac_sign=o["ac_sign"],
                   circuit=o["circuit"], x0={}, long_periods=0, long_window=0)


def comparison(study, results, quick) -> str:
    from bifurc.report import class_at
    from bifurc.studies.thesis_replay import well_frequency
    presets = {case: preset for case, preset, _ in study.CASES}
    lines = [f"# {study.NAME}: toolkit against the thesis", "",
             (study.__doc__ or "").strip(), "",
             f"Size: {'quick' if quick else 'full'} ({len((study.QUICK if quick else study.FULL)['values'])} values, "
             f"{(study.QUICK if quick else study.FULL)['transient']} transient + "
             f"{(study.QUICK if quick else study.FULL)['record']} recorded relay periods per value).", "",
             "Measured beside each class (3 s from the case's own start, as `bifurc study thesis-replay` does for the "
             "thesis' start): the label a 3 s run supports, the FFT peak of x, x's range against the thesis' +-5 mm "
             "sensor, and the DC and peak AC forces at the stop.", ""]
    wells = {}
    for case, ds in results.items():
        V = ds.attrs.get("param_V", math.nan)
        law = ds.attrs.get("dc_law", "listing")
        if law not in wells:
            wells[law] = well_frequency(law)
        lines += [f"## {case} (V = {V:g} V, R = {ds.attrs.get('param_R'):g} ohm, C = {ds.attrs.get('param_C'):g} F, "
                  f"k = {ds.attrs.get('param_k'):g} N/m, dc_law {law}, AC sign {ds.attrs.get('ac_sign')})", "",
                  "| relay [Hz] | toolkit | impacts in record | thesis numerical | thesis experiment | agrees with numerical "
                  "| 3 s run supports | FFT peak of x, 3 s [Hz] | x range, 3 s [mm] | at the stop: DC, peak AC [N] |",
                  "|---|---|---|---|---|---|---|---|---|---|"]
        notes = []
        for w in study.AT:
            c = class_at(ds, w)
            r = _measured(study, ds, presets.get(case), w)
            tn, te = study.THESIS_NUMERICAL[w], study.THESIS_EXPERIMENT[w]
            ok = c["label"] == "periodic" and c["period"] == tn
            lines.append(f"| {w} | {c['text']} | {c['n_impacts']} | period-{tn} | period-{te} | {'yes' if ok else 'no'} "
                         f"| {r['label_3s']} | {r['fft_peak_3s_hz']:.2f} | {r['x_min_mm']:.1f} .. {r['x_max_mm']:.1f} "
                         f"| {r['F_dc_stop_N']:+.2f}, {r['F_ac_peak_stop_N']:+.2f} |")
            if not ok:
                notes.append(f"- {w} Hz: " + _sentence(w, c, tn, r, wells[law]))
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
    p = argparse.ArgumentParser(prog="python -m bifurc.studies.run", description=__doc__.splitlines()[0])
    p.add_argument("study", choices=sorted(STUDIES))
    p.add_argument("--quick", action="store_true", help="the reduced size (integer frequencies only, short runs)")
    p.add_argument("-o", "--output", default="out/study", help="output folder (default out/study)")
    p.add_argument("--case", action="append", default=None, help="run only this case (repeatable)")
    p.add_argument("--force", action="store_true", help="write into a non-empty output folder, replacing files")
    args = p.parse_args(argv)
    run_study(args.study, args.output, quick=args.quick, cases=args.case, overwrite=args.force, hint="use --force")
    print(_written(args.study, args.output))
    return 0


if __name__ == "__main__":
    sys.exit(main())
