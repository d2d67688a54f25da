"""The census' grid independence alone (issue 31): thesis-1dof, `measured` law, 10 Hz, 21 values x 200 starts at
100 and at 200 cells per side, no linking; every fraction (attractors summed by label, outcomes) of the second
against the first census' 95 % interval (:func:`attractors.grid_change`).  Not run in CI.

    python benchmarks/attractors_grid.py
    PYTHONPATH=/path/to/an/older/export python benchmarks/attractors_grid.py    # the same for another checkout
"""
from __future__ import annotations

import importlib.util
import pathlib

_spec = importlib.util.spec_from_file_location("_bench_attractors", pathlib.Path(__file__).with_name("attractors.py"))
bench = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(bench)


def main():
    import bifurc
    print(f"bifurc from {pathlib.Path(bifurc.__file__).parent}; {bench.load()}")
    ds, s1, c1 = bench.census(21, 200, link=False)
    half, s2, c2 = bench.census(21, 200, cells=200, link=False)
    print(f"100 cells: {s1:.1f} s ({c1:.1f} s CPU); 200 cells: {s2:.1f} s ({c2:.1f} s CPU); {bench.grid_change(ds, half)}")


if __name__ == "__main__":
    main()
