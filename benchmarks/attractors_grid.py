"""The census' grid independence alone (issue 31): thesis-1dof, `measured` law, 10 Hz, 21 values x 200 starts at
100 and at 200 cells per side, no linking; every fraction (attractors summed by label, outcomes) of the second
against the first census' 95 % interval (:func:`attractors.grid_change`).  Not run in CI.

    python benchmarks/attractors_grid.py
    python benchmarks/attractors_grid.py --control   # the measure's noise floor: the same 100-cell census of the
                                                     # starts perturbed by 1e-12 (relative), no grid change
    PYTHONPATH=/path/to/an/older/export python benchmarks/attractors_grid.py    # the same for another checkout
"""
from __future__ import annotations

import importlib.util
import pathlib

_spec = importlib.util.spec_from_file_location("_bench_attractors", pathlib.Path(__file__).with_name("attractors.py"))
bench = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(bench)


def perturbed_starts(rel: float = 1e-12):
    """The benchmark's 200 box starts (seed 1), each state multiplied by 1 + rel N(0, 1) (seed 2), as given starts
    (the census' grid then spans the scene's declared box: the benchmark's box)."""
    import bifurc
    import maps
    import numpy as np
    pb = maps.problem("thesis-1dof", params={"relay_hz": 10.0}, dc_law="measured")
    p = np.asarray(bifurc.Box(n=200, box=bench.BOX, seed=1).draw(pb).points, dtype=float)
    return bifurc.Given(p * (1.0 + rel * np.random.default_rng(2).standard_normal(p.shape)))


def main(argv=None):
    import argparse

    import bifurc
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--control", action="store_true", help="100 cells against 100 cells of perturbed starts")
    a = ap.parse_args(argv)
    print(f"bifurc from {pathlib.Path(bifurc.__file__).parent}; {bench.load()}")
    ds, s1, c1 = bench.census(21, 200, link=False)
    if a.control:
        same, s2, c2 = bench.census(21, 200, link=False, starts=perturbed_starts())
        print(f"100 cells: {s1:.1f} s ({c1:.1f} s CPU); 100 cells, starts perturbed by 1e-12: {s2:.1f} s "
              f"({c2:.1f} s CPU); {bench.grid_change(ds, same)}")
        return
    half, s2, c2 = bench.census(21, 200, cells=200, link=False)
    print(f"100 cells: {s1:.1f} s ({c1:.1f} s CPU); 200 cells: {s2:.1f} s ({c2:.1f} s CPU); {bench.grid_change(ds, half)}")


if __name__ == "__main__":
    main()
