import sys, time, numpy as np
from bifurc.attractors import identify
from _census_setup import job
rows = []
orig = identify._polish
def pol(smap, orbit, k0, n, g, *a):
    t = time.process_time()
    r = orig(smap, orbit, k0, n, g, *a)
    P = g.scaled(orbit.points)
    e = np.max(np.abs(P[n:] - P[:-n])[:, np.isfinite(g.width)], axis=1)
    first, last = e[:n].max(), e[-n:].max()
    rows.append((n, r is not None, last / max(first, 1e-300), last, time.process_time() - t))
    return r
identify._polish = pol
for v in map(float, sys.argv[1:]):
    rows.clear()
    job.census({"V": float(v)})
    print(v)
    for ok in (True, False):
        sel = [x for x in rows if x[1] == ok]
        if sel:
            r = np.array([x[2] for x in sel]); tm = sum(x[4] for x in sel)
            print(f"  ok={ok}: {len(sel)} calls {tm:.2f} s; last/first mismatch quantiles "
                  f"{np.round(np.quantile(r, [0, .1, .25, .5, .75, .9, 1]), 4).tolist()}; "
                  f"n(last<first/2)={int((r < .5).sum())} n(last<first)={int((r < 1).sum())}")
    print("   ok rows:", [(x[0], round(x[2], 4), float('%.2g' % x[3])) for x in rows if x[1]])
