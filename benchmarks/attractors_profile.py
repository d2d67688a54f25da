"""Where the attractor census' time goes beyond the bare periods (issue 31, section 5); not run in CI.

    python benchmarks/attractors_profile.py [V ...] [--starts N] [--profile FILE]

One process: for each value (default 122 136 192 206 V; thesis-1dof as benchmarks/attractors.py runs it: the
`matlab-listing` preset since 2026-11-26 15:00, the scene's default `thesis-text` before; `measured` law, 10 Hz, box
x=0:0.03, v=-1.5:1.5, seed 1, 100 cells per side) the census of the fresh starts, then a bare batch ensemble of the same
starts each run for the periods it spent in the census (strobe points only), side by side.  With ``--profile``
the census calls run under cProfile and the functions are ranked by cumulative time.
"""
from __future__ import annotations

import argparse
import cProfile
import os
import pstats
import time

import numpy as np


def lanes() -> None:
    """CPU seconds of 1000 periods on 1, 2 and 4 lanes of one batch call (events=False), from the first 4 of 40
    box starts still aperiodic after 300 periods at 171 and 213 V (chaotic attractors)."""
    import maps
    from bifurc.attractors.starts import make_starts
    from maps.poincare import StroboscopicMap
    pb = maps.problem("thesis-1dof", params={"relay_hz": 10.0}, dc_law="measured")
    starts = list(np.asarray(make_starts(pb, "box", n=40, box={"x": (0.0, 0.03), "v": (-1.5, 1.5)}, seed=1).points,
                             dtype=float))
    smap = StroboscopicMap(pb, tol=1e-10)
    for v in (171.0, 213.0):
        smap = smap.at(dict(V=v))
        pre = smap.orbits([{}] * len(starts), starts, 300, batch_size=4, events=False)
        chaotic = [o.final for o in pre if np.ptp(o.points[-64:, 0]) > 1e-4][:4]
        for m in (1, 2, 4):
            c = time.process_time()
            smap.orbits([{}] * m, chaotic[:m], 1000, k0=300, batch_size=4, events=False)
            print(f"{v:g} V: {m} of 4 lanes x 1000 periods: {time.process_time() - c:.3f} s CPU")


def _labels(r) -> list:
    """Each start's outcome in words: its attractor's label, or the outcome's name."""
    from bifurc.attractors.census import outcome_labels
    return outcome_labels(r.outcomes, r.found)


