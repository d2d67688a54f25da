"""2-DOF progression sweep throughput: what `bifurc diagram --scene prototype --soil LAW` runs, against
a bare heyoka ensemble of the same trajectories (issue 18, section 5).

prototype scene (dynamics-listing numbers, 90 V RMS = 127.3 V amplitude, F_static 31.1 N), N relay
frequencies in [4, 8.8] Hz, 200 transient + 100 recorded relay periods (300 in all), tol 1e-10,
for each soil law.  Measured side by side in one run:

1. the product path, ``bifurc.sweep.sweep`` on ``--workers`` processes (batch engine, 4 SIMD lanes),
   with the progression measures (always stored for 2-DOF scenes), classification in reduced
   coordinates, no Lyapunov exponent, grazing or error estimate (``lyapunov=False, grazing=False,
   error_sample=0``), wall time including the pool start and each worker's compilation; and the
   same with everything (exponents where not periodic, grazing, error estimate);
2. a baseline OUTSIDE the product, defined here: a bare heyoka batch ensemble (4 lanes) of the same
   trajectories, with the least Python possible: one event per guard surface that can change the
   mode (observation-only surfaces left out), whose callback applies the first matching guard's new
   flags and reset, then the model's settle function (stick, slip) where it may act, also after every
   relay switch (a time event), with no event log, budget, classification or storage; the state
   kept at every relay-period end (what the progression rate needs), in the same number of
   processes.  Both are also run on 2 values, and the marginal ratio (N values less 2) removes the
   fixed costs (pool start, each worker's compilations) from the comparison.

    python benchmarks/progression.py [--n 200] [--workers 2] [--transient 200] [--record 100]
"""
from __future__ import annotations

import argparse
import math
import os
import time
from dataclasses import dataclass, field

import numpy as np

import maps
from maps.hybrid import settle_may_act
from bifurc.executor import map_values
from bifurc.sweep import sweep
from frequency_diagram import BareBatch, _Same

LAWS = ("viscous", "coulomb", "drift")
PARAMS = {"V": 90.0 * math.sqrt(2.0)}


@dataclass(frozen=True)
class Problem:
    """The benchmark's problem, for the bare baseline (picklable)."""

    params: dict
    soil: str = "drift"
    scene: str = "prototype"
    transient: int = 200
    record: int = 100
    tol: float = 1e-10
    x0: dict = field(default_factory=dict)


