"""Where the attractor atlas' time goes (issue 31): its stages as the census states them (not CI).

    python benchmarks/atlas_stages.py [--n 29] [--starts 200] [--law measured] [--from 80] [--preset matlab-listing]

The atlas study's census (thesis-1dof at 10 Hz in V, box x=0:0.03, v=-1.5:1.5, seed 1) run by :func:`bifurc.attractors`
on 2 workers; printed from the dataset's attributes: every value's fresh starts (``fresh_seconds``, and the CPU of
their stages summed over the workers: ``fresh_cpu_seconds_<stage>``), the seeding with the neighbouring values'
attractors and the matching (``seeding_seconds``), the linking of each periodic appearance or disappearance by
continuation across its step (``linking_seconds``, on the workers), then each change with its link and evidence
(``event_link``, ``event_evidence``).  Public API only; before 2026-11-29 it ran the census' private stages one by one
and timed each link alone (``link_event``), which the census does not report.
"""
from __future__ import annotations

import argparse
import time

import numpy as np


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--n", type=int, default=29)
    ap.add_argument("--starts", type=int, default=200)
    ap.add_argument("--law", default="measured")
    ap.add_argument("--from", dest="lo", type=float, default=80.0)
    ap.add_argument("--preset", default="matlab-listing")
    a = ap.parse_args(argv)
    import bifurc
    import maps
    values = np.linspace(a.lo, 220.0, a.n)
    pb = maps.problem("thesis-1dof", a.preset, {"relay_hz": 10.0}, dc_law=a.law)
    clock = time.perf_counter()
    ds = bifurc.attractors(pb, "V", values, starts=bifurc.Box(n=a.starts, box={"x": (0.0, 0.03), "v": (-1.5, 1.5)},
                                                             seed=1), run=bifurc.Run(workers=2, progress=False))
    total = time.perf_counter() - clock
    at = ds.attrs
    cpu = ", ".join(f"{k.removeprefix('fresh_cpu_seconds_')} {float(x):.1f}" for k, x in at.items()
                    if k.startswith("fresh_cpu_seconds_"))
    ids = [j for j, lab in enumerate(ds.attractor_label.values) if str(lab).startswith("A")]
    print(f"{a.law}, {a.n} values in {a.lo:g}-220 V x {a.starts} starts, {total:.1f} s end to end: fresh starts "
          f"{float(at['fresh_seconds']):.1f} s on {at['workers']} workers (CPU by stage [s]: {cpu}); seeding and "
          f"matching {float(at['seeding_seconds']):.1f} s; linking {float(at['linking_seconds']):.1f} s; {len(ids)} "
          f"attractor ids; {at['links']} changes:")
    for i, j in zip(*np.nonzero(ds.event.values[:, ids])):
        j = ids[j]
        print(f"  {float(values[i]):g} V, {ds.attractor_label.values[j]}: {ds.event_link.values[i, j] or '-'} "
              f"({ds.event_evidence.values[i, j]})")


if __name__ == "__main__":
    main()
