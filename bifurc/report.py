"""Markdown reports of every dataset kind: the classification report of a diagram and a short
summary of a regime map, time history, orbit, branch, work-precision study or stability suite
(:func:`report` dispatches on ``attrs["bifurc_kind"]``)."""
from __future__ import annotations

import math
import warnings

import numpy as np

from .storage.grid import OffGridWarning, nearest_index
from .storage.load import in_convention, require_kind
from .labels.classify import CLASS_LABELS, describe

def class_at(ds, value, branch=None) -> dict:
    """Class of the grid value nearest to ``value``: {value, text, code, period, impacts, lyapunov, ...}.

    A value outside the grid is refused; one half a grid step or more from every grid value is
    warned about (:func:`bifurc.storage.grid.nearest_index`)."""
    require_kind(ds, "diagram", "class_at")
    par = ds.attrs["swept_parameter"]
    b = branch or str(ds.branch.values[0])
    i = nearest_index(ds[par].values, value, par, ds[par].attrs.get("units", ""))
    sub = ds.sel(branch=b).isel({par: i})
    code = int(sub.class_code)
    return {"value": float(sub[par]), "branch": b, "code": code,
            "label": CLASS_LABELS[code] if code >= 0 else "missing",
            "text": describe(code, int(sub.period), int(sub.impacts_per_period),
                             float(sub.progression_per_period) if "progression_per_period" in sub else None)
            if code >= 0 else "missing",
            "period": int(sub.period), "impacts": int(sub.impacts_per_period), "lyapunov": float(sub.lyapunov),
            "recurrence": float(sub.recurrence), "convergence_rate": float(sub.convergence_rate),
            "n_impacts": int(sub.n_impacts), "min_clearance": float(sub.min_clearance),
            "forcing_period": int(sub.forcing_period)}


def _intervals(values, texts):
    out, start = [], 0
    for i in range(1, len(values) + 1):
        if i == len(values) or texts[i] != texts[start]:
            out.append((values[start], values[i - 1], texts[start], i - start))
            start = i
    return out


#: not-converged reasons by kind: (words the reason starts with or contains, what it means)
#: the kind of the values a sweep's --time-budget cut (its remedy is time, not --budget)
CUT_KIND = "cut by the sweep's time budget (--time-budget)"
UNDECIDED_KINDS = (
    ("time budget", CUT_KIND),
    ("contain a threshold", "exponent undecided: a trajectory's interval contains the chaos threshold"),
    ("within +-", "exponent near zero without positive evidence of a torus"),
    ("not stationary", "not stationary at the budget (intermittency or a long transient)"),
    ("contracting", "contracting, yet no period up to --max-period"),
    ("still decays", "a transient still approaching a periodic orbit"),
    ("near ", "a periodic orbit still converging"),
    ("other trajectories", "the exponent needs other trajectories"),
)


def undecided_summary(ds) -> list[str]:
    """One line per kind of not-converged reason of a diagram or map: its count and the one-line remedy.

    A value's ``budget_needed`` is the budget its evidence asks for. Where that is more than
    :data:`bifurc.labels.anytime.HOPELESS` budgets the sweep itself stopped extending it: a longer budget is
    unlikely to decide it, and no budget is suggested. Otherwise the largest such budget is suggested with
    its estimated computation time for those values: the periods each integrated (its copies included),
    scaled by the new budget over the old one, at the dataset's own measured seconds per relay period.
    Empty when every value is decided."""
    from .labels.anytime import BUDGET, HOPELESS
    codes = np.asarray(ds.class_code.values).ravel()
    reasons = np.asarray(ds.class_reason.values).ravel()
    need = np.asarray(ds.budget_needed.values).ravel() if "budget_needed" in ds else np.zeros(codes.size)
    used = np.asarray(ds.periods_integrated.values).ravel() if "periods_integrated" in ds else np.zeros(codes.size)
    bad = np.flatnonzero(codes == CLASS_LABELS.index("not-converged"))
    if not bad.size:
        return []
    groups: dict = {}
    for i in bad:
        kind = next((what for key, what in UNDECIDED_KINDS if key in str(reasons[i])), str(reasons[i]) or "no reason")
        groups.setdefault(kind, []).append((int(need[i]), int(used[i])))
    budget = ds.attrs.get("budget_periods", "?")
    old = int(budget) if str(budget).isdigit() else BUDGET
    rate = _seconds_per_period(ds)
    out = [f"{bad.size} not-converged (budget {budget} relay periods per value):"]
    for kind, needs in sorted(groups.items(), key=lambda kv: -len(kv[1])):
        out.append(f"  {len(needs)}: {kind}; {_remedy(kind, needs, old, HOPELESS * old, rate)}")
    return out


