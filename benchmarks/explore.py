"""The explorer's response times (issue 49's targets, on 2 cores): a click, a branch, a zoom.

    python benchmarks/explore.py [--repeat 3] [--no-record]

- click: :meth:`bifurc.explore.app.Explorer.select` at 8.5 Hz of the main job's problem (period 17, 12 impacts):
  the time history after the record and the periodic orbit with its multipliers, moved into the page's sources;
  the integrators compiled once before (the explorer compiles them while the page loads).  Target <= 0.5 s.
- branch: the branch of the impact oscillator's period-1 orbit through e = 0.15 continued to both ends of a diagram
  over e (:meth:`bifurc.explore.compute.Computer.branch`, 200 points at most each way).  Target <= 2 s for 200 points.
- zoom: 200 new values of the main job (8 to 9 Hz) swept by the explorer's warm zoom processes, one per core
  (:class:`bifurc.explore.compute.Spares`, ready as a page has them after a click; :class:`bifurc.explore.compute.Zoom`):
  first progress (a chunk of 5 values stored), the first picture (300 + 100 relay periods, no extension), then the
  anytime labels (undecided values extended up to the budget).
  Target: first picture <= 5 s, progress from the first second.
- census zoom: a stored census of the impact oscillator (Omega 1.2 and 1.35, 200 starts in its box, seed 0)
  zoomed on Omega 1.25 to 1.3 by the census page's warm processes: 20 values with 25 starts each
  (:func:`bifurc.attractors` with the stored settings, starts kind and seed), first progress and the whole picture.
- map zoom: a stored 2 x 2 regime map of the main job's problem (relay_hz 8 and 9 Hz x V 80 and 100 V, 300 + 100
  relay periods) zoomed on the rectangle 8.4-8.6 Hz x 85-95 V: 12 x 12 cells (:func:`bifurc.regime_map`), first
  progress (a row), first picture (300 + 100 periods, no extension) and the anytime labels.
  No target in issue 49; the figures are stated with the machine's load.

Prints each figure and writes a record to benchmarks/results/ (unless --no-record).
"""
from __future__ import annotations

import argparse
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import bifurc
import maps

sys.path.insert(0, str(Path(__file__).resolve().parent))


def _diagram(folder, scene, param, values, **kw):
    path = Path(folder) / f"{scene}.nc"
    pb = maps.problem(scene, **kw.pop("problem", {}))
    bifurc.sweep(pb, param, np.asarray(values, float), bifurc.Diagram(**kw),
                 run=bifurc.Run(workers=1, progress=False, path=str(path)))
    return bifurc.load(path)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--no-record", action="store_true")
    ap.add_argument("--only", nargs="+", choices=PARTS, default=PARTS, help="the parts to measure (default: all)")
    args = ap.parse_args(argv)
    from record import Run
    parts = [p for p in PARTS if p in args.only]
    run = Run(f"explorer: {', '.join(parts)}", "python benchmarks/explore.py" +
              (f" --only {' '.join(parts)}" if parts != list(PARTS) else ""),
              notes="issue 49's targets: click <= 0.5 s for a period up to 20, branch <= 2 s for 200 points, zoom "
                    "first picture <= 5 s with progress from the first second; the census and map zooms have none")
    from bifurc.explore import CensusComputer, Computer, MapComputer
    folder = tempfile.mkdtemp(prefix="bifurc-explore-bench-")
    print(f"load average before: {os.getloadavg()}, cores: {os.cpu_count()}", flush=True)
    main_job = dict(problem=dict(preset="matlab-listing", params={"V": 90}), budget=6000)
    d = _diagram(folder, "thesis-1dof", "relay_hz", [8.5], **main_job) if {"click", "zoom"} & set(parts) else None
    if "click" in args.only:
        _click(run, d, args.repeat)
    if "branch" in args.only:
        _branch(run, folder, args.repeat)
    if "zoom" in args.only:
        _zoom(run, "zoom 200 values", Computer(d), (8.0, 9.0, 200), {}, "first picture (300 + 100 periods)",
              target="5 s", last="anytime labels (budget 6000)")
    if "census-zoom" in args.only:
        path = Path(folder) / "census.nc"
        bifurc.attractors("impact-oscillator", "Omega", [1.2, 1.35], params=OSC, starts="box", n_starts=200, seed=0,
                          workers=1, progress=False, path=str(path))
        c = CensusComputer(bifurc.load(path))
        _zoom(run, "census zoom 20 values x 25 starts", c, (1.25, 1.3), {}, "whole picture",
              note="impact oscillator; " + c.zoom_plan()["note"])
    if "map-zoom" in args.only:
        path = Path(folder) / "map.nc"
        bifurc.regime_map(maps.problem("thesis-1dof", preset="matlab-listing"), "relay_hz", [8.0, 9.0], "V",
                          [80.0, 100.0], transient=300, record=100, budget=400, error_sample=0, workers=1,
                          progress=False, path=str(path))
        _zoom(run, "map zoom 12 x 12 cells", MapComputer(bifurc.load(path)), (8.4, 8.6), {"second": (85.0, 95.0)},
              "first picture (300 + 100 periods)", last="anytime labels (budget 400)")
    print(f"load average after: {os.getloadavg()}")
    if not args.no_record:
        print(f"wrote {run.write()}")
    return 0


