"""A zoom's first picture on two checkouts, both with their warm zoom processes ready, interleaved (issue 49: first
picture <= 5 s for 200 values of the main job on 2 cores): ``explore_zoom_compare.py --warm-both``.

    python benchmarks/explore_zoom_warm.py OLD_CHECKOUT NEW_CHECKOUT [--rounds 3] [--no-record] [--notes TEXT]

Each measurement is a fresh process in the checkout (``PYTHONPATH`` set to it) that stores a one-value diagram of
the main job's problem (8.5 Hz), starts :class:`bifurc.explore.compute.Spares` and waits until they are ready (as a
page a few seconds after the first click), then zooms on 8 to 9 Hz with 200 values: first progress (a chunk
stored) and first picture (every value at 300 + 100 relay periods, no extension).  Rounds alternate old, new (then
new, old) so that a burst of load falls on both; the ratio of the medians is the figure to trust on a loaded
machine.
"""
from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from explore_zoom_compare import main as compare  # noqa: E402


def main(argv=None) -> int:
    return compare(["--warm-both", *(sys.argv[1:] if argv is None else argv)], script="explore_zoom_warm.py")


if __name__ == "__main__":
    raise SystemExit(main())
