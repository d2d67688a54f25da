"""The census the diagnostics share: thesis-1dof, measured law, 10 Hz, 200 box starts (seed 1) in x = 0-30 mm,
v = -1.5-1.5 m/s, 100 cells per side, default settings; the job warmed (JIT done)."""
import numpy as np

import maps
from bifurc.attractors.census import Settings
from bifurc.attractors.identify import Grid
from bifurc.attractors.job import CensusJob
from bifurc.attractors.starts import make_starts

pb = maps.problem("thesis-1dof", params={"relay_hz": 10.0}, dc_law="measured")
st = make_starts(pb, "box", n=200, box={"x": (0.0, 0.03), "v": (-1.5, 1.5)}, seed=1)
starts = np.asarray(st.points, dtype=float)
grid = Grid.over(st.box, pb.system, 100, pb.state_vector())
job = CensusJob(pb, (), starts, grid, Settings())
job.warm()
