import sys, time, numpy as np
from maps import StroboscopicMap
from _census_setup import job, pb, starts
S = list(starts)
smap = StroboscopicMap(pb, tol=1e-10); smap.orbits([{}], [S[0]], 1, batch_size=4, events=False)
for v in map(float, sys.argv[1:]):
    r = job.census({"V": float(v)})
    spent = [max(1, int(p)) for p in r.spent]
    smap = smap.at(dict(V=v))
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
