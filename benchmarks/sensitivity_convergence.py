"""Is the sensitivity study's per-sample regime map converged at a shorter transient and record?

Runs the medium form (the full form's inputs and 9 x 9 cells at N = 8: 107 samples) at ``--transient`` +
``--record`` relay periods and compares each sample's outputs with those of the medium form at the full
form's 200 + 60 (``--reference``: the samples.json that ``benchmarks/sensitivity.py`` wrote): the samples
whose hammering share differs, by how many cells, and the CPU time of both (this run measured here, the
reference's from its own run).  A shorter setting is justified only where no share moves.

    python benchmarks/sensitivity_convergence.py [--transient 100] [--record 40] [--workers 2]
        [--reference out/bench-sensitivity/samples.json] [--out out/bench-sensitivity-short]
"""
from __future__ import annotations

import argparse
import json
import os
import shutil
import time

import numpy as np

from sensitivity import _cpu   # benchmarks/sensitivity.py (this folder is on sys.path when run as a script)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--transient", type=int, default=100)
    ap.add_argument("--record", type=int, default=40)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--reference", default="out/bench-sensitivity/samples.json")
    ap.add_argument("--out", default="out/bench-sensitivity-short")
    a = ap.parse_args()
    import studies.sensitivity as S
    ref = json.loads(open(a.reference).read())
    print(f"load average at start: {os.getloadavg()}; cores: {os.cpu_count()}")
    shutil.rmtree(a.out, ignore_errors=True)
    size = dict(S.MEDIUM, transient=a.transient, record=a.record)
    t, c = time.perf_counter(), _cpu()
    res = S.run(a.out, size=size, workers=a.workers, progress=True)
    wall, cpu = time.perf_counter() - t, _cpu() - c
    cells = size["n"] ** 2
    short = np.asarray(res["outputs_per_sample"]["share_p1"]) * cells
    full = np.asarray(ref["outputs"]["share_p1"]) * cells
    moved = np.flatnonzero(np.round(short) != np.round(full))
    print(f"{a.transient} + {a.record} periods: {res['n_samples']} samples in {wall:.0f} s wall, {cpu:.0f} s CPU")
    print(f"hammering cells per sample, 200 + 60 against {a.transient} + {a.record}: {int(full.sum())} and "
          f"{int(short.sum())} cells in all; samples that differ: {moved.size} of {full.size}"
          + (f" (rows {moved.tolist()}, by {np.abs(short - full)[moved].round().astype(int).tolist()} cells)"
             if moved.size else ""))
    print(f"load average at end: {os.getloadavg()}")


if __name__ == "__main__":
    main()