def _remedy(kind: str, needs: list, budget: int, hopeless: int, rate: float) -> str:
    """The remedy of ``needs`` (each value's (budget_needed, periods_integrated)) of one kind of reason
    (see :func:`undecided_summary`)."""
    if kind == CUT_KIND:
        return "raise --time-budget, or drop it"
    within = [(n, p) for n, p in needs if 0 < n <= hopeless]
    beyond = sum(n > hopeless for n, _ in needs)
    if not within:
        return ("a longer budget is unlikely to decide (its evidence asks for more than "
                f"{hopeless} relay periods: an exponent near the threshold)" if beyond else "see class_reason")
    wanted = max(n for n, _ in within)
    seconds = rate * sum(p for _, p in within) * wanted / budget
    cost = f" (about {_duration(seconds)} of computation for {len(within)} value" \
           f"{'s' if len(within) > 1 else ''})" if math.isfinite(seconds) and seconds > 0 else ""
    rest = f"; {beyond} more unlikely to be decided by a longer budget" if beyond else ""
    return f"try --budget {wanted}{cost}{rest}"


def _seconds_per_period(ds) -> float:
    """Computation seconds per relay period of one value, measured on this dataset (NaN: not recorded)."""
    periods = float(np.nansum(ds.periods_integrated.values)) if "periods_integrated" in ds else math.nan
    secs = float(ds.attrs.get("values_seconds", math.nan))
    return secs / periods if periods > 0 else math.nan


def _duration(seconds: float) -> str:
    """"40 s", "12 min", "3.5 h"."""
    return f"{seconds:.0f} s" if seconds < 120 else f"{seconds / 60:.0f} min" if seconds < 7200 else \
        f"{seconds / 3600:.1f} h"


