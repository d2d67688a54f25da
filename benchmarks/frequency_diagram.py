"""Frequency diagram throughput: what `bifurc diagram` runs, against a serial loop and bare heyoka.

thesis-1dof, preset matlab-listing, V = 90 V, N relay frequencies in [2, 10] Hz,
300 transient + 100 recorded relay periods, tol 1e-10.  Measured side by side in one run:

1. the product path, ``bifurc.sweep.sweep`` (= ``bifurc diagram``), on ``--workers`` processes,
   wall time including the process pool start and one compilation per worker:
   a. in full: orbits, classification, Lyapunov exponents where not periodic, grazing
      bisection, error estimate (heyoka batch mode, 4 SIMD lanes);
   b. the stroboscopic diagram alone (``lyapunov=False, grazing=False, error_sample=0``), in
      batch mode and with ``batch_size=1`` (one ``HybridRun`` per value);
2. baselines OUTSIDE the product, defined in this file: bare heyoka ensembles of the same
   trajectories with the least Python possible (flip the contact flag at contact/release,
   switch the relay, nothing else: no event log, no classification, no storage) in the same
   number of processes, on the scalar integrator (a propagate_until loop) and on the batch
   integrator (4 lanes, event callbacks), the latter also with the Lyapunov companions that
   1a integrates;
3. a serial loop: 1b with ``batch_size=1`` in one process over every ``--serial-stride``-th
   value, extrapolated to all N values.

    python benchmarks/frequency_diagram.py [--n 1000] [--workers 2] [--serial-stride 10]

``--default-diagram`` times instead the default diagram (`bifurc diagram --scene thesis-1dof
--param relay_hz --from 2 --to 10 --n 1000 --transient 300 --record 100`: the CLI's defaults,
through ``bifurc.sweep.sweep``) with the Lyapunov exponent from the tangent vector (the default)
and from Benettin's companions, with and without the record extension, interleaved over
``--rounds`` rounds so that the machine's load falls on every variant alike.
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
from bifurc.executor import map_values
from bifurc.sweep import sweep


@dataclass(frozen=True)
class Problem:
    """The benchmark's problem, for the bare baselines (picklable)."""

    params: dict
    scene: str = "thesis-1dof"
    transient: int = 300
    record: int = 100
    tol: float = 1e-10
    x0: dict = field(default_factory=dict)


def par_index(system, name) -> int:
    """Index of a parameter or flag in the integrator's ``pars``: the layout of the public
    ``HybridSystem.par_vector`` (parameters, then flags)."""
    if name in system.param_names:
        return list(system.param_names).index(name)
    return len(system.param_names) + list(system.flag_names).index(name)


