"""How reproducible a chaotic set's verdict is (issue 31, grid independence): the census of thesis-1dof (`measured`
law, 10 Hz, the 200 box starts of `benchmarks/attractors.py`) at one value; each new non-periodic set's lifetime is
estimated again from the same record with other perturbation seeds (:func:`bifurc.attractors.lifetime.
estimate_lifetime`), and each estimate's verdict printed.  Not run in CI.

    python benchmarks/internal/attractors_lifetime.py 185 [--seeds 10] [--cells 100] [--copies 48]
"""
from __future__ import annotations

import argparse

import numpy as np


def main(argv=None):
    import maps
    from bifurc.attractors import census as C
    from bifurc.attractors.identify import Grid
    from bifurc.attractors.lifetime import estimate_lifetime
    from bifurc.attractors.starts import make_starts
    from maps.poincare import StroboscopicMap
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("value", type=float)
    ap.add_argument("--seeds", type=int, default=10)
    ap.add_argument("--cells", type=int, default=100)
    ap.add_argument("--copies", type=int, default=None, help="copies per estimate (default the census')")
    a = ap.parse_args(argv)
    pb = maps.problem("thesis-1dof", params={"relay_hz": 10.0}, dc_law="measured")
    st = make_starts(pb, "box", n=200, box={"x": (0.0, 0.03), "v": (-1.5, 1.5)}, seed=1)
    smap = StroboscopicMap(pb, tol=1e-10)
    smap = smap.at(dict(V=a.value))
    kw = {} if a.copies is None else {"copies": a.copies}
    census_persists = C._persists

    def again(smap, record, k0, s):
        got = estimate_lifetime(smap, record, k0, s.persist, max_period=s.max_period, **kw) if kw \
            else census_persists(smap, record, k0, s)
        print(f"V = {a.value:g}, the census' estimate: {got.text()}: {got.verdict(s.persist)}", flush=True)
        for seed in range(1, a.seeds + 1):
            g = estimate_lifetime(smap, record, k0, s.persist, max_period=s.max_period, seed=seed, **kw)
            print(f"  seed {seed}: {g.text()}: {g.verdict(s.persist)}", flush=True)
        return got
    C._persists = again
    C.census_at(smap, list(np.asarray(st.points, float)), Grid.over(st.box, pb.system, a.cells, pb.state_vector()),
                C.Settings())


if __name__ == "__main__":
    main()
