"""Period-1/period-2 classification report (markdown) from a sweep Dataset."""
from __future__ import annotations

import math

import numpy as np

from .sweeps.classify import CLASS_LABELS, describe

__all__ = ["classification_report", "class_at"]


def class_at(ds, value, branch=None) -> dict:
    """Class of the grid value nearest to ``value``: {value, text, code, period, impacts, lyapunov, ...}."""
    par = ds.attrs["swept_parameter"]
    b = branch or str(ds.branch.values[0])
    sub = ds.sel(branch=b).sel({par: value}, method="nearest")
    code = int(sub.class_code)
    return {"value": float(sub[par]), "branch": b, "code": code,
            "label": CLASS_LABELS[code] if code >= 0 else "missing",
            "text": describe(code, int(sub.period), int(sub.impacts_per_period),
                             float(sub.progression_per_period) if "progression_per_period" in sub else None)
            if code >= 0 else "missing",
            "period": int(sub.period), "impacts": int(sub.impacts_per_period), "lyapunov": float(sub.lyapunov),
            "recurrence": float(sub.recurrence), "convergence_rate": float(sub.convergence_rate),
            "n_impacts": int(sub.n_impacts), "min_gap": float(sub.min_gap),
            "forcing_period": int(sub.forcing_period)}


def _intervals(values, texts):
    out, start = [], 0
    for i in range(1, len(values) + 1):
        if i == len(values) or texts[i] != texts[start]:
            out.append((values[start], values[i - 1], texts[start], i - start))
            start = i
    return out


def classification_report(ds, at=None) -> str:
    """Markdown: settings, class counts, classes at chosen values, intervals, grazing, errors.

    ``at``: parameter values to tabulate (default: the integers inside the grid).
    """
    a = ds.attrs
    par = a["swept_parameter"]
    units = ds[par].attrs.get("units", "")
    values = ds[par].values
    lines = [f"# Classification report: {a['scene']}, {par} sweep ({a['mode']})", ""]
    keys = [k for k in sorted(a) if k.startswith("param_") and not k.endswith(("_units", "_source"))]
    lines += ["## Settings", "",
              f"- grid: {values.size} values of `{par}` from {values.min():g} to {values.max():g} {units}",
              f"- per value: {a['transient_periods']} transient + {a['recorded_periods']} recorded relay periods "
              f"(extended up to {a.get('max_record_periods', a['recorded_periods'])} to hold three forcing periods; "
              f"`record_used`); "
              f"heyoka tol {a['tol']:g}; circuit {a.get('circuit')}; AC sign {a.get('ac_sign')}; "
              f"DC-force law {a.get('dc_law', 'not recorded')}"
              + (f"; soil {a['soil']}" + (" with compaction" if a.get("soil_compaction", "none") != "none" else "")
                 + " (classes in relative coordinates, the common shift of bar, rig and soil front removed; the progression per period in the class text)"
                 if a.get("soil", "none") != "none" else ""),
              f"- initial state: {a.get('initial_state', '')}",
              f"- classification: period n, a multiple of the forcing period q (`forcing_period`; none "
              f"when q = 0) up to {a['max_period']}, when the recurrence distance <= "
              f"rtol {a['classification_rtol']:g} x scale + atol {a['classification_atol']:g} over the whole "
              f"record; otherwise a decaying recurrence is *not-converged*, and a Lyapunov exponent over "
              f"{a.get('lyapunov_steps', '?')} periods decides chaotic (> {a.get('lyapunov_threshold', float('nan')):.3g}) "
              "vs quasi-periodic, unless its 95 % interval contains the threshold; undecided is *not-converged* "
              f"(`class_reason` says why); exponent by {a.get('lyapunov_method', 'companion (not recorded)')}",
              "- parameters: " + ", ".join(f"{k[6:]} = {a[k]:g} {a.get(k + '_units', '')}" for k in keys), ""]
    codes = ds.class_code.values
    lines += ["## Class counts", "", "| class | " + " | ".join(map(str, ds.branch.values)) + " |",
              "|---|" + "---|" * ds.sizes["branch"]]
    for c, label in enumerate(CLASS_LABELS):
        counts = [(codes[bi] == c).sum() for bi in range(ds.sizes["branch"])]
        if any(counts):
            lines.append(f"| {label} | " + " | ".join(str(int(n)) for n in counts) + " |")
    lines.append("")
    if at is None:
        at = [v for v in range(int(math.ceil(values.min())), int(math.floor(values.max())) + 1)]
    if len(at):
        lines += [f"## Class at chosen values of {par}", "",
                  f"| {par} [{units}] | branch | class | impacts in record | Lyapunov [1/period] | "
                  "recurrence | decay/period | forcing period |", "|---|---|---|---|---|---|---|---|"]
        for b in ds.branch.values:
            for v in at:
                c = class_at(ds, v, str(b))
                lines.append(f"| {c['value']:g} | {b} | {c['text']} | {c['n_impacts']} | {c['lyapunov']:.3g} | "
                             f"{c['recurrence']:.3g} | {c['convergence_rate']:.3g} | {c['forcing_period']} |")
        lines.append("")
    lines += ["## Intervals", ""]
    for bi, b in enumerate(ds.branch.values):
        sub = ds.isel(branch=bi)
        texts = [describe(int(c), int(n), int(m)) if c >= 0 else "missing"
                 for c, n, m in zip(sub.class_code.values, sub.period.values, sub.impacts_per_period.values)]
        lines.append(f"- **{b}**: " + "; ".join(
            f"{lo:g}-{hi:g}: {t} ({n})" if lo != hi else f"{lo:g}: {t}" for lo, hi, t, n in _intervals(values, texts)))
    lines.append("")
    if ds.sizes.get("grazing", 0):
        lines += ["## Grazing", ""] + [f"- {par} = {g:.6g} {units} ({b}, bisection to {x:g})" for g, b, x in
                                       zip(ds.grazing_value.values, ds.grazing_branch.values, ds.grazing_xtol.values)]
        lines.append("")
    n_graze = int(np.sum(ds.grazing_flag.values == 1))
    lines += [f"Orbits flagged grazing (slowest impact < {a.get('grazing_speed_threshold_m_s')} m/s or clearance "
              f"< {a.get('grazing_gap_threshold_m')} m): {n_graze}.", ""]
    st = ds.status.values
    lines += ["## Numerical error and run time", "",
              f"- sweep wall time {a.get('sweep_seconds', float('nan')):.1f} s; "
              f"{float(np.nansum(ds.run_seconds.values)):.1f} s integrating, "
              f"{int(np.sum(ds.n_steps.values))} Taylor steps",
              f"- escaped {int((st == 1).sum())}, failed {int((st == 2).sum())}"]
    if "error_estimate_tol" in a:
        lines.append(f"- error estimate (tol {a['error_estimate_tol']:g}): one relay period from the same recorded "
                     f"states differs by up to {a.get('error_map_step_rel', float('nan')):.2g} (relative to each "
                     f"state's scale); periodic values re-run whole: stroboscopic points differ by up to "
                     f"{a['error_map_points_rel']:.2g}, contact times by up to {a['error_impact_time_s']:.2g} s "
                     f"(nan: no periodic value sampled); contact counts differ at "
                     f"{a['error_impact_count_mismatches']} of the re-run values. On chaotic orbits the points are "
                     "not reproducible at any tolerance (sensitive dependence); the class is.")
    return "\n".join(lines) + "\n"
