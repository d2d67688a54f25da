"""Regime-map throughput and memory: what `bifurc map` runs, locally and on a Dask LocalCluster.

thesis-1dof, preset matlab-listing (its `listing` DC law), relay_hz 2-10 Hz x V 25-300 V,
300 transient + 100 recorded relay periods per cell, tol 1e-10, Lyapunov exponents and the
error estimate on, streamed to disk (``path``), as `bifurc map` does.  Measured in one run:

1. ``bifurc.regime_map`` on ``--n x --n2`` cells with ``--workers`` local processes: wall time
   (process start and compilation included), cells per second, peak resident memory of this
   process and of the largest worker (``getrusage``).  A grid smaller than 100 x 100 prints the
   100 x 100 time extrapolated from its cells per second, labelled as such.
2. the same function on a Dask LocalCluster (processes, one thread each) with 1 and then 2
   workers on ``--dask-n x --dask-n2`` cells, chunks of ``--chunk`` cells for both: the speed-up
   and the scheduling share of the 1-worker run, 1 - (cell time) / (wall time), which says
   whether the grid is large enough (target < 5 %).

3. with ``--bare-n``: what the integration alone costs.  On a ``--bare-n x --bare-n2`` sub-grid
   spanning the same plane, in this one process (compilation done beforehand), the CPU time of
   ``bifurc.regime_map`` (everything; and without the error estimate) against the bare heyoka
   ensemble of ``benchmarks/frequency_diagram.py`` (``BareBatchTangent``: the same transient and
   tangent-vector record, records as long as the product's, with the least Python possible), and
   the 100 x 100 wall time on 2 cores that the bare ensemble alone implies (its CPU per cell times
   10 000 / 2: a floor under the 180 s target, not a measurement).

    python benchmarks/regime_map.py [--n 100] [--n2 100] [--workers 2] [--dask-n 16] [--dask-n2 16] [--chunk 16]
                                    [--bare-n 10 --bare-n2 10]
"""
from __future__ import annotations

import argparse
import os
import resource
import tempfile
import time

import numpy as np

from bifurc import regime_map

PROBLEM = dict(scene="thesis-1dof", param="relay_hz", param2="V", preset="matlab-listing", dc_law="listing",
               tol=1e-10, progress=False)


def grid(n, n2):
    return dict(values=np.linspace(2.0, 10.0, n), values2=np.linspace(25.0, 300.0, n2))


def local_run(args):
    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.perf_counter()
        ds = regime_map(**PROBLEM, **grid(args.n, args.n2), transient=args.transient, record=args.record,
                        workers=args.workers, path=os.path.join(tmp, "map.nc"))
        wall = time.perf_counter() - t0
    cells = args.n * args.n2
    print(f"1. bifurc.regime_map, {args.n} x {args.n2} = {cells} cells x ({args.transient} + {args.record}) periods, "
          f"{args.workers} local workers: {wall:.1f} s wall ({cells / wall:.1f} cells/s; cell time "
          f"{ds.attrs['values_seconds']:.1f} s)")
    if cells != 10_000 or (args.transient, args.record) != (300, 100):
        est = 10_000 / cells * wall * (400 / (args.transient + args.record))
        print(f"   EXTRAPOLATED (not measured) 100 x 100 x (300 + 100): {est:.0f} s at this grid's cells/s "
              f"(target <= 180 s)")
    else:
        print(f"   100 x 100 target <= 180 s: {'met' if wall <= 180 else 'NOT met'}")
    codes = np.bincount(ds.class_code.values.ravel().clip(0), minlength=7)
    print(f"   classes (code: cells): {dict(enumerate(codes.tolist()))}")
    me = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    kids = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024
    total = me + args.workers * kids
    print(f"   peak RSS: main {me:.0f} MiB, largest worker {kids:.0f} MiB; main + {args.workers} x worker = "
          f"{total:.0f} MiB (target < 1024 MiB: {'met' if total < 1024 else 'NOT met'})")


