"""How many of the stable periodic orbits that the thesis-orbits study lists (thesis-1dof, `matlab-listing` preset,
`measured` law, 10 Hz) the attractor census recovers from random starts and its previous values' attractors (issue 31,
section 5; not CI).

    python benchmarks/attractors_recovery.py [--n 21] [--starts 200] [--range 80 220] [-o census.nc | --census census.nc]
                                             [--branches DIR | --save-branches DIR] [--link] [--refine]

Two counts, side by side (and with ``--link`` a third):

- by label: every line "stable period-P with M impacts per period for V in [a, b] V" of studies/thesis_orbits/
  report.md's section "DC law `measured`, relay 10 Hz" is an orbit expected at each census value inside [a, b];
  it counts as recovered where the census has an attractor of period P with M impacts at that value.  Two orbits
  sharing a label are counted once, and the census' orbit is credited whichever of them it is.
- by state: the thesis-orbits branches (continued again here with the study's own settings, or read from a study
  output folder ``--branches DIR``) give, at every census value inside a stable stretch, the orbit there polished
  by Newton (`find_periodic_orbit`, tol 1e-10) from the branch point beside it (on the branch's section: the
  continuation moves the sampling phase off an orbit in contact at phase 0; then carried to phase 0); it counts as recovered where a
  census attractor of its period has every node within 1e-6 of each state's scale of the orbit's nodes, at some
  phase.
- links (``--link``): of every fold and period doubling the branches locate inside the census' range, whether the
  census has the stable orbit ending there at the census value beside it (by state) and marks an appearance or
  disappearance across the step linked to that kind of event located within 1e-4 V of it (a fold where the branch
  is a period-m orbit taken twice is the birth at that orbit's period doubling: linked as a period doubling; before
  2026-11-26 18:00 the kind alone was compared).  A stable stretch between two located events that no branch
  point samples (a fold and a period doubling 0.03-0.05 V apart) is polished from the branch points on either
  side of them (since 2026-11-26 23:50; before, such orbits were "not on the branch").
- ``--refine``: the census values are refined at the branches' events (``bifurc.attractors(..., refine=)``): a
  value between each two located events sharing a step.  The census still takes no orbit from them.

The census (V in 80-220 V, box x=0:0.03, v=-1.5:1.5, seed 1) gets no orbit from continuation: only its random starts
and the seeding with the previous value's attractors.  Both use the thesis-orbits study's preset (`matlab-listing`):
before 2026-11-26 15:00 this benchmark ran the census under the scene's default preset (`thesis-text`: R = 30 Ohm,
C = 0.3 mF against 25 Ohm and 0.28 mF), another model than the one whose orbits it counted.
"""
from __future__ import annotations

import argparse
import pathlib
import re
import sys
import time

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]
REPORT = ROOT / "studies" / "thesis_orbits" / "report.md"
LINE = re.compile(r"stable period-(\d+) with (\d+) impacts? per period for V in \[([\d.]+)[^,]*, ([\d.]+)[^\]]*\]")
LAW, HZ = "measured", 10.0
RTOL = 1e-6


def expected(values, path=REPORT) -> set:
    """{(value index, period, impacts)} of the stable orbits listed for the measured law at 10 Hz."""
    text = path.read_text()
    part = text.split("## DC law `measured`, relay 10 Hz", 1)[1].split("\n## ", 1)[0]
    out = set()
    for p, m, a, b in LINE.findall(part):
        for i, v in enumerate(values):
            if float(a) - 1e-9 <= v <= float(b) + 1e-9:
                out.add((i, int(p), int(m)))
    return out


def branches(folder):
    """The thesis-orbits study's branches for the measured law at 10 Hz: read from ``folder``
    (branches_measured_10Hz_*.nc) or continued again with the study's full settings."""
    import xarray as xr
    if folder:
        files = sorted(pathlib.Path(folder).glob(f"branches_{LAW}_{HZ:g}Hz_*.nc"))
        if not files:
            sys.exit(f"attractors_recovery: no branches_{LAW}_{HZ:g}Hz_*.nc in {folder}")
        return [xr.load_dataset(f) for f in files]
    sys.path.insert(0, str(ROOT))
    from studies import thesis_orbits
    return thesis_orbits._case(LAW, HZ, thesis_orbits.FULL, progress=True)["branches"]


def save_branches(bs, folder) -> None:
    """The branches as the study writes them (``--branches`` reads them back)."""
    folder = pathlib.Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    for k, ds in enumerate(bs):
        ds.to_netcdf(folder / f"branches_{LAW}_{HZ:g}Hz_{k}.nc")


