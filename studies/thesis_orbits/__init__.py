"""Where does the 1-DOF thesis model hammer periodically?  Answered by continuation, not only by
simulation.

For each DC-force law (docs/model.md section 1: `listing`, `fit`, `measured`) and relay frequency 5 and
10 Hz (q = 1: the mains forcing repeats every relay period), periodic orbits are found by Newton's
method from simulations started at several voltages (``seeds``; a simulation's end that Newton
cannot correct is tried again after as many periods more; one on a stable branch already followed
is not followed again) and from the sweep's values classified
periodic (the first ``sweep_seeds`` in V that no stable branch already holds) and continued in the
AC voltage V
over 25-300 V by pseudo-arclength (:func:`bifurc.continue_orbit`), stable and unstable parts
alike, with folds, period doublings, Neimark-Sacker points and grazings located.  Beside each, the
brute-force classes of a sweep in V (:func:`bifurc.sweep`, same law and relay frequency).  The
matlab-listing numbers throughout (Table C.1); the DC law is the only thing that changes.
Nothing is tuned to agree with the thesis.
"""
from __future__ import annotations

import math
import time as _time
from pathlib import Path

import numpy as np

from .. import provenance

NAME = "thesis-orbits"
SCENE = "thesis-1dof"
PRESET = "matlab-listing"
LAWS = ("listing", "fit", "measured")
V_RANGE = (25.0, 300.0)
FULL = dict(relays=(5.0, 10.0), laws=LAWS, seeds=(25.0, 50.0, 90.0, 150.0, 200.0, 300.0), max_points=200,
            sweep_n=56, sweep_seeds=6, transient=300, record=100)
QUICK = dict(relays=(10.0,), laws=("listing", "measured"), seeds=(90.0, 200.0), max_points=40, sweep_n=12,
             sweep_seeds=2, transient=100, record=40)


def run(out, quick=False, progress=True, overwrite=False) -> dict:
    """Every case into folder ``out``: ``report.md``, ``orbits_<law>_<hz>Hz.png``, ``branches_*.nc``."""
    from bifurc.studykit import write_netcdf, write_text
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    size = QUICK if quick else FULL
    clock = _time.perf_counter()
    cases = []
    for law in size["laws"]:
        for hz in size["relays"]:
            case = _case(law, hz, size, progress)
            for k, ds in enumerate(case["branches"]):
                write_netcdf(ds, out / f"branches_{law}_{hz:g}Hz_{k}.nc", overwrite=overwrite)
            _figure(case, out / f"orbits_{law}_{hz:g}Hz.png", overwrite)
            cases.append(case)
    seconds = _time.perf_counter() - clock
    write_text(out / "report.md", report(cases, quick, seconds), overwrite=overwrite)
    return {"cases": cases, "seconds": seconds}


def _case(law, hz, size, progress) -> dict:
    from bifurc import OrbitNotFound, continue_orbit, sweep
    from maps import ParameterError
    params = {"relay_hz": hz}
    diagram = sweep(SCENE, "V", np.linspace(*V_RANGE, size["sweep_n"]), preset=PRESET, dc_law=law, params=params,
                    transient=size["transient"], record=size["record"], progress=False)
    branches, misses, again = [], [], []
    seeds = [(float(V), None) for V in size["seeds"]] + _periodic_values(diagram)
    from_sweep = 0
    for seed, start in seeds:
        if start is not None:
            if _on_stable_branch(branches, seed, start[2]):
                continue                   # the sweep's orbit lies on a branch already followed
            if from_sweep == size["sweep_seeds"]:
                break
            from_sweep += 1
        transient, first = size["transient"], True
        for end in (V_RANGE[1], V_RANGE[0]):
            if end == seed:
                continue
            # a simulation's end that Newton cannot correct (a chaotic transient: it lands near no
            # orbit) is tried once more after as many periods again
            tries = (transient,) if start is not None or transient != size["transient"] else (transient, 2 * transient)
            for transient in tries:
                try:
                    ds = continue_orbit(SCENE, "V", (seed, end), preset=PRESET, dc_law=law, params=params,
                                        transient=transient, max_points=size["max_points"],
                                        start=None if start is None else start[:2],
                                        period=None if start is None else start[2][0])
                    break
                except (OrbitNotFound, ParameterError) as exc:
                    ds, why = None, getattr(exc, "reason", str(exc))
            if ds is None:
                misses.append((seed, "the sweep point" if start else
                               f"the simulation ({' and '.join(str(t) for t in tries)} periods)", why))
                break
            if first and start is None and _seed_followed(branches, ds, seed):
                again.append((seed, int(ds.period.values[0]), int(ds.impacts_per_period.values[0])))
                break                      # the simulation landed on a stable branch already followed
            first = False
            branches.append(ds)
            if progress:
                print(f"{law:8s} {hz:g} Hz, from V = {seed:g} toward {end:g}: {ds.sizes['point']} points, "
                      f"{ds.sizes['special']} special, {ds.attrs['run_seconds']:.1f} s", flush=True)
    return {"law": law, "hz": hz, "diagram": diagram, "branches": branches, "misses": misses, "again": again}


