"""The fresh-start census at the values where the 281 x 1000 census of b75bcd9 left most starts not_converged
(thesis-1dof, `matlab-listing`, `measured`, 10 Hz; 1000 box starts x=0:0.03, v=-1.5:1.5, seed 1; 100 cells per side;
no seeding from neighbouring values): each start's outcome counted by label, the census' CPU time, in one process.
Run from a checkout's root (PYTHONPATH=. python benchmarks/reports/attractors-recovery/undecided.py [V ...]) at two
commits to compare them."""
import collections
import sys
import time

import numpy as np

import maps
from bifurc.attractors.census import Memory, Settings, census_at, outcome_labels
from bifurc.attractors.identify import Grid
from bifurc.attractors.starts import make_starts
from maps.poincare import StroboscopicMap
try:
    from maps.provenance import code_version
except ImportError:                # before f537126
    from maps.provenance import git_commit

    def code_version():
        return f"git {git_commit()}"

MODEL = dict(preset="matlab-listing", params={"relay_hz": 10.0}, dc_law="measured")
BOX = {"x": (0.0, 0.03), "v": (-1.5, 1.5)}


def main(values):
    pb = maps.problem("thesis-1dof", **MODEL)
    st = make_starts(pb, "box", n=1000, box=BOX, seed=1)
    grid = Grid.over(st.box, pb.system, 100, pb.state_vector())
    smap = StroboscopicMap(pb, tol=1e-10)
    print(f"# {code_version()}")
    for v in values:
        smap = smap.at(dict(V=v))
        t = time.process_time()
        out, found, spent = census_at(smap, list(np.asarray(st.points, dtype=float)), grid, Settings(),
                                      memory=Memory())
        counts = collections.Counter(outcome_labels(out, found))
        print(f"{v:g} V: {time.process_time() - t:.1f} s CPU, {np.mean(spent):.1f} periods per start; "
              + ", ".join(f"{k} {n}" for k, n in counts.most_common()), flush=True)
        for a in found:
            if not a.periodic:
                lo, hi = a.lyapunov_interval
                print(f"   {a.label()}: exponent {a.lyapunov:.4f} [{lo:.4f}, {hi:.4f}] per relay period; {a.how}")


if __name__ == "__main__":
    main([float(v) for v in sys.argv[1:]] or [99.5, 136.0, 179.5, 211.5])
