"""The attractor atlas of the thesis 1-DOF model at 10 Hz in V: what does the mole settle to, and from switch-on?

For each DC-force law (`listing`, `fit`, `measured`; docs/model.md section 1), thesis-1dof with the
matlab-listing numbers at 10 Hz relay over V: every attractor the census finds from random starts in the box
x = 0-30 mm, v = -1.5-1.5 m/s with its basin fraction (95 % Wilson interval), and the switch-on probability of
each hammering orbit (mechanical period-1, one impact per relay period: the thesis' period-1) from the scene's
switch-on distribution (the bar at rest on the stop, the circuit at rest, with its declared spread), both by
:func:`bifurc.attractors`; beside them the stable branches at 10 Hz of the thesis-orbits study
(studies/thesis_orbits/report.md, continuation).  A start still on a chaotic saddle at the census' budget (2000
relay periods) is "transient"; the "eventual" column apportions those starts by where the starts that left the same
saddle went (bifurc.attractors.eventual; shown where it differs from the basin fraction).  Nothing is tuned to agree
with anything.
"""
from __future__ import annotations

import time as _time
from pathlib import Path

import numpy as np

NAME = "attractor-atlas"
SCENE = "thesis-1dof"
PRESET = "matlab-listing"
LAWS = ("listing", "fit", "measured")
BOX = {"x": (0.0, 0.03), "v": (-1.5, 1.5)}
FULL = dict(values=(80.0, 220.0, 29), starts=200, switch_on=100, link=True)
QUICK = dict(values=(120.0, 220.0, 3), starts=24, switch_on=12, link=False)   # `--quick` and the tests: < 2 min
#: relay periods per start before it counts as transient: the budget the committed reports were made with (the
#: census' default until issue 45 gave every verb one default, 6000)
BUDGET = 2000
#: the longest period the census searches [strobe periods]: the committed reports' (the census' default until
#: issue 45 gave every verb one default, 100)
MAX_PERIOD = 16


def run(out, quick=False, progress=True, overwrite=False) -> dict:
    """Every census into folder ``out``: ``<law>-box.nc``, ``<law>-switch-on.nc``, ``<law>.png`` and
    ``report.md``; returns {(law, kind): dataset}."""
    import bifurc
    from bifurc import plot_attractors
    from bifurc.studykit import write_text
    out = Path(out)
    size = QUICK if quick else FULL
    clock = _time.perf_counter()
    values = np.linspace(*size["values"])
    results = {}
    for law in LAWS:
        kw = dict(preset=PRESET, params={"relay_hz": 10.0}, dc_law=law, seed=1, progress=progress,
                  link=size["link"], overwrite=True, budget=BUDGET,
                  max_period=MAX_PERIOD)
        box = bifurc.attractors(SCENE, "V", values, starts="box", box=BOX, n_starts=size["starts"],
                                path=out / f"{law}-box.nc", **kw)
        sw = bifurc.attractors(SCENE, "V", values, starts="switch-on", n_starts=size["switch_on"],
                               path=out / f"{law}-switch-on.nc", **kw)
        for kind, ds in (("box", box), ("switch-on", sw)):
            ds.attrs["study"], ds.attrs["study_case"] = NAME, f"{law}-{kind}"
            results[law, kind] = ds
        plot_attractors(box, out / f"{law}.png", overwrite=True)
    write_text(out / "report.md", report(results, quick, _time.perf_counter() - clock), overwrite=True)
    return results


def hammering(ds):
    """Per (V, attractor): a mechanical period-1 orbit with one impact per relay period."""
    return (ds.period_mechanical == 1) & (ds.impacts_per_period_mechanical == 1)


def _rows(ds) -> list:
    """(V, label, fraction, low, high, eventual fraction with its interval as text, hammering) of every attractor
    present at each value and every outcome some start had."""
    rows, hammers, still = [], hammering(ds).values, neutral(ds).values
    for i, v in enumerate(ds["V"].values):
        for j, name in enumerate(ds.attractor_label.values):
            f = float(ds.basin_fraction.values[i, j])
            if name.startswith("A") and bool(ds.present.values[i, j]) or f > 0:
                ev = (ds.eventual_fraction.values[i, j], ds.eventual_fraction_low.values[i, j],
                      ds.eventual_fraction_high.values[i, j])
                rows.append((float(v), str(name), _label(ds, i, j, still[i, j]), f,
                             float(ds.basin_fraction_low.values[i, j]), float(ds.basin_fraction_high.values[i, j]),
                             "" if ev[0] == f else f"{ev[0]:.3f} ({ev[1]:.3f}-{ev[2]:.3f})", bool(hammers[i, j])))
    return rows


def _label(ds, i, j, is_neutral: bool) -> str:
    name = str(ds.attractor_label.values[j])
    if not name.startswith("A"):
        return name
    from bifurc.labels import describe
    text = describe(int(ds.class_code.values[i, j]), int(ds.period.values[i, j]), int(ds.impacts_per_period.values[i, j]))
    return text + " (neutral: no area contraction)" if is_neutral else text


def neutral(ds):
    """Per (V, attractor): a non-periodic set whose area rate's 95 % interval contains 0 (no contraction shown: an
    invariant set of undamped motion, as the tori of an area-preserving map, not an attractor of a dissipative one)."""
    from bifurc.studykit import no_contraction
    return no_contraction(ds.area_rate_low, ds.area_rate_high)


