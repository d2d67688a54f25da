import sys, time, collections
from bifurc.attractors import identify
from _census_setup import job
why = collections.Counter(); tm = collections.Counter()
orig = identify.find_periodic_orbit
def fpo(*a, **k):
    t = time.process_time()
    try:
        po = orig(*a, **k)
        r = "converged stable" if po.stable else "converged unstable"
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
    job.census({"V": float(v)})
    print(v)
    for r, c in why.most_common(): print(f"   {c:4d} {tm[r]:6.2f} s  {r}")
