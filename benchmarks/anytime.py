"""The anytime classification's overhead: a diagram with the default budget against a fixed-record
run of the same total relay periods, side by side in one run.

    python benchmarks/anytime.py [--n 1000] [--workers 2]

The default diagram (thesis-1dof, matlab-listing, 90 V, 2-10 Hz) extends undecided values up to the
budget, with the exponent's copies; it stores each value's ``periods_integrated``.  The fixed run
gives every value the same number of relay periods on one trajectory (the transient, then one
record of the mean total less the transient, with its tangent vector), nothing extended.  The ratio
of their wall times is the overhead of judging, extending and copying (issue 27's target: 1.3x).
Also printed: the classes of both, and how many values the default run decided.
"""
from __future__ import annotations

import argparse
import collections
import os
import time

import numpy as np

import bifurc
from bifurc import ClassCode


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--n", type=int, default=1000)
    ap.add_argument("--workers", type=int, default=2)
    args = ap.parse_args(argv)
    values = np.linspace(2.0, 10.0, args.n)
    kw = dict(preset="matlab-listing", params={"V": 90.0}, progress=False, workers=args.workers)
    print(f"load average before: {os.getloadavg()}, cores: {os.cpu_count()}", flush=True)
    t0 = time.perf_counter()
    a = bifurc.sweep("thesis-1dof", "relay_hz", values, **kw)
    wall_a = time.perf_counter() - t0
    total = int(a.periods_integrated.sum())
    per_value = max(400, round(total / args.n))
    record = per_value - 300
    t0 = time.perf_counter()
    f = bifurc.sweep("thesis-1dof", "relay_hz", values, transient=300, record=record, max_record=record,
                     budget=per_value, **kw)
    wall_f = time.perf_counter() - t0
    print(f"load average after: {os.getloadavg()}")

    def counts(ds):
        c = collections.Counter(ClassCode(int(x)).label for x in ds.class_code.values.ravel())
        return ", ".join(f"{k} {v}" for k, v in sorted(c.items()))

    undecided = int(np.sum(a.class_code.values == ClassCode.NOT_CONVERGED))
    print(f"anytime (default budget {a.attrs['budget_periods']}): {wall_a:.1f} s wall, {total} relay periods "
          f"integrated ({total / args.n:.0f} per value, copies included); {counts(a)}; decided "
          f"{args.n - undecided} of {args.n}")
    print(f"fixed record ({per_value} periods per value, one trajectory): {wall_f:.1f} s wall; {counts(f)}")
    print(f"\n| run | wall [s] | relay periods per value | decided |\n|---|---|---|---|\n"
          f"| anytime (default) | {wall_a:.1f} | {total / args.n:.0f} | {args.n - undecided} / {args.n} |\n"
          f"| fixed record | {wall_f:.1f} | {per_value} | "
          f"{int(np.sum(f.class_code.values != ClassCode.NOT_CONVERGED))} / {args.n} |\n"
          f"\nratio anytime / fixed: {wall_a / wall_f:.2f} (target <= 1.3)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
