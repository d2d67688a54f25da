"""A 200-point branch of a thesis-1dof orbit in V with multipliers at every point (issue 13 target:
at most 10 s on 2 cores, the one-time compile reported apart).

thesis-1dof, matlab-listing numbers, `measured` DC law (Table 4.1), relay 5 Hz (q = 1), tol 1e-12:
the period-1 orbit with 2 impacts per period found from a 300-period simulation at V = 200 V
(x0 = the scene's default, 1 mm above the stop), continued toward 300 V and then toward 25 V by
`bifurc.continue_orbit` (max 100 points each way, multiplier errors off), the product's own path.
Beside it, side by side: the plain map step and the exact-Jacobian step of the same orbit, so that
a point's cost reads in map steps.  Run: python benchmarks/continuation.py
"""
from __future__ import annotations

import os
import time

import bifurc
import maps

PARAMS = {"relay_hz": 5.0, "V": 200.0}


def main():
    print(f"load average before: {os.getloadavg()}")
    sc = maps.get_scene("thesis-1dof").with_options(dc_law="measured")
    smap = maps.StroboscopicMap(sc, sc.parameters(preset="matlab-listing", **PARAMS), tol=1e-12)
    o = smap.orbit(sc.initial_state(), 10, transient=300)
    t = time.perf_counter()
    smap.linearize(o.state(0), 300, params=("V",))
    print(f"one-time compile of the variational integrator (cold in this process): {time.perf_counter() - t:.2f} s")
    steps = {}
    for label, f in (("plain map step", lambda s, k: smap.step(s, k)),
                     ("exact Jacobian step (state and V)", lambda s, k: smap.linearize(s, k, params=("V",)))):
        best = []
        for _ in range(3):
            t = time.perf_counter()
            for k in range(10):
                f(o.state(k), 300 + k)
            best.append((time.perf_counter() - t) / 10)
        steps[label] = min(best)
        print(f"{label:36s} {steps[label] * 1e3:7.3f} ms")
    total, points, iters = 0.0, 0, 0
    for end in (300.0, 25.0):
        t = time.perf_counter()
        ds = bifurc.continue_orbit("thesis-1dof", "V", (200.0, end), preset="matlab-listing", dc_law="measured",
                                   params={"relay_hz": 5.0}, max_points=100, error=False)
        dt = time.perf_counter() - t
        total += dt
        points += ds.sizes["point"]
        iters += int(ds.attrs["newton_iterations_total"])
        print(f"toward {end:5.0f} V: {ds.sizes['point']:3d} points over {float(ds.V.min()):.4g}-{float(ds.V.max()):.4g} V "
              f"in {dt:.2f} s ({ds.sizes['special']} special points); {ds.attrs['branch_stop_reasons']}")
    print(f"branch: {points} points in {total:.2f} s (target <= 10 s for 200 points), {total / points * 1e3:.1f} ms "
          f"per point = {total / points / steps['exact Jacobian step (state and V)']:.1f} exact-Jacobian steps; "
          f"{iters / points:.2f} Newton iterations per point")
    print(f"load average after: {os.getloadavg()}")


if __name__ == "__main__":
    main()