def _seed_followed(branches, ds, V) -> bool:
    """True when the orbit a branch ``ds`` starts from (at ``V``) is stable and lies on a stable
    stretch of an earlier branch with the same period and impact count."""
    key = (int(ds.period.values[0]), int(ds.impacts_per_period.values[0]))
    return int(ds.stable.values[0]) == 1 and _on_stable_branch(branches, V, key)


def _parent_doubling(ds, i: int, branches) -> str:
    """For a fold bracketed where a period-2m branch is born (special ``i`` of ``ds``, its note says
    so), the located period doubling of a period-m orbit within its tolerance, from ``branches``."""
    from bifurc.studykit import BIRTH_NOTE, SPECIAL_KINDS
    if BIRTH_NOTE not in str(ds.special_note.values[i]):
        return ""
    value, width = float(ds.special_value.values[i]), float(ds.special_tolerance.values[i])
    m = int(ds.period.values[int(ds.special_point.values[i])]) // 2
    pd = SPECIAL_KINDS.index("period_doubling")
    found = sorted({round(float(other.special_value.values[j]), 8) for other in branches
                    for j in range(other.sizes.get("special", 0))
                    if int(other.special_kind.values[j]) == pd and math.isfinite(float(other.special_tolerance.values[j]))
                    and int(other.period.values[int(other.special_point.values[j])]) == m
                    and abs(float(other.special_value.values[j]) - value) <= width})
    return "" if not found else (f" (located: the period-{m} branch's period doubling at V = "
                                 f"{', '.join(f'{v:.8g}' for v in found)} V)")


def _kind_label(kind: str, value: float, tol: float) -> str:
    """A bounding special point's kind, with its tolerance where it is coarser than 1e-6 relative
    (a bracket or an extrapolation, not a converged location)."""
    return kind if tol <= 1e-6 * max(1.0, abs(float(value))) else f"{kind} +- {float(tol):.1g}"


def _end(value: float, kind: str | None) -> str:
    """An interval end for the report: a located special point to 8 digits with its kind, else
    the stable point sampled there to 6 (enough to tell it from a located end beside it)."""
    return f"{value:.6g}" if kind is None else f"{value:.8g} ({kind.replace('_', ' ')})"


def _periodic_values(diagram) -> list:
    """[(V, (HybridState, k, (period, impacts)))] of the sweep values classified periodic, in V."""
    from bifurc import sweep_point
    d = diagram.isel(branch=0)
    out = []
    for V, n, m in zip(d.V.values, d.period.values, d.impacts_per_period.values):
        if n > 0:
            state, k = sweep_point(diagram, float(V))
            out.append((float(V), (state, k, (int(n), int(m)))))
    return out


def _on_stable_branch(branches, V, key) -> bool:
    return any(lo <= V <= hi and (n, m) == tuple(key) for ds in branches for lo, hi, n, m in stable_intervals(ds))