def _nodes(ds, names, idx, period):
    """A (period x states) array of a dataset's strobe states at index ``idx`` (a tuple before the node axis)."""
    return np.array([[float(ds[n].values[idx + (k,)]) for n in names] for k in range(period)])


def stable_orbits(bs, values, names, pb) -> dict:
    """{value index: [(period, impacts, nodes, {branch index: branch point})]}: the stable orbits of the branches
    ``bs`` at each census value, each polished by Newton at that value from the branch point beside it on the
    branch's section (its sampling phase) and brought to the census' section, phase 0 (distinct by state; the
    branches and points it was polished from)."""
    from bifurc import OrbitNotFound, find_periodic_orbit
    from maps import HybridState, StroboscopicMap
    maps_at = {}
    out: dict = {i: [] for i in range(len(values))}
    for b, ds in enumerate(bs):
        V, stable = ds["V"].values, ds.stable.values
        events = _events_between_points(ds)
        for i, v in enumerate(values):
            for p in range(len(V) - 1):
                ends = [V[p], V[p + 1], *events.get(p, ())]
                if not (min(ends) <= v <= max(ends)) or not (stable[p] or stable[p + 1] or p in events):
                    continue
                if stable[p] or stable[p + 1]:
                    tries = [p if stable[p] and (not stable[p + 1] or abs(V[p] - v) <= abs(V[p + 1] - v)) else p + 1]
                else:       # a stable stretch between two located events that no branch point samples
                    tries = [p, p + 1]
                for q in tries:
                    period, phase, k0 = int(ds.period.values[q]), float(ds.section_phase.values[q]), \
                        int(ds.section_k0.values[q])
                    for ph in {0.0, phase}:
                        if ph not in maps_at:
                            maps_at[ph] = StroboscopicMap(pb, tol=1e-10, phase=ph)
                        maps_at[ph] = maps_at[ph].at(dict(V=float(v)))
                    try:
                        po = find_periodic_orbit(maps_at[phase], HybridState(_nodes(ds, names, (q,), 1)[0]), period,
                                                 k0=k0, tol=1e-10)
                    except OrbitNotFound:
                        continue
                    if po.stable:
                        break
                else:
                    continue
                nodes = np.array([s.y for s in po.nodes]) if phase == 0.0 else np.array([
                    maps_at[phase].linearize(s, k0 + j, until=maps_at[0.0].sample_time(k0 + j + 1)).state.y
                    for j, s in enumerate(po.nodes)])
                known = next((o for o in out[i] if same(nodes, o[2])), None)
                if known is None:
                    out[i].append((period, int(po.impacts_per_period), nodes, {b: q}))
                else:
                    known[3].setdefault(b, q)
    return out


def _events_between_points(ds) -> dict:
    """{branch point p: [values of the folds and period doublings located between points p and p + 1]}."""
    out: dict = {}
    for k in range(ds.sizes.get("special", 0)):
        if _kind(ds, k) in ("fold", "period_doubling"):
            out.setdefault(int(ds.special_point.values[k]), []).append(float(ds.special_value.values[k]))
    return out


def _kind(ds, k) -> str:
    """A branch's special point ``k`` by its kind's name (the stored flag_meanings of special_kind)."""
    return ds.special_kind.attrs["flag_meanings"].split()[int(ds.special_kind.values[k])]


def located(bs, low, high) -> list:
    """[(kind, value, branch index, special point index)]: the folds and period doublings the branches locate in
    [low, high] (to their stated tolerance), each once (the first branch locating it)."""
    out = []
    for b, ds in enumerate(bs):
        for k in range(ds.sizes.get("special", 0)):
            kind, value = _kind(ds, k), float(ds.special_value.values[k])
            if kind in ("fold", "period_doubling") and low <= value <= high and np.isfinite(
                    float(ds.special_tolerance.values[k])) and not any(
                    o[0] == kind and abs(o[1] - value) <= 1e-6 * value for o in out):
                out.append((kind, value, b, int(ds.special_point.values[k])))
    return out


