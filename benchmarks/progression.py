"""2-DOF progression sweep throughput: what `bifurc diagram --scene prototype --soil LAW` runs, against
a bare heyoka ensemble of the same trajectories (issue 18, section 5).

prototype scene (dynamics-listing numbers, 90 V RMS = 127.3 V amplitude, F_static 31.1 N), N relay
frequencies in [4, 8.8] Hz, 200 transient + 100 recorded relay periods (300 in all), tol 1e-10,
for each soil law.  Measured side by side in one run, ``--rounds`` times interleaved (best of them; wall time and
CPU time of this process and its finished workers):

1. the product path, ``bifurc.sweeps.sweep.sweep`` on ``--workers`` processes (batch engine, 4 SIMD lanes),
   with the progression measures (always stored for 2-DOF scenes), classification in reduced
   coordinates, no Lyapunov exponent, grazing or error estimate (``lyapunov=False, grazing=False,
   error_sample=0``), wall time including the pool start and each worker's compilation; and once
   with everything (exponents where not periodic, grazing, error estimate);
2. a baseline OUTSIDE the product, defined here: a bare heyoka batch ensemble (4 lanes) of the same
   trajectories with the same events, with the least Python possible: the transient with one event per
   guard surface that can change the mode, then the recorded window (as long as the product's) with
   the observation-only surfaces too (where the product measures free-flight minima and the deepest
   penetration), each surface detecting the directions the product's does; the callback applies the
   first matching guard's new flags and reset, then the model's settle function (stick, slip) where it
   may act, also after every relay switch (a time event), with no event log, budget, classification
   or storage; the state kept at every relay-period end (what the progression rate needs), in the same
   number of processes.  The script checks that it is the same work: rates, escapes and their times,
   Taylor steps against the product's;
3. the previous baseline ("one-pass bare"): all periods in one pass without the observation stops,
   every surface detected in both directions (fewer events than the product under viscous and drift
   soil, more under coulomb, whose one-sided slip guards it also stops at the wrong way).

Both are also run on 2 values, and the marginal ratio (N values less 2) removes the fixed costs
(pool start, each worker's compilations) from the comparison.  The first sweep in a process also
imports xarray and, at its first Dataset, dask (~1.3 s of CPU, idle): it is timed apart first, on 2
values, so that it falls on no law's rounds (a command-line run pays it every time).

    python benchmarks/progression.py [--n 200] [--workers 2] [--transient 200] [--record 100] [--rounds 2]
"""
from __future__ import annotations

import argparse
import math
import os
import resource
import time
from dataclasses import dataclass, field

import numpy as np

