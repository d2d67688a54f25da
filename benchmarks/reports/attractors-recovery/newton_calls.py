"""Newton calls in the census at a few values (thesis-1dof, `matlab-listing`, `measured`, 10 Hz, N box starts
x=0:0.03, v=-1.5:1.5, seed 1, 100 cells per side, fresh starts only): the outcomes by label, then each kind of Newton
run (converged on a stable or an unstable orbit; failed, by the first words of its reason) with its count, CPU
seconds and iteration counts (failures: -1).  Run from a checkout's root at two commits to compare them:
PYTHONPATH=. python benchmarks/reports/attractors-recovery/newton_calls.py N V [V ...]"""
import collections
import sys
import time

import numpy as np

import maps
import bifurc.attractors.identify as I
from bifurc.attractors.census import Memory, Settings, census_at, outcome_labels
from bifurc.attractors.identify import Grid
from bifurc.attractors.starts import make_starts
from bifurc.orbits.periodic import OrbitNotFound
from maps.poincare import StroboscopicMap
MODEL = dict(preset="matlab-listing", params={"relay_hz": 10.0}, dc_law="measured")
BOX = {"x": (0.0, 0.03), "v": (-1.5, 1.5)}
calls = []
orig = I.find_periodic_orbit
def wrapped(*a, **k):
    c = time.process_time()
    try:
        po = orig(*a, **k)
        calls.append(("ok-stable" if po.stable else "ok-unstable", po.iterations, time.process_time() - c, a[2]))
        return po
    except OrbitNotFound as e:
        calls.append(("fail:" + str(e)[:40], -1, time.process_time() - c, a[2]))
        raise
I.find_periodic_orbit = wrapped
try:
    from maps.provenance import code_version
except ImportError:
    code_version = None
pb = maps.problem("thesis-1dof", **MODEL)
smap = StroboscopicMap(pb, tol=1e-10)
n = int(sys.argv[1])
vals = [float(v) for v in sys.argv[2:]]
print(f"# {code_version() if code_version else ''}")
for V in vals:
    calls.clear()
    smap = smap.at(dict(V=V))
    st = make_starts(pb, "box", n=n, box=BOX, seed=1)
    grid = Grid.over(st.box, pb.system, 100, pb.state_vector())
    c = time.process_time()
    out, found, periods = census_at(smap, list(np.asarray(st.points, dtype=float)), grid, Settings(), memory=Memory())
    tot = time.process_time() - c
    agg = collections.defaultdict(lambda: [0, 0.0, []])
    for what, it, t, per in calls:
        key = what if what.startswith("ok") else what.split(";")[0][:45]
        agg[key][0] += 1; agg[key][1] += t; agg[key][2].append(it)
    print(sorted(collections.Counter(outcome_labels(out, found)).items()))
    print(f"{V} V: census {tot:.1f} s CPU; Newton {sum(c[2] for c in calls):.1f} s in {len(calls)} calls")
    for k, (cnt, t, its) in sorted(agg.items(), key=lambda x: -x[1][1]):
        print(f"   {k:45s} {cnt:4d} calls {t:6.2f} s  iterations {collections.Counter(its).most_common(6)}")