def links(ds, bs, orbits, values, names, n_att) -> list:
    """For every located fold and period doubling in the census' range: (kind, value, verdict), the verdict
    "linked" where the census has the stable orbit that ends there (by state) at the census value beside it and
    marks its appearance or disappearance across the step with that kind; else what it has."""
    out = []
    for kind, value, b, sp in located(bs, values[0], values[-1]):
        i = int(np.searchsorted(values, value))
        if i == 0 or i == len(values):
            continue
        ending = [(abs(o[3][b] - sp), side, o[2]) for side in (i - 1, i) for o in orbits[side] if b in o[3]]
        if not ending:
            out.append((kind, value, "its stable orbit is not on the branch at the census values beside it"))
            continue
        _, side, nodes = min(ending, key=lambda e: e[0])
        j = next((j for j in range(n_att) if ds.present.values[side, j] and int(ds.period.values[side, j]) ==
                  len(nodes) and same(nodes, _nodes(ds, names, (side, j), len(nodes)))), None)
        if j is None:
            out.append((kind, value, f"its stable orbit at {values[side]:g} V is not met by the census"))
            continue
        said = [str(ds.event_link.values[r, j]) for r in (i - 1, i) if int(ds.event.values[r, j])]
        if kind == "fold" and _birth(bs[b], sp, names):
            kind = "period_doubling"          # the daughter's branch folds where it is its parent taken twice
        named = [e for r in (i - 1, i) for jj in range(n_att) if int(ds.event.values[r, jj])
                 for e in _named(str(ds.event_link.values[r, jj]), str(ds.event_evidence.values[r, jj]))]
        hit = any(k == kind and lo - TOL_V <= value <= hi + TOL_V for k, lo, hi in named)
        out.append((kind, value, "linked" if hit else f"census attractor {j} at {values[side]:g} V: "
                    + (", ".join(said) or "no event across the step")))
    return out


#: how far [V] a located event may lie from the one the census names (both located by Newton to 1e-8 or better)
TOL_V = 1e-4


def _named(link: str, evidence: str) -> list:
    """The located event a census change is linked to: [(kind, low, high)], a value or a bracket "in V = a to b"
    read from its evidence (none for "global")."""
    bracket = re.search(r"bracketed in V = ([-\d.e+]+) to ([-\d.e+]+)", evidence)
    at = re.search(r"V = ([-\d.e+]+)", evidence)
    if link == "global" or not (bracket or at):
        return []
    return [(link, float(bracket.group(1)), float(bracket.group(2))) if bracket else
            (link, float(at.group(1)), float(at.group(1)))]


#: relative half-period mismatch below which a fold reads as a period-doubling birth: the value the continuation's
#: special-point rule uses (its ``BIRTH_MISMATCH``), restated here so the check reads the branch on its own
BIRTH = 0.3


