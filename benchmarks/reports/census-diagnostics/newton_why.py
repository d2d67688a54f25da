import sys, time, numpy as np, collections
import maps
from bifurc.attractors import identify
from bifurc.attractors.census import Settings
from bifurc.attractors.identify import Grid
from bifurc.attractors.job import CensusJob
from bifurc.attractors.starts import make_starts
pb = maps.problem("thesis-1dof", params={"relay_hz": 10.0}, dc_law="measured")
st = make_starts(pb, "box", n=200, box={"x": (0.0, 0.03), "v": (-1.5, 1.5)}, seed=1)
starts = np.asarray(st.points, dtype=float)
grid = Grid.over(st.box, pb.system, 100, pb.state_vector())
job = CensusJob(pb, "V", starts, grid, Settings())
job.warm()
why = collections.Counter(); tm = collections.Counter()
orig = identify.find_periodic_orbit
def fpo(*a, **k):
    t = time.process_time()
    try:
        po = orig(*a, **k)
        r = "converged stable" if po.stable else f"converged unstable"
        return po
    except Exception as e:
        r = type(e).__name__ + ": " + str(e).split(";")[0][:60]
        r = r.split(" at iteration")[0].split(" after")[0]
        raise
    finally:
        why[r] += 1; tm[r] += time.process_time() - t
identify.find_periodic_orbit = fpo
for v in map(float, sys.argv[1:]):
    why.clear(); tm.clear()
    job(v)
    print(v)
    for r, c in why.most_common(): print(f"   {c:4d} {tm[r]:6.2f} s  {r}")
