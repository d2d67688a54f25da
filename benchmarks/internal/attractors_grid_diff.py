"""Which starts the grid changes, and where they really settle (issue 31, grid independence): the census of
thesis-1dof (the model of `benchmarks/attractors.py`: `matlab-listing`, `measured` law, 10 Hz; its 200 box starts,
seed 1) at each value on 100 and on 200 cells per side, start by start (one process, no seeding from neighbouring
values).  Each start whose outcome (an attractor's label, or the outcome's name) differs is printed with the periods it
ran and the ages at which it was recorded on each grid (a record runs beside the start's path since 31a2bd1; before,
it became the path), then run ``--periods`` relay periods in one batch call (strobe points only) and judged by a
tolerance of the states (period n <= 16 to 1e-5 over its last 64 points, and the first period from which it
repeats).  Not run in CI.  Until 2026-11-26 20:20 it ran one value under the scene's default preset (`thesis-text`).

    python benchmarks/internal/attractors_grid_diff.py [V ...] [--periods 4000]   # default 115 122 136 164 171 199 213 V
"""
from __future__ import annotations

import argparse
import os
import sys
import time

import numpy as np


def census(smap, pb, starts, box, cells) -> tuple[list, list, list]:
    """(outcome in words, periods run, ages at its records) per start of the census at ``smap``'s value."""
    from bifurc.attractors import census as C
    from bifurc.attractors.identify import Grid
    ages: dict = {}
    plain, plain_track, made = C._record_and_classify, C.Track, []

    def logged(smap_, tracks, rest, *args):
        for i in rest:
            ages.setdefault(id(tracks[i]), []).append(tracks[i].periods)
        return plain(smap_, tracks, rest, *args)

    class Seen(plain_track):
        def __init__(self, *args, **kw):
            super().__init__(*args, **kw)
            made.append(self)
    C._record_and_classify, C.Track = logged, Seen
    try:
        out, found, spent = C.census_at(smap, starts, Grid.over(box, pb.system, cells, pb.state_vector()),
                                        C.Settings())
    finally:
        C._record_and_classify, C.Track = plain, plain_track
    return C.outcome_labels(out, found), spent, [ages.get(id(t), []) for t in made]


def main(argv=None):
    import maps
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))  # benchmarks/
    from attractors import BOX, MODEL
    from bifurc.attractors.lifetime import fall_index, periodic_tail
    from bifurc.attractors.starts import make_starts
    from maps.poincare import StroboscopicMap
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("values", nargs="*", type=float, default=[115.0, 122.0, 136.0, 164.0, 171.0, 199.0, 213.0])
    ap.add_argument("--periods", type=int, default=4000)
    a = ap.parse_args(argv)
    pb = maps.problem("thesis-1dof", **MODEL)
    st = make_starts(pb, "box", n=200, box=BOX, seed=1)
    starts = list(np.asarray(st.points, float))
    smap = StroboscopicMap(pb, tol=1e-10)
    for v in a.values:
        smap = smap.at(dict(V=v))
        clock = time.perf_counter()
        got = {cells: census(smap, pb, starts, st.box, cells) for cells in (100, 200)}
        diff = [i for i in range(len(starts)) if got[100][0][i] != got[200][0][i]]
        print(f"V = {v:g}: {len(diff)} of {len(starts)} starts differ between 100 and 200 cells "
              f"({time.perf_counter() - clock:.0f} s)", flush=True)
        if not diff:
            continue
        runs = smap.orbits([{}] * len(diff), [starts[i] for i in diff], a.periods, batch_size=4, events=False)
        for i, o in zip(diff, runs):
            n = next((n for n in range(1, 17) if periodic_tail(o.points[-64:], [n], rtol=1e-5)), 0)
            when = fall_index(o.points, list(range(1, 17)), 64, rtol=1e-5) if n else None
            print(f"  start {i}: 100 cells {got[100][0][i]} after {got[100][1][i]} periods (records at "
                  f"{got[100][2][i]}); 200 cells {got[200][0][i]} after {got[200][1][i]} (records at {got[200][2][i]}); "
                  f"run {a.periods} periods: " + (f"period {n} from period {when}" if n else "aperiodic"), flush=True)


if __name__ == "__main__":
    main()
