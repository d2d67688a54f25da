"""The attractor census' speed targets (issue 31, section 5); not run in CI.

    python benchmarks/attractors.py --quick     # 21 values x 200 starts; Duffing basins on 100 x 100
    python benchmarks/attractors.py             # also 281 values x 1000 starts and the 500 x 500 Duffing grid

Prints, side by side: the census end to end on thesis-1dof (`matlab-listing` preset, as the thesis-orbits study whose
orbits attractors_recovery.py counts; `measured` law, 10 Hz, V in 80-220 V, box x=0:0.03, v=-1.5:1.5; before
2026-11-26 15:00 the scene's default preset `thesis-text` was run: R = 30 Ohm, C = 0.3 mF against 25 Ohm, 0.28 mF); its cost per start against a bare batch ensemble running the same starts, each for the
periods it spent in the census, interleaved value by value in one process; the census at half the grid cell size
(every fraction, attractors summed by label, against the first census' 95 % interval); cells per second on the
forced Duffing oscillator's stroboscopic basins (x'' + d x' + b x + x^3 = F cos(w t), d = 0.15, b = -1, F = 0.27,
w = 0.1).
"""
from __future__ import annotations

import argparse
import math
import time

import numpy as np

#: the model every census here runs: thesis-1dof under these options (the thesis-orbits study's preset)
MODEL = dict(preset="matlab-listing", params={"relay_hz": 10.0}, dc_law="measured")
BOX = {"x": (0.0, 0.03), "v": (-1.5, 1.5)}

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


def census(n_values, n_starts, cells=100, workers=None, link=True, starts="box"):
    """The thesis-1dof census (module docstring) and its wall and CPU seconds; ``starts`` as
    :func:`bifurc.attractors` takes them (default: ``n_starts`` in the box, seed 1)."""
    import resource

    import bifurc
    kids = lambda: resource.getrusage(resource.RUSAGE_CHILDREN)  # noqa: E731 - worker processes, once reaped
    t, c, k = time.perf_counter(), time.process_time(), kids()
    ds = bifurc.attractors("thesis-1dof", "V", np.linspace(80, 220, n_values), **MODEL, box=BOX, n_starts=n_starts,
                           starts=starts, seed=1, cells=cells, progress=False, workers=workers, link=link)
    k2 = kids()
    return ds, time.perf_counter() - t, time.process_time() - c + (k2.ru_utime - k.ru_utime) + (k2.ru_stime - k.ru_stime)


def interleaved(n_values, n_starts, cells=100):
    """Census and bare ensemble side by side, value after value in this process: the census of a value's fresh
    starts (``bifurc.attractors`` at the one value on one worker, the CPU of its stages: the dataset's
    ``fresh_cpu_seconds_<stage>``), then a bare batch ensemble of the same starts, each run for the strobe periods it
    spent in the census (``start_periods``; strobe points only, ``events=False``).  Returns wall and CPU seconds of
    both (the census' wall: of the whole call) and the mean periods per start."""
    import bifurc
    import maps
    pb = maps.problem("thesis-1dof", **MODEL)
    sampler = bifurc.Box(n=n_starts, box=BOX, seed=1)
    starts = list(np.asarray(sampler.draw(pb).points, dtype=float))
    values = np.linspace(80, 220, n_values)
    one = dict(method=bifurc.Census(cells=cells, link=False), run=bifurc.Run(workers=1, progress=False))
    bifurc.attractors(pb, "V", values[:1], starts=bifurc.Box(n=1, box=BOX, seed=1), **one)   # compiled before the clock
    smap = maps.StroboscopicMap(pb, tol=1e-10)
    smap.orbits([{}], [starts[0]], 1, batch_size=4, events=False)
    wall, cpu, spent = np.zeros(2), np.zeros(2), []
    for v in values:
        t = time.perf_counter()
        ds = bifurc.attractors(pb, "V", [float(v)], starts=sampler, **one)
        wall[0] += time.perf_counter() - t
        cpu[0] += sum(float(x) for k, x in ds.attrs.items() if k.startswith("fresh_cpu_seconds_"))
        periods = ds.start_periods.values[0]
        t, c = time.perf_counter(), time.process_time()
        smap.at({"V": float(v)}).orbits([{}] * len(starts), starts, [max(1, int(p)) for p in periods], batch_size=4,
                                        events=False)
        wall[1], cpu[1] = wall[1] + time.perf_counter() - t, cpu[1] + time.process_time() - c
        spent.extend(periods)
    return wall, cpu, float(np.mean(spent))


def duffing(side: int) -> None:
    """Cells per second of the forced Duffing oscillator's stroboscopic basins on a side x side slice."""
    import bifurc
    t = time.perf_counter()
    dd = bifurc.attractors(duffing_scene(), "F", [0.27], starts="slice", shape=(side, side), progress=False,
                           link=False)
    sec = time.perf_counter() - t
    print(f"Duffing basins {side} x {side}: {sec:.1f} s, {side * side / sec:.0f} cells per second; "
          f"fractions {np.round(dd.basin_fraction.values[0], 3).tolist()} ({list(dd.attractor_label.values)}); "
          f"{dd.attrs['workers']} workers; {load()}")


