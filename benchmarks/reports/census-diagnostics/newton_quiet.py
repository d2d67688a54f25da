import sys, time, collections
from bifurc.attractors import census
from _census_setup import job
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
    job.census({"V": float(v)})
    print(v, dict(nrec))
    for k in sorted({k[:3] for k in stat}):
        print("   ", k, stat[k + ("n",)], round(stat[k + ("s",)], 2))