def classification_report(ds, at=None, period_of: str = "full") -> str:
    """Markdown: settings, class counts, classes at chosen values, intervals, grazing, errors.

    ``at``: parameter values to tabulate (default: the integers inside the grid); ``period_of``:
    "full" (the whole state's period) or "mechanical" (the bar's alone, the thesis' period-n).
    """
    require_kind(ds, "diagram", "classification_report")
    ds = in_convention(ds, period_of)
    a = ds.attrs
    par = a["swept_parameter"]
    units = ds[par].attrs.get("units", "")
    values = ds[par].values
    lines = [f"# Classification report (diagram): {a['scene']}, {par} sweep ({a['mode']})", ""]
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
              f"- classification (anytime: an undecided value is extended up to {a.get('budget_periods', '?')} relay "
              f"periods, transient included): period n, a multiple of the forcing period q (`forcing_period`; none "
              f"when q = 0) up to {a['max_period']}, when the recurrence distance <= "
              f"rtol {a['classification_rtol']:g} x scale + atol {a['classification_atol']:g} over the stationary "
              f"window (`transient_used`, `record_used`); otherwise chaotic when every one of "
              f"{a.get('lyapunov_trajectories', 4)} tangent trajectories' exponent interval lies above the threshold "
              f"2 ln(n)/n, quasi-periodic when they lie within it and the 0-1 test and a converged rotation number "
              f"show a torus; else *not-converged* (`class_reason` says why, `budget_needed` what would decide it); "
              f"exponent by {a.get('lyapunov_method', 'companion (not recorded)')}",
              f"- period convention: {_convention(ds)}",
              "- parameters: " + _params(a), ""]   # no unit shown for "1" (dc_scale = 1, not "1 1")
    codes = ds.class_code.values
    lines += ["## Class counts", "", "| class | " + " | ".join(map(str, ds.branch.values)) + " |",
              "|---|" + "---|" * ds.sizes["branch"]]
    for c, label in enumerate(CLASS_LABELS):
        counts = [(codes[bi] == c).sum() for bi in range(ds.sizes["branch"])]
        if any(counts):
            lines.append(f"| {label} | " + " | ".join(str(int(n)) for n in counts) + " |")
    lines.append("")
    undecided = undecided_summary(ds)
    if undecided:
        lines += ["## Undecided values", ""] + [f"- {line.strip()}" for line in undecided] + [""]
    quiet = at is None      # the default values are the report's own choice: no warning when between grid values
    if at is None:
        at = [v for v in range(int(math.ceil(values.min())), int(math.floor(values.max())) + 1)]
    if len(at):
        lines += [f"## Class at chosen values of {par}", "",
                  f"| {par} [{units}] | branch | class | impacts in record | Lyapunov [1/period] | "
                  "recurrence | decay/period | forcing period |", "|---|---|---|---|---|---|---|---|"]
        for b in ds.branch.values:
            for v in at:
                with warnings.catch_warnings():
                    if quiet:
                        warnings.simplefilter("ignore", OffGridWarning)
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
    lines += _error_lines(ds)
    return "\n".join(lines) + "\n"


def _convention(ds) -> str:
    """The two period conventions, the one this report reads, and where they differ."""
    if "period_mechanical" not in ds:
        return "full state (this file stores no mechanical period)"
    differ = int(np.sum(np.char.str_len(np.asarray(ds.period_difference.values, dtype=str)) > 0))
    reads = ("this report reads the **mechanical** one" if ds.attrs.get("period_convention") == "mechanical"
             else "this report reads the **full** one (`--period-of mechanical` for the thesis' convention)")
    return (f"{reads}; the full convention counts the whole state (electrical states included); "
            f"the mechanical one (`period_mechanical`, `impacts_per_period_mechanical`) the mechanical states alone (the thesis' "
            f"period-n); they differ at {differ} value(s) (`period_difference` says why)")


def _error_lines(ds) -> list[str]:
    """The report's section on numerical error and run time."""
    a = ds.attrs
    st = ds.status.values
    lines = ["## Numerical error and run time", "",
              f"- sweep wall time {a.get('sweep_seconds', float('nan')):.1f} s; "
              f"{float(np.nansum(ds.run_seconds.values)):.1f} s integrating, "
              f"{int(np.sum(ds.n_steps.values))} Taylor steps",
              f"- escaped {int((st == 1).sum())}, failed {int((st == 2).sum())}"]
    if "error_estimate_tol" in a:
        lines.append(f"- error estimate (tol {a['error_estimate_tol']:g}): one relay period from the same recorded "
                     f"states differs by up to {a.get('error_map_step_rel', float('nan')):.2g} (relative to each "
                     f"state's scale); periodic values re-run whole: stroboscopic points differ by up to "
                     f"{a['error_map_points_rel']:.2g}, contact times by up to {a['error_impact_time_s']:.2g} s"
                     f"{' (nan: no periodic value sampled)' if a['error_impact_time_s'] != a['error_impact_time_s'] else ''}; contact counts differ at "
                     f"{a['error_impact_count_mismatches']} of the re-run values. On chaotic orbits the points are "
                     "not reproducible at any tolerance (sensitive dependence); the class is.")
    return lines


def _params(a, skip=()) -> str:
    keys = [k for k in sorted(a) if k.startswith("param_") and not k.endswith(("_units", "_source"))
            and k[6:] not in skip]
    units = {k: a.get(k + "_units", "") for k in keys}
    return ", ".join(f"{k[6:]} = {a[k]:g}" + (f" {units[k]}" if units[k] not in ("", "1") else "") for k in keys)


