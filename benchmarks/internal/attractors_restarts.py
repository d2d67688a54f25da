"""Does restarting the batch engine every chunk change when a start comes to rest? (issue 31, the 129-136 V grid
differences; not run in CI.)  Ten of the census' 200 box starts (thesis-1dof, `measured` law, 10 Hz, 136 V) that
differ between the 100- and 200-cell censuses are run 2000 relay periods four ways: in one batch call; in chunks
of 40 periods from each chunk's final HybridState (as the census runs them); and so with a 48-period tangent
record (as the census identifies a start) every 400 or every 120 periods.  Printed: the period from which each
repeats with a period n <= 16 to 1e-5 of the states (None: still not, after 2000 periods).

    python benchmarks/internal/attractors_restarts.py
    python benchmarks/internal/attractors_restarts.py --all    # all 200 starts, one call against chunks of 40: how many
                                                      # repeat with a period by 500, 1000 and 2000 periods

The ten starts were chosen as differing between the grids, and they came to rest early in one long call: on
another path their times are fresh draws, so they alone cannot show a systematic effect; ``--all`` can.
"""
from __future__ import annotations

import numpy as np

STARTS = [2, 21, 63, 72, 146, 150, 160, 194, 77, 91]


def run(smap, P, record_every: int | None):
    from bifurc.attractors.lifetime import fall_index
    if record_every is None:
        o = smap.orbits([{}] * len(P), list(P), 2000, batch_size=4, events=False)
        return [fall_index(oo.points, list(range(1, 17)), 64, rtol=1e-5) for oo in o]
    states, k, pts, t = list(P), [0] * len(P), [[p] for p in P], 0
    while t < 2000:
        rec = record_every and t and t % record_every == 0
        n = 48 if rec else 40
        o = smap.orbits([{}] * len(P), states, n, k0=k, batch_size=4, **({"tangent": True} if rec else
                                                                         {"events": False}))
        for j, oo in enumerate(o):
            pts[j].extend(oo.points[1:])
            states[j], k[j] = oo.final, k[j] + n
        t += n
    return [fall_index(np.array(p), list(range(1, 17)), 64, rtol=1e-5) for p in pts]


def main(argv=None):
    import argparse

    import maps
    from bifurc.attractors.starts import make_starts
    from maps.poincare import StroboscopicMap
    pb = maps.problem("thesis-1dof", params={"relay_hz": 10.0}, dc_law="measured")
    st = make_starts(pb, "box", n=200, box={"x": (0.0, 0.03), "v": (-1.5, 1.5)}, seed=1)
    smap = StroboscopicMap(pb, tol=1e-10)
    smap = smap.at(dict(V=136.0))
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--all", action="store_true")
    if ap.parse_args(argv).all:
        P = np.asarray(st.points, float)
        for what, every in (("one batch call", None), ("chunks of 40, no records", 0)):
            t = np.array([np.inf if j is None else j for j in run(smap, P, every)])
            print(f"{what}: of {len(P)} starts, repeating with a period by 500 / 1000 / 2000 periods: "
                  f"{int(np.sum(t <= 500))} / {int(np.sum(t <= 1000))} / {int(np.sum(t <= 2000))}", flush=True)
        return
    P = np.asarray(st.points, float)[STARTS]
    print(f"starts {STARTS}")
    for what, every in (("one batch call", None), ("chunks of 40, no records", 0),
                        ("chunks, a tangent record every 400", 400), ("chunks, a tangent record every 120", 120)):
        print(f"{what}: {run(smap, P, every)}", flush=True)


if __name__ == "__main__":
    main()
