"""A zoom's first picture on two checkouts, both with their warm zoom processes ready, interleaved (issue 49: first
picture <= 5 s for 200 values of the main job on 2 cores).

    python benchmarks/explore_zoom_warm.py OLD_CHECKOUT NEW_CHECKOUT [--rounds 5] [--no-record]

Each measurement is :func:`explore_zoom_compare.measure` with ``warm=True``: a fresh process in the checkout
(``PYTHONPATH`` set to it) stores a one-value diagram of the main job's problem (8.5 Hz), starts
:class:`bifurc.explore.compute.Spares` and waits until they are ready (as a page a few seconds after the first
click), then zooms on 8 to 9 Hz with 200 values: first progress (a chunk stored) and first picture (every value at
300 + 100 relay periods, no extension).  Rounds alternate old, new (then new, old) so that a burst of load falls on
both; the ratio new / old of the medians is the figure to trust on a loaded machine.
"""
from __future__ import annotations

import argparse
import os
import statistics
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from explore_zoom_compare import measure  # noqa: E402


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("old", type=Path)
    ap.add_argument("new", type=Path)
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--no-record", action="store_true")
    ap.add_argument("--notes", default="", help="appended to the record's notes (what old and new are)")
    args = ap.parse_args(argv)
    from record import Run
    run = Run("explorer zoom, warm processes: old and new interleaved",
              " ".join(["python benchmarks/explore_zoom_warm.py", *map(str, (argv or sys.argv[1:]))]),
              notes="issue 49: a zoom over 200 values of the main job shows a first picture within 5 s on 2 cores; "
                    "both checkouts with their warm zoom processes ready. " + args.notes)
    got: dict = {"old": [], "new": []}
    for r in range(args.rounds):
        for name in (("old", "new") if r % 2 == 0 else ("new", "old")):
            load = os.getloadavg()[0]
            m = measure(getattr(args, name), True)
            got[name].append(m)
            print(f"round {r + 1} {name}: first progress {m['first_progress']:.2f} s, first picture "
                  f"{m['first_picture']:.2f} s (load {load:.1f})", flush=True)
    for name, ms in got.items():
        for key in ("first_progress", "first_picture"):
            vals = [m[key] for m in ms]
            print(f"{name} {key}: best {min(vals):.2f} s, median {statistics.median(vals):.2f} s")
            run.figure(f"zoom 200 values, {name}, warm: {key.replace('_', ' ')} (median of {len(vals)})",
                       round(statistics.median(vals), 2), "s", target="5 s" if key == "first_picture" else "1 s")
    ratios = [n["first_picture"] / o["first_picture"] for o, n in zip(got["old"], got["new"])]
    old, new = (statistics.median(m["first_picture"] for m in got[k]) for k in ("old", "new"))
    print(f"first picture new / old: medians {new / old:.3f}, per round {', '.join(f'{x:.3f}' for x in ratios)}")
    run.figure("first picture: new / old (medians)", round(new / old, 3), "")
    run.figure("first picture: new / old (median of the rounds' ratios)", round(statistics.median(ratios), 3), "")
    if not args.no_record:
        print(f"wrote {run.write()}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
