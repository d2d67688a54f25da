"""The product's paths timed on two checkouts, interleaved, best of N: is any path slower?

    python benchmarks/compare_commits.py OLD_CHECKOUT NEW_CHECKOUT [--rounds 5] [--only NAME,...]

Each checkout runs with its own Python (``<checkout>/.venv/bin/python``, else this one) in a fresh
process per measurement, from its own folder, through the public API only (so that both sides run
the same calls). The rounds alternate old, new, old, new, ... so that a burst of load on the shared
machine falls on both; each path's figure is the best of its rounds, and the ratio new / old is
printed side by side with a 1.05 limit. Inside a process a path is warmed (compiled) first, then
timed as the best of runs filling ``MIN_SECONDS``.
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

MIN_SECONDS = 1.0
LIMIT = 1.05

#: name -> (what it times, the code: defines ``work()`` and optionally ``setup``; ``work`` is timed)
PATHS = {
    "trajectory": ("one thesis-1dof trajectory, 2 s at 9 Hz, 90 V, matlab-listing (HybridRun.advance)", """
import maps
sc = maps.get_scene("thesis-1dof").with_options(dc_law="listing")
p = sc.parameters(preset="matlab-listing", V=90.0, relay_hz=9.0)
y0 = sc.system.state_vector(sc.initial_state())
def work():
    run = maps.HybridRun(sc.system, dict(p), y0, tol=1e-12)
    run.advance(2.0)
"""),
    "map step": ("100 stroboscopic map steps (StroboscopicMap.orbit, scalar engine)", """
import maps
sc = maps.get_scene("thesis-1dof").with_options(dc_law="listing")
smap = maps.StroboscopicMap(sc, sc.parameters(preset="matlab-listing", V=90.0, relay_hz=9.0))
y0 = sc.initial_state()
def work():
    smap.orbit(y0, 100)
"""),
    "exact Jacobian": ("10 exact-Jacobian map steps (StroboscopicMap.linearize with V and relay_hz)", """
import maps
sc = maps.get_scene("thesis-1dof").with_options(dc_law="listing")
smap = maps.StroboscopicMap(sc, sc.parameters(preset="matlab-listing", V=90.0, relay_hz=9.0))
s0 = smap.orbit(sc.initial_state(), 1, transient=50).state(0)
def work():
    s = s0
    for k in range(10):
        s = smap.linearize(s, 50 + k, params=("V", "relay_hz")).state
"""),
    "periodic orbit": ("a period-2 orbit by Newton with multiplier error (bifurc.periodic_orbit, 4 Hz, 120 V)", """
import bifurc
def work():
    bifurc.periodic_orbit("thesis-1dof", preset="matlab-listing", params={"V": 120.0, "relay_hz": 4.0},
                          transient=100)
"""),
    "continuation": ("a branch of the impact oscillator in e, 40 points (bifurc.continue_orbit)", """
import bifurc
def work():
    bifurc.continue_orbit("impact-oscillator", "e", (0.2, -0.2), max_points=40, error=False)
"""),
    "diagram": ("the README's main job in-process: 81 values, 2 workers (bifurc.sweep)", """
import numpy as np, bifurc
v = np.linspace(2, 10, 81)
def work():
    bifurc.sweep("thesis-1dof", "relay_hz", v, preset="matlab-listing", params={"V": 90.0}, progress=False,
                 workers=2)
"""),
    "regime map": ("a 12 x 12 regime map, 2 workers (bifurc.regime_map)", """
import numpy as np, bifurc
def work():
    bifurc.regime_map("thesis-1dof", "relay_hz", np.linspace(3, 10, 12), "V", np.linspace(60, 200, 12),
                      preset="matlab-listing", transient=100, record=30, progress=False, workers=2)
"""),
    "progression": ("a 2-DOF prototype sweep under the drift soil, 24 values, 2 workers", """
import numpy as np, bifurc
def work():
    bifurc.sweep("prototype", "relay_hz", np.linspace(4.0, 8.8, 24), soil="drift", transient=100, record=50,
                 lyapunov=False, grazing=False, error_sample=0, progress=False, workers=2)
"""),
    "census": ("an attractor census of the impact oscillator, 3 values x 50 starts, 1 worker (bifurc.attractors)", """