def _counts(codes, meanings) -> list[str]:
    """Markdown table rows "| meaning | count |" of the non-zero counts of flag codes."""
    codes = np.asarray(codes).ravel()
    return [f"| {m} | {int((codes == c).sum())} |" for c, m in enumerate(meanings) if (codes == c).any()]


def map_report(ds) -> str:
    """A regime map: its grid, class counts and grazing cells."""
    a = ds.attrs
    p1, p2 = a["swept_parameter"], a["swept_parameter2"]
    lines = [f"# Regime map report (map): {a.get('scene', '')}, {p1} x {p2}", "",
             f"- grid: {ds.sizes[p1]} values of `{p1}` x {ds.sizes[p2]} values of `{p2}`",
             f"- parameters: {_params(a, (p1, p2))}", "", "## Class counts", "", "| class | cells |", "|---|---|"]
    lines += _counts(ds.class_code.values, CLASS_LABELS)
    missing = int((ds.class_code.values < 0).sum())
    lines += ([f"| missing | {missing} |"] if missing else []) + ["",
              f"Cells flagged grazing: {int((ds.grazing_flag.values == 1).sum())}."]
    return "\n".join(lines) + "\n"


def history_report(ds) -> str:
    """A time history: how the run ended, its contacts and the model's DC-force law."""
    a = ds.attrs
    n = ds.sizes.get("impact", 0)
    lines = [f"# Time history report (history): {a.get('scene', '')}", "",
             f"- status: {a.get('status', 'not recorded')}, reached t = {float(a.get('t_end_reached', np.nan)):.6g} s"
             + (f" ({a['failure']})" if "failure" in a else ""),
             f"- {ds.sizes.get('t', 0)} samples; {a.get('n_steps', '?')} Taylor steps, {a.get('n_events', '?')} events",
             f"- impacts: {n}" + (f", first at t = {float(ds.impact_time.values[0]):.6g} s, speeds "
                                  f"{np.nanmin(np.abs(ds.impact_velocity.values)):.3g} to "
                                  f"{np.nanmax(np.abs(ds.impact_velocity.values)):.3g} m/s" if n else ""),
             f"- DC-force law: {a.get('dc_law', 'not recorded')} ({a.get('dc_law_source', 'source not recorded')})",
             f"- parameters: {_params(a)}"]
    return "\n".join(lines) + "\n"


def _multipliers(abs_, arg) -> str:
    return ", ".join(f"{m:.4g}" + (f" (arg {t:.3g} rad)" if abs(t) > 1e-12 else "") for m, t in zip(abs_, arg))


def orbit_report(ds) -> str:
    """A periodic orbit: period, impacts, multipliers and stability."""
    a = ds.attrs
    stable = int(ds.stable.values) == 1
    lines = [f"# Periodic orbit report (orbit): {a.get('scene', '')}", "",
             f"- period {int(ds.period.values)} strobe periods, {int(ds.impacts_per_period.values)} impacts per period",
             f"- {'stable' if stable else 'unstable'}: largest multiplier modulus "
             f"{float(np.max(ds.multiplier_abs.values)):.6g}",
             f"- Floquet multipliers: {_multipliers(ds.multiplier_abs.values, ds.multiplier_arg.values)} "
             f"(change at tol/100: {float(ds.multiplier_error.values):.2g})",
             f"- Newton residual {float(ds.newton_residual.values):.2g} after {a.get('newton_iterations', '?')} "
             f"iterations; min clearance {float(ds.min_clearance.values):.6g} m",
             f"- parameters: {_params(a)}"]
    return "\n".join(lines) + "\n"


