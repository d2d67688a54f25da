"""Stated tolerances of codimension-two points against their real errors (issue 28, section 4): not a timing.

The smooth test system of tests/test_codim2.py (a stroboscopic map known in closed form: cusp at (a, b) = (0, 0),
fold-flips at (+-1/4, 3/4)); its two fold curves from the branch in a at b = 1 and the period-doubling curve from
the branch in b at a = -1/4, as tests/test_codim2.py continues them, once with error=False (the stated tolerance is
the bracket, at least the corrector's acceptance) and once with error=True (re-located at tol/100: a measured
bound).  Prints each point's real error, stated tolerance and their ratio side by side.
Run: python benchmarks/codim2_tolerances.py   (~15 s)
"""
from __future__ import annotations

import math
import os
import re
import subprocess
import sys
import time

import bifurc

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests"))
from test_codim2 import cusp_flip_system  # noqa: E402  (the test's system: one definition)

NUMBER = r"([-+\d.eE]+)"


def points(ds):
    """(kind, a, b, stated tolerance) of the dataset's codimension-two points, whichever parameter is first."""
    first = ds.attrs["curve_parameters"].split()[0]
    out = []
    for kind, x, y, tol in re.findall(rf"(\w+) on curve \d+: \([^)]*\) = \({NUMBER}, {NUMBER}\) \+- {NUMBER}",
                                      ds.attrs["curve_codim2"]):
        a, b = (float(x), float(y)) if first == "a" else (float(y), float(x))
        out.append((kind, a, b, float(tol)))
    return out


def main():
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
    print(f"commit {commit}, {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, load {os.getloadavg()[0]:.1f}")
    print(f"{'error':>6} {'kind':>10} {'a':>22} {'b':>22} {'real error':>11} {'stated':>9} {'ratio':>9}")
    for error in (False, True):
        fold = bifurc.continue_orbit(cusp_flip_system(), "a", (-1.0, 1.0), params={"a": -1.0, "b": 1.0},
                                     x0={"x": -1.3, "y1": 0.0, "y2": 0.0}, period=1, param2="b", span2=(1.0, -0.5),
                                     max_points=200, error=error)
        flip = bifurc.continue_orbit(cusp_flip_system(), "b", (0.0, 1.5), params={"a": -0.25, "b": 0.0},
                                     x0={"x": -0.63, "y1": 0.0, "y2": 0.0}, period=1, param2="a",
                                     span2=(-0.25, 0.5), error=error)
        for kind, a, b, tol in points(fold) + points(flip):
            exact = (0.0, 0.0) if kind == "cusp" else (math.copysign(0.25, a), 0.75)
            err = max(abs(a - exact[0]), abs(b - exact[1]))
            print(f"{str(error):>6} {kind:>10} {a:22.17g} {b:22.17g} {err:11.3g} {tol:9.2g} {tol / err:9.3g}")


if __name__ == "__main__":
    main()