def dask_runs(args):
    from dask.distributed import Client, LocalCluster
    walls, cell_time = {}, {}
    for n_workers in (1, 2):
        with LocalCluster(n_workers=n_workers, processes=True, threads_per_worker=1, dashboard_address=None) as c, \
                Client(c) as client:
            t0 = time.perf_counter()
            ds = regime_map(**PROBLEM, **grid(args.dask_n, args.dask_n2), transient=args.transient, record=args.record,
                            scheduler=client, chunk_size=args.chunk)
            walls[n_workers] = time.perf_counter() - t0
            cell_time[n_workers] = ds.attrs["values_seconds"]
    cells = args.dask_n * args.dask_n2
    share = 1.0 - cell_time[1] / walls[1]
    print(f"2. Dask LocalCluster, {args.dask_n} x {args.dask_n2} = {cells} cells, chunks of {args.chunk}: 1 worker "
          f"{walls[1]:.1f} s, 2 workers {walls[2]:.1f} s: speed-up {walls[1] / walls[2]:.2f}x (target >= 1.6x); "
          f"scheduling and start share of the 1-worker run {100 * share:.1f} % (target < 5 %)")


def bare_floor(args):
    """Product against the bare tangent-vector ensemble on the same cells, CPU time in one process."""
    from frequency_diagram import BareBatchTangent, Problem, cpu_seconds
    W, V = np.linspace(2.0, 10.0, args.bare_n), np.linspace(25.0, 300.0, args.bare_n2)
    sc = __import__("maps").get_scene("thesis-1dof").with_options(dc_law="listing")
    run = dict(**PROBLEM, values=W, values2=V, transient=args.transient, record=args.record, workers=1)
    regime_map(**dict(run, values=W[:1], values2=V[:1], transient=3, record=3))       # compile
    cpu = {}
    for label, kw in (("everything", {}), ("without error estimate", dict(error_sample=0))):
        c0 = cpu_seconds()
        ds = regime_map(**run, **kw)
        cpu[label] = cpu_seconds() - c0
    used = ds["record_used"].values
    bare = 0.0
    for j, v in enumerate(V):
        problem = Problem(sc.parameters(preset="matlab-listing", V=float(v)), transient=args.transient,
                          record=args.record, tol=PROBLEM["tol"],
                          records=tuple((float(w), int(r)) for w, r in zip(W, used[:, j]) if 0 < r != args.record))
        base = BareBatchTangent(problem)
        base.warm()
        c0 = cpu_seconds()
        base.run_many(W)
        bare += cpu_seconds() - c0
    cells = W.size * V.size
    print(f"3. {args.bare_n} x {args.bare_n2} = {cells} cells in one process, CPU time (compiled beforehand): "
          f"bifurc.regime_map {cpu['everything']:.1f} s ({cpu['without error estimate']:.1f} s without the error "
          f"estimate), bare tangent-vector ensemble {bare:.1f} s: ratio {cpu['everything'] / bare:.2f} "
          f"({cpu['without error estimate'] / bare:.2f})")
    print(f"   per cell: product {1e3 * cpu['everything'] / cells:.1f} ms, bare {1e3 * bare / cells:.1f} ms; "
          f"the bare ensemble alone implies {bare / cells * 10_000 / 2:.0f} s for 100 x 100 on 2 cores "
          f"(a floor, extrapolated; target <= 180 s)")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--n", type=int, default=100)
    ap.add_argument("--n2", type=int, default=100)
    ap.add_argument("--transient", type=int, default=300)
    ap.add_argument("--record", type=int, default=100)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--dask-n", type=int, default=16)
    ap.add_argument("--dask-n2", type=int, default=16)
    ap.add_argument("--chunk", type=int, default=16, help="cells per Dask task")
    ap.add_argument("--skip-local", action="store_true")
    ap.add_argument("--skip-dask", action="store_true")
    ap.add_argument("--bare-n", type=int, default=0, help="sub-grid for the bare-ensemble comparison (0: none)")
    ap.add_argument("--bare-n2", type=int, default=10)
    args = ap.parse_args(argv)
    print(f"load average before: {os.getloadavg()} on {os.cpu_count()} cores")
    if not args.skip_local:
        local_run(args)
    if not args.skip_dask:
        dask_runs(args)
    if args.bare_n:
        bare_floor(args)
    print(f"load average after: {os.getloadavg()}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
