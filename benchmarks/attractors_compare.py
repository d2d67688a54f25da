"""Two censuses start by start: the outcome labels written by `attractors_profile.py --save` at two commits.

    python benchmarks/attractors_compare.py BEFORE.json AFTER.json

Prints, per value where any start's outcome differs, the number of such starts and both censuses' counts by
label (attractors by class, period and impacts; the outcomes by name).
"""
from __future__ import annotations

import json
import sys
from collections import Counter


def main(argv=None):
    a, b = (json.load(open(f)) for f in (argv or sys.argv[1:])[:2])
    changed = 0
    for v in a:
        diff = sum(x != y for x, y in zip(a[v], b[v]))
        changed += diff
        if diff:
            print(f"{v} V: {diff} of {len(a[v])} starts differ; before {dict(sorted(Counter(a[v]).items()))}; "
                  f"after {dict(sorted(Counter(b[v]).items()))}")
    print(f"{changed} of {sum(len(x) for x in a.values())} starts differ over {len(a)} values")


if __name__ == "__main__":
    main()
