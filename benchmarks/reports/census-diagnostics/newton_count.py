import sys, time
sys.argv=[sys.argv[0]]
from bifurc.attractors import identify
from bifurc.attractors.identify import same_orbit
from _census_setup import job
log=[]
orig=identify._polish
def pol(smap, orbit, k0, n, grid, *a):
    t=time.process_time()
    r=orig(smap, orbit, k0, n, grid, *a)
    log.append((n, r, time.process_time()-t, sys._getframe(2).f_code.co_name))
    return r
identify._polish=pol
for v in (122,136,192,206):
    log.clear()
    r = job.census({"V": float(v)})
    ok=[x for x in log if x[1] is not None]
    orbs=[]
    for x in ok:
        if not any(same_orbit(x[1], o, 1) for o in orbs): orbs.append(x[1])
    by={}
    for n,res,dt,caller in log:
        k=(caller, n, res is not None); by.setdefault(k,[0,0.0]); by[k][0]+=1; by[k][1]+=dt
    print(v, "calls", len(log), "ok", len(ok), "distinct", len(orbs), "time", round(sum(x[2] for x in log),2))
    for k in sorted(by): print("   ", k, by[k][0], round(by[k][1],2))
