"""Thesis 1-DOF relay-frequency study, 2 to 10 Hz (thesis Fig 4.27, section 4.8).

For each case (preset and voltage) a bifurcation diagram over the relay
frequency, the class at 2, 3, ..., 10 Hz, and a comparison with what the thesis
reports: numerically period-1 at 2, 3, 4, 5, 9, 10 Hz and period-2 at 6, 7, 8 Hz
(Fig 4.27); experimentally period-1 at all of them (Figs 3.9-3.17).  The thesis'
period is the bar's (its plots show x): the toolkit's class is read in the mechanical convention
(``period_mechanical``: x and v alone), with the full state's period beside it where they differ
(the coil current's sign alternates every relay period).  Nothing is tuned to agree.
"""
import math
from pathlib import Path

import numpy as np

NAME = "thesis-1dof-relay"
#: what run() writes, as `bifurc study` reports it
WRITES = "comparison.md and one .nc/.png/.md per case"
SCENE = "thesis-1dof"
PARAM = "relay_hz"
#: (case name, preset, parameter overrides): the presets as the thesis gives them, and 90 V
#: (the upper end of the experiments' 70-90 V, amplitude or RMS not stated)
CASES = [
    ("thesis-text", "thesis-text", {}),
    ("matlab-listing", "matlab-listing", {}),
    ("matlab-listing-90V", "matlab-listing", {"V": 90.0}),
]
FULL = dict(values=np.round(np.linspace(2.0, 10.0, 81), 10), transient=300, record=100)
QUICK = dict(values=np.arange(2.0, 11.0), transient=60, record=30)
AT = list(range(2, 11))
THESIS_NUMERICAL = {2: 1, 3: 1, 4: 1, 5: 1, 6: 2, 7: 2, 8: 2, 9: 1, 10: 1}  # period per Fig 4.27
THESIS_EXPERIMENT = {w: 1 for w in AT}                                      # Figs 3.9-3.17
THESIS_SIMULATED_SECONDS = 3.0                                              # tf = 3 in the listings


def run(out, quick=False, progress=True, overwrite=False, cases=None) -> dict:
    """Every case (or those named in ``cases``) into folder ``out``: ``<case>.nc`` (sweep dataset),
    ``<case>.png`` (diagram), ``<case>.md`` (classification report) and ``comparison.md``: the
    toolkit's class next to the thesis' claims, one sentence per disagreement.  Returns {case: dataset}."""
    from bifurc import classification_report, plot_diagram
    from bifurc.studykit import write_text
    from bifurc import sweep
    out = Path(out)
    size = QUICK if quick else FULL
    out.mkdir(parents=True, exist_ok=True)
    results = {}
    for case, preset, overrides in CASES:
        if cases and case not in cases:
            continue
        ds = sweep(SCENE, PARAM, size["values"], preset=preset, params=overrides,
                   transient=size["transient"], record=size["record"], path=out / f"{case}.nc", progress=progress,
                   overwrite=overwrite)
        ds.attrs["study"] = NAME
        ds.attrs["study_case"] = case
        plot_diagram(ds, out / f"{case}.png", overwrite=overwrite)
        write_text(out / f"{case}.md", classification_report(ds, at=AT, period_of="mechanical"), overwrite=overwrite)
        results[case] = ds
    write_text(out / "comparison.md", comparison(results, quick), overwrite=overwrite)
    return results


def _sentence(w, c, thesis_n, r, f_well):
    """One sentence on a disagreement with the thesis' period at relay frequency w [Hz], its causes
    measured: the 3 s run from the same start (studies.thesis_replay.measure) beside the sweep's class."""
    from ..thesis_replay import T_THESIS, budget
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
    parts.append(f"x spans {r['x_min_mm']:.1f} to {r['x_max_mm']:.1f} mm; {budget(r)}")
    parts.append(f"a {T_THESIS:g} s run from the same start supports {r['label_3s']}")
    text = "; ".join(p for p in parts if p)
    return text[0].upper() + text[1:] + "."


def _measured(ds, case_preset, w):
    """The replay's measured columns for a sweep case at relay w [Hz]: its own preset, law, V, AC sign
    and start, 3 s only (studies.thesis_replay.measure)."""
    from ..thesis_replay import measure
    o = {k: ds.attrs.get(k) for k in ("dc_law", "ac_sign", "circuit")}
    return measure(float(w), float(ds.attrs["param_V"]), o["dc_law"], preset=case_preset, ac_sign=o["ac_sign"],
                   circuit=o["circuit"], x0={}, long_periods=0, long_window=0)


def comparison(results, quick) -> str:
    from bifurc import class_at
    from bifurc.studykit import in_convention
    from ..thesis_replay import well_frequency
    presets = {case: preset for case, preset, _ in CASES}
    lines = [f"# {NAME}: toolkit against the thesis", "",
             (__doc__ or "").strip(), "",
             f"Size: {'quick' if quick else 'full'} ({len((QUICK if quick else FULL)['values'])} values, "
             f"{(QUICK if quick else FULL)['transient']} transient + "
             f"{(QUICK if quick else FULL)['record']} recorded relay periods per value).", "",
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
                  "| relay [Hz] | toolkit (mechanical period) | full state | impacts in record | thesis numerical | thesis experiment | agrees with numerical "
                  "| 3 s run supports | FFT peak of x, 3 s [Hz] | x range, 3 s [mm] | at the stop: DC, peak AC [N] |",
                  "|---|---|---|---|---|---|---|---|---|---|---|"]
        notes = []
        for w in AT:
            c, full = class_at(in_convention(ds, "mechanical"), w), class_at(ds, w)
            r = _measured(ds, presets.get(case), w)
            tn, te = THESIS_NUMERICAL[w], THESIS_EXPERIMENT[w]
            ok = c["label"] == "periodic" and c["period"] == tn
            lines.append(f"| {w} | {c['text']} | {'same' if full['text'] == c['text'] else full['text']} | {c['n_impacts']} | period-{tn} | period-{te} | {'yes' if ok else 'no'} "
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


#: the report whose findings `bifurc study thesis-1dof-relay --check` compares
REPORT = "comparison.md"


def findings(results, quick) -> list:
    """What the comparison states, per case: the class at each integer relay frequency in the mechanical
    convention (text, exact) and how many agree with the thesis' numerical period (exact)."""
    from bifurc.studykit import Finding
    from bifurc import class_at
    from bifurc.studykit import in_convention
    out = []
    for case, ds in results.items():
        dm = in_convention(ds, "mechanical")
        agree = 0
        for w in AT:
            c = class_at(dm, w)
            agree += c["label"] == "periodic" and c["period"] == THESIS_NUMERICAL[w]
            out.append(Finding(f"{case}: class at {w} Hz (mechanical period)", c["text"]))
        out.append(Finding(f"{case}: integer frequencies agreeing with the thesis' numerical period", agree, 0,
                           "of 9"))
    return out
