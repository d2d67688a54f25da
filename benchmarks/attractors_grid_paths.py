"""Whether the attractor census gives each start the same outcome on two grids (issue 31, section 5); not CI.

    python benchmarks/attractors_grid_paths.py [V ...] [--starts 200] [--cells 100 200]

For each value (default 115 122 136 164 171 199 213 V; thesis-1dof as benchmarks/attractors.py runs it: `matlab-listing`,
`measured` law, 10 Hz, box x=0:0.03, v=-1.5:1.5, seed 1) the census of the same box starts on grids of 100 and 200 cells
per side (one process, no seeding from neighbouring values), start by start: the starts whose outcome (an attractor's
label, or the outcome's name) differs, with the periods each ran and the periods at which it was recorded (a record
runs beside the start's path since 31a2bd1; before, it became the path).  A start's path is its chunks of 40 relay
periods whatever the census decides, so a difference is a decision of the census that hangs on the grid.
"""
from __future__ import annotations

import argparse
import time

import numpy as np


def census(pb, starts, box, cells, value):
    """(labels, periods, record ages per start) of the census of ``starts`` at ``value`` on ``cells`` per side."""
    from bifurc.attractors import census as C
    from bifurc.attractors.census import OUTCOMES, Settings, census_at
    from bifurc.attractors.identify import Grid
    from maps.poincare import StroboscopicMap
    smap = StroboscopicMap(pb, tol=1e-10)
    smap.set_params(V=float(value))
    ages: dict = {}
    plain = C._record_and_classify

    def logged(smap_, tracks, rest, *args):
        for i in rest:
            ages.setdefault(id(tracks[i]), []).append(tracks[i].periods)
        return plain(smap_, tracks, rest, *args)
    made: list = []
    plain_track = C.Track

    class Seen(plain_track):
        def __init__(self, *args, **kw):
            super().__init__(*args, **kw)
            made.append(self)
    C._record_and_classify, C.Track = logged, Seen
    try:
        out, found, spent = census_at(smap, starts, Grid.over(box, pb.system, cells, pb.state_vector()), Settings())
    finally:
        C._record_and_classify, C.Track = plain, plain_track
    names = {k: n for n, k in OUTCOMES.items()}
    labels = [names[o] if o < 0 else found[o].label() for o in out]
    return labels, spent, [ages.get(id(t), []) for t in made]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("values", nargs="*", type=float, default=[115.0, 122.0, 136.0, 164.0, 171.0, 199.0, 213.0])
    ap.add_argument("--starts", type=int, default=200)
    ap.add_argument("--cells", type=int, nargs=2, default=(100, 200))
    a = ap.parse_args(argv)
    import maps
    from attractors import BOX, MODEL
    from bifurc.attractors.starts import make_starts
    pb = maps.problem("thesis-1dof", **MODEL)
    st = make_starts(pb, "box", n=a.starts, box=BOX, seed=1)
    starts = list(np.asarray(st.points, dtype=float))
    for v in a.values:
        clock = time.perf_counter()
        one, two = (census(pb, starts, st.box, c, v) for c in a.cells)
        differ = [i for i in range(len(starts)) if one[0][i] != two[0][i]]
        print(f"{v:g} V: {len(differ)} of {len(starts)} starts differ between {a.cells[0]} and {a.cells[1]} cells per "
              f"side ({time.perf_counter() - clock:.0f} s)", flush=True)
        for i in differ:
            print(f"   start {i}: {one[0][i]} after {one[1][i]} periods, recorded at {one[2][i]} | {two[0][i]} after "
                  f"{two[1][i]} periods, recorded at {two[2][i]}", flush=True)


if __name__ == "__main__":
    main()
