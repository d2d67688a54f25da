"""Where the census' relay periods go (issue 31, section 5: why the 30 s and 65-periods-per-start targets are far):
each start's periods split into those before it first met a chaotic saddle or long-lived transient and those
after.  Not run in CI.

    python benchmarks/internal/attractors_saddle_cost.py [V ...]     # default: the benchmark's 21 values, 80-220 V

thesis-1dof as in benchmarks/attractors.py (`matlab-listing` preset since 2026-11-26 15:00; before, the
scene's default `thesis-text`), `measured` law, 10 Hz, 200 box starts x=0:0.03, v=-1.5:1.5 (seed 1), 100 cells per side, one process.
A start "meets" a saddle when the census first treats it as on one (its chunk shares a known saddle's cells, or
its record is a set whose lifetime is not surely above the horizon); the saddle is "short" where its lifetime's
interval lies below `Settings.persist`, "long-lived" otherwise.  The census is not changed: its functions are
wrapped to note when each start met a saddle.
"""
from __future__ import annotations

import sys
import time

import numpy as np


def _instrument(C):
    """Wrap the census' saddle decisions so that each Track notes (periods, saddle index) when it first met one."""
    tracks = []
    init = C.Track.__init__

    def track_init(self, *a, **k):
        init(self, *a, **k)
        self.met = None
        tracks.append(self)
    C.Track.__init__ = track_init
    on = C._on_saddle

    def on_saddle(t, saddles):
        hit = on(t, saddles)
        if hit and t.met is None:
            cells = {c for c in t.last_keys if c is not None}
            t.met = (t.periods, next(j for j, sd in enumerate(saddles) if sd.cells & cells))
        return hit
    C._on_saddle = on_saddle
    new = C._saddle_of

    def saddle_of(smap, a, record, k0, grid, s, found, q, saddles):
        sd = new(smap, a, record, k0, grid, s, found, q, saddles)
        if sd is not None:
            j = next(j for j, x in enumerate(saddles) if x is sd)
            end = np.asarray(record.final_state, dtype=float)
            for t in tracks:        # the start just recorded: its state is the record's end
                if t.met is None and t.last is not None and np.array_equal(np.asarray(t.state.y), end):
                    t.met = (t.periods, j)
        return sd
    C._saddle_of = saddle_of
    return tracks


def main(argv=None):
    import bifurc.attractors.census as C
    values = [float(v) for v in (argv if argv is not None else sys.argv[1:])] or list(np.linspace(80, 220, 21))
    from _census import box_census      # the census of benchmarks/attractors.py
    _, starts, grid, smap = box_census()
    tracks = _instrument(C)
    s = C.Settings()
    total = np.zeros(3)
    print("V [V] | CPU [s] | periods per start | after meeting a short saddle | after a long-lived one | saddles "
          "(lifetime, verdict)")
    for v in values:
        del tracks[:]
        smap = smap.at(dict(V=v))
        mem = C.Memory()
        clock = time.process_time()
        out, found, spent = C.census_at(smap, starts, grid, s, memory=mem)
        cpu = time.process_time() - clock
        kind = ["short" if sd.lifetime_interval[1] < s.persist else "long-lived" for sd in mem.saddles]
        after = {"short": 0, "long-lived": 0}
        for t, p in zip(tracks[:len(starts)], spent):
            if t.met is not None:
                after[kind[t.met[1]]] += p - t.met[0]
        row = np.array([sum(spent), after["short"], after["long-lived"]]) / len(starts)
        total += row
        print(f"{v:g} | {cpu:.1f} | {row[0]:.0f} | {row[1]:.0f} | {row[2]:.0f} | "
              f"{[(round(sd.lifetime), k) for sd, k in zip(mem.saddles, kind)]}", flush=True)
    total /= len(values)
    print(f"mean over the values: {total[0]:.1f} periods per start, {total[1]:.1f} of them after meeting a short "
          f"saddle, {total[2]:.1f} after a long-lived transient, {total[0] - total[1] - total[2]:.1f} otherwise")


if __name__ == "__main__":
    main()
