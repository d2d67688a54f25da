"""One map step with its exact Jacobian against a plain map step, side by side (issue 11 target <= 5x).

thesis-1dof, matlab-listing, listing DC law, 90 V, 8.5 Hz, tol 1e-12: the steps of an orbit after a
300-period transient (contacts included).  Plain: StroboscopicMap.step; exact: .linearize (the
variational equations with saltation, n x n sensitivities); finite differences (2n plain steps)
for reference.  The compile time of the variational integrator is reported apart (cold, this
process).  Run: python benchmarks/jacobian.py
"""
from __future__ import annotations

import os
import time

import maps


def main():
    print(f"load average before: {os.getloadavg()}")
    sc = maps.get_scene("thesis-1dof").with_options(dc_law="listing")   # matlab-listing's law
    p = sc.parameters(preset="matlab-listing", V=90.0, relay_hz=8.5)   # a period-17 orbit with 12 impacts
    smap = maps.StroboscopicMap(sc, p, tol=1e-12)
    o = smap.orbit(sc.initial_state(), 30, transient=300)
    states = [o.state(k) for k in range(30)]
    t0 = time.perf_counter()
    smap.linearize(states[0], 300)
    cold = time.perf_counter() - t0
    print(f"variational integrator: first linearize (compile included) {cold:.2f} s")
    timings = {"plain step": [], "exact Jacobian (linearize)": [], "finite differences (2n steps)": []}
    for rep in range(5):
        for label, f in (("plain step", lambda s, k: smap.step(s, k)),
                         ("exact Jacobian (linearize)", lambda s, k: smap.linearize(s, k)),
                         ("finite differences (2n steps)", lambda s, k: smap.jacobian(s, k, method="fd"))):
            t = time.perf_counter()
            for k, s in enumerate(states):
                f(s, 300 + k)
            timings[label].append((time.perf_counter() - t) / len(states))
    best = {k: min(v) for k, v in timings.items()}
    base = best["plain step"]
    for k, v in best.items():
        print(f"{k:32s} {v * 1e3:8.3f} ms per relay period   {v / base:5.2f}x plain")
    print(f"impacts in the 30 periods: {int(o.impacts_per_step.sum())}")
    print(f"load average after: {os.getloadavg()}")


if __name__ == "__main__":
    main()
