"""Peak memory of a large sweep streamed to disk, on the path `bifurc diagram` runs.

thesis-1dof, matlab-listing, V = 90 V, ``--n`` relay frequencies in [2, 10] Hz by
``bifurc.sweeps.sweep.sweep(..., path=...)``: every completed chunk is saved under ``<path>.parts/``
and the Dataset is assembled at the end.  Prints the peak resident set size of this process
and of the largest worker process (``getrusage``).  The default transient is shortened (30
periods) to keep the run to minutes on 2 cores: memory depends on the recorded window (100
periods, 400 impact slots per value), not on the transient.  Lyapunov exponents, grazing search
and the error estimate are on, as in `bifurc diagram`; ``--lean`` turns them off.

    python benchmarks/memory.py [--n 5000] [--transient 30] [--record 100] [--workers 2] [--batch-size 4] [--lean]
"""
from __future__ import annotations

import argparse
import os
import resource
import tempfile
import time

import numpy as np

from bifurc import sweep


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--n", type=int, default=5000)
    ap.add_argument("--transient", type=int, default=30)
    ap.add_argument("--record", type=int, default=100)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--batch-size", type=int, default=4, help="SIMD lanes (1: one HybridRun per value)")
    ap.add_argument("--lean", action="store_true", help="no Lyapunov exponents, grazing search or error estimate")
    args = ap.parse_args(argv)
    print(f"load average before: {os.getloadavg()}")
    lean = dict(lyapunov=False, grazing=False, error_sample=0) if args.lean else {}
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "sweep.nc")
        t0 = time.perf_counter()
        ds = sweep("thesis-1dof", "relay_hz", np.linspace(2.0, 10.0, args.n), preset="matlab-listing",
                   params={"V": 90.0}, transient=args.transient, record=args.record, tol=1e-10, path=path,
                   workers=args.workers, batch_size=args.batch_size, progress=False, **lean)
        wall = time.perf_counter() - t0
        size = os.path.getsize(path) / 2**20
        ok = int((ds["status"] == 0).sum())
    me = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    kids = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024
    print(f"bifurc.sweep{' (lean)' if args.lean else ''}, batch_size {args.batch_size}: {args.n} values x "
          f"({args.transient} + {args.record}) periods, {args.workers} workers: {wall:.1f} s, file {size:.0f} MiB, "
          f"status ok {ok}/{args.n}")
    print(f"peak RSS: main process {me:.0f} MiB, largest worker {kids:.0f} MiB")
    total = me + args.workers * kids
    print(f"target < 1 GB (main + {args.workers} x worker = {total:.0f} MiB): {'met' if total < 1024 else 'NOT met'}")
    print(f"load average after: {os.getloadavg()}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