def branch_report(ds) -> str:
    """A continued branch: its points and the special points with their kinds and parameter values."""
    a = ds.attrs
    par = a["continuation_parameter"]
    units = a.get("continuation_parameter_units", "")
    p = ds[par].values
    lines = [f"# Branch report (branch): {a.get('scene', '')}, continuation in {par}", "",
             f"- {ds.sizes['point']} points, {par} from {np.min(p):.6g} to {np.max(p):.6g} {units}; "
             f"{int((ds.stable.values == 1).sum())} stable",
             f"- branches: {a.get('branch_labels', '')} (stopped: {a.get('branch_stop_reasons', '')})",
             f"- parameters: {_params(a, (par,))}", "", "## Special points", ""]
    kinds = ds.special_kind.attrs["flag_meanings"].split()
    if not ds.sizes.get("special", 0):
        lines.append("None located.")
    else:
        lines += [f"| kind | {par} [{units}] | tolerance | note |", "|---|---|---|---|"]
        for i in range(ds.sizes["special"]):
            lines.append(f"| {kinds[int(ds.special_kind.values[i])]} | {float(ds.special_value.values[i]):.8g} | "
                         f"{float(ds.special_tolerance.values[i]):.2g} | {ds.special_note.values[i]} |")
    return "\n".join(lines) + "\n"


def accuracy_report(ds) -> str:
    """A work-precision study: per method, the fastest run at each error level reached (a table)."""
    a = ds.attrs
    lines = [f"# Work-precision report (accuracy): {a.get('scene', '')}, {float(a.get('t_end', np.nan)):g} s", "",
             f"- reference: {a.get('reference_precision')} at tol {float(a.get('reference_tol', np.nan)):g} "
             f"(error bound {float(a.get('reference_error_bound', np.nan)):.2g}), "
             f"{a.get('reference_n_impacts', '?')} impacts", "",
             "| method | tol | run time [s] | final-state error | impacts |", "|---|---|---|---|---|"]
    for i in range(ds.sizes["run"]):
        lines.append(f"| {ds.method.values[i]} | {float(ds.tol.values[i]):g} | {float(ds.run_seconds.values[i]):.3g} "
                     f"| {float(ds.final_state_error.values[i]):.2g} | {int(ds.n_impacts.values[i])} |")
    return "\n".join(lines) + "\n"


def stability_report(ds) -> str:
    """The numerical stability suite: verdict counts."""
    lines = [f"# Stability suite report (stability): {ds.attrs.get('suite', '')}, {ds.sizes['case']} cases", "",
             "| verdict | cases |", "|---|---|"]
    lines += _counts(ds.verdict.values, ds.verdict.attrs["flag_meanings"].split())
    return "\n".join(lines) + "\n"


def attractors_report(ds) -> str:
    """The attractor census: per value, each attractor present with its basin fraction and 95 % interval, the
    eventual fraction where the transient starts' apportioning changes it, and its event with the parameter value
    where the event was located on the attractor's continued branch (:func:`bifurc.attractors.dataset.event_text`)."""
    from .attractors.dataset import attractor_text, event_text, eventual_text
    par = ds.attrs["swept_parameter"]
    lines = [f"# Attractor census (attractors): {ds.attrs.get('scene', '')}, {ds.sizes[par]} values of {par} x "
             f"{ds.sizes['start']} starts", "", f"| {par} | attractor | class | basin fraction | 95 % interval | "
             "eventual (95 %) | event |", "|---|---|---|---|---|---|---|"]
    events = ds.event.attrs["flag_meanings"].split()
    for i, v in enumerate(ds[par].values):
        for j, label in enumerate(ds.attractor_label.values):
            if ds.basin_fraction.values[i, j] > 0 or ds.present.values[i, j] or ds.event.values[i, j]:
                what = attractor_text(ds, i, j)
                if ds.present.values[i, j] and ds.basin_fraction.values[i, j] <= 0 and label.startswith("A"):
                    what += " (no start landed; seeded from a neighbouring value)"
                if label == "transient":
                    life = float(ds.lifetime.values[i, j])
                    what = "on a chaotic saddle at the budget" + (f" (mean lifetime {life:.0f} strobe periods)"
                                                                  if np.isfinite(life) else "")
                ev = int(ds.event.values[i, j])
                ev_text = f"{events[ev]}: {event_text(ds, i, j)}" if ev else ""
                lines.append(f"| {v:g} | {label} | {what} | {ds.basin_fraction.values[i, j]:.3f} | "
                             f"[{ds.basin_fraction_low.values[i, j]:.3f}, {ds.basin_fraction_high.values[i, j]:.3f}] "
                             f"| {eventual_text(ds, i, j)} | {ev_text} |")
    return "\n".join(lines) + "\n"