def _neutral_note(ds) -> str:
    import bifurc
    still = neutral(ds).values
    n = int(still.sum())
    k = len(bifurc.Outcome)        # the outcomes' entries, after the attractors
    sets = int(((ds.present.values[:, :-k] > 0) & (ds.period.values[:, :-k] == 0)).sum())
    share = float(np.where(still, ds.basin_fraction.values, 0.0).sum() / ds.sizes["V"])
    if not n:
        return (f"Non-periodic sets: {sets} (value, set) entries, none without area contraction (for each the sum of "
                f"its two leading Lyapunov exponents is below 0 or not estimated)." if sets else "No non-periodic set.")
    return (f"Non-periodic sets: {sets} (value, set) entries; {n} of them show no area contraction (the sum of their "
            f"two leading Lyapunov exponents has a 95 % interval containing 0: the bar's flight between impacts is "
            f"undamped, docs/model.md), holding {share:.3f} of the box starts on average over the values: invariant "
            f"sets of conservative motion, on which a start keeps its own amplitude, not attractors.")


def _stages(ds) -> str:
    """Where a census' time went: its fresh starts (every worker), the seeding and matching, the linking."""
    a = ds.attrs
    return (f"{a['census_seconds']:.0f} s ({a['workers']} workers: fresh starts {a['fresh_seconds']:.0f} s, seeding and "
            f"matching {a['seeding_seconds']:.0f} s, linking {a['links']} changes {a['linking_seconds']:.0f} s)")


def _branches(law: str) -> list:
    """The thesis-orbits study's stable branches at 10 Hz under ``law`` (its committed report's summary)."""
    path = Path(__file__).parent.parent / "thesis_orbits" / "report.md"
    if not path.exists():
        return ["(studies/thesis_orbits/report.md not found)"]
    tag = f"- `{law}`, 10 Hz:"
    return [line[2:] for line in path.read_text().splitlines() if line.startswith(tag)] or ["(none listed)"]


def report(results, quick, seconds) -> str:
    size = QUICK if quick else FULL
    lines = [f"# {NAME}: attractors of thesis-1dof at 10 Hz in V{' (quick)' if quick else ''}", "",
             __doc__.split("\n\n", 1)[1].strip(), "",
             f"Size: {'quick' if quick else 'full'}: V = {size['values'][0]:g}-{size['values'][1]:g} V in "
             f"{size['values'][2]} values, {size['starts']} box starts and {size['switch_on']} switch-on starts per "
             f"value (seed 1), linking {'on' if size['link'] else 'off'}.  Run time {seconds:.0f} s.", ""]
    for law in LAWS:
        box, sw = results[law, "box"], results[law, "switch-on"]
        lines += [f"## DC law `{law}`", "", "| V [V] | attractor | class | basin fraction (box) | 95 % interval | "
                  "eventual (95 %) | hammering |", "|---|---|---|---|---|---|---|"]
        lines += [f"| {v:g} | {n} | {lab} | {f:.3f} | {lo:.3f}-{hi:.3f} | {ev} | {'yes' if h else ''} |"
                  for v, n, lab, f, lo, hi, ev, h in _rows(box)]
        lines += ["", _neutral_note(box), "", "Switch-on (from the scene's switch-on distribution):", "",
                  "| V [V] | outcome | class | probability | 95 % interval | eventual (95 %) | hammering |",
                  "|---|---|---|---|---|---|---|"]
        lines += [f"| {v:g} | {n} | {lab} | {f:.3f} | {lo:.3f}-{hi:.3f} | {ev} | {'yes' if h else ''} |"
                  for v, n, lab, f, lo, hi, ev, h in _rows(sw) if f > 0]
        lines += ["", "Run times: " + "; ".join(f"{kind} {_stages(ds)}" for kind, ds in (("box", box), ("switch-on", sw))),
                  "", "Beside them, the thesis-orbits study's stable branches at 10 Hz (continuation):", ""]
        lines += [f"- {b}" for b in _branches(law)] + [""]
    return "\n".join(lines)


def switch_on_hammering(ds) -> np.ndarray:
    """Per value: the switch-on probability of landing on a hammering orbit (all hammering orbits together)."""
    return np.where(hammering(ds).values, ds.basin_fraction.values, 0.0).sum(axis=1)


def findings(results, quick) -> list:
    """Per law: the distinct attractors the box census found (+-1), the share of box starts on neutral motion
    (undamped flight: no impact, no area contraction) averaged over V (+- 0.05), and the switch-on probability of
    hammering at the highest V (+- 0.15: its Wilson interval at these sizes is wider)."""
    from bifurc.studykit import Finding, attractor_count
    out = []
    for law in LAWS:
        box, sw = results[law, "box"], results[law, "switch-on"]
        n_att = attractor_count(box)
        top = float(sw["V"].values[-1])
        column = list(box.attractor_label.values).index("neutral")
        neutral_share = float(box.basin_fraction.isel(attractor=column).mean())
        out += [Finding(f"{law}: distinct attractors from the box starts", n_att, 1, "1"),
                Finding(f"{law}: share of the box starts whose motion is neutral, mean over V", neutral_share, 0.05, "1"),
                Finding(f"{law}: switch-on probability of hammering at {top:g} V", float(switch_on_hammering(sw)[-1]),
                        0.15, "1")]
    return out
