"""Where the census' starts really settle: each of the 200 starts of `benchmarks/attractors.py` (thesis-1dof,
`measured` law, 10 Hz, box x=0:0.03, v=-1.5:1.5, seed 1) run for a long time, against the census' fractions at
100 and 200 cells per side (issue 31's grid independence; not run in CI).

    python benchmarks/internal/attractors_truth.py 122 143 [--periods 3000]

Each start runs ``--periods`` relay periods on the batch engine (strobe points only), then 64 more with events;
it has settled on a period n (the least n <= 16) where its last 64 points repeat after n periods to 1e-5 of each
state's scale, with the impacts of its last n periods; else it is still aperiodic (chaotic or a slow transient).
The census at the same value (fresh starts only, one process) is printed beside, by label.
"""
from __future__ import annotations

import argparse
import time
from collections import Counter

import numpy as np


def settled(v: float, periods: int):
    """Counter of (period, impacts per period) after ``periods`` (period 0: aperiodic), and the seconds taken."""
    import maps
    from bifurc.attractors.lifetime import periodic_tail as _periodic_tail
    from bifurc.attractors.starts import make_starts
    from maps.poincare import StroboscopicMap
    pb = maps.problem("thesis-1dof", params={"relay_hz": 10.0}, dc_law="measured")
    st = make_starts(pb, "box", n=200, box={"x": (0.0, 0.03), "v": (-1.5, 1.5)}, seed=1)
    smap = StroboscopicMap(pb, tol=1e-10)
    smap = smap.at(dict(V=v))
    clock = time.perf_counter()
    first = smap.orbits([{}] * 200, list(np.asarray(st.points, float)), periods, batch_size=4, events=False)
    tail = smap.orbits([{}] * 200, [o.final for o in first], 64, k0=periods, batch_size=4, events=True)
    out = Counter()
    for o in tail:
        n = next((n for n in range(1, 17) if _periodic_tail(o.points, [n], rtol=1e-5)), 0)
        out[(n, int(o.impacts_per_step[-n:].sum()) if n else -1)] += 1
    return out, time.perf_counter() - clock


def census_labels(v: float, cells: int) -> tuple[Counter, list]:
    """The census' count by label at ``v`` on ``cells`` per side, and how each non-periodic set was judged (its
    mean lifetime; the saddles and long-lived transients, whose starts ran on, too)."""
    import maps
    from bifurc.attractors.census import Memory, Settings, census_at, outcome_labels
    from bifurc.attractors.identify import Grid
    from bifurc.attractors.starts import make_starts
    from maps.poincare import StroboscopicMap
    pb = maps.problem("thesis-1dof", params={"relay_hz": 10.0}, dc_law="measured")
    st = make_starts(pb, "box", n=200, box={"x": (0.0, 0.03), "v": (-1.5, 1.5)}, seed=1)
    smap = StroboscopicMap(pb, tol=1e-10)
    smap = smap.at(dict(V=v))
    mem = Memory()
    out, found, _ = census_at(smap, list(np.asarray(st.points, float)), Grid.over(st.box, pb.system, cells,
                                                                                 pb.state_vector()), Settings(),
                              memory=mem)
    sets = [a.how for a in found if not a.periodic] + [a.how for a in mem.saddles]
    return Counter(outcome_labels(out, found)), sets


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("values", type=float, nargs="+")
    ap.add_argument("--periods", type=int, default=3000)
    a = ap.parse_args(argv)
    for v in a.values:
        got, sec = settled(v, a.periods)
        text = ", ".join(f"{'aperiodic' if n == 0 else f'{n}:{m}'} {k}" for (n, m), k in sorted(got.items()))
        print(f"V = {v:g}: after {a.periods} periods ({sec:.0f} s): {text}")
        for cells in (100, 200):
            c, sets = census_labels(v, cells)
            print(f"  census, {cells} cells per side: " + ", ".join(f"{lab} {k}" for lab, k in sorted(c.items())))
            for how in sets:
                print(f"    non-periodic set: {how}")


if __name__ == "__main__":
    main()