def _birth(br, point: int, names) -> bool:
    """Whether a fold at branch point ``point`` is a period-2m orbit's birth at a period-m orbit's period doubling:
    its nodes nearly repeat after m periods (each state's largest difference between the two halves, relative to
    that state's largest magnitude on the orbit, below :data:`BIRTH`)."""
    period = int(br.period.values[point])
    if period % 2 or "node" not in br.dims or br.sizes["node"] < period:
        return False
    Y = np.stack([np.asarray(br[n].values, dtype=float)[point, :period] for n in names], axis=-1)  # node, state
    scale = np.abs(Y).max(axis=0)
    scale = np.where(scale > 1e-12 * scale.max(), scale, 1.0)
    return float(np.max(np.abs(Y[:period // 2] - Y[period // 2:]) / scale)) < BIRTH


def same(A, B, rtol=RTOL) -> bool:
    """Whether two orbits' node arrays (period x states) are one orbit at some phase: every node within ``rtol`` of
    each state's scale (its largest magnitude over both orbits, at least 1e-9)."""
    if A.shape != B.shape:
        return False
    tol = rtol * np.maximum(np.max(np.abs(np.vstack([A, B])), axis=0), 1e-9)
    return any(np.all(np.abs(A - np.roll(B, -s, axis=0)) <= tol) for s in range(len(A)))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--n", type=int, default=21)
    ap.add_argument("--starts", type=int, default=200)
    ap.add_argument("--range", type=float, nargs=2, default=(80.0, 220.0), metavar=("LOW", "HIGH"), help="V [V]")
    ap.add_argument("-o", dest="out", help="write the census dataset here (netCDF; its values are kept in "
                    "OUT.parts as they finish, and a stopped run resumes there)")
    ap.add_argument("--census", help="read the census dataset from this file instead of running it")
    ap.add_argument("--branches", help="a thesis-orbits output folder with branches_measured_10Hz_*.nc")
    ap.add_argument("--save-branches", metavar="DIR", help="write the branches continued here to DIR")
    ap.add_argument("--link", action="store_true", help="link the census' changes and count the located folds and "
                    "period doublings linked")
    ap.add_argument("--refine", action="store_true", help="add a census value between each two events the branches "
                    "locate in one step (bifurc.attractors' refine=)")
    a = ap.parse_args(argv)

    import bifurc
    import maps
    sys.path.insert(0, str(ROOT))
    from studies.thesis_orbits import PRESET
    bs = branches(a.branches) if a.refine else None
    clock = time.perf_counter()
    if a.census:
        ds = bifurc.load(a.census)
    else:
        ds = bifurc.attractors("thesis-1dof", "V", np.linspace(*a.range, a.n), preset=PRESET,
                               params={"relay_hz": HZ}, dc_law=LAW, box={"x": (0.0, 0.03), "v": (-1.5, 1.5)},
                               n_starts=a.starts, seed=1, progress=False, link=a.link, path=a.out, refine=bs)
    values = ds["V"].values
    sec = time.perf_counter() - clock
    assert ds.attrs.get("preset") == PRESET, ds.attrs.get("preset")
    n_att = ds.sizes["attractor"] - len(bifurc.Outcome)
    have = {(i, int(ds.period.values[i, j]), int(ds.impacts_per_period.values[i, j]))
            for i in range(len(values)) for j in range(n_att) if ds.present.values[i, j]}
    want = expected(values)
    got = want & have
    if "values_added_at_events" in ds.attrs:
        print(f"values added between events the branches locate in one step: {ds.attrs['values_added_at_events']}")
    print(f"census {len(values)} values x {ds.sizes['start']} starts in {sec:.1f} s ({PRESET}, {LAW}, {HZ:g} Hz; "
          f"{ds.attrs.get('workers')} workers, {ds.attrs.get('periods_per_start_mean', float('nan')):.1f} relay "
          f"periods per start, linking {ds.attrs.get('linking_seconds', 0.0):.1f} s)")
    print(f"by label: stable orbits listed by thesis-orbits at these values: {len(want)}; recovered with the same "
          f"period and impacts: {len(got)} ({100 * len(got) / max(1, len(want)):.0f} %; target 95 %)")
    pb = maps.problem("thesis-1dof", preset=PRESET, params={"relay_hz": HZ, "V": float(values[0])}, dc_law=LAW)
    names = list(pb.system.state_names)
    clock = time.perf_counter()
    bs = bs if bs is not None else branches(a.branches)
    if a.save_branches:
        save_branches(bs, a.save_branches)
    orbits = stable_orbits(bs, values, names, pb)
    n_want = sum(len(o) for o in orbits.values())
    missed, resting = [], []
    x = names.index("x")
    for i, found in orbits.items():
        mine = [_nodes(ds, names, (i, j), int(ds.period.values[i, j])) for j in range(n_att)
                if ds.present.values[i, j] and 0 < ds.period.values[i, j] <= ds.sizes["node"]]
        for p, m, nodes, _ in found:
            if any(same(nodes, c) for c in mine):
                continue
            if m == 0 and any(c.shape == nodes.shape and np.all(c[:, x] <= 0.0) for c in mine):
                resting.append(values[i])
            else:
                missed.append((values[i], p, m))
    n_got = n_want - len(missed) - len(resting)
    print(f"by state: stable orbits on the thesis-orbits branches at these values (Newton at each value, "
          f"{time.perf_counter() - clock:.0f} s): {n_want}; recovered, nodes within {RTOL:g} of scale: {n_got} "
          f"({100 * n_got / max(1, n_want):.0f} %); with the bar at rest on the stop found in contact instead of "
          f"stuck at {len(resting)} values: {n_got + len(resting)} ({100 * (n_got + len(resting)) / max(1, n_want):.0f} "
          f"%; target 95 %)")
    if resting:
        print(STUCK)
    for v, p, m in missed:
        print(f"  missed at V = {v:g}: period-{p} with {m} impacts per period")
    if "event_link" in ds and ds.attrs.get("links", 0):
        got = links(ds, bs, orbits, values, names, n_att)
        n_linked = sum(v == "linked" for _, _, v in got)
        print(f"links: of the {len(got)} folds and period doublings the branches locate inside {values[0]:g}-"
              f"{values[-1]:g} V, {n_linked} linked to the census' appearance or disappearance of the orbit ending there")
        for kind, value, verdict in got:
            if verdict != "linked":
                print(f"  {kind} at {value:.8g} V: {verdict}")


#: why a resting orbit is counted apart
STUCK = ("  (the continuation's resting orbit is the bar stuck on the stop, x = e, v = 0, the stick mode entered where\n"
         "  its contact's speed amplitude falls below stick_speed; the census' starts come to rest on the stop in contact,\n"
         "  x < 0 on the compliant stop, still vibrating with the AC force's ripple above stick_speed, so never stuck:\n"
         "  one physical state, two hybrid states that the stick rule's hysteresis both keeps)")


if __name__ == "__main__":
    main()
