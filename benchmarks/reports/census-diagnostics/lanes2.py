import time, numpy as np, maps
from maps import StroboscopicMap
from bifurc.attractors.starts import make_starts
pb = maps.problem("thesis-1dof", params={"relay_hz": 10.0}, dc_law="measured")
st = make_starts(pb, "box", n=40, box={"x": (0.0, 0.03), "v": (-1.5, 1.5)}, seed=1)
S = list(np.asarray(st.points, dtype=float))
smap = StroboscopicMap(pb, tol=1e-10)
for V in (171.0, 213.0):
    smap = smap.at(dict(V=V))
    pre = smap.orbits([{}] * 40, S, 300, batch_size=4, events=False)
    # starts still aperiodic after 300 periods (spread of the last 64 points)
    ch = [o.final for o in pre if np.ptp(o.points[-64:, 0]) > 1e-4][:4]
    print(V, "aperiodic after 300:", len(ch))
    for m in (1, 2, 4):
        c = time.process_time()
        smap.orbits([{}] * m, ch[:m], 1000, k0=300, batch_size=4, events=False)
        print(f"   {m} lanes x 1000 periods: {time.process_time() - c:.3f} s CPU")
