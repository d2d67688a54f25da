"""A 200-point branch of a thesis-1dof orbit in V with multipliers at every point (issue 13 target:
at most 10 s on 2 cores, the one-time compile reported apart).

thesis-1dof, matlab-listing numbers, `measured` DC law (Table 4.1), relay 10 Hz (q = 1), tol 1e-12:
the stable period-1 orbit with one impact per period (the thesis' hammering regime) that a
300-period simulation from the scene's default start (1 mm above the stop) reaches at V = 96.63 V,
continued toward 300 V and then toward 25 V by `bifurc.continue_orbit` (max 100 points each way,
multiplier errors off), the product's own path, until the branch ends (an impact lost, a fold);
timed warm (a first, untimed call compiles what the branch needs).
Until 2026-11-24 the script followed the orbit seeded at 200 V, 5 Hz: since the stick guard that
simulation comes to rest on the stop, so it measured the resting branch (0.4 Newton iterations
per point), not a hammering one.
Beside it, side by side: the plain map step and the exact-Jacobian step of the same orbit, so that
a point's cost reads in map steps.

Issue 28 adds two figures: a 200-point frequency-response branch of the impact oscillator (w0 = 1,
zeta = 0.05, F = 0.5, e = 0, r = 0.7, Omega from 2.5 toward 20 at max_points 200, max_step 0.03, multipliers at every
point; target <= 5 s warm on 2 cores), and the period-17 thesis-1dof orbit (listing law, 8.5 Hz,
V = 90 V, tol 1e-10) continued 50 points in V (max_step 0.05): ms and Newton iterations per point.
Run: python benchmarks/continuation.py
"""
from __future__ import annotations

import os
import time

import bifurc
import maps

PARAMS = {"relay_hz": 10.0, "V": 96.63}


def main():
    print(f"load average before: {os.getloadavg()}")
    sc = maps.get_scene("thesis-1dof").with_options(dc_law="measured")
    smap = maps.StroboscopicMap(sc, sc.parameters(preset="matlab-listing", **PARAMS), tol=1e-12)
    o = smap.orbit(sc.initial_state(), 10, transient=300)
    print(f"seed: {PARAMS}, impacts per period {o.impacts_per_step.tolist()}")
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
    def branch():
        total, points, iters, lines = 0.0, 0, 0, []
        for end in (300.0, 25.0):
            t = time.perf_counter()
            ds = bifurc.continue_orbit("thesis-1dof", "V", (PARAMS["V"], end), preset="matlab-listing",
                                       dc_law="measured", params={"relay_hz": PARAMS["relay_hz"]}, max_points=100,
                                       error=False)
            dt = time.perf_counter() - t
            total += dt
            points += ds.sizes["point"]
            iters += int(ds.attrs["newton_iterations_total"])
            lines.append(f"toward {end:5.0f} V: {ds.sizes['point']:3d} points over {float(ds.V.min()):.4g}-"
                         f"{float(ds.V.max()):.4g} V in {dt:.2f} s ({ds.sizes['special']} special points); "
                         f"{ds.attrs['branch_stop_reasons']}")
        return total, points, iters, lines

    cold = branch()[0]     # the first call in this process compiles the branch's derivative functions
    total, points, iters, lines = branch()
    print("\n".join(lines))
    print(f"first call (one-time compiles included): {cold:.2f} s; warm, the same branch: {total:.2f} s")
    print(f"branch: {points} points in {total:.2f} s, {total / points * 1e3:.1f} ms per point = "
          f"{total / points / steps['exact Jacobian step (state and V)']:.1f} exact-Jacobian steps; "
          f"{iters / points:.2f} Newton iterations per point; at this rate 200 points take "
          f"{200 * total / points:.1f} s (target <= 10 s, compile apart)")
    frequency_response()
    period_17()
    print(f"load average after: {os.getloadavg()}")


def _timed(run):
    """(dataset, seconds) of a warm call: a first call compiles."""
    run()
    t = time.perf_counter()
    ds = run()
    return ds, time.perf_counter() - t


def frequency_response():
    """200 points of the impact oscillator's 1:1 branch in Omega, multipliers at every point."""
    p = dict(w0=1.0, zeta=0.05, F=0.5, Omega=2.5, e=0.0, r=0.7)
    ds, dt = _timed(lambda: bifurc.continue_orbit("impact-oscillator", "Omega", (2.5, 20.0), params=p,
                                                  max_points=200, max_step=0.03, error=False))
    n = ds.sizes["point"]
    print(f"impact oscillator, frequency response in Omega: {n} points over {float(ds.Omega.min()):.4g}-"
          f"{float(ds.Omega.max()):.4g} rad/s in {dt:.2f} s warm ({dt / n * 1e3:.1f} ms per point, "
          f"{int(ds.attrs['newton_iterations_total']) / n:.2f} Newton iterations per point; target 200 points "
          f"<= 5 s); {ds.attrs['branch_stop_reasons']}")


def period_17():
    """The period-17 thesis-1dof orbit at 8.5 Hz continued 50 points in V."""
    sc = maps.get_scene("thesis-1dof").with_options(dc_law="listing")
    smap = maps.StroboscopicMap(sc, sc.parameters(preset="matlab-listing", V=90.0, relay_hz=8.5), tol=1e-10)
    o = smap.orbit(sc.initial_state(), 2, transient=300)
    start = (o.state(0), 300)
    ds, dt = _timed(lambda: bifurc.continue_orbit("thesis-1dof", "V", (90.0, 150.0), preset="matlab-listing",
                                                  dc_law="listing", params={"relay_hz": 8.5}, start=start,
                                                  period=17, tol=1e-10, max_points=50, max_step=0.05,
                                                  error=False))
    n = ds.sizes["point"]
    print(f"thesis-1dof period 17 at 8.5 Hz in V: {n} points over {float(ds.V.min()):.5g}-{float(ds.V.max()):.5g} V "
          f"in {dt:.2f} s warm: {dt / n * 1e3:.0f} ms per point, "
          f"{int(ds.attrs['newton_iterations_total']) / n:.2f} Newton iterations per point; "
          f"{ds.attrs['branch_stop_reasons']}")


if __name__ == "__main__":
    main()