def stable_intervals(ds, located: bool = False) -> list:
    """[(V_low, V_high, period, impacts)] of consecutive stable points with one period and impact count.

    ``located=True``: each end of the run reaches the located special point (fold, period doubling,
    Neimark-Sacker, grazing: finite tolerance) nearest to it between the run's end point and the
    next point along the branch, and a located fold inside the run (the branch turns back) counts
    too; the tuples gain what bounds each end: (V_low, V_high, period, impacts, low_kind,
    high_kind), a kind (with "+- tol" where its location is coarser than 1e-6 relative) or None
    where the end is a stable point sampled."""
    runs, run = [], None
    ids = _branch_ids(ds)
    for i, (st, n, m) in enumerate(zip(ds.stable.values, ds.period.values, ds.impacts_per_period.values)):
        key = (int(n), int(m))
        if st == 1 and run is not None and run[2] == key and ids[i] == ids[i - 1]:
            run[1] = i
            continue
        if run is not None:
            runs.append(run)
        run = [i, i, key] if st == 1 else None
    if run is not None:
        runs.append(run)
    V = ds.V.values
    out = []
    for i0, i1, key in runs:
        points = [(float(V[i]), None) for i in range(i0, i1 + 1)]
        if not located:
            out.append((min(points)[0], max(points)[0]) + key)
            continue
        # the run's V-extent: its points, the special points bounding its ends and the located folds
        # inside it (a branch that turns back within a stable run reaches its extreme V there)
        for i, k in ((i0, i0 - 1), (i1, i1)):
            near = _bounding_special(ds, i, k)
            if near is not None:
                points.append(near)
        points += _located_folds(ds, i0, i1)
        lo, hi = min(points, key=lambda e: e[0]), max(points, key=lambda e: e[0])
        out.append((lo[0], hi[0]) + key + (lo[1], hi[1]))
    return out


def _located_folds(ds, i0: int, i1: int) -> list:
    """[(value, "fold")] of the located folds recorded between points of the run i0..i1."""
    from bifurc.studykit import SPECIAL_KINDS
    if "special" not in ds.dims:
        return []
    fold = SPECIAL_KINDS.index("fold")
    return [(float(v), _kind_label("fold", v, tol)) for kind, v, tol, k in zip(ds.special_kind.values, ds.special_value.values,
                                                          ds.special_tolerance.values, ds.special_point.values)
            if int(kind) == fold and math.isfinite(float(tol)) and i0 <= int(k) < i1]


def _branch_ids(ds) -> np.ndarray:
    """The branch of each point (one branch where the dataset does not say)."""
    return ds.branch_id.values if "branch_id" in ds else np.zeros(ds.sizes["point"], int)


def _bounding_special(ds, i: int, k: int):
    """(value, kind) of the located special point nearest to point ``i`` among those recorded between
    points k and k + 1 (``special_point == k``), on the side of ``i`` away from the run; None if none."""
    from bifurc.studykit import LOCATED_KINDS, SPECIAL_KINDS
    if "special" not in ds.dims or k < 0:
        return None
    V, ids = ds.V.values, _branch_ids(ds)
    other = k + 1 if k == i else k          # the neighbour of i away from the run (may not exist)
    if other < ds.sizes["point"] and ids[other] != ids[i]:
        other = ds.sizes["point"]           # the run's end is its branch's end
    if k != i and ids[k] != ids[i]:
        return None                         # the run starts its branch: nothing recorded before it
    best = None
    for j in range(ds.sizes["special"]):
        kind = SPECIAL_KINDS[int(ds.special_kind.values[j])]
        value, tol = float(ds.special_value.values[j]), float(ds.special_tolerance.values[j])
        if int(ds.special_point.values[j]) != k or kind not in LOCATED_KINDS or not math.isfinite(tol):
            continue
        if other < ds.sizes["point"] and kind != "fold":    # a fold lies beyond both points beside it
            if not min(V[i], V[other]) - tol <= value <= max(V[i], V[other]) + tol:
                continue
        if best is None or abs(value - V[i]) < abs(best[0] - V[i]):
            best = (value, _kind_label(kind, value, tol))
    return best


#: what benchmarks/stick_onset_continuity.py found past the stick onsets of the measured law's branch at 10 Hz
STICK_ONSET_NOTE = (
    "Past each stick onset the branch restarts into an orbit with one impact more.  The same family "
    "(`python benchmarks/stick_onset_continuity.py`, benchmarks/README.md): each such piece, continued back, stops "
    "3.6e-5 to 8e-4 V above its onset where sticking sets in, its strobe state as far from the n-impact orbit's at "
    "the onset as that orbit's own slope times the distance (to 3 %): the state is continuous; the largest "
    "multiplier differs by 0.2-4.5 % (the map is only piecewise smooth there).  The short stretch between, where "
    "both pieces' maps show a stick, is skipped by the restart's first try (0.00205 V), not resolved.")


def _restarted_at_stick_onset(branches) -> bool:
    """Some branch was restarted past a stick onset (its stop reasons say so)."""
    reasons = (ds.attrs.get("branch_stop_reasons", "") for ds in branches)
    return any("sticking sets in" in r and "continued from" in r for r in reasons)