class BareProgression(BareBatch):
    """:class:`frequency_diagram.BareBatch` on a 2-DOF scene with every guard surface an event."""

    record_states = True

    def _setup(self):
        import heyoka as hy
        system = maps.get_scene(self.task.scene).with_options(soil=self.task.soil).system
        index = {f: len(system.param_names) + k for k, f in enumerate(system.flag_names)}
        me = self

        self.flag_index = index

        class Surface(_Same):
            def __init__(self, group):
                self.group = group

            def __call__(self, ta, d_sgn, j):
                flags = {f: me.pars[i, j] for f, i in index.items()}
                for g in self.group:
                    if g.direction in (0, d_sgn) and all(flags[k] == v for k, v in g.when.items()):
                        break
                else:
                    return True
                params = me.lane_params[j]
                y = me.state[:, j]
                if g.reset is not None:
                    y = system.reset_function(g)(y.copy(), params)
                    me.state[:, j] = y
                new = {}
                if g.then is not None:
                    new = dict(g.then(0.0, y, flags, params) if callable(g.then) else g.then)
                for k, v in new.items():
                    me.pars[index[k], j] = v
                me.settle(j, ta.time[j])
                if me.pars[index["escaped"], j]:
                    me.done[j] = True
                    return False
                return True

        groups = [grp for grp in system.event_groups() if not all(g.observes_only for g in grp)]
        events = [hy.t_event_batch(grp[0].expr, direction=hy.event_direction.any, cooldown=1e-10,
                                   callback=Surface(grp)) for grp in groups]
        self._build(system, events + [self.relay_event(system)])
        self.lane_params = [None] * self.batch_size

    def settle(self, j, t):
        """The model's own consistency rule (stick, slip) on lane ``j``, where it may act."""
        system, index = self.system, self.flag_index
        if system.settle is None:
            return
        flags = {f: self.pars[i, j] for f, i in index.items()}
        if not settle_may_act(system, flags):
            return
        out = system.settle(t, self.state[:, j].copy(), flags, self.lane_params[j])
        if isinstance(out, tuple):
            out, y = out
            self.state[:, j] = y
        for k, v in (out or {}).items():
            self.pars[index[k], j] = v

    def after_switch(self, j):
        self.settle(j, self._ta.time[j])

    def start_flags(self, j, t, params, y0):
        """The system's own start rule (the drift soil starts in elastic contact)."""
        flags = self.system.initial_flags(t, params)
        flags.update(self.system.mode_at(y0, params, flags))
        self.lane_params[j] = params
        return flags

    def run_many(self, values):
        """The rate [m/s] over the recorded window of each value (NaN: escaped)."""
        self.warm()
        T, R = self.task.transient, self.task.record
        self._run([(float(W), self.y0, 0, T + R, None) for W in values])
        out = []
        for W, kept in zip(values, self.kept):
            if kept is None or len(kept) < T + R:
                out.append(float("nan"))
                continue
            x2 = np.array([y[2] for y in kept])
            out.append(float((x2[T - 1] - x2[T + R - 1]) * W / R))
        return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--n", type=int, default=200)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--transient", type=int, default=200)
    ap.add_argument("--record", type=int, default=100)
    ap.add_argument("--laws", default=",".join(LAWS))
    args = ap.parse_args(argv)
    print(f"load average before: {os.getloadavg()}, cores: {os.cpu_count()}")
    values = np.linspace(4.0, 8.8, args.n)
    rows = []
    for law in args.laws.split(","):
        base = dict(soil=law, params=PARAMS, transient=args.transient, record=args.record, tol=1e-10,
                    progress=False, workers=args.workers)
        t0 = time.perf_counter()
        ds = sweep("prototype", "relay_hz", values, lyapunov=False, grazing=False, error_sample=0, **base)
        lean = time.perf_counter() - t0
        t0 = time.perf_counter()
        sweep("prototype", "relay_hz", values, **base)
        full = time.perf_counter() - t0
        problem = Problem(maps.get_scene("prototype").with_options(soil=law).parameters(**PARAMS), soil=law,
                          transient=args.transient, record=args.record)
        bare = BareProgression(problem)
        t0 = time.perf_counter()
        rates = np.array(map_values(bare, values, workers=args.workers))
        bare_wall = time.perf_counter() - t0
        two = values[[0, -1]]
        t0 = time.perf_counter()
        sweep("prototype", "relay_hz", two, lyapunov=False, grazing=False, error_sample=0, **base)
        lean2 = time.perf_counter() - t0
        t0 = time.perf_counter()
        map_values(BareProgression(problem), two, workers=args.workers)
        bare2 = time.perf_counter() - t0
        mine = ds.progression_rate.values[0]
        both = np.isfinite(rates) & np.isfinite(mine)
        agree = float(np.nanmax(np.abs(rates[both] - mine[both]) / np.maximum(np.abs(mine[both]), 1e-9))) \
            if both.any() else math.nan
        print(f"{law}: sweep with progression measures {lean:.2f} s, with everything {full:.2f} s, bare ensemble "
              f"{bare_wall:.2f} s: ratio {lean / bare_wall:.2f} (target <= 1.3); status ok "
              f"{int((ds.status.values == 0).sum())}/{values.size}; rates agree with the bare ensemble's to "
              f"{agree:.2g} relative on {int(both.sum())} values (median rate {1e3 * np.nanmedian(mine):.3g} mm/s); "
              f"on 2 values: {lean2:.2f} s against {bare2:.2f} s, marginal ratio "
              f"{(lean - lean2) / (bare_wall - bare2):.2f}", flush=True)
        rows.append((law, lean, full, bare_wall, (lean - lean2) / (bare_wall - bare2)))
    print(f"load average after: {os.getloadavg()}")
    print("\n| soil | sweep + progression [s] | with exponents, grazing, error [s] | bare ensemble [s] | ratio | "
          "marginal ratio |")
    print("|---|---|---|---|---|---|")
    for law, lean, full, bare_wall, marginal in rows:
        print(f"| {law} | {lean:.1f} | {full:.1f} | {bare_wall:.1f} | {lean / bare_wall:.2f} | {marginal:.2f} |")


if __name__ == "__main__":
    main()
