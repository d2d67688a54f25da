"""Where the attractor atlas' time goes (issue 31): its stages timed one by one, and each link alone (not CI).

    python benchmarks/atlas_stages.py [--n 29] [--starts 200] [--law measured] [--from 80] [--preset matlab-listing]

The atlas study's census (thesis-1dof at 10 Hz in V, box x=0:0.03, v=-1.5:1.5, seed 1) taken apart as
:func:`bifurc.attractors` runs it: every value's fresh starts on 2 workers (``_fresh``), the seeding with the previous
value's attractors and the matching (``_follow``, in this process), then each periodic appearance or disappearance
continued across its step (``link_event``) one after another, each timed alone.
"""
from __future__ import annotations

import argparse
import time

import numpy as np


def census_job(law: str, preset, values, n_starts: int):
    """(problem, grid, settings, job) of the atlas study's box census."""
    from bifurc.attractors.census import Settings
    from bifurc.attractors.identify import Grid
    from bifurc.attractors.job import CensusJob
    from bifurc.attractors.starts import make_starts
    from maps import problem
    pb = problem("thesis-1dof", preset, {"relay_hz": 10.0}, dc_law=law)
    st = make_starts(pb, "box", n=n_starts, box={"x": (0.0, 0.03), "v": (-1.5, 1.5)}, seed=1)
    grid = Grid.over(st.box, pb.system, 100, pb.state_vector())
    s = Settings()
    job = CensusJob(pb.with_values(V=float(values[0])), tuple({"V": float(v)} for v in values),
                    np.asarray(st.points, float), grid, s, 1e-10)
    return pb, grid, s, job


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--n", type=int, default=29)
    ap.add_argument("--starts", type=int, default=200)
    ap.add_argument("--law", default="measured")
    ap.add_argument("--from", dest="lo", type=float, default=80.0)
    ap.add_argument("--preset", default="matlab-listing")
    a = ap.parse_args(argv)
    from bifurc.attractors import atlas
    from bifurc.attractors.follow import link_event
    from maps import StroboscopicMap
    values = np.linspace(a.lo, 220.0, a.n)
    pb, grid, s, job = census_job(a.law, a.preset, values, a.starts)
    clock = time.perf_counter()
    import bifurc
    fresh, workers, _, _ = atlas._fresh(job, bifurc.Run(workers=2, progress=False), ("V",))
    t_fresh = time.perf_counter() - clock
    smap = StroboscopicMap(pb.with_values(V=float(values[0])), tol=1e-10)
    clock = time.perf_counter()
    points = [{"V": float(v)} for v in values]
    per_value, _, links, n_ids, _ = atlas._follow(smap, points, list(range(len(points))), fresh, grid, s, 20.0, True)
    t_follow = time.perf_counter() - clock
    print(f"{a.law}, {a.n} values in {a.lo:g}-220 V x {a.starts} starts: fresh starts {t_fresh:.1f} s on {workers} "
          f"workers; seeding and matching {t_follow:.1f} s; {n_ids} attractor ids; {len(links)} changes, "
          f"{sum(x[2].periodic for x in links)} periodic (linked by continuation):")
    total = 0.0
    for (key, what, att, step) in links:
        if not att.periodic or step is None:
            continue
        _, here, there, _ = step
        clock = time.perf_counter()
        kind, why = link_event(pb, "V", att, here, there, 1e-10)
        dt = time.perf_counter() - clock
        total += dt
        print(f"  {what} {att.label()} at {here:g} V (absent at {there:g} V): {dt:.1f} s, {kind}")
    print(f"linking, one after another: {total:.1f} s")


if __name__ == "__main__":
    main()