def report(cases, quick, seconds) -> str:
    from bifurc import class_at
    from bifurc.studykit import SPECIAL_KINDS
    lines = [f"# {NAME}: periodic orbits of thesis-1dof continued in V ({'quick' if quick else 'full'} run)", "",
             f"Scene {SCENE}, preset {PRESET} (Table C.1), V over {V_RANGE[0]:g}-{V_RANGE[1]:g} V; relay frequency and "
             f"DC-force law per section.  Orbits are solved by Newton's method by multiple shooting with exact "
             f"Jacobians and followed by pseudo-arclength continuation (`bifurc.continue_orbit`); the classes "
             f"beside them come from a brute-force sweep in V (`bifurc.sweep`).  Run time {seconds:.0f} s.", "",
             provenance(NAME, quick), ""]
    hammering = []
    for c in cases:
        law, hz, diagram = c["law"], c["hz"], c["diagram"]
        lines += [f"## DC law `{law}`, relay {hz:g} Hz", ""]
        if not c["branches"]:
            lines.append("No periodic orbit was found from any seed.")
        for ds in c["branches"]:
            V = ds.V.values
            if V.size == 0:       # the seed's orbit did not converge: its reason, no points
                lines.append(f"- a seed's branch has no point: {ds.attrs['branch_stop_reasons']}")
                continue
            lines.append(f"- branch from V = {V[0]:g} V: {ds.sizes['point']} points over {V.min():.4g}-{V.max():.4g} V; "
                         f"{ds.attrs['branch_stop_reasons']}")
            if "flag_stuck_bar" in ds and np.all(ds.flag_stuck_bar.values[:, 0] == 1):
                lines.append("  - the bar rests on the stop (stuck) throughout: not a hammering orbit (its position and "
                             "velocity are held on the stop, multipliers 0; the circuit's multipliers decide stability)")
            for lo, hi, n, m, klo, khi in stable_intervals(ds, located=True):
                lines.append(f"  - stable period-{n} with {m} impact{'s' if m != 1 else ''} per period for V in "
                             f"[{_end(lo, klo)}, {_end(hi, khi)}] V")
                if m >= 1:
                    stroke = _stroke(ds, law, hz, lo, hi) if (n, m) == (1, 1) else ""
                    hammering.append((law, hz, _end(lo, klo), _end(hi, khi), n, m, stroke))
            for i in range(ds.sizes["special"]):
                kind = SPECIAL_KINDS[int(ds.special_kind[i])]
                tol = float(ds.special_tolerance[i])
                mu = ds.special_multiplier_abs.values[i]
                lines.append(f"  - {kind} at V = {float(ds.special_value[i]):.8g} V"
                             + ("" if not math.isfinite(tol) else f" (+- {tol:.1g})")
                             + (f"; multipliers |mu| = {', '.join(f'{m:.4g}' for m in mu)}" if np.isfinite(mu).any()
                                else f": {ds.special_note.values[i]}{_parent_doubling(ds, i, c['branches'])}"))
        for seed, n, m in c.get("again", []):
            lines.append(f"- the simulation at V = {seed:g} V lands on a stable period-{n} orbit with {m} impact"
                         f"{'s' if m != 1 else ''} per period already followed")
        for seed, source, why in c["misses"]:
            lines.append(f"- no orbit from {source} at V = {seed:g} V: {why}")
        if law == "measured" and hz == 10.0 and _restarted_at_stick_onset(c["branches"]):
            lines += ["", STICK_ONSET_NOTE]
        lines += ["", "Brute-force classes of the sweep at the same law and frequency:", "",
                  "| V [V] | class | on a stable continued branch |", "|---|---|---|"]
        for V in diagram.V.values[:: max(1, diagram.sizes['V'] // 12)]:
            cl = class_at(diagram, float(V))
            on = [f"period-{n}, {m} impacts" for ds in c["branches"] for lo, hi, n, m in stable_intervals(ds)
                  if lo <= V <= hi]
            lines.append(f"| {V:.4g} | {cl['text']} | {'; '.join(on) or '-'} |")
        lines.append("")
    lines += ["## Where the thesis model hammers periodically", ""]
    if hammering:
        for law, hz, lo, hi, n, m, stroke in hammering:
            lines.append(f"- `{law}`, {hz:g} Hz: stable period-{n} with {m} impact{'s' if m != 1 else ''} per period "
                         f"for V in [{lo}, {hi}] V" + (f"; {stroke}" if stroke else ""))
    else:
        lines.append("Nowhere on the continued branches: no stable orbit with an impact was found.")
    ones = [h for h in hammering if h[4] == 1 and h[5] == 1]
    lines += ["", "Period-1 with one impact per relay period (the thesis' period-1; a hammering stroke only where the "
                  "bar rises millimetres, a chatter where it rises micrometres): "
              + ("; ".join(f"`{law}` at {hz:g} Hz for V in [{lo}, {hi}] V ({stroke})"
                           for law, hz, lo, hi, _, _, stroke in ones) if ones else "not found on any continued branch.")]
    return "\n".join(lines) + "\n"


def _stroke(ds, law, hz, lo, hi) -> str:
    """The stroke of a period-1 one-impact orbit at the stable point nearest the middle of [lo, hi] V:
    x's range over one relay period and its impact speed and energy (one period simulated from the
    branch's node), as text."""
    from maps import simulate
    V = ds.V.values
    mid = 0.5 * (lo + hi)
    ok = np.flatnonzero((ds.stable.values == 1) & (V >= lo) & (V <= hi))
    if not ok.size:
        return ""
    k = int(ok[np.argmin(np.abs(V[ok] - mid))])
    states = [s for s in ("x", "v", "i", "z") if s in ds]
    x0 = {s: float(ds[s].values[k, 0]) for s in states}
    run = simulate(SCENE, periods=1, preset=PRESET, dc_law=law, params={"relay_hz": hz, "V": float(V[k])}, x0=x0,
                   dt=1e-5)
    x = 1e3 * run.x.values
    speeds = np.abs(run.impact_velocity.values[np.isfinite(run.impact_velocity.values)])
    m = float(ds.attrs.get("param_m", np.nan))
    if not speeds.size:
        return f"at {V[k]:.4g} V: x {x.min():.3g}..{x.max():.3g} mm, no impact in the simulated period"
    energy = 0.5 * m * speeds.max() ** 2 if math.isfinite(m) else math.nan
    return (f"at {V[k]:.4g} V the bar spans x {x.min():.3g}..{x.max():.3g} mm and strikes at {speeds.max():.3g} m/s"
            + (f" ({1e3 * energy:.3g} mJ)" if math.isfinite(energy) else ""))


def _figure(case, path, overwrite):
    import matplotlib.pyplot as plt

    from bifurc.studykit import save_figure
    from bifurc import plot_branch
    fig, ax = plt.subplots(figsize=(9, 5.5))
    first = True
    for k, ds in enumerate(case["branches"]):
        V = ds.V.values
        if V.size == 0:          # a seed whose orbit did not converge: a branch of no point
            continue
        way = "lower" if V[min(1, V.size - 1)] < V[0] else "higher"
        plot_branch(ds, ax=ax, diagram=case["diagram"] if first else None, colour=k,
                    label=f"from {V[0]:g} V toward {way} V")
        first = False
    if first:
        from bifurc import plot_diagram
        plt.close(fig)
        plot_diagram(case["diagram"], path, overwrite=overwrite)
        return
    ax.set_title(f"thesis-1dof, DC law {case['law']}, relay {case['hz']:g} Hz: continued orbits over the sweep",
                 fontsize=10)
    save_figure(fig, path, overwrite=overwrite)


def findings(results, quick) -> list:
    """What the report states, per DC law and relay frequency: the branches continued (exact), the special
    points located (+-2: a step may land on either side of a borderline point), and each stable period-1
    one-impact interval's ends as the report states them (the located fold, period doubling or grazing that
    bounds it, else the last stable point sampled; +- 1e-3 V); "none" where there is none."""
    from bifurc.studykit import Finding
    out = []
    for c in results["cases"]:
        tag = f"{c['law']} {c['hz']:g} Hz"
        branches = [ds for ds in c["branches"] if ds.sizes.get("point", 0)]
        out += [Finding(f"{tag}: branches continued", len(branches), 0, "branches"),
                Finding(f"{tag}: special points located", sum(ds.sizes.get("special", 0) for ds in branches), 2,
                        "points")]
        ones = sorted((lo, hi) for ds in branches for lo, hi, n, m, *_ in stable_intervals(ds, located=True)
                      if (n, m) == (1, 1))
        if not ones:
            out.append(Finding(f"{tag}: stable period-1 one-impact intervals", "none"))
        for j, (lo, hi) in enumerate(ones):
            out += [Finding(f"{tag}: stable period-1 one-impact interval {j + 1}, low end", float(lo), 1e-3, "V"),
                    Finding(f"{tag}: stable period-1 one-impact interval {j + 1}, high end", float(hi), 1e-3, "V")]
    return out