import bifurc
OSC = dict(w0=1.0, zeta=0.05, F=0.3, Omega=1.3, e=-1.0, r=0.8)
def work():
    bifurc.attractors("impact-oscillator", "Omega", [1.25, 1.3, 1.35], params=OSC, box={"x": (-1.0, 2.0),
                      "v": (-2.0, 2.0)}, n_starts=50, seed=3, progress=False, workers=1)
"""),
    "census like for like": ("the census path at the old defaults on both sides (2000 periods per start, periods up "
                             "to 16: `budget`/`max_period`, before the step `max_periods`/`max_period`)", """
import bifurc
OSC = dict(w0=1.0, zeta=0.05, F=0.3, Omega=1.3, e=-1.0, r=0.8)
KW = dict(budget=2000, max_period=16) if hasattr(bifurc, "Census") else dict(max_periods=2000, max_period=16)
def work():
    bifurc.attractors("impact-oscillator", "Omega", [1.25, 1.3, 1.35], params=OSC, box={"x": (-1.0, 2.0),
                      "v": (-2.0, 2.0)}, n_starts=50, seed=3, progress=False, workers=1, **KW)
"""),
}

_TIMER = """
import json, time
{code}
work()                                   # warm: compile, import, start the pools once
best, spent, runs = float("inf"), 0.0, 0
while spent < {min_seconds} or runs < 1:
    t0 = time.perf_counter(); work(); dt = time.perf_counter() - t0
    best, spent, runs = min(best, dt), spent + dt, runs + 1
print(json.dumps({{"best": best, "runs": runs}}))
"""


def python_of(checkout: Path) -> str:
    exe = checkout / ".venv" / "bin" / "python"
    return str(exe) if exe.exists() else sys.executable


def measure(checkout: Path, name: str) -> float:
    code = _TIMER.format(code=PATHS[name][1], min_seconds=MIN_SECONDS)
    env = dict(os.environ, MPLBACKEND="Agg", PYTHONPATH=str(checkout))
    out = subprocess.run([python_of(checkout), "-c", code], cwd=checkout, env=env, capture_output=True, text=True)
    if out.returncode:
        raise SystemExit(f"{name} on {checkout}: {out.stderr.strip().splitlines()[-1]}")
    return json.loads(out.stdout.strip().splitlines()[-1])["best"]


def commit_of(checkout: Path) -> str:
    r = subprocess.run(["git", "-C", str(checkout), "rev-parse", "--short", "HEAD"], capture_output=True, text=True)
    return r.stdout.strip() or "?"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("old", type=Path)
    ap.add_argument("new", type=Path)
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--only", default=None, help="comma-separated path names (default: all)")
    args = ap.parse_args(argv)
    names = args.only.split(",") if args.only else list(PATHS)
    unknown = [n for n in names if n not in PATHS]
    if unknown:
        ap.error(f"unknown path {unknown[0]!r}; paths: {', '.join(PATHS)}")
    print(f"old {args.old} ({commit_of(args.old)}), new {args.new} ({commit_of(args.new)}); "
          f"{args.rounds} interleaved rounds; load average {os.getloadavg()}", flush=True)
    rows = []
    for name in names:
        times = {"old": [], "new": []}
        for _ in range(args.rounds):
            for side, path in (("old", args.old), ("new", args.new)):
                times[side].append(measure(path, name))
        old, new = min(times["old"]), min(times["new"])
        rows.append((name, old, new))
        print(f"{name}: old {', '.join(f'{t:.4g}' for t in times['old'])} s; new "
              f"{', '.join(f'{t:.4g}' for t in times['new'])} s; best {old:.4g} -> {new:.4g} s, "
              f"ratio {new / old:.3f}", flush=True)
    print(f"\nload average after: {os.getloadavg()}\n")
    print("| path | what | old best [s] | new best [s] | new / old | <= 1.05 |")
    print("|---|---|---|---|---|---|")
    for name, old, new in rows:
        print(f"| {name} | {PATHS[name][0]} | {old:.4g} | {new:.4g} | {new / old:.3f} | "
              f"{'yes' if new / old <= LIMIT else 'NO'} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
