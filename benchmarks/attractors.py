"""The attractor census' speed targets (issue 31, section 5); not run in CI.

    python benchmarks/attractors.py --quick     # 21 values x 200 starts; Duffing basins on 100 x 100
    python benchmarks/attractors.py             # also 281 values x 1000 starts and the 500 x 500 Duffing grid

Prints, side by side: the census end to end on thesis-1dof (`measured` law, 10 Hz, V in 80-220 V, box
x=0:0.03, v=-1.5:1.5); its cost per start against a bare batch ensemble running the same starts for the same
mean number of periods; the census at half the grid cell size (largest change of a fraction against its
interval); cells per second on the forced Duffing oscillator's stroboscopic basins
(x'' + d x' + b x + x^3 = F cos(w t), d = 0.15, b = -1, F = 0.27, w = 0.1).
"""
from __future__ import annotations

import argparse
import math
import time

import numpy as np


def duffing_scene():
    import maps
    from maps import HybridSystem, Parameter, State

    def system():
        import heyoka as hy
        return HybridSystem(
            "forced-duffing", states=[State("x", "1", "position"), State("v", "1", "velocity")],
            parameters=[Parameter(n, "1", n, -10, 10) for n in ("d", "b", "F", "w")],
            rhs=lambda s: [s.v, s.F * hy.cos(s.w * s.t) - s.d * s.v - s.b * s.x - s.x * s.x * s.x],
            guards=lambda s: [], strobe_period=lambda p: 2 * math.pi / p["w"],
            forcing=lambda p: [p["w"] / (2 * math.pi)])
    return maps.Scene("forced-duffing", "forced Duffing oscillator (benchmarks/attractors.py)", None, preset=None,
                      overrides={"d": (0.15, "issue 31"), "b": (-1.0, "issue 31"), "F": (0.27, "issue 31"),
                                 "w": (0.1, "issue 31")}, x0={"x": 0.0, "v": 0.0}, builder=system,
                      box={"x": (-2.5, 2.5), "v": (-2.5, 2.5)})


def census(n_values, n_starts, cells=100, workers=None, link=True):
    import resource

    import bifurc
    kids = lambda: resource.getrusage(resource.RUSAGE_CHILDREN)  # noqa: E731 - worker processes, once reaped
    t, c, k = time.perf_counter(), time.process_time(), kids()
    ds = bifurc.attractors("thesis-1dof", "V", np.linspace(80, 220, n_values), params={"relay_hz": 10.0},
                           dc_law="measured", box={"x": (0.0, 0.03), "v": (-1.5, 1.5)}, n_starts=n_starts,
                           seed=1, cells=cells, progress=False, workers=workers, link=link)
    k2 = kids()
    return ds, time.perf_counter() - t, time.process_time() - c + (k2.ru_utime - k.ru_utime) + (k2.ru_stime - k.ru_stime)


def bare(ds):
    """Seconds of a bare batch ensemble in this process: the same starts at every value, each for the census'
    mean number of periods per start, strobe points only (``events=False``, the census' own chunks' mode)."""
    import maps
    from maps.poincare import StroboscopicMap
    pb = maps.problem("thesis-1dof", params={"relay_hz": 10.0}, dc_law="measured")
    smap = StroboscopicMap(pb, tol=1e-10)
    starts = np.stack([ds[f"start_{s}"].values for s in pb.system.state_names], axis=1)
    n = max(1, int(round(ds.attrs["periods_per_start_mean"])))
    smap.orbits([{}], [starts[0]], 1, batch_size=4, events=False)          # compiled before the clock
    t = time.perf_counter()
    for v in ds.V.values:
        smap.set_params(V=float(v))
        smap.orbits([{}] * len(starts), list(starts), n, batch_size=4, events=False)
    return time.perf_counter() - t, n


def load() -> str:
    import os
    return f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true")
    a = ap.parse_args(argv)
    print(load())
    ds, sec, cpu = census(21, 200)
    n_att = int((ds.present.values[:, :-3] > 0).any(axis=0).sum())
    print(f"census thesis-1dof measured 10 Hz, 21 values x 200 starts, {ds.attrs['workers']} workers, linked: "
          f"{sec:.1f} s end to end ({cpu:.1f} s CPU in all processes; target 30 s); {n_att} attractors; {ds.attrs['periods_per_start_mean']:.1f} "
          f"periods per start on average (max {ds.attrs['periods_per_start_max']})")
    one, sec1, cpu1 = census(21, 200, workers=1, link=False)
    b, n = bare(one)
    print(f"cost per start, one process, no linking: census {sec1:.1f} s ({cpu1:.1f} s CPU) vs bare batch ensemble "
          f"{b:.1f} s (the same 4200 starts, {n} periods each, strobe points only): ratio {sec1 / b:.2f} "
          f"(target <= 1.3)")
    print(load())
    half, sec2, _ = census(21, 200, cells=200)
    cols = min(ds.sizes["attractor"], half.sizes["attractor"])
    width = (ds.basin_fraction_high - ds.basin_fraction_low).values
    print(f"grid halved (200 cells per side): {sec2:.1f} s; {n_att} vs "
          f"{int((half.present.values[:, :-3] > 0).any(axis=0).sum())} attractors; outcome fractions "
          f"(escaped, not_converged, failed) change by at most "
          f"{float(np.max(np.abs(ds.basin_fraction.values[:, -3:] - half.basin_fraction.values[:, -3:]))):.3f} "
          f"(interval widths up to {float(np.nanmax(width)):.3f}; {cols} columns compared by id only for outcomes)")
    import bifurc
    for side in ((100,) if a.quick else (100, 500)):
        t = time.perf_counter()
        dd = bifurc.attractors(duffing_scene(), "F", [0.27], starts="slice", shape=(side, side), progress=False,
                               link=False)
        sec = time.perf_counter() - t
        print(f"Duffing basins {side} x {side}: {sec:.1f} s, {side * side / sec:.0f} cells per second; "
              f"fractions {np.round(dd.basin_fraction.values[0], 3).tolist()} ({list(dd.attractor_label.values)})")
    if not a.quick:
        ds, sec, _ = census(281, 1000)
        print(f"census 281 values x 1000 starts: {sec / 60:.1f} min (target 15 min)")


if __name__ == "__main__":
    main()
