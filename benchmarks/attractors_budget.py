"""What a shorter periods' budget costs the census' answers (issue 31, section 5: the 30 s target).  Not run in CI.

    python benchmarks/attractors_budget.py [--budgets 2000 1000 500] [--n 21] [--starts 200]

The census of benchmarks/attractors.py (thesis-1dof, `matlab-listing`, `measured` law, 10 Hz, V in 80-220 V, box
x=0:0.03, v=-1.5:1.5, seed 1, 100 cells per side, every core, linking off) at each ``max_periods`` budget, one after
the other: wall seconds, relay periods per start, the share of starts "transient" (still on a chaotic saddle at the
budget) and "not_converged".  Each shorter budget's eventual fractions (transients apportioned by their saddle's
observed exits, :mod:`bifurc.attractors.eventual`) are compared with the first (longest) budget's, attractors summed
by label at each value: how many (value, label) pairs' intervals do not contain the longest budget's eventual
fraction, and the mean interval width of each.
"""
from __future__ import annotations

import argparse
import time

import numpy as np


def by_label(ds, i) -> dict:
    """{label: (eventual, low, high)} at value index ``i``, the attractors of one label summed (bounds summed: a
    conservative interval of the sum)."""
    from attractors import words
    out, text = {}, words(ds)
    for j, name in enumerate(ds.attractor_label.values):
        if str(name).startswith("A"):
            if not ds.present.values[i, j]:
                continue
            name = text[i, j]
        got = np.array([ds[k].values[i, j] for k in ("eventual_fraction", "eventual_fraction_low",
                                                     "eventual_fraction_high")])
        out[str(name)] = out.get(str(name), np.zeros(3)) + got
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--budgets", nargs="+", type=int, default=[2000, 1000, 500])
    ap.add_argument("--n", type=int, default=21)
    ap.add_argument("--starts", type=int, default=200)
    a = ap.parse_args(argv)
    import bifurc
    from attractors import BOX, MODEL
    runs = {}
    for b in a.budgets:
        t = time.perf_counter()
        ds = bifurc.attractors("thesis-1dof", "V", np.linspace(80, 220, a.n), **MODEL, box=BOX, n_starts=a.starts,
                               seed=1, progress=False, link=False, budget=b)
        wall = time.perf_counter() - t
        labels = list(ds.attractor_label.values)
        share = {k: float(ds.basin_fraction.values[:, labels.index(k)].mean()) for k in ("transient", "not_converged")}
        print(f"max_periods {b}: {wall:.1f} s wall, {ds.attrs['periods_per_start_mean']:.1f} relay periods per start; "
              f"mean share transient {share['transient']:.3f}, not_converged {share['not_converged']:.3f}", flush=True)
        runs[b] = ds
    ref = runs[a.budgets[0]]
    for b in a.budgets[1:]:
        ds, outside, pairs, widths = runs[b], [], 0, ([], [])
        for i, v in enumerate(ds["V"].values):
            mine, theirs = by_label(ds, i), by_label(ref, i)
            for name in sorted(set(mine) | set(theirs)):
                m = mine.get(name, np.zeros(3))
                r = theirs.get(name, np.zeros(3))
                if not (m.any() or r.any()):
                    continue
                pairs += 1
                widths[0].append(m[2] - m[1])
                widths[1].append(r[2] - r[1])
                if not m[1] - 1e-12 <= r[0] <= m[2] + 1e-12:
                    outside.append(f"{v:g} V {name}: {m[0]:.3f} ({m[1]:.3f}-{m[2]:.3f}) vs {r[0]:.3f}")
        print(f"max_periods {b} against {a.budgets[0]}: {len(outside)} of {pairs} (value, label) eventual fractions of "
              f"the longer budget outside the shorter one's interval; mean interval width {np.mean(widths[0]):.3f} "
              f"against {np.mean(widths[1]):.3f}", flush=True)
        for line in outside:
            print("   " + line)


if __name__ == "__main__":
    main()
