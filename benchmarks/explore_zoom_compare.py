"""A zoom's first progress and first picture on two checkouts, interleaved (issue 49: first picture <= 5 s for 200
values of the main job, progress from the first second).

    python benchmarks/explore_zoom_compare.py OLD_CHECKOUT NEW_CHECKOUT [--rounds 3] [--warm-both] [--no-record]

Each measurement is a fresh process in the checkout (``PYTHONPATH`` set to it): a one-value stored diagram of the
main job's problem (8.5 Hz), then :class:`bifurc.explore.compute.Zoom` over 8 to 9 Hz on 200 values, timed from the
zoom's start to its first stored chunk ("first progress") and to its first picture of every value (300 + 100
relay periods, no extension).  Where the checkout has :class:`bifurc.explore.compute.Spares` (warm zoom processes,
started after the page's first click), a second figure "new, warm" waits for them to be ready before the zoom, as
on a page a few seconds after a click.  Rounds alternate old, new, new warm so that a burst of load falls on all.
With ``--warm-both`` both checkouts run with their warm processes ready ("old, warm" and "new, warm", the order
reversed every other round), for two checkouts that both have them.
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
from pathlib import Path

CODE = r"""
import json, sys, tempfile, time
import numpy as np, maps, bifurc
from bifurc.explore import compute
warm = sys.argv[1] == "warm"
folder = tempfile.mkdtemp()
pb = maps.problem("thesis-1dof", preset="matlab-listing", params={"V": 90})
bifurc.sweep(pb, "relay_hz", np.array([8.5]), bifurc.Diagram(budget=6000, error_sample=0),
             run=bifurc.Run(workers=1, progress=False, path=folder + "/d.nc"))
c = compute.Computer(bifurc.load(folder + "/d.nc"))
spares = None
if warm:
    spares = compute.Spares(c).fill()
    while spares.ready() < spares.n:
        time.sleep(0.05)
z = compute.Zoom(c, 8.0, 9.0, 200, spares=spares) if spares else compute.Zoom(c, 8.0, 9.0, 200)
first = None
while True:
    s = z.poll()
    if s["error"]:
        raise SystemExit(s["error"])
    if first is None and (s["done"] or s["stage"] > 0):
        first = s["seconds"]
    if s["stage"] >= 1:
        break
    time.sleep(0.02)
picture = s["seconds"]
z.close()
if spares:
    spares.close()
print(json.dumps({"first_progress": first, "first_picture": picture}))
"""


def measure(checkout: Path, warm: bool) -> dict:
    env = dict(os.environ, PYTHONPATH=str(checkout), MPLBACKEND="Agg")
    out = subprocess.run([sys.executable, "-c", CODE, "warm" if warm else "cold"], cwd=checkout, env=env,
                         capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def checkouts(doc: str, rounds: int, argv=None, more=()) -> argparse.Namespace:
    """The arguments of a benchmark of two checkouts: old, new, --rounds, --no-record, --notes (and ``more``
    flags, each off by default)."""
    ap = argparse.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("old", type=Path)
    ap.add_argument("new", type=Path)
    ap.add_argument("--rounds", type=int, default=rounds)
    ap.add_argument("--no-record", action="store_true")
    ap.add_argument("--notes", default="", help="appended to the record's notes (what old and new are)")
    for flag in more:
        ap.add_argument(flag, action="store_true")
    return ap.parse_args(argv)


def main(argv=None, script: str = "explore_zoom_compare.py") -> int:
    args = checkouts(__doc__, 3, argv, more=("--warm-both",))
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    from record import Run
    run = Run("explorer zoom, warm processes: old and new interleaved" if args.warm_both else
              "explorer zoom: old and new interleaved", " ".join([f"python benchmarks/{script}",
                                                                  *map(str, (argv or sys.argv[1:]))]),
              notes="issue 49: a zoom over 200 values of the main job shows a first picture within 5 s, progress "
                    "from the first second; 1000 such values took 12.3 s idle at b962ece (about 2.5 s for 200)" +
                    (f"; {args.notes}" if args.notes else ""))
    sides = {"old, warm": (args.old, True), "new, warm": (args.new, True)} if args.warm_both else \
        {"old": (args.old, False), "new": (args.new, False), "new, warm": (args.new, True)}
    got: dict = {k: [] for k in sides}
    for r in range(args.rounds):
        for name, (checkout, warm) in (list(sides.items())[::-1] if r % 2 else sides.items()):
            load = os.getloadavg()[0]
            m = measure(checkout, warm)
            got[name].append(m)
            print(f"round {r + 1} {name:10s}: first progress {m['first_progress']:.2f} s, first picture "
                  f"{m['first_picture']:.2f} s (load {load:.1f})", flush=True)
    for name, ms in got.items():
        for key in ("first_progress", "first_picture"):
            vals = [m[key] for m in ms]
            print(f"{name:10s} {key}: best {min(vals):.2f} s, median {statistics.median(vals):.2f} s")
            run.figure(f"zoom 200 values, {name}: {key.replace('_', ' ')} (median of {len(vals)})",
                       round(statistics.median(vals), 2), "s", target="5 s" if key == "first_picture" else "1 s")
    base = "old, warm" if args.warm_both else "old"
    old, new = (statistics.median(m["first_picture"] for m in got[k]) for k in (base, "new, warm"))
    ratios = [n["first_picture"] / o["first_picture"] for o, n in zip(got[base], got["new, warm"])]
    print(f"first picture new warm / {base}: medians {new / old:.3f}, per round "
          f"{', '.join(f'{x:.3f}' for x in ratios)}")
    run.figure(f"first picture: new warm / {base} (medians)", round(new / old, 3), "")
    if not args.no_record:
        print(f"wrote {run.write()}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
