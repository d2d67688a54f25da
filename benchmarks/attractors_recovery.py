"""How many of the stable periodic orbits that the thesis-orbits study lists (thesis-1dof, `measured` law, 10 Hz)
the attractor census recovers from random starts and its previous values' attractors (issue 31, section 5; not CI).

    python benchmarks/attractors_recovery.py [--n 21] [--starts 200]

Reads studies/thesis_orbits/report.md's section "DC law `measured`, relay 10 Hz": every line "stable period-P
with M impacts per period for V in [a, b] V" is an orbit expected at each census value inside [a, b] (ends
included, to 1e-9).  It counts as recovered where the census has an attractor of period P with M impacts per
period at that value.  The census (V in 80-220 V, box x=0:0.03, v=-1.5:1.5, seed 1) gets no orbit from
continuation: only its random starts and the seeding with the previous value's attractors.
"""
from __future__ import annotations

import argparse
import pathlib
import re
import time

import numpy as np

REPORT = pathlib.Path(__file__).resolve().parents[1] / "studies" / "thesis_orbits" / "report.md"
LINE = re.compile(r"stable period-(\d+) with (\d+) impacts? per period for V in \[([\d.]+)[^,]*, ([\d.]+)[^\]]*\]")


def expected(values, path=REPORT) -> set:
    """{(value index, period, impacts)} of the stable orbits listed for the measured law at 10 Hz."""
    text = path.read_text()
    part = text.split("## DC law `measured`, relay 10 Hz", 1)[1].split("\n## ", 1)[0]
    out = set()
    for p, m, a, b in LINE.findall(part):
        for i, v in enumerate(values):
            if float(a) - 1e-9 <= v <= float(b) + 1e-9:
                out.add((i, int(p), int(m)))
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--n", type=int, default=21)
    ap.add_argument("--starts", type=int, default=200)
    a = ap.parse_args(argv)
    import bifurc
    from bifurc.attractors.census import OUTCOMES
    values = np.linspace(80, 220, a.n)
    clock = time.perf_counter()
    ds = bifurc.attractors("thesis-1dof", "V", values, params={"relay_hz": 10.0}, dc_law="measured",
                           box={"x": (0.0, 0.03), "v": (-1.5, 1.5)}, n_starts=a.starts, seed=1, progress=False,
                           link=False)
    sec = time.perf_counter() - clock
    want = expected(values)
    have = {(i, int(ds.period.values[i, j]), int(ds.impacts_per_period.values[i, j]))
            for i in range(len(values)) for j in range(ds.sizes["attractor"] - len(OUTCOMES)) if ds.present.values[i, j]}
    got = want & have
    share = 100 * len(got) / max(1, len(want))
    print(f"census {a.n} values x {a.starts} starts in {sec:.1f} s; stable orbits listed by thesis-orbits at these "
          f"values: {len(want)}; recovered with the same period and impacts: {len(got)} ({share:.0f} %; target 95 %)")
    for i, p, m in sorted(want - got):
        print(f"  missed at V = {values[i]:g}: period-{p} with {m} impacts per period")


if __name__ == "__main__":
    main()
