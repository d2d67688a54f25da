"""Where the attractor census' time goes beyond the bare periods (issue 31, section 5); not run in CI.

    python benchmarks/attractors_profile.py [V ...] [--starts N] [--profile FILE]

One process: for each value (default 122 136 192 206 V; thesis-1dof as benchmarks/attractors.py runs it: the
`matlab-listing` preset since 2026-11-26 15:00, the scene's default `thesis-text` before; `measured` law, 10 Hz, box
x=0:0.03, v=-1.5:1.5, seed 1, 100 cells per side) the census of the fresh starts, then a bare batch ensemble of the same
starts each run for the periods it spent in the census (strobe points only), side by side.  With ``--profile``
the census calls run under cProfile and the functions are ranked by cumulative time.  Public API only: each value's
census is ``bifurc.attractors`` at that one value on one worker; its CPU seconds by stage are the dataset's
``fresh_cpu_seconds_<stage>`` attributes and each start's periods its ``start_periods`` (before 2026-11-29 this
script wrapped the census' functions in place to time them by caller: "orbits from census_at", from
"_record_and_classify", "Newton"; since then ``--split`` prints the census' own stages: chunks, identify, exits).
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
    import bifurc
    import maps
    pb = maps.problem("thesis-1dof", params={"relay_hz": 10.0}, dc_law="measured")
    starts = list(np.asarray(bifurc.Box(n=40, box={"x": (0.0, 0.03), "v": (-1.5, 1.5)}, seed=1).draw(pb).points,
                             dtype=float))
    smap = maps.StroboscopicMap(pb, tol=1e-10)
    for v in (171.0, 213.0):
        smap = smap.at(dict(V=v))
        pre = smap.orbits([{}] * len(starts), starts, 300, batch_size=4, events=False)
        chaotic = [o.final for o in pre if np.ptp(o.points[-64:, 0]) > 1e-4][:4]
        for m in (1, 2, 4):
            c = time.process_time()
            smap.orbits([{}] * m, chaotic[:m], 1000, k0=300, batch_size=4, events=False)
            print(f"{v:g} V: {m} of 4 lanes x 1000 periods: {time.process_time() - c:.3f} s CPU")


def _labels(ds) -> list:
    """Each start's outcome in words at the dataset's one value: its attractor's class in words, or the outcome's
    name (``ds.bifurc.table()``'s description)."""
    words = dict(zip(ds.bifurc.table()["attractor"], ds.bifurc.table()["description"]))
    return [words.get(str(lab), str(lab)) for lab in ds.attractor_label.values[ds.start_attractor.values[0]]]


def _census(pb, v, starts, apportion=False):
    """The census of the ``starts`` sampler's starts at V = ``v`` on one worker (the calling process): its dataset
    and CPU seconds, those of the fresh starts' census by stage summed (the dataset's ``fresh_cpu_seconds_<stage>``;
    a dict of them the third)."""
    import bifurc
    ds = bifurc.attractors(pb, "V", [float(v)], bifurc.Census(link=False, apportion=apportion), starts=starts,
                           run=bifurc.Run(workers=1, progress=False))
    split = {k.removeprefix("fresh_cpu_seconds_"): float(x) for k, x in ds.attrs.items()
             if k.startswith("fresh_cpu_seconds_")}
    return ds, sum(split.values()), split


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("values", nargs="*", type=float, default=[122.0, 136.0, 192.0, 206.0])
    ap.add_argument("--starts", type=int, default=200)
    ap.add_argument("--profile", metavar="FILE", help="write the census' cProfile stats here and print a ranking")
    ap.add_argument("--split", action="store_true", help="print the census' CPU seconds by stage (chunks, identify, exits)")
    ap.add_argument("--lanes", action="store_true", help="only the cost of 1, 2 and 4 batch lanes on chaotic "
                                                         "trajectories (171 and 213 V): what a persistence copy costs")
    ap.add_argument("--apportion", action="store_true", help="also the census with apportion=True after each value's "
                    "followed one (issue 47 section 2): its CPU against the bare ensemble of the followed periods")
    ap.add_argument("--save", metavar="FILE", help="write each start's outcome (attractor label or outcome name) "
                                                   "per value here (JSON), to compare two commits start by start")
    a = ap.parse_args(argv)
    import bifurc
    import maps
    print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
    if a.lanes:
        return lanes()
    from attractors import BOX, MODEL       # the census of benchmarks/attractors.py
    pb = maps.problem("thesis-1dof", **MODEL)
    sampler = bifurc.Box(n=a.starts, box=BOX, seed=1)
    starts = np.asarray(sampler.draw(pb).points, dtype=float)
    _census(pb, a.values[0], bifurc.Box(n=1, box=BOX, seed=1))       # compiled before the clock
    smap = maps.StroboscopicMap(pb, tol=1e-10)
    smap.orbits([{}], [starts[0]], 1, batch_size=4, events=False)
    prof = cProfile.Profile() if a.profile else None
    total, saved, apportioned = np.zeros(2), {}, [0.0]
    for v in a.values:
        if prof:
            prof.enable()
        ds, tc, split = _census(pb, v, sampler)
        if prof:
            prof.disable()
        spent = ds.start_periods.values[0]
        t = time.process_time()
        smap.at({"V": float(v)}).orbits([{}] * len(starts), list(starts), [max(1, int(p)) for p in spent],
                                        batch_size=4, events=False)
        tb = time.process_time() - t
        total += (tc, tb)
        saved[f"{v:g}"] = _labels(ds)
        if a.apportion:
            da, ta, _ = _census(pb, v, sampler, apportion=True)
            apportioned[0] += ta
            stopped = int(np.sum(da.attractor_label.values[da.start_attractor.values[0]] == "transient"))
            print(f"{v:g} V apportioned: census {ta:.1f} s CPU, against the bare ensemble of the followed periods "
                  f"{ta / tb:.2f}, against the followed census {ta / tc:.2f}; {np.mean(da.start_periods.values):.1f} "
                  f"periods per start; {stopped} starts stopped on saddles", flush=True)
        labels = _labels(ds)
        outs = {o: labels.count(o) for o in sorted(set(labels))}
        print(f"{v:g} V: census {tc:.1f} s CPU, bare {tb:.1f} s CPU, ratio {tc / tb:.2f}; {np.mean(spent):.1f} "
              f"periods per start; starts by outcome {outs}", flush=True)
        if a.split:
            print("   census CPU by stage [s]: " + ", ".join(f"{k} {x:.1f}" for k, x in split.items()), flush=True)
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
