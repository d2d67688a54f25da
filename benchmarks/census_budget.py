"""The census' budget and period search, and the one judge, measured start by start (issue 45 section 2).

    python benchmarks/census_budget.py --values 6 --starts 100 [--old OLD_CHECKOUT]

For each value of thesis-1dof (`matlab-listing`, `measured` law, 10 Hz, V in 80-220 V, box x=0:0.03,
v=-1.5:1.5: benchmarks/attractors.py's census) the census of one value's starts (``census_at``, one process) runs
in fresh processes, interleaved value by value, under each configuration: this checkout with (budget, max_period) =
(2000, 16), (2000, 100), (6000, 100), and with --old the old checkout at (2000, 16).  Prints each configuration's wall
and CPU seconds (summed over the values) and, against a reference configuration, how many starts changed outcome
(an attractor by its class, period and impacts; the other outcomes by name).
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time

CHILD = r"""
import json, sys, time, numpy as np
import maps
from bifurc.attractors.census import Settings, census_at
from bifurc.attractors.identify import Grid
from bifurc.attractors.starts import make_starts
from bifurc.labels.classify import describe
from bifurc.labels.codes import OUTCOMES
from maps.poincare import StroboscopicMap
volts, n, budget, max_period = float(sys.argv[1]), int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4])
BOX = {"x": (0.0, 0.03), "v": (-1.5, 1.5)}
pb = maps.problem("thesis-1dof", preset="matlab-listing", params={"relay_hz": 10.0}, dc_law="measured")
st = make_starts(pb, "box", n=n, box=BOX, seed=1)
grid = Grid.over(st.box, pb.system, 100, pb.state_vector())
smap = StroboscopicMap(pb, tol=1e-10)
smap.set_params(V=volts)
smap.orbits([{}], [np.asarray(st.points[0], float)], 1, batch_size=4, events=False)     # compiled before the clock
names = {v: k for k, v in OUTCOMES.items()}
t, c = time.perf_counter(), time.process_time()
out, found, spent = census_at(smap, [np.asarray(p, float) for p in st.points], grid,
                              Settings(max_periods=budget, max_period=max_period), k0=0)
wall, cpu = time.perf_counter() - t, time.process_time() - c
labels = [describe(found[o].code, found[o].period, found[o].impacts) if o >= 0 else names[o] for o in out]
print(json.dumps({"wall": wall, "cpu": cpu, "labels": labels, "periods": float(np.mean(spent))}))
"""


def run(checkout: str, volts: float, n: int, budget: int, max_period: int) -> dict:
    env = dict(os.environ, PYTHONPATH=checkout, MPLBACKEND="Agg")
    out = subprocess.run([sys.executable, "-c", CHILD, str(volts), str(n), str(budget), str(max_period)], cwd=checkout,
                         env=env, capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def main(argv=None) -> None:
    import numpy as np
    ap = argparse.ArgumentParser()
    ap.add_argument("--values", type=int, default=6)
    ap.add_argument("--starts", type=int, default=100)
    ap.add_argument("--old", default=None, help="an old checkout, run at (2000, 16)")
    a = ap.parse_args(argv)
    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    configs = [("new 2000/16", here, 2000, 16), ("new 2000/100", here, 2000, 100), ("new 6000/100", here, 6000, 100)]
    if a.old:
        configs.insert(0, ("old 2000/16", a.old, 2000, 16))
    res = {c[0]: [] for c in configs}
    print(f"load before: {os.getloadavg()}", flush=True)
    for i, v in enumerate(np.linspace(80, 220, a.values)):
        order = configs if i % 2 == 0 else configs[::-1]       # alternate the order: a burst of load falls on all
        for name, where, budget, mp in order:
            r = run(where, float(v), a.starts, budget, mp)
            res[name].append((float(v), r))
            print(f"{v:7.2f} V {name:14s} wall {r['wall']:7.1f} s cpu {r['cpu']:7.1f} s mean periods {r['periods']:7.0f}"
                  f"  load {os.getloadavg()[0]:.1f}", flush=True)
    print("\nconfiguration: wall, CPU seconds summed over the values")
    for name, rows in res.items():
        print(f"  {name:14s} {sum(r['wall'] for _, r in rows):8.1f} {sum(r['cpu'] for _, r in rows):8.1f}")
    pairs = [("new 2000/16", "new 2000/100"), ("new 2000/100", "new 6000/100")]
    if a.old:
        pairs.insert(0, ("old 2000/16", "new 2000/16"))
    for ref, other in pairs:
        moved = []
        for (v, r0), (_, r1) in zip(res[ref], res[other]):
            diff = [(x, y) for x, y in zip(r0["labels"], r1["labels"]) if x != y]
            moved.append((v, len(diff), sorted({f"{x} -> {y}" for x, y in diff})))
        total = sum(m[1] for m in moved)
        print(f"\n{ref} -> {other}: {total} of {a.values * a.starts} starts changed outcome")
        for v, k, what in moved:
            if k:
                print(f"  {v:7.2f} V: {k}: {'; '.join(what)[:400]}")
    print(f"load after: {os.getloadavg()}")


if __name__ == "__main__":
    main()