def words(ds) -> dict:
    """{(value index, attractor index): its class in words} of a one-parameter census, for every row of
    ``ds.bifurc.table()`` (the attractors present or reached, the outcomes reached)."""
    table = ds.bifurc.table()
    param = ds.basin_fraction.dims[0]
    value = {float(x): i for i, x in enumerate(ds[param].values)}
    entry = {str(lab): j for j, lab in enumerate(ds.attractor_label.values)}
    return {(value[float(x)], entry[str(lab)]): text
            for x, lab, text in zip(table[param], table["attractor"], table["description"])}


def by_label(ds) -> dict:
    """{(value index, label): starts} of one census: attractors with the same class, period and impacts at a value
    are summed (their ids differ between two censuses), outcomes by name."""
    out = {}
    for (i, j), label in words(ds).items():
        k = int(ds.basin_count.values[i, j])
        if k:
            out[(i, label)] = out.get((i, label), 0) + k
    return out


def wilson(k: int, n: int) -> tuple[float, float]:
    """The 95 % Wilson score interval of a fraction ``k`` of ``n`` (scipy)."""
    from scipy.stats import binomtest
    ci = binomtest(k, n).proportion_ci(0.95, method="wilson")
    return ci.low, ci.high


def grid_change(ds, half) -> str:
    """Every fraction (attractors by label, and the outcomes) of the census at half the cell size against the
    first census' 95 % Wilson interval of the same fraction."""
    n = ds.sizes["start"]
    a, b = by_label(ds), by_label(half)
    worst, outside, width = 0.0, [], 0.0
    for key in sorted(set(a) | set(b)):
        fa, fb = a.get(key, 0) / n, b.get(key, 0) / n
        lo, hi = wilson(a.get(key, 0), n)
        width = max(width, hi - lo)
        worst = max(worst, abs(fb - fa))
        if not lo - 1e-12 <= fb <= hi + 1e-12:      # the interval of 0 of n starts at 0 up to round-off
            outside.append(f"{float(ds[ds.basin_fraction.dims[0]].values[key[0]]):g} {key[1]}: {fa:.3f} -> {fb:.3f}")
    tail = (": " + "; ".join(outside)) if outside else ""
    return (f"largest change of a fraction {worst:.3f} (intervals up to {width:.3f} wide); {len(outside)} of "
            f"{len(set(a) | set(b))} fractions outside the first census' interval{tail}")


def attractor_count(ds) -> int:
    """The distinct attractors of a census: attractor ids (A0, A1, ...; not the outcomes' entries) present at some
    value."""
    ids = np.char.startswith(ds.attractor_label.values.astype(str), "A")
    return int((ds.present.values[:, ids] > 0).any(axis=0).sum())


def load() -> str:
    import os
    return f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--duffing", type=int, metavar="SIDE", help="only the Duffing basins on a SIDE x SIDE grid")
    a = ap.parse_args(argv)
    print(load())
    if a.duffing:
        return duffing(a.duffing)
    ds, sec, cpu = census(21, 200)
    n_att = attractor_count(ds)
    print(f"census thesis-1dof measured 10 Hz, 21 values x 200 starts, {ds.attrs['workers']} workers, linked: "
          f"{sec:.1f} s end to end ({cpu:.1f} s CPU in all processes; target 30 s); {n_att} attractors; {ds.attrs['periods_per_start_mean']:.1f} "
          f"periods per start on average (max {ds.attrs['periods_per_start_max']})")
    wall, cpu, mean = interleaved(21, 200)
    print(f"cost per start, one process, census and bare ensemble interleaved value by value: census {wall[0]:.1f} s "
          f"({cpu[0]:.1f} s CPU) vs bare batch ensemble {wall[1]:.1f} s ({cpu[1]:.1f} s CPU) running the same 4200 "
          f"starts each for the periods it spent in the census ({mean:.1f} on average, strobe points only): ratio "
          f"{wall[0] / wall[1]:.2f} wall, {cpu[0] / cpu[1]:.2f} CPU (target <= 1.3)")
    print(load())
    half, sec2, _ = census(21, 200, cells=200)
    print(f"grid halved (200 cells per side): {sec2:.1f} s; {n_att} vs "
          f"{attractor_count(half)} attractors; {grid_change(ds, half)}")
    for side in ((100,) if a.quick else (100, 500)):
        duffing(side)
    if not a.quick:
        ds, sec, _ = census(281, 1000)
        print(f"census 281 values x 1000 starts: {sec / 60:.1f} min (target 15 min)")


if __name__ == "__main__":
    main()
