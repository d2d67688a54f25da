"""The thesis census end to end (benchmarks/attractors.py's 21 values x 200 starts, `matlab-listing`, `measured`
law, 10 Hz, V in 80-220 V, box x = 0:0.03, v = -1.5:1.5, seed 1, 100 cells a side, 2 workers) in two checkouts,
one after the other, each in a fresh process from its own folder through the public API:

    python benchmarks/census_checkouts.py OLD_CHECKOUT NEW_CHECKOUT [--budget N] [--rounds 1]

``--budget``: the periods per start, passed under each checkout's own name for it (``budget``; ``max_periods``
before issue 45); default: each checkout's own default.  Prints wall and CPU seconds (workers included) per
checkout and the ratio new / old.  Not interleaved within a value: run it on an idle machine.
"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys
from pathlib import Path

_CODE = """
import json, resource, sys, time
import numpy as np
import bifurc

def main(budget):
    kw = dict(preset="matlab-listing", params={"relay_hz": 10.0}, dc_law="measured",
              box={"x": (0.0, 0.03), "v": (-1.5, 1.5)}, n_starts=200, seed=1, cells=100, progress=False, workers=2)
    if budget:
        import inspect
        new = "method" in inspect.signature(bifurc.attractors).parameters      # issue 45's form: budget=
        kw["budget" if new else "max_periods"] = budget
    t = time.perf_counter()
    ds = bifurc.attractors("thesis-1dof", "V", np.linspace(80, 220, 21), **kw)
    wall = time.perf_counter() - t
    me, kids = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = me.ru_utime + me.ru_stime + kids.ru_utime + kids.ru_stime
    print(json.dumps({"wall": wall, "cpu": cpu, "attractors": int(ds.sizes["attractor"])}))

if __name__ == "__main__":
    main(int(sys.argv[1]))
"""


def measure(checkout: Path, budget: int) -> dict:
    py = checkout / ".venv" / "bin" / "python"
    out = subprocess.run([str(py) if py.exists() else sys.executable, "-c", _CODE, str(budget)], cwd=checkout,
                         capture_output=True, text=True, check=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("old", type=Path)
    ap.add_argument("new", type=Path)
    ap.add_argument("--budget", type=int, default=0, help="periods per start (default: each checkout's own)")
    ap.add_argument("--rounds", type=int, default=1)
    a = ap.parse_args(argv)
    got = {"old": [], "new": []}
    for _ in range(a.rounds):
        for side in ("old", "new"):
            r = measure(getattr(a, side), a.budget)
            got[side].append(r)
            print(f"{side} {getattr(a, side)}: {r['wall']:.1f} s wall, {r['cpu']:.1f} s CPU, "
                  f"{r['attractors']} attractor rows", flush=True)
    best = {k: min(r["wall"] for r in v) for k, v in got.items()}
    print(f"best wall: old {best['old']:.1f} s, new {best['new']:.1f} s, ratio {best['new'] / best['old']:.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