#: the parts of the benchmark
PARTS = ("click", "branch", "zoom", "census-zoom", "map-zoom")
#: the census' and the map's scene parameters (the impact oscillator's, as in tests/test_explore.py)
OSC = dict(w0=1.0, zeta=0.05, F=0.3, Omega=1.3, e=-1.0, r=0.8)


def _click(run, d, repeat):
    from bifurc.explore import Explorer
    ex = Explorer(d, zoom=False)
    ex._warm.result()                                       # what the page does while it loads
    ex.select(8.5, wait=True)                               # the first click also builds the orbit's map
    clicks = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        ex.select(8.5, wait=True)
        clicks.append(time.perf_counter() - t0)
    print(f"click 8.5 Hz (period 17): {ex.history_text} | {ex.orbit_text[:80]}...")
    print(f"  click: best {min(clicks):.3f} s, median {statistics.median(clicks):.3f} s of {repeat}")
    run.figure("click: time history and orbit, 8.5 Hz, period 17 (best)", round(min(clicks), 3), "s", target="0.5 s")
    run.figure("click: time history and orbit, 8.5 Hz, period 17 (median)", round(statistics.median(clicks), 3), "s")
    ex.close()


def _branch(run, folder, repeat):
    from bifurc.explore import Computer

    osc = _diagram(folder, "impact-oscillator", "e", np.linspace(-0.2, 0.6, 17), transient=100, record=50, budget=150)
    c = Computer(osc)
    c.branch(0.15, max_points=5)                           # compile
    times, points = [], 0
    for _ in range(repeat):
        t0 = time.perf_counter()
        b = c.branch(0.15, max_points=200)
        times.append(time.perf_counter() - t0)
        points = sum(br.sizes["point"] for br in b["branches"])
    print(f"  branch through e = 0.15: {points} points, best {min(times):.3f} s, median "
          f"{statistics.median(times):.3f} s ({b['error'] or 'no refusal'})")
    run.figure("branch: impact oscillator through e = 0.15, both ways (best)", round(min(times), 3), "s",
               note=f"{points} points")
    run.figure("branch: time per 200 points (best, scaled)", round(min(times) * 200 / max(points, 1), 3), "s",
               target="2 s")


def _zoom(run, label, computer, args, kw, picture, target=None, last=None, note=None):
    """A zoom by warm processes (ready, as a page has them after a click): first progress, the first picture, and
    the last stage when there are two."""
    from bifurc.explore import Spares, Zoom
    spares = Spares(computer).fill()                        # what the page starts after the first click
    while spares.ready() < spares.n:
        time.sleep(0.05)
    z = Zoom(computer, *args, spares=spares, **kw)
    first_progress = first_picture = None
    while True:
        s = z.poll()
        if s["error"]:
            raise SystemExit(f"{label} failed: {s['error']}")
        if first_progress is None and (s["done"] or s["stage"] > 0):
            first_progress = s["seconds"]
        if first_picture is None and s["stage"] >= 1:
            first_picture = s["seconds"]
        if s["stage"] >= len(z.stages):
            end = s["seconds"]
            break
        time.sleep(0.05)
    z.close()
    spares.close()
    print(f"  {label}: first progress {first_progress:.2f} s, {picture} {first_picture:.2f} s"
          + (f", {last} {end:.1f} s" if last else ""))
    run.figure(f"{label}: first progress (a chunk done)", round(first_progress, 2), "s")
    run.figure(f"{label}: {picture}", round(first_picture, 2), "s", **({"target": target} if target else {}),
               **({"note": note} if note else {}))
    if last:
        run.figure(f"{label}: {last}", round(end, 1), "s")


if __name__ == "__main__":
    raise SystemExit(main())
