"""Which starts the grid changes, and where they really settle (issue 31, grid independence): the census of
thesis-1dof (`measured` law, 10 Hz, the 200 box starts of `benchmarks/attractors.py`) at one value on 100 and on
200 cells per side; each start whose outcome differs is then run ``--periods`` relay periods in one batch call
(strobe points only) and judged by a tolerance of the states (period n <= 16 to 1e-5 over its last 64 points,
and the first period from which it repeats).  Not run in CI.

    python benchmarks/attractors_grid_diff.py 136 [--periods 4000]
"""
from __future__ import annotations

import argparse

import numpy as np


def main(argv=None):
    import maps
    from bifurc.attractors.census import OUTCOMES, Settings, census_at
    from bifurc.attractors.identify import Grid
    from bifurc.attractors.lifetime import fall_index, periodic_tail
    from bifurc.attractors.starts import make_starts
    from maps.poincare import StroboscopicMap
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("value", type=float)
    ap.add_argument("--periods", type=int, default=4000)
    a = ap.parse_args(argv)
    pb = maps.problem("thesis-1dof", params={"relay_hz": 10.0}, dc_law="measured")
    st = make_starts(pb, "box", n=200, box={"x": (0.0, 0.03), "v": (-1.5, 1.5)}, seed=1)
    smap = StroboscopicMap(pb, tol=1e-10)
    smap.set_params(V=a.value)
    names = {k: n for n, k in OUTCOMES.items()}
    got = {}
    for cells in (100, 200):
        out, found, spent = census_at(smap, list(np.asarray(st.points, float)),
                                      Grid.over(st.box, pb.system, cells, pb.state_vector()), Settings())
        got[cells] = ([names[o] if o < 0 else found[o].label() for o in out], spent)
    diff = [i for i in range(len(st)) if got[100][0][i] != got[200][0][i]]
    print(f"V = {a.value:g}: {len(diff)} of {len(st)} starts differ between 100 and 200 cells")
    runs = smap.orbits([{}] * len(diff), list(np.asarray(st.points, float)[diff]), a.periods, batch_size=4,
                       events=False)
    for i, o in zip(diff, runs):
        n = next((n for n in range(1, 17) if periodic_tail(o.points[-64:], [n], rtol=1e-5)), 0)
        when = fall_index(o.points, list(range(1, 17)), 64, rtol=1e-5) if n else None
        print(f"  start {i}: 100 cells {got[100][0][i]} after {got[100][1][i]} periods; 200 cells {got[200][0][i]} "
              f"after {got[200][1][i]}; run {a.periods} periods: " +
              (f"period {n} from period {when}" if n else "aperiodic"))


if __name__ == "__main__":
    main()
