import sys, time, numpy as np
import maps
from bifurc.attractors.census import Settings
from bifurc.attractors.identify import Grid
from bifurc.attractors.job import CensusJob
from bifurc.attractors.starts import make_starts
from maps.poincare import StroboscopicMap
pb = maps.problem("thesis-1dof", params={"relay_hz": 10.0}, dc_law="measured")
st = make_starts(pb, "box", n=200, box={"x": (0.0, 0.03), "v": (-1.5, 1.5)}, seed=1)
S = list(np.asarray(st.points, dtype=float))
grid = Grid.over(st.box, pb.system, 100, pb.state_vector())
job = CensusJob(pb, "V", np.asarray(S), grid, Settings()); job.warm()
smap = StroboscopicMap(pb, tol=1e-10); smap.orbits([{}], [S[0]], 1, batch_size=4, events=False)
for v in map(float, sys.argv[1:]):
    r = job(v)
    spent = [max(1, int(p)) for p in r.spent]
    smap.set_params(V=v)
    c = time.process_time()
    smap.orbits([{}] * 200, S, spent, batch_size=4, events=False)
    bare = time.process_time() - c
    c = time.process_time()
    state, k, act = list(S), [0] * 200, list(range(200))
    while act:
        n = [min(40, spent[i] - k[i]) for i in act]
        os_ = smap.orbits([{}] * len(act), [state[i] for i in act], n, k0=[k[i] for i in act], batch_size=4, events=False)
        for i, o, m in zip(act, os_, n):
            state[i], k[i] = o.final, k[i] + m
        act = [i for i in act if k[i] < spent[i]]
    chunked = time.process_time() - c
    print(f"{v:g} V: bare {bare:.2f} s, chunked 40 {chunked:.2f} s, ratio {chunked / bare:.2f}, mean spent {np.mean(spent):.0f}")
