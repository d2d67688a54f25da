"""The census the diagnoses here share: benchmarks/attractors.py's model (thesis-1dof, `matlab-listing`, `measured`
law, 10 Hz), its box starts (seed 1), the recurrence grid over the box and the map, built from the census' internals
as these scripts follow its private steps."""
from __future__ import annotations

import os
import sys

import numpy as np


def box_census(n: int = 200, cells: int = 100):
    """(problem, the ``n`` starts as a list of state arrays, the grid of ``cells`` per box side, the map at tol 1e-10)."""
    import maps
    from bifurc.attractors.identify import Grid
    from bifurc.attractors.starts import make_starts
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))      # benchmarks/
    from attractors import BOX, MODEL
    pb = maps.problem("thesis-1dof", **MODEL)
    st = make_starts(pb, "box", n=n, box=BOX, seed=1)
    grid = Grid.over(st.box, pb.system, cells, pb.state_vector())
    return pb, list(np.asarray(st.points, dtype=float)), grid, maps.StroboscopicMap(pb, tol=1e-10)
