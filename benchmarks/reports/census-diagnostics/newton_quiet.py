import sys, time, numpy as np, collections
import maps
from bifurc.attractors import identify, census
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
stat = collections.Counter()
orig = census.from_chunk
def fc(*a, **k):
    t = sys._getframe(1).f_locals['t']
    quiet = t.periods < t.quiet_until
    c = time.process_time()
    r = orig(*a, **k)
    key = ("quiet" if quiet else "normal", "tries>0" if t.tries else "tries=0", "found" if r is not None else "none")
    stat[key + ("n",)] += 1
    stat[key + ("s",)] += time.process_time() - c
    return r
census.from_chunk = fc
nrec = collections.Counter()
origr = census._record_and_classify
def rc(smap, tracks, rest, *a):
    nrec['records'] += len(rest)
    nrec['calls'] += 1
    return origr(smap, tracks, rest, *a)
census._record_and_classify = rc
for v in map(float, sys.argv[1:]):
    stat.clear(); nrec.clear()
    job(v)
    print(v, dict(nrec))
    for k in sorted({k[:3] for k in stat}):
        print("   ", k, stat[k + ("n",)], round(stat[k + ("s",)], 2))