class BareTrajectory:
    """The same hybrid trajectory with the least Python possible; returns the final x."""

    def __init__(self, task):
        self.task = task
        self._ta = None

    def _setup(self):
        system = maps.get_scene(self.task.scene).with_options(dc_law="listing").system   # matlab-listing's law
        ta, _ = system.integrator(self.task.tol)
        self.system, self._ta = system, ta
        groups = system.event_groups()        # public: one heyoka event per surface, in this order
        self.on_contact = {i for i, g in enumerate(groups) if any(x.name == "contact" for x in g)}
        self.on_release = {i for i, g in enumerate(groups) if any(x.name == "release" for x in g)}
        self.on_escape = {i for i, g in enumerate(groups) if any(x.name.startswith("escape") for x in g)}
        self.n_groups = len(groups)
        self.i_contact = par_index(system, "contact")
        self.i_relay = par_index(system, "P")
        self.y0 = system.state_vector(maps.get_scene(self.task.scene).initial_state(**self.task.x0))

    def __call__(self, W):
        if self._ta is None:
            self._setup()
        ta, system = self._ta, self.system
        params = dict(self.task.params, relay_hz=float(W))
        flags = system.initial_flags(0.0, params)
        ta.time = 0.0
        ta.state[:] = self.y0
        ta.reset_cooldowns()
        ta.pars[:] = np.asarray(system.par_vector(params, flags)[:len(ta.pars)])
        n_half = 2 * (self.task.transient + self.task.record)
        time_limit = maps.hybrid.hy.taylor_outcome.time_limit
        for n in range(1, n_half + 1):
            t_sw = (n // 2 + (0.5 if n % 2 else 0.0)) / W
            while True:
                outcome = ta.propagate_until(t_sw)[0]
                if outcome == time_limit:
                    break
                g = -int(outcome) - 1
                if not 0 <= g < self.n_groups:       # non-finite state or other failure
                    return float("nan")
                if g in self.on_contact and ta.pars[self.i_contact] == 0.0:
                    ta.pars[self.i_contact] = 1.0
                elif g in self.on_release and ta.pars[self.i_contact] == 1.0:
                    ta.pars[self.i_contact] = 0.0
                elif g in self.on_escape:
                    return float("nan")
            ta.pars[self.i_relay] = 0.0 if n % 2 else 1.0
        return float(ta.state[0])

    def warm(self):
        if self._ta is None:
            self._setup()


class _Same:
    """heyoka deep-copies event callbacks; this one's copies are itself."""

    def __deepcopy__(self, memo):
        return self


class BareBatch(_Same):
    """The same trajectories on heyoka's batch integrator with the least Python possible.

    4 lanes; the relay switch is a time event and the contact flag flips on the contact
    surface's crossing sign, both in event callbacks; a lane is refilled when its value is
    done; only the final x is kept (no event log, settle, escape or stick handling, no
    classification, no storage).  ``__call__`` per value, ``run_many`` per chunk.
    """

    batch_size = 4

    def __init__(self, task):
        self.task = task
        self._ta = None

    def _setup(self):
        import heyoka as hy
        system = maps.get_scene(self.task.scene).with_options(dc_law="listing").system   # matlab-listing's law
        contact = next(g for g in system.guards if g.name == "contact")
        self.i_contact = par_index(system, "contact")
        me = self

        class Contact(_Same):
            def __call__(self, ta, d_sgn, j):
                me.pars[me.i_contact, j] = 1.0 if d_sgn < 0 else 0.0
                return True

        events = [hy.t_event_batch(contact.expr, direction=hy.event_direction.any, cooldown=1e-10,
                                   callback=Contact()), self.relay_event(system)]
        self._build(system, events)

    def relay_event(self, system):
        """The relay switch as a batch time event (next instant in the extra parameter ``i_next``)."""
        import heyoka as hy
        self.i_P = par_index(system, "P")
        self.i_next = len(system.param_names) + len(system.flag_names)
        me = self

        class Relay(_Same):
            def __call__(self, ta, d_sgn, j):
                n = me.n_sw[j]
                me.pars[me.i_P, j] = 0.0 if n % 2 else 1.0
                me.n_sw[j] = m = n + 1
                me.pars[me.i_next, j] = (m // 2 + (0.5 if m % 2 else 0.0)) / me.W[j]
                me.after_switch(j)
                if not n % 2 and me.keep[j] is not None:
                    me.period_end(j, n // 2)
                if n >= me.last[j]:
                    me.done[j] = True
                    return False
                return True

        return hy.t_event_batch((hy.time - hy.par[self.i_next]) * hy.par[par_index(system, "relay_hz")],
                                direction=hy.event_direction.positive, cooldown=1e-10, callback=Relay())

    def _build(self, system, events):
        import heyoka as hy
        self._ta = hy.taylor_adaptive_batch(system.heyoka_system(), np.zeros((len(system.states), 4)),
                                            tol=self.task.tol, t_events=events)
        self.system, self.pars, self.state = system, self._ta.pars, self._ta.state
        self.y0 = system.state_vector(maps.get_scene(self.task.scene).initial_state(**self.task.x0))
        self.last = 2 * (self.task.transient + self.task.record)

    def warm(self):
        if self._ta is None:
            self._setup()

    def __call__(self, W):
        return self.run_many([W])[0]

    def run_many(self, values):
        """One trajectory of transient + record periods per value; the final x of each."""
        self.warm()
        jobs = [(float(W), self.y0, 0, self.task.transient + self.task.record, None) for W in values]
        return [float(y[0]) for y in self._run(jobs)]

    def period_end(self, j, k):
        """Lane j ends relay period k: keep the state (record) or renormalise (companion)."""
        keep, ref = self.keep[j], self.ref[j]
        if ref is None:
            keep.append(self.state[:, j].copy())
            return
        y = ref[k - self.k0[j]]
        dz = (self.state[:, j] - y) * self.inv_scale[j]
        dist = math.sqrt(float(dz @ dz))
        if k > self.k0[j]:
            keep.append(math.log(dist / 1e-8))
        z = y + (self.state[:, j] - y) * (1e-8 / dist)
        self.state[:, j] = z
        self.pars[self.i_contact, j] = 1.0 if z[0] < self.task.params["e"] else 0.0
        self.pars[self.i_P, j] = 1.0
        self._ta.reset_cooldowns(j)

    def _run(self, jobs):
        """Jobs (W, y0, k0, periods, reference or None); returns each job's final state, and
        in ``self.kept`` its period-end states (reference None) or log growths (companion)."""
        self.warm()
        ta, B = self._ta, 4
        out, lane_of = [None] * len(jobs), [None] * B
        self.kept, self.steps = [None] * len(jobs), [0] * len(jobs)
        waiting = list(range(len(jobs)))[::-1]
        self.n_sw, self.W, self.done, self.last = [1] * B, [1.0] * B, [False] * B, [0] * B
        self.keep, self.ref, self.k0, self.inv_scale = [None] * B, [None] * B, [0] * B, [None] * B
        target = np.zeros(B)

        def load():
            hi = np.array(ta.time, dtype=float)
            for j in range(B):
                if lane_of[j] is None:
                    i = waiting.pop() if waiting else None
                    W, y0, k0, periods, ref = jobs[i if i is not None else 0]
                    params = dict(self.task.params, relay_hz=W)
                    flags = self.start_flags(j, k0 / W, params, y0)
                    self.pars[:, j] = self.system.par_vector(params, flags) + [(k0 + 0.5) / W]
                    self.state[:, j] = y0
                    self.n_sw[j], self.W[j], self.done[j] = 2 * k0 + 1, W, False
                    self.last[j], self.k0[j], self.ref[j] = 2 * (k0 + periods), k0, ref
                    if i is not None:
                        self.kept[i] = self.keep[j] = [] if ref is not None or self.record_states else None
                    if ref is not None:
                        self.inv_scale[j] = 1.0 / np.maximum(np.max(np.abs(ref), axis=0), 1e-9)
                    hi[j] = k0 / W
                    target[j] = (k0 + periods + 1) / W if i is not None else hi[j]
                    lane_of[j] = i if i is not None else -1
                    ta.reset_cooldowns(j)
            ta.set_dtime(hi, np.zeros(B))

        load()
        while any(i is not None and i >= 0 for i in lane_of):
            ta.propagate_until(target)
            for j, r in enumerate(ta.propagate_res):     # each job's Taylor steps
                if lane_of[j] is not None and lane_of[j] >= 0:
                    self.steps[lane_of[j]] += int(r[3])
            for j in range(B):
                if lane_of[j] is not None and lane_of[j] >= 0 and self.done[j]:
                    out[lane_of[j]] = self.state[:, j].copy()
                    lane_of[j] = None
            if any(i is None for i in lane_of):
                load()
        return out

    record_states = False

    def after_switch(self, j):
        """Lane ``j`` has switched its relay (nothing more here)."""

    def start_flags(self, j, t, params, y0):
        """The flags of lane ``j``'s start: the relay's, and contact when starting inside the stop."""
        flags = self.system.initial_flags(t, params)
        flags["contact"] = 1.0 if y0[0] < params["e"] else 0.0
        return flags


class BareBatchLyapunov(BareBatch):
    """As :class:`BareBatch`, plus what a Lyapunov exponent needs: the transient, the recorded
    window (states kept at period ends) and a Benettin companion renormalised toward them
    every period, as three passes of the same minimal loop; returns the exponents."""

    record_states = True

    def run_many(self, values):
        self.warm()
        T, R = self.task.transient, self.task.record
        ends = self._run([(float(W), self.y0, 0, T, None) for W in values])
        self._run([(float(W), y, T, R, None) for W, y in zip(values, ends)])
        refs = [np.array([y] + k) for y, k in zip(ends, self.kept)]
        rng = np.random.default_rng(1)
        comp = [(float(W), r[0] + 1e-8 * rng.standard_normal(r.shape[1]) * np.max(np.abs(r), axis=0) / 2, T, R, r)
                for W, r in zip(values, refs)]
        self._run(comp)
        return [float(np.mean(k)) if k else float("nan") for k in self.kept]


def default_diagram(args):
    """The CLI's default diagram, variants side by side (see the module docstring)."""
    values = np.linspace(2.0, 10.0, args.n)
    variants = {"companion, record not extended (before)": dict(lyapunov_method="companion", max_record=args.record),
                "companion, record extended": dict(lyapunov_method="companion"),
                "tangent vector, record extended (after: the default)": dict(lyapunov_method="tangent")}
    walls = {k: [] for k in variants}
    cpus = {k: [] for k in variants}

    def cpu():   # this process and its finished workers [s]: less sensitive than wall time to the shared load
        me, kids = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
        return me.ru_utime + me.ru_stime + kids.ru_utime + kids.ru_stime

    for r in range(args.rounds):
        for label, kw in variants.items():
            load = os.getloadavg()[0]
            t0, c0 = time.perf_counter(), cpu()
            ds = sweep("thesis-1dof", "relay_hz", values, transient=args.transient, record=args.record,
                       workers=args.workers, progress=False, **kw)
            wall = time.perf_counter() - t0
            walls[label].append(wall)
            cpus[label].append(cpu() - c0)
            codes = ds["class_code"].values.ravel()
            print(f"round {r + 1}, {label}: {wall:.2f} s wall, {cpus[label][-1]:.1f} s CPU (load {load:.2f} before), sweep "
                  f"{ds.attrs['sweep_seconds']:.2f} s, classes {dict(zip(*np.unique(codes, return_counts=True)))}, "
                  f"records extended {int((ds['record_used'] > args.record).sum())}", flush=True)
    print(f"load average after: {os.getloadavg()}")
    base = min(walls["companion, record not extended (before)"])
    base_cpu = min(cpus["companion, record not extended (before)"])
    for label, w in walls.items():
        print(f"{label:55s} best {min(w):6.2f} s wall ({min(w) / base:.2f} x before), {min(cpus[label]):6.1f} s CPU "
              f"({min(cpus[label]) / base_cpu:.2f} x before)  all walls: " + ", ".join(f"{x:.2f}" for x in w))
    best = min(walls["tangent vector, record extended (after: the default)"])
    print(f"default diagram <= 20 s wall: {best:.2f} s   {'met' if best <= 20 else 'NOT met'}")
    return 0


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--n", type=int, default=1000)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--serial-stride", type=int, default=10)
    ap.add_argument("--transient", type=int, default=300)
    ap.add_argument("--record", type=int, default=100)
    ap.add_argument("--output", default=None, help="netCDF path prefix for the diagrams (default: in memory)")
    ap.add_argument("--default-diagram", action="store_true",
                    help="time the CLI's default diagram, tangent vector against companions (see above)")
    ap.add_argument("--rounds", type=int, default=2, help="rounds of --default-diagram")
    args = ap.parse_args(argv)
    print(f"load average before: {os.getloadavg()}, cores: {os.cpu_count()}")
    if args.default_diagram:
        return default_diagram(args)
    values = np.linspace(2.0, 10.0, args.n)
    problem = Problem(maps.get_scene("thesis-1dof").parameters(preset="matlab-listing", V=90.0),
                      transient=args.transient, record=args.record)
    base = dict(preset="matlab-listing", params={"V": 90.0}, transient=args.transient, record=args.record,
                tol=problem.tol, progress=False)
    lean = dict(lyapunov=False, grazing=False, error_sample=0)

    def timed(label, vals, workers, **kw):
        path = args.output and f"{args.output}.{label.replace(' ', '-')}.nc"
        t0 = time.perf_counter()
        ds = sweep("thesis-1dof", "relay_hz", vals, workers=workers, path=path, **base, **kw)
        wall = time.perf_counter() - t0
        codes = ds["class_code"].values.ravel()
        print(f"bifurc.sweep, {label}: {vals.size} values, {workers} workers: {wall:.2f} s wall "
              f"(per-value times sum to {float(ds['run_seconds'].sum()):.1f} s; status ok "
              f"{int((ds['status'] == 0).sum())}/{vals.size}; {int(ds['n_steps'].sum())} Taylor steps; "
              f"classes {dict(zip(*np.unique(codes, return_counts=True)))})")
        return wall, ds

    walls = {}
    walls["full"], _ = timed("full (bifurc diagram)", values, args.workers)
    walls["batch"], _ = timed("stroboscopic only, batch mode", values, args.workers, **lean)
    walls["scalar"], scalar = timed("stroboscopic only, batch_size=1", values, args.workers, batch_size=1, **lean)
    x_scalar = scalar["x"].isel(branch=0, sample=-1).values

    bares = {}
    for label, bare_cls in (("scalar", BareTrajectory), ("batch", BareBatch),
                            ("batch + Lyapunov companions", BareBatchLyapunov)):
        t0 = time.perf_counter()
        final = map_values(bare_cls(problem), values, workers=args.workers)
        bares[label] = time.perf_counter() - t0
        print(f"bare heyoka ensemble ({label}; outside the product), {args.workers} workers: {bares[label]:.2f} s wall")
        if label == "scalar":
            print(f"  bare scalar vs bifurc.sweep (batch_size=1) final x: max |diff| = "
                  f"{np.nanmax(np.abs(np.array(final) - x_scalar)):.2e} m")

    sub = values[::args.serial_stride]
    t0 = time.perf_counter()
    sweep("thesis-1dof", "relay_hz", sub, workers=1, batch_size=1, **base, **lean)
    serial = (time.perf_counter() - t0) * values.size / sub.size
    print(f"serial loop (bifurc.sweep, batch_size=1, 1 process) over {sub.size} of the values, extrapolated to "
          f"{args.n}: {serial:.1f} s")
    print(f"load average after: {os.getloadavg()}")
    full, wall = walls["full"], walls["batch"]
    print(f"\nbifurc diagram (full) wall:                {full:7.2f} s")
    print(f"stroboscopic diagram wall <= 20 s:          {wall:7.2f} s   {'met' if wall <= 20 else 'NOT met'}")
    print(f"throughput vs serial loop >= 3x:            {serial / wall:7.2f} x   "
          f"{'met' if serial / wall >= 3 else 'NOT met'}  (processes alone, batch_size=1: {serial / walls['scalar']:.2f} x)")
    eff = walls["batch"] / bares["batch"]
    print(f"stroboscopic diagram / bare ensemble <= 1.5: {eff:6.2f}     {'met' if eff <= 1.5 else 'NOT met'}"
          f"  (batch_size=1 / bare scalar: {walls['scalar'] / bares['scalar']:.2f})")
    r = full / bares["batch + Lyapunov companions"]
    print(f"full diagram / bare ensemble of the same trajectories, companions included <= 1.5: "
          f"{r:5.2f}   {'met' if r <= 1.5 else 'NOT met'}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
