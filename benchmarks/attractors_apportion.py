"""Apportioning a known saddle's starts against following every start (issue 47 section 2); not run in CI.

    python benchmarks/attractors_apportion.py [--n 21] [--starts 200] [--rounds 2] [--save DIR]

The census of benchmarks/attractors.py (thesis-1dof, `matlab-listing`, `measured` law, 10 Hz, V in 80-220 V, box
x=0:0.03, v=-1.5:1.5, seed 1, 100 cells, 2 workers, linked) run ``--rounds`` times each way, interleaved (follow,
apportion, follow, apportion, ...), end to end; then once more apportioned with seed 2 (other starts).  Compared:

- each (value, attractor label) pair's fraction, a two-sample z test at 99 % (|z| > 2.576 rejects): the apportioned
  basin fraction against the followed census' eventual fraction (its starts still transient at the budget apportioned
  by the exits of the starts that left the same saddle) and against its basin fraction; variances from each
  fraction's 95 % interval (half width / 1.96, squared).  Seed 1 against seed 1 shares the starts (the samples are
  positively correlated, so the test is conservative: fewer rejections than independent samples would give); seed 2
  against seed 1 is a true two-sample test.  Attractors with the same label at a value are summed (their variances
  too); the outcomes (escaped, not_converged, ...) are compared as labels, "transient" left out.
- the stable periodic orbits present at each value (by label: period and impacts), followed against apportioned.
"""
from __future__ import annotations

import argparse
import os
import time

import numpy as np

Z99 = 2.5758293035489


def census(n, starts, apportion, seed=1):
    import bifurc
    from attractors import BOX, MODEL
    t = time.perf_counter()
    ds = bifurc.attractors("thesis-1dof", "V", np.linspace(80, 220, n), **MODEL, box=BOX, n_starts=starts, seed=seed,
                           cells=100, progress=False, workers=2, apportion=apportion)
    return ds, time.perf_counter() - t


def by_label(ds, which="basin_fraction") -> dict:
    """{(value index, label): (fraction, variance)} with attractors of one label at a value summed."""
    from attractors import words
    out, text = {}, words(ds)
    f, lo, hi = (ds[which + s].values for s in ("", "_low", "_high"))
    for i in range(f.shape[0]):
        for j in range(ds.sizes["attractor"]):
            if not np.isfinite(f[i, j]):
                continue
            if str(ds.attractor_label.values[j]).startswith("A"):
                if not ds.present.values[i, j]:
                    continue
                label = text[i, j]
            else:
                label = str(ds.attractor_label.values[j])
                if label == "transient":
                    continue
            var = ((hi[i, j] - lo[i, j]) / (2 * 1.959963984540054)) ** 2
            a, v = out.get((i, label), (0.0, 0.0))
            out[(i, label)] = (a + float(f[i, j]), v + float(var))
    return out


def two_sample(a: dict, b: dict) -> tuple[int, int, list]:
    """(pairs tested, pairs rejected at 99 %, the rejected ones with z); a pair absent on one side has fraction 0 and
    variance 0 there; pairs with fraction 0 on both sides are not tested."""
    tested, rejected = 0, []
    for key in sorted(set(a) | set(b)):
        (fa, va), (fb, vb) = a.get(key, (0.0, 0.0)), b.get(key, (0.0, 0.0))
        if fa == 0 and fb == 0:
            continue
        tested += 1
        z = (fa - fb) / np.sqrt(max(va + vb, 1e-300))
        if abs(z) > Z99:
            rejected.append((key, round(fa, 4), round(fb, 4), round(float(z), 2)))
    return tested, len(rejected), rejected


def stable_orbits(ds) -> set:
    """{(value index, label)} of the periodic attractors present."""
    import bifurc
    from attractors import words
    return {(i, text) for (i, j), text in words(ds).items()
            if ds.present.values[i, j] and int(ds.class_code.values[i, j]) == int(bifurc.ClassCode.PERIODIC)}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--n", type=int, default=21)
    ap.add_argument("--starts", type=int, default=200)
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--save", metavar="DIR", help="write the censuses here (netCDF)")
    a = ap.parse_args(argv)
    load = lambda: f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores"  # noqa: E731
    print(load(), flush=True)
    times, runs = {False: [], True: []}, {}
    for r in range(a.rounds):
        for apportion in (False, True):
            ds, sec = census(a.n, a.starts, apportion)
            times[apportion].append(sec)
            runs[apportion] = ds
            print(f"round {r + 1}, {'apportioned' if apportion else 'followed'}: {sec:.1f} s end to end, "
                  f"{ds.attrs['periods_per_start_mean']:.1f} periods per start; {load()}", flush=True)
    other, sec = census(a.n, a.starts, True, seed=2)
    print(f"apportioned, seed 2: {sec:.1f} s; {load()}", flush=True)
    fol, app = runs[False], runs[True]
    if a.save:
        os.makedirs(a.save, exist_ok=True)
        for name, ds in (("followed", fol), ("apportioned", app), ("apportioned-seed2", other)):
            ds.to_netcdf(os.path.join(a.save, f"{name}.nc"))
    best = {k: min(v) for k, v in times.items()}
    print(f"wall, best of {a.rounds} interleaved: followed {best[False]:.1f} s, apportioned {best[True]:.1f} s "
          f"(ratio {best[True] / best[False]:.3f}); all: followed {[round(t, 1) for t in times[False]]}, "
          f"apportioned {[round(t, 1) for t in times[True]]}")
    for title, x, y in (("apportioned vs followed (eventual), seed 1", by_label(app), by_label(fol, "eventual_fraction")),
                        ("apportioned vs followed (basin), seed 1", by_label(app), by_label(fol)),
                        ("apportioned seed 2 vs followed (eventual) seed 1", by_label(other),
                         by_label(fol, "eventual_fraction"))):
        tested, rej, which = two_sample(x, y)
        print(f"{title}: {rej} of {tested} (value, label) pairs rejected at 99 % ({100 * rej / max(tested, 1):.2f} %)"
              + (f": {which}" if which else ""))
    so_f, so_a, so_2 = stable_orbits(fol), stable_orbits(app), stable_orbits(other)
    print(f"stable periodic orbits (value, label): followed {len(so_f)}, apportioned {len(so_a)}; only followed "
          f"{sorted(so_f - so_a)}; only apportioned {sorted(so_a - so_f)}; apportioned seed 2: {len(so_2)}, "
          f"missing against followed seed 1 {len(so_f - so_2)}")
    print(f"links: followed {fol.attrs['links']}, apportioned {app.attrs['links']}")
    print(load())


if __name__ == "__main__":
    main()
