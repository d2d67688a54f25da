import sys, collections
from bifurc.attractors import census
from bifurc.attractors.identify import near_periods, contracting
from bifurc.labels.classify import candidate_periods
from _census_setup import job
stat = collections.Counter()
orig = census.identify
def ident(smap, o, k, g, **kw):
    f = sys._getframe(1).f_locals
    t, mem = f['t'], f['mem']
    cells = {c for c in t.last_keys if c is not None}
    sad = any(sd.cells & cells for sd in mem.saddles)
    near = near_periods(t.last.points, g, candidate_periods(1, 16))[:2]
    con = any(contracting(t.last.points, g, n) for n in near)
    a = orig(smap, o, k, g, **kw)
    res = "none" if a is None else ("periodic" if a.periodic else "nonperiodic")
    stat[("near" if near else "far", "saddle" if sad else "-", "contracting" if con else "-", res)] += 1
    return a
census.identify = ident
for v in map(float, sys.argv[1:]):
    stat.clear()
    job.census({"V": float(v)})
    print(v)
    for k, c in sorted(stat.items()): print("   ", k, c)