def _timed(smap) -> dict:
    """Accumulate CPU seconds of ``smap.orbits`` by calling function and of Newton (find_periodic_orbit)."""
    import sys

    from bifurc.attractors import identify
    spent: dict = {}

    def wrap(fn, name=None):
        def inner(*args, **kw):
            caller = sys._getframe(1).f_code.co_name
            if caller == "main":
                return fn(*args, **kw)       # the bare ensemble, not the census
            key = name or f"orbits from {caller}"
            t = time.process_time()
            try:
                return fn(*args, **kw)
            finally:
                spent[key] = spent.get(key, 0.0) + time.process_time() - t
        return inner
    # on the class: ``smap.at(values)`` copies the map, and a wrapper bound to the instance would run every value at the
    # instance's own parameters (before 2026-11-29 ``--split`` timed every value's census at the base problem's V)
    cls = type(smap)
    cls.orbits = wrap(cls.orbits)
    identify.find_periodic_orbit = wrap(identify.find_periodic_orbit, "Newton")
    return spent


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("values", nargs="*", type=float, default=[122.0, 136.0, 192.0, 206.0])
    ap.add_argument("--starts", type=int, default=200)
    ap.add_argument("--profile", metavar="FILE", help="write the census' cProfile stats here and print a ranking")
    ap.add_argument("--split", action="store_true", help="time the census' batch calls by caller and Newton")
    ap.add_argument("--lanes", action="store_true", help="only the cost of 1, 2 and 4 batch lanes on chaotic "
                                                         "trajectories (171 and 213 V): what a persistence copy costs")
    ap.add_argument("--apportion", action="store_true", help="also the census with apportion=True after each value's "
                    "followed one (issue 47 section 2): its CPU against the bare ensemble of the followed periods")
    ap.add_argument("--save", metavar="FILE", help="write each start's outcome (attractor label or outcome name) "
                                                   "per value here (JSON), to compare two commits start by start")
    a = ap.parse_args(argv)
    import maps
    from bifurc.attractors.census import Settings
    from bifurc.labels.codes import OUTCOMES
    from bifurc.attractors.identify import Grid
    from bifurc.attractors.job import CensusJob
    from bifurc.attractors.starts import make_starts
    from maps.poincare import StroboscopicMap
    print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
    if a.lanes:
        return lanes()
    from attractors import BOX, MODEL       # the census of benchmarks/attractors.py
    pb = maps.problem("thesis-1dof", **MODEL)
    st = make_starts(pb, "box", n=a.starts, box=BOX, seed=1)
    starts = list(np.asarray(st.points, dtype=float))
    job = CensusJob(pb, (), np.asarray(starts), Grid.over(st.box, pb.system, 100, pb.state_vector()), Settings())
    job.warm()
    smap = StroboscopicMap(pb, tol=1e-10)
    smap.orbits([{}], [starts[0]], 1, batch_size=4, events=False)
    prof = cProfile.Profile() if a.profile else None
    split = _timed(job._map()) if a.split else None
    total, saved, apportioned = np.zeros(2), {}, [0.0]
    for v in a.values:
        t = time.process_time()
        if prof:
            prof.enable()
        r = job.census({"V": float(v)})
        if prof:
            prof.disable()
        tc = time.process_time() - t
        t = time.process_time()
        smap.at({"V": float(v)}).orbits([{}] * len(starts), starts, [max(1, int(p)) for p in r.spent], batch_size=4, events=False)
        tb = time.process_time() - t
        total += (tc, tb)
        saved[f"{v:g}"] = _labels(r)
        if a.apportion:
            import dataclasses
            job_a = dataclasses.replace(job, settings=dataclasses.replace(job.settings, apportion=True))
            job_a._smap = job._smap
            t = time.process_time()
            ra = job_a.census({"V": float(v)})
            ta = time.process_time() - t
            apportioned[0] += ta
            print(f"{v:g} V apportioned: census {ta:.1f} s CPU, against the bare ensemble of the followed periods "
                  f"{ta / tb:.2f}, against the followed census {ta / tc:.2f}; {np.mean(ra.spent):.1f} periods per "
                  f"start; {sum(o == OUTCOMES['transient'] for o in ra.outcomes)} starts stopped on saddles whose copies gave "
                  f"{[len(e) for e in ra.exits]} exits", flush=True)
            if split:
                split.clear()
        outs = {o: r.outcomes.count(o) for o in sorted(set(r.outcomes))}
        print(f"{v:g} V: census {tc:.1f} s CPU, bare {tb:.1f} s CPU, ratio {tc / tb:.2f}; {np.mean(r.spent):.1f} "
              f"periods per start; outcomes {outs}; attractors "
              f"{[x.label() for x in r.found]}", flush=True)
        if split:
            print("   census CPU by part [s]: " + ", ".join(f"{k} {v:.1f}" for k, v in split.items())
                  + f", the rest {tc - sum(split.values()):.1f}", flush=True)
            split.clear()
    print(f"total: census {total[0]:.1f} s CPU, bare {total[1]:.1f} s CPU, ratio {total[0] / total[1]:.2f}; "
          f"load average {os.getloadavg()[0]:.1f}")
    if a.apportion:
        print(f"apportioned: census {apportioned[0]:.1f} s CPU, {apportioned[0] / total[1]:.2f} of the bare ensemble of "
              f"the followed periods, {apportioned[0] / total[0]:.2f} of the followed census")
    if a.save:
        import json
        with open(a.save, "w") as f:
            json.dump(saved, f)
    if prof:
        prof.dump_stats(a.profile)
        pstats.Stats(a.profile).sort_stats("cumulative").print_stats(45)


if __name__ == "__main__":
    main()
