"""The attractor census on a Dask cluster (issue 47, section 5): 1 -> 2 workers scaling and the cost per start;
not run in CI.

    python benchmarks/attractors_dask.py                 # 8 values x 100 starts, LocalCluster of 1 then 2 workers
    python benchmarks/attractors_dask.py --values 16 --starts 200 --repeat 2

Runs the census of benchmarks/attractors.py (thesis-1dof, `matlab-listing`, `measured` law, 10 Hz, V in 80-220 V,
box x=0:0.03, v=-1.5:1.5, seed 1) on a ``dask.distributed.LocalCluster`` (processes, one thread each) of 1 and of 2
workers, interleaved ``--repeat`` times, best of each; checks the two datasets are equal on every variable but the
run time; writes a record to benchmarks/results/ (the load at the start and the end: the machine is shared).  The
cost per start (the one-worker run's fresh starts' seconds / (values x starts)) gives the expected wall time of a
larger census on N cores: points x starts x cost / N, plus the calling process' seeding and linking per value (which
do not spread) times the points.
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from attractors import BOX, MODEL  # noqa: E402

from record import Run  # noqa: E402


def census_on(address_or_client, values, n_starts, link):
    import bifurc
    t = time.perf_counter()
    ds = bifurc.attractors("thesis-1dof", "V", values, **MODEL, box=BOX, n_starts=n_starts, seed=1, progress=False,
                           scheduler=address_or_client, link=link)
    return ds, time.perf_counter() - t


def same(a, b) -> list:
    """The variables on which two census datasets differ (run time aside)."""
    out = []
    for k in a.data_vars:
        x, y = a[k].values, b[k].values
        equal = np.array_equal(x, y, equal_nan=True) if x.dtype.kind == "f" else np.array_equal(x, y)
        if not equal:
            out.append(k)
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--values", type=int, default=8)
    ap.add_argument("--starts", type=int, default=100)
    ap.add_argument("--repeat", type=int, default=1)
    ap.add_argument("--link", action="store_true", help="also link the events (runs in the calling process)")
    ap.add_argument("--no-record", action="store_true")
    a = ap.parse_args(argv)
    from dask.distributed import Client, LocalCluster
    values = np.linspace(80, 220, a.values)
    cmd = f"python benchmarks/attractors_dask.py --values {a.values} --starts {a.starts} --repeat {a.repeat}" + \
        (" --link" if a.link else "")
    run = Run(f"census on a Dask LocalCluster, 1 and 2 workers, {a.values} x {a.starts}", cmd)
    best, data = {1: np.inf, 2: np.inf}, {}
    for _ in range(a.repeat):
        for n in (1, 2):
            with LocalCluster(n_workers=n, processes=True, threads_per_worker=1, dashboard_address=None) as cl, \
                    Client(cl) as client:
                ds, sec = census_on(client, values, a.starts, a.link)
            best[n] = min(best[n], sec)
            data[n] = ds
            print(f"{n} worker(s): {sec:.1f} s", flush=True)
    diff = same(data[1], data[2])
    one = data[1].attrs
    cost = float(one["fresh_seconds"]) / (a.values * a.starts)          # one worker: its wall is its CPU
    serial = (float(one["seeding_seconds"]) + float(one["linking_seconds"])) / a.values
    speedup = best[1] / best[2]
    per64 = 281 * 1000 * cost / 64 + 281 * serial
    print(f"1 -> 2 workers: {best[1]:.1f} -> {best[2]:.1f} s, {speedup:.2f}x; datasets differ on: {diff or 'none'}")
    print(f"fresh starts on one worker: {cost * 1e3:.1f} ms per start; seeding and linking {serial:.2f} s per value "
          f"in the calling process; 281 x 1000 on 64 cores: {per64 / 60:.1f} min")
    if not a.no_record:
        run.figure(f"census {a.values} x {a.starts} on a LocalCluster, 1 worker", round(best[1], 2), "s")
        run.figure(f"census {a.values} x {a.starts} on a LocalCluster, 2 workers", round(best[2], 2), "s")
        run.figure("1 -> 2 workers speed-up", round(speedup, 3), "x", target=">= 1.7x")
        run.figure("fresh starts' census per start on one worker", round(cost * 1e3, 2), "ms")
        run.figure("seeding and linking per value in the calling process", round(serial, 3), "s")
        run.figure("281 x 1000 on 64 cores (281 x 1000 x cost / 64 + 281 x seeding and linking)", round(per64 / 60, 2),
                   "min")
        print(run.write(notes=f"datasets of 1 and 2 workers equal on every variable: {not diff}. Best of "
                              f"{a.repeat}; the machine is shared (load above)."))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
