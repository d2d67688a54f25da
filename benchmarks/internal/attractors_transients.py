"""Are the census' "transient" starts in a chaotic transient, and does ``eventual_fraction`` say where they go?
(issue 31).  Not run in CI.

    python benchmarks/internal/attractors_transients.py [V ...] [--more 6000]   # default 115 136 185 190 192 V

thesis-1dof as benchmarks/attractors.py runs it (`matlab-listing`, `measured` law, 10 Hz, 200 box starts x=0:0.03,
v=-1.5:1.5, seed 1, 100 cells per side), one process, no seeding from neighbouring values.  At each value the census
runs (``max_periods`` 2000); each start it calls "transient" is then run ``--more`` relay periods on from where the
census left it (one batch call, strobe points only) and judged by a tolerance of the states
(:func:`bifurc.attractors.lifetime.fall_index`: from which point it repeats with a period n <= 16 to 1e-6 of each
state's scale over its last 64 points).  Printed: how many are still aperiodic at the end against the number the
saddle's lifetime predicts (the sum over the starts of exp(-more / lifetime), and at the ends of the lifetime's
interval); where the others settled (the census'
attractor whose nodes the last point lies on within 1e-3 cells, else "another orbit"); and, per attractor, the
eventual fraction's interval beside the fraction the continued starts give (direct counts plus where the transient
starts went; those still aperiodic counted neither way, so the latter is a range).
"""
from __future__ import annotations

import argparse
import math
import time

import numpy as np


def _settled_on(point, found, grid) -> int | None:
    """The index of the census' periodic attractor whose nodes ``point`` lies on within 1e-3 cells, or None."""
    for j, a in enumerate(found):
        if a.periodic and np.min(np.max(np.abs(grid.scaled(a.points[:a.period]) - grid.scaled(point)), axis=1)) < 1e-3:
            return j
    return None


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("values", nargs="*", type=float, default=[115.0, 136.0, 185.0, 190.0, 192.0])
    ap.add_argument("--more", type=int, default=6000, help="relay periods each transient start runs on")
    a = ap.parse_args(argv)
    from bifurc.attractors import census as C
    from bifurc.attractors.eventual import eventual_fractions
    from bifurc.attractors.lifetime import fall_index
    from bifurc.labels.classify import candidate_periods
    from _census import box_census      # the census of benchmarks/attractors.py
    _, starts, grid, smap = box_census()
    tracks, plain = [], C.Track.__init__

    def noted(self, *args, **kw):
        plain(self, *args, **kw)
        tracks.append(self)
    C.Track.__init__ = noted
    T = C.OUTCOMES["transient"]
    for v in a.values:
        clock = time.perf_counter()
        del tracks[:]
        smap = smap.at(dict(V=v))
        mem = C.Memory()
        out, found, _ = C.census_at(smap, starts, grid, C.Settings(), memory=mem)
        mine = [i for i, o in enumerate(out) if o == T]
        keys = list(range(len(found))) + list(C.OUTCOMES.values())
        ev, lo, hi = eventual_fractions(out, mem.via, mem.saddles, keys)
        runs = smap.orbits([{}] * len(mine), [tracks[i].state for i in mine], a.more,
                           k0=[tracks[i].k for i in mine], batch_size=4, events=False)
        periods = candidate_periods(smap.forcing_period_steps, 16)
        still, went, predicted = 0, {}, np.zeros(3)
        for i, o in zip(mine, runs):
            sd = mem.saddles[mem.via[i]]
            predicted += [math.exp(-a.more / tau) for tau in (sd.lifetime, *sd.lifetime_interval)]
            if o.status != "ok":
                went[o.status] = went.get(o.status, 0) + 1
            elif fall_index(o.points, periods, 64) is None:
                still += 1
            else:
                j = _settled_on(o.points[-1], found, grid)
                name = found[j].label() + f" (A{j})" if j is not None else "another orbit"
                went[name] = went.get(name, 0) + 1
        lives = sorted({tuple(round(x) for x in (sd.lifetime, *sd.lifetime_interval))
                        for sd in (mem.saddles[mem.via[i]] for i in mine)})
        print(f"V = {v:g}: {len(mine)} of {len(out)} starts transient (saddle lifetimes {lives} relay periods: "
              f"estimate, interval); after {a.more} more periods {still} still aperiodic (the lifetime predicts "
              f"{predicted[0]:.1f}, its interval {predicted[1]:.1f}-{predicted[2]:.1f}); settled: "
              f"{went} ({time.perf_counter() - clock:.0f} s)")
        for j, f in enumerate(found):
            direct = sum(o == j for o in out)
            gone = sum(n for name, n in went.items() if name.endswith(f"(A{j})"))
            print(f"   A{j} {f.label()}: basin {direct / len(out):.3f}; eventual {ev[j]:.3f} [{lo[j]:.3f}, {hi[j]:.3f}]"
                  f"; continued {(direct + gone) / len(out):.3f}-{(direct + gone + still) / len(out):.3f}", flush=True)


if __name__ == "__main__":
    main()
