"""Peak memory of a large sweep streamed to disk.

thesis-1dof, matlab-listing, V = 90 V, ``--n`` relay frequencies in [2, 10] Hz written chunk by
chunk into a netCDF file by ``bifurc.parallel.sweep_dataset(..., path=...)``.  Prints the peak
resident set size of this process and of the largest worker process (``getrusage``).
The default transient is shortened (30 periods) to keep the run to minutes on 2 cores: memory
depends on the recorded window (100 periods, 1600 impact slots per value), not on the transient.

    python benchmarks/memory.py [--n 5000] [--transient 30] [--record 100] [--workers 2] [--scalar]
"""
from __future__ import annotations

import argparse
import os
import resource
import tempfile
import time

import numpy as np

import maps
from bifurc.parallel import BatchStroboscopicTask, StroboscopicTask, sweep_dataset


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--n", type=int, default=5000)
    ap.add_argument("--transient", type=int, default=30)
    ap.add_argument("--record", type=int, default=100)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--scalar", action="store_true", help="scalar task instead of heyoka batch mode")
    args = ap.parse_args(argv)
    print(f"load average before: {os.getloadavg()}")
    sc = maps.get_scene("thesis-1dof").with_options(dc_law="listing")   # matlab-listing's law
    cls = StroboscopicTask if args.scalar else BatchStroboscopicTask
    task = cls(sc, "relay_hz", sc.parameters(preset="matlab-listing", V=90.0),
                            transient=args.transient, record=args.record, tol=1e-10)
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "sweep.nc")
        t0 = time.perf_counter()
        ds = sweep_dataset(task, np.linspace(2.0, 10.0, args.n), workers=args.workers, path=path)
        wall = time.perf_counter() - t0
        size = os.path.getsize(path) / 2**20
        ok = int((ds["status"] == 0).sum())
        ds.close()
    me = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    kids = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024
    print(f"{cls.__name__}: {args.n} values x ({args.transient} + {args.record}) periods, {args.workers} workers: {wall:.1f} s, "
          f"file {size:.0f} MiB, status ok {ok}/{args.n}")
    print(f"peak RSS: main process {me:.0f} MiB, largest worker {kids:.0f} MiB")
    total = me + args.workers * kids
    print(f"target < 1 GB (main + {args.workers} x worker = {total:.0f} MiB): {'met' if total < 1024 else 'NOT met'}")
    print(f"load average after: {os.getloadavg()}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