import maps
from maps.studykit import forcing_period_steps, settle_may_act
from bifurc.studykit import map_values
import bifurc
from bifurc import sweep
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
    """:class:`frequency_diagram.BareBatch` on a 2-DOF scene with every guard surface an event.

    ``observations=False``: the surfaces that change the mode only (the transient's integrator);
    True: the observation-only ones too (the recorded window's: the product stops there to measure
    free-flight minima and the deepest penetration).  :meth:`run_many` runs the product's events:
    the transient without observation stops, then the record with them, each value's record as
    long as the product's (``bifurc.Diagram.record_for``, extended where the forcing period q needs it);
    ``one_pass=True`` (the previous baseline) runs all periods in one pass without observation stops.
    """

    record_states = True

    def __init__(self, task, observations=False, one_pass=False):
        super().__init__(task)
        self.observations, self.one_pass = observations, one_pass
        self.directions = not one_pass      # the previous baseline detected every surface in both directions
        self.record_pass = None if observations or one_pass else BareProgression(task, observations=True)
        self.carry, self.end_flags, self.escape_t = {}, {}, {}

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
                flags = me.lane_flags[j]
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
                if g.observes_only:             # the product: an observation changes nothing, no settle
                    return True
                new = {}
                if g.then is not None:
                    new = g.then(0.0, y, dict(flags), params) if callable(g.then) else g.then
                    if isinstance(new, tuple):  # (flags, state): the mode entered with a projection
                        new, y = new
                        me.state[:, j] = y
                for k, v in (new or {}).items():
                    me.pars[index[k], j] = v
                    flags[k] = v
                me.settle(j, ta.time[j])
                if me.pars[index["escaped"], j]:
                    me.escape_t[me.W[j]] = float(ta.time[j])
                    me.done[j] = True
                    return False
                return True

        groups = [grp for grp in system.event_groups() if self.observations or not all(g.observes_only for g in grp)]
        sense = {1: hy.event_direction.positive, -1: hy.event_direction.negative}

        def direction(grp):     # as the product's: a surface whose guards share one direction detects only it
            ds = {g.direction for g in grp}
            return sense.get(ds.pop(), hy.event_direction.any) if len(ds) == 1 else hy.event_direction.any

        events = [hy.t_event_batch(grp[0].expr, direction=direction(grp) if self.directions else hy.event_direction.any,
                                   cooldown=1e-10, callback=Surface(grp)) for grp in groups]
        self._build(system, events + [self.relay_event(system)])
        self.lane_params = [None] * self.batch_size
        self.lane_flags = [None] * self.batch_size      # each lane's flags, kept with its pars

    def settle(self, j, t):
        """The model's own consistency rule (stick, slip) on lane ``j``, where it may act."""
        system, index = self.system, self.flag_index
        if system.settle is None:
            return
        flags = self.lane_flags[j]
        if not settle_may_act(system, flags):
            return
        out = system.settle(t, self.state[:, j].copy(), dict(flags), self.lane_params[j])
        if isinstance(out, tuple):
            out, y = out
            self.state[:, j] = y
        for k, v in (out or {}).items():
            self.pars[index[k], j] = v
            flags[k] = v

    def after_switch(self, j):
        self.lane_flags[j]["P"] = float(self.pars[self.i_P, j])     # the relay flag, switched by the time event
        self.settle(j, self._ta.time[j])

    def period_end(self, j, k):
        """Keep the state; at the end of the pass also the flags (the record pass starts in them)."""
        super().period_end(j, k)
        if 2 * k >= self.last[j]:
            self.end_flags[self.W[j]] = {f: float(self.pars[i, j]) for f, i in self.flag_index.items()}

    def start_flags(self, j, t, params, y0):
        """The flags the transient ended in, else the system's own start rule (the drift soil
        starts in elastic contact)."""
        self.lane_params[j] = params
        if params["relay_hz"] in self.carry:
            flags = dict(self.carry[params["relay_hz"]])
        else:
            flags = self.system.initial_flags(t, params)
            flags.update(self.system.mode_at(y0, params, flags))
        self.lane_flags[j] = dict(flags)
        return flags

    def records(self, values):
        """Each value's record length, as the product's (extended for a long forcing period q)."""
        method = bifurc.Diagram(record=self.task.record)
        return [method.record_for(forcing_period_steps(self.task.params["f_mains"], float(W))) for W in values]

    def run_many(self, values):
        """Per value: (rate [m/s] over the recorded window (NaN: escaped), escape time [s] (NaN:
        none), Taylor steps)."""
        self.warm()
        T, R = self.task.transient, self.task.record
        self.escape_t = {}
        nan = float("nan")
        if self.one_pass:
            self._run([(float(W), self.y0, 0, T + R, None) for W in values])
            rates = [float((k[T - 1][2] - k[T + R - 1][2]) * W / R) if k is not None and len(k) >= T + R else nan
                     for W, k in zip(values, self.kept)]
            return [(r, self.escape_t.get(float(W), nan), n) for r, W, n in zip(rates, values, self.steps)]
        ends = self._run([(float(W), self.y0, 0, T, None) for W in values])
        steps = list(self.steps)
        alive = [i for i, k in enumerate(self.kept) if k is not None and len(k) >= T and float(values[i]) not in self.escape_t]
        rec = self.record_pass
        rec.warm()
        rec.escape_t = {}
        rec.carry = {float(values[i]): self.end_flags[float(values[i])] for i in alive}
        lengths = self.records(values)
        if alive:
            rec._run([(float(values[i]), ends[i], T, lengths[i], None) for i in alive])
        self.escape_t.update(rec.escape_t)
        rates = [nan] * len(values)
        for i, kept, n in zip(alive, rec.kept if alive else [], rec.steps if alive else []):
            steps[i] += n
            if kept is not None and len(kept) >= R:
                rates[i] = float((ends[i][2] - kept[R - 1][2]) * values[i] / R)
        return [(r, self.escape_t.get(float(W), nan), n) for r, W, n in zip(rates, values, steps)]