def census_table(ds):
    """An attractors dataset as a tidy table: one row per (point, attractor or outcome) present or reached by a
    start, with its class in words, basin fraction and interval, periods (strobe and mechanical), impacts, exponent
    and its interval, lifetime and its verdict, every Floquet multiplier (``multiplier_abs_k``, ``multiplier_arg_k``,
    k = 1 largest) and its state at the section (node 0, ``<state>_at_section``); ``df.attrs["units"]`` maps each
    column to its units."""
    import pandas as pd
    require_kind(ds, "attractors", "census_table")
    dims = tuple(d for d in ds.basin_fraction.dims)
    names = [k for k, v in ds.data_vars.items() if v.dims == dims]
    cols = {k: ds[k] for k in names}
    units = {k: ds[k].attrs.get("units", "") for k in names}
    verdicts = ds.lifetime_verdict.attrs["flag_meanings"].split() if "lifetime_verdict" in ds else []
    if "multiplier_abs" in ds:
        for m in range(ds.sizes["multiplier"]):
            for part in ("abs", "arg"):
                k = f"multiplier_{part}_{m + 1}"
                cols[k], units[k] = ds[f"multiplier_{part}"].isel(multiplier=m, drop=True), \
                    ds[f"multiplier_{part}"].attrs.get("units", "")
    for st in [k for k, v in ds.data_vars.items() if v.dims == dims + ("node",) and not k.startswith("flag_")]:
        k = f"{st}_at_section"
        cols[k], units[k] = ds[st].isel(node=0, drop=True), ds[st].attrs.get("units", "")
    df = pd.DataFrame({k: v.values.ravel() for k, v in cols.items()})
    grid = np.meshgrid(*[np.arange(ds.sizes[d]) for d in dims], indexing="ij")
    for d, idx in zip(dims, grid):
        df.insert(list(dims).index(d), d, ds[d].values[idx.ravel()] if d != "attractor" else
                  ds.attractor_label.values[idx.ravel()])
        units[d] = ds[d].attrs.get("units", "") if d != "attractor" else "1"
    keep = (df["basin_fraction"] > 0) | (df["present"] > 0)
    df = df[keep.values].reset_index(drop=True)
    codes = df["class_code"].to_numpy()
    from .attractors.dataset import flow_text
    words = (lambda c, n, m: flow_text(c, n)) if "sample_step" in ds.attrs else describe
    df.insert(len(dims), "description", [
        words(int(c), int(n), int(m)) if lab.startswith("A") and c >= 0 else lab.replace("_", " ")
        for c, n, m, lab in zip(codes, df["period"], df["impacts_per_period"], df["attractor"])])
    if verdicts:
        df["lifetime_verdict"] = [verdicts[int(v)] for v in df["lifetime_verdict"]]
    df.attrs["units"] = {k: units.get(k, "") for k in df.columns}
    return df


#: the report of each dataset kind
REPORTS = {"attractors": attractors_report, "diagram": classification_report, "map": map_report, "history": history_report, "orbit": orbit_report,
           "branch": branch_report, "accuracy": accuracy_report, "stability": stability_report}


def report(ds, kind: str, **kw) -> str:
    """The Markdown report of ``ds``, a dataset of ``kind`` (keywords: the diagram's ``at``)."""
    return REPORTS[kind](ds, **kw)