def cpu() -> float:
    """CPU seconds of this process and its finished worker processes (less sensitive than wall time
    to a shared machine's load)."""
    me, kids = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return me.ru_utime + me.ru_stime + kids.ru_utime + kids.ru_stime


def _agreement(law, out, full, values) -> None:
    """How the bare ensembles' rates and escapes agree with the product's sweep."""
    ds = out["product"]
    mine, status = ds.progression_rate.values[0], ds.status.values[0]
    ended = np.where(status == 1, ds.failure_time.values[0], np.nan)       # escaped: when
    steps = ds.n_steps.values[0]
    print(f"{law}: with everything (exponents, grazing, error estimate) {full:.2f} s; status ok "
          f"{int((status == 0).sum())}/{values.size}, median rate {1e3 * np.nanmedian(mine):.3g} mm/s, "
          f"{int(steps.sum())} Taylor steps")
    for label in ("bare", "one-pass bare"):
        b = np.array(out[label], dtype=float)
        both = np.isfinite(b[:, 0]) & np.isfinite(mine)
        agree = float(np.nanmax(np.abs(b[both, 0] - mine[both]) / np.maximum(np.abs(mine[both]), 1e-9))) \
            if both.any() else math.nan
        esc = np.isfinite(b[:, 1]) | np.isfinite(ended)
        dt = np.abs(b[esc, 1] - ended[esc])
        print(f"  {label}: rates agree to {agree:.2g} relative on {int(both.sum())} values; escaped "
              f"{int(np.isfinite(b[:, 1]).sum())} (product {int(np.isfinite(ended).sum())}), escape times "
              f"agree to median {np.nanmedian(dt) if esc.any() else math.nan:.2g} s, max "
              f"{np.nanmax(dt) if esc.any() else math.nan:.2g} s; Taylor steps {int(b[:, 2].sum())} "
              f"({b[:, 2].sum() / steps.sum() - 1:+.2%} against the product's)")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--n", type=int, default=200)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--transient", type=int, default=200)
    ap.add_argument("--record", type=int, default=100)
    ap.add_argument("--laws", default=",".join(LAWS))
    ap.add_argument("--rounds", type=int, default=2, help="rounds of the product and bare runs, interleaved")
    args = ap.parse_args(argv)
    print(f"load average before: {os.getloadavg()}, cores: {os.cpu_count()}")
    values = np.linspace(4.0, 8.8, args.n)
    two = values[[0, -1]]
    rows = []
    # the first sweep in a process imports xarray, whose first Dataset imports dask (a one-time cost of the
    # process, in a thread beside the workers): timed here apart, so that no law's rounds carry it
    t0 = time.perf_counter()
    sweep("prototype", "relay_hz", two, soil=LAWS[0], params=PARAMS, transient=args.transient, record=args.record,
          lyapunov=False, grazing=False, error_sample=0, progress=False, workers=args.workers)
    cold = time.perf_counter() - t0
    t0 = time.perf_counter()
    sweep("prototype", "relay_hz", two, soil=LAWS[0], params=PARAMS, transient=args.transient, record=args.record,
          lyapunov=False, grazing=False, error_sample=0, progress=False, workers=args.workers)
    print(f"first sweep in this process (2 values): {cold:.2f} s, the same again {time.perf_counter() - t0:.2f} s",
          flush=True)
    for law in args.laws.split(","):
        base = dict(soil=law, params=PARAMS, transient=args.transient, record=args.record, tol=1e-10,
                    progress=False, workers=args.workers)
        lean = dict(lyapunov=False, grazing=False, error_sample=0)
        problem = Problem(maps.get_scene("prototype").with_options(soil=law).parameters(**PARAMS), soil=law,
                          transient=args.transient, record=args.record)
        runs = {"product": lambda v: sweep("prototype", "relay_hz", v, **lean, **base),
                "bare": lambda v: map_values(BareProgression(problem), v, workers=args.workers),
                "one-pass bare": lambda v: map_values(BareProgression(problem, one_pass=True), v, workers=args.workers)}
        walls = {k: [] for k in runs}
        cpus = {k: [] for k in runs}
        out = {}
        for r in range(args.rounds):
            for label, run in runs.items():
                load = os.getloadavg()[0]
                t0, c0 = time.perf_counter(), cpu()
                out[label] = run(values)
                walls[label].append(time.perf_counter() - t0)
                cpus[label].append(cpu() - c0)
                print(f"{law}, round {r + 1}: {label} {walls[label][-1]:.2f} s wall, {cpus[label][-1]:.2f} s CPU "
                      f"(load {load:.2f} before)", flush=True)
        t0 = time.perf_counter()
        sweep("prototype", "relay_hz", values, **base)
        full = time.perf_counter() - t0
        fixed = {}
        for label, run in runs.items():
            t0 = time.perf_counter()
            run(two)
            fixed[label] = time.perf_counter() - t0
        _agreement(law, out, full, values)
        best = {k: min(w) for k, w in walls.items()}
        ratio = {k: best["product"] / best[k] for k in ("bare", "one-pass bare")}
        marginal = {k: (best["product"] - fixed["product"]) / (best[k] - fixed[k]) for k in ratio}
        cpu_ratio = {k: min(cpus["product"]) / min(cpus[k]) for k in ratio}
        print(f"  best of {args.rounds}: product {best['product']:.2f} s, bare {best['bare']:.2f} s: ratio "
              f"{ratio['bare']:.2f} (target <= 1.3), marginal {marginal['bare']:.2f}, CPU {cpu_ratio['bare']:.2f}; "
              f"against the one-pass bare {best['one-pass bare']:.2f} s: {ratio['one-pass bare']:.2f}, marginal "
              f"{marginal['one-pass bare']:.2f}, CPU {cpu_ratio['one-pass bare']:.2f}; on 2 values: "
              + ", ".join(f"{k} {v:.2f} s" for k, v in fixed.items()), flush=True)
        rows.append((law, walls, full, ratio, marginal, cpu_ratio))
    print(f"load average after: {os.getloadavg()}")
    print("\n| soil | sweep + progression [s] | with exponents, grazing, error [s] | bare ensemble [s] | ratio | "
          "marginal ratio | CPU ratio | one-pass bare [s] | ratio to it | CPU ratio to it |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for law, walls, full, ratio, marginal, cpu_ratio in rows:
        w = {k: ", ".join(f"{x:.1f}" for x in v) for k, v in walls.items()}
        print(f"| {law} | {w['product']} | {full:.1f} | {w['bare']} | {ratio['bare']:.2f} | {marginal['bare']:.2f} | "
              f"{cpu_ratio['bare']:.2f} | {w['one-pass bare']} | {ratio['one-pass bare']:.2f} | "
              f"{cpu_ratio['one-pass bare']:.2f} |")


if __name__ == "__main__":
    main()
