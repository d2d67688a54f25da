"""The batch engine: heyoka's batch mode, ``batch_size`` orbit jobs per SIMD pass.

Each lane carries its own parameter values, start, flags, switch instants and sampling
clock.  What keeps the lanes busy and Python out of the way:

- the next clock instant (a periodic switch or a sample time, whichever comes first) is a
  terminal *time event* ``(t - t_next) / T = 0`` per lane, so lanes with different relay
  frequencies never wait for each other;
- every transition is applied in the event's callback, inside ``propagate_until``, with the
  rules of :mod:`maps.transitions` (the same as the scalar engine's);
- a lane whose job ends is refilled at once with the next job.

With ``tangent=True`` the integrator also carries one tangent vector u per lane (u' = (df/dy) u,
heyoka's ``diff`` of the vector field), which the callbacks update by the saltation rule at every
state event and by the projection's Jacobian where a settle projects the state
(:meth:`maps.variational.Derivatives.transition`; a relay switch at a fixed time needs nothing),
and renormalise to unit length at every recorded sample (:mod:`maps.tangent`).

Supported: systems with at most one periodic switch.  heyoka deep-copies event callbacks;
the callbacks here return themselves from ``__deepcopy__`` so that every copy sees the
engine's live lanes.
"""
from __future__ import annotations

import math
import time as _time
from collections import deque

import numpy as np

from collections.abc import Mapping

from .. import transitions as tr
from ..hybrid import EVENT_COOLDOWN
from ..parameters import ParameterError
from ..tangent import renormalise, tangent_sample
from .base import Engine, OrbitJob, OrbitResult

#: relative distance within which two clock instants are the same instant
_SAME_INSTANT = 1e-13
#: [s] the clock instant of a parked lane: never reached, and finite so the clock event stays finite
_FAR = 1e30


def unsupported(system) -> str | None:
    """Why ``system`` cannot run on the batch engine, or None if it can."""
    if len(system.switches) > 1:
        return (f"the batch engine supports at most one periodic switch; "
                f"{system.name!r} has {len(system.switches)}")
    return None


class _Lane:
    __slots__ = ("job", "res", "W", "n_sw", "t_sw", "k_next", "t_k", "rec_k", "last", "flags", "params",
                 "events", "recording", "budget", "done", "start_clock", "tangent", "timed", "in_mode_since",
                 "mode_total")


class _GridLane:
    """A lane of :meth:`BatchEngine._run_grid`: its flags, their changes ``(t, flags after, their key)`` and its
    event count."""

    __slots__ = ("start", "start_key", "flags", "key", "log", "count", "cap")

    def __init__(self, flags, key, cap):
        self.start = self.flags = flags
        self.start_key = self.key = key
        self.log, self.count, self.cap = [], 0, cap


#: what a guard crossing does in a run on the sampling grid (:meth:`BatchEngine._grid_rule`), besides new flags
_PASS, _OBSERVED, _HALT = object(), object(), object()


class BatchEngine(Engine):
    """A compiled batch integrator for one system structure, tolerance and width, and its lane loop."""

    name = "batch"

    def __init__(self, system, tol: float, *, batch_size: int = 4, observations: bool = True,
                 max_events_per_period: int = 10_000, tangent: bool = False):
        import heyoka as hy
        super().__init__(system, tol, max_events_per_period=max_events_per_period, observations=observations)
        reason = unsupported(system)
        if reason:
            raise ParameterError(reason)
        if batch_size < 1:
            raise ParameterError(f"batch_size = {batch_size}: need at least 1 lane")
        self.B, self.hy = int(batch_size), hy
        groups = tr.event_surfaces(system, observations)
        self.choices = [tr.GuardChoice(g) for g in groups]
        self.sw = system.switches[0] if system.switches else None
        self.i_next = len(system.param_names) + len(system.flag_names)   # next clock instant [s]
        self.i_rate = self.i_next + 1                                     # 1 / sampling period [1/s]
        self.i_flag = dict(system._flag_index)
        events = [hy.t_event_batch(grp[0].expr, cooldown=EVENT_COOLDOWN, callback=_GuardCallback(self, gi),
                                   direction=grp[0].heyoka_direction() if not self.choices[gi].mixed
                                   else hy.event_direction.any) for gi, grp in enumerate(groups)]
        events.append(hy.t_event_batch((hy.time - hy.par[self.i_next]) * hy.par[self.i_rate],
                                       direction=hy.event_direction.positive, cooldown=EVENT_COOLDOWN,
                                       callback=_ClockCallback(self)))
        self.n = len(system.states)
        self.tangent = bool(tangent)
        dynamics = system.heyoka_system()
        t0 = _time.perf_counter()
        if self.tangent:
            from ..variational import Derivatives, tangent_equations
            self.derivatives = Derivatives(system)
            dynamics = dynamics + tangent_equations(system)
        self.ta = hy.taylor_adaptive_batch(dynamics, np.zeros((len(dynamics), self.B)), tol=tol,
                                           t_events=events)
        self.compile_seconds = _time.perf_counter() - t0
        self.state, self.pars, self.time = self.ta.state, self.ta.pars, self.ta.time   # live views
        self.lanes: list = [None] * self.B
        self.grid_lanes: list | None = None       # the lanes of a run on the sampling grid (:meth:`_run_grid`)
        self.grid_rules: dict = {}                # (surface, sign, flags) -> what a crossing does (:meth:`_grid_rule`)
        self.on_grid = self.sw is None and not self.tangent and _flags_only(system, groups)

    # ----- per-lane helpers -------------------------------------------------------
    def _set_flags(self, j, lane, changes, t):
        pars, i_flag = self.pars, self.i_flag
        for k, v in changes.items():
            lane.flags[k] = v
            pars[i_flag[k], j] = v
        if lane.timed is not None and lane.timed[0] in changes and lane.res.points:
            self._time_mode(lane, t)

    @staticmethod
    def _time_mode(lane, t):
        """Bank the time in the timed mode up to ``t`` [s] and note whether the lane is in it now."""
        flag, value = lane.timed
        if lane.in_mode_since is not None:
            lane.mode_total += t - lane.in_mode_since
        lane.in_mode_since = t if lane.flags.get(flag) == value else None

    def _apply(self, j, lane, out: tr.Outcome, t) -> bool:
        """Write a transition's outcome into lane j, count and log its records; False: the lane ended."""
        if out is tr.NOTHING:
            return True
        if out.y is not None:
            self.state[:self.n, j] = out.y
        if out.changes:
            self._set_flags(j, lane, out.changes, t)
        for name, y_minus, _, _ in out.records:
            cap = lane.budget.count(name, t)
            if cap is not None:
                self._end(j, lane, "failed", str(cap), t)
                return False
            if lane.recording:
                lane.events.append((name, t, y_minus))
        if out.halted:
            name = out.records[0][0] if out.records else "settle"
            self._end(j, lane, "escaped", f"{name}: the state left the model's domain at t = {t:.9g} s", t)
            return False
        return True

    def _sample(self, j, lane, t):
        res = lane.res
        if lane.tangent:
            self._renormalise_tangent(j, lane, first=not res.points)
        if lane.timed is not None:
            self._time_mode(lane, t)
            res.mode_time.append(lane.mode_total)
        res.times.append(t)
        res.points.append(self.state[:self.n, j].copy())
        res.flags.append(dict(lane.flags))
        if lane.job.log and lane.recording and len(res.points) > 1:
            res.period_events.append(lane.events)
            lane.events = []

    def _renormalise_tangent(self, j, lane, first):
        """At a recorded sample: the tangent vector starts (``first``), or is logged and scaled back
        to unit length (a vector that is no longer finite or vanished ends the tangent: no more logs)."""
        lane.tangent = tangent_sample(self.state[self.n:, j], lane.res.tangent, lane.job.tangent if first else None,
                                      lane.job.shift)

    def _tangent_transition(self, j, lane, out, t, flags_before, guard=None, y_now=None):
        """The tangent vector through a transition (saltation, projection)."""
        if not lane.tangent or out is tr.NOTHING or (out.y is None and not out.changes):
            return
        u = self.state[self.n:, j]
        y_minus = out.records[0][1] if guard is not None else None
        Y, _ = self.derivatives.transition(u[:, None], out, t, lane.params, flags_before, lane.flags,
                                           guard, y_minus, y_now)
        u[:] = Y[:, 0]

    def _renormalise(self, j, lane, t, i):
        """Companion: back to d0 from the reference's i-th state, flags by the system's rule."""
        job = lane.job
        z, stretch = renormalise(job.reference[i], self.state[:self.n, j], job.d0, job.scale, job.shift)
        lane.res.stretch.append(stretch)
        if not math.isfinite(stretch):
            return False
        self.state[:self.n, j] = z
        flags = tr.start_flags(self.system, t, z, lane.params, None)
        self._set_flags(j, lane, {k: v for k, v in flags.items() if lane.flags.get(k) != v}, t)
        self.ta.reset_cooldowns(j)
        return self._apply(j, lane, tr.settle(self.system, t, z, lane.flags, lane.params), t)

    def _end(self, j, lane, status="ok", failure="", t=math.nan):
        res = lane.res
        res.status, res.failure = status, failure
        if status != "ok":
            res.failure_time = t
            if lane.job.log:
                res.tail_events = lane.events
        res.final_time = float(self.time[j])
        res.final_state = self.state[:self.n, j].copy()
        res.final_flags = dict(lane.flags)
        res.n_events = lane.budget.total
        lane.done = True

    def _load(self, j, job: OrbitJob, res, target, hi, lo):
        """Put ``job`` into lane j (state, time, parameters, flags, clock)."""
        sw, system = self.sw, self.system
        lane = _Lane()
        lane.job, lane.res = job, res
        lane.params = job.params
        t0 = job.sample_time(job.k0)
        lane.flags = tr.start_flags(system, t0, job.y0, job.params, job.flags)
        if sw is not None:
            lane.W = float(job.params[sw.frequency])
            lane.n_sw = sw.index_at(t0, lane.W) + 1
            lane.t_sw = sw.instants(lane.W, lane.n_sw)
        else:
            lane.W, lane.n_sw, lane.t_sw = 0.0, 0, math.inf
        lane.k_next = job.k0 + 1
        lane.t_k = job.sample_time(lane.k_next)
        lane.rec_k = job.k0 + job.transient
        lane.last = lane.rec_k + job.record
        lane.events, lane.recording, lane.done = [], False, False
        lane.tangent = self.tangent and job.tangent is not None
        lane.timed = job.timed if job.reference is None else None
        lane.in_mode_since, lane.mode_total = None, 0.0
        lane.budget = tr.EventBudget(None, self.max_events_per_period)
        lane.start_clock = _time.perf_counter()
        hi[j], lo[j] = t0, 0.0
        self.state[:, j] = 0.0
        self.state[:self.n, j] = system.on_mode_set(job.y0, job.params, lane.flags, t0) if system.mode_projections \
            else job.y0
        self.pars[:, j] = system.par_vector(job.params, lane.flags) + [min(lane.t_sw, lane.t_k, _FAR), 1.0 / job.period]
        self.ta.reset_cooldowns(j)
        target[j] = job.sample_time(lane.last + 1)     # never reached: the last sample ends the lane
        self.lanes[j] = lane
        out = tr.settle(system, t0, self.state[:self.n, j], lane.flags, lane.params)
        if not self._apply(j, lane, out, t0):
            return
        if job.transient == 0:
            lane.recording = job.log
            if job.reference is None:
                self._sample(j, lane, t0)
        if lane.last == job.k0:
            self._end(j, lane)

    # ----- the loop ---------------------------------------------------------------
    def run(self, jobs: list[OrbitJob]) -> list[OrbitResult]:
        """Integrate every job; one :class:`OrbitResult` per job, in order."""
        if not jobs:
            return []
        if self.on_grid and all(_plain(j) for j in jobs):
            return self._run_grid(jobs)
        return self._run_lanes(jobs)

    def _run_grid(self, jobs: list[OrbitJob]) -> list[OrbitResult]:
        """Plain jobs (:func:`_plain`) of a system without a clock whose guards only set flags (:func:`_flags_only`):
        ``B`` jobs of one length at a time, integrated by heyoka's ``propagate_grid`` over their sample times (no
        clock event, no Python per sample), the guards' flag changes written by :meth:`_grid_event`.  The samples
        are the dense output at the sample times (the lane loop stops at them as events: the same states to
        round-off).  A group where any lane fails, escapes or exceeds the event cap runs again on the lane loop
        (:meth:`_run_lanes`), which reports it."""
        hy, B, n = self.hy, self.B, self.n
        results: list = [None] * len(jobs)
        order = sorted(range(len(jobs)), key=lambda i: jobs[i].record)
        groups, i = [], 0
        while i < len(order):
            m = jobs[order[i]].record
            g = [order[i]]
            i += 1
            while i < len(order) and len(g) < B and jobs[order[i]].record == m:
                g.append(order[i])
                i += 1
            groups.append(g)
        ok = int(hy.taylor_outcome.time_limit)
        for g in groups:
            clock = _time.perf_counter()
            lanes = [g[j] if j < len(g) else g[0] for j in range(B)]      # spare lanes repeat the first job
            m = jobs[g[0]].record
            grid = np.empty((m + 1, B))
            self.grid_lanes = [None] * B
            for j, idx in enumerate(lanes):
                job = jobs[idx]
                k = np.arange(job.k0, job.k0 + m + 1, dtype=float)       # as OrbitJob.sample_time
                grid[:, j] = job.offset + (k / job.rate if job.rate is not None else k * job.period)
                flags = tr.start_flags(self.system, grid[0, j], job.y0, job.params, job.flags)
                self.state[:, j] = job.y0
                # the clock instant beyond the last sample, never reached (at _FAR, (t - t_next) / T of the order
                # of 1e30 spoils heyoka's steps in every lane: errors of 1e15 over 10 samples of the Lorenz-84 flow)
                self.pars[:, j] = self.system.par_vector(job.params, flags) + [grid[-1, j] + job.period,
                                                                               1.0 / job.period]
                self.grid_lanes[j] = _GridLane(flags, self._flag_key(flags), self.max_events_per_period * max(m, 1))
            self.ta.set_dtime(grid[0].copy(), np.zeros(B))
            self.ta.reset_cooldowns()
            self.grid_stop = False
            try:
                out = self.ta.propagate_grid(grid)
            finally:
                lanes_run, self.grid_lanes = self.grid_lanes, None
            points = out[-1] if isinstance(out, tuple) else out
            if self.grid_stop or any(int(r[0]) != ok for r in self.ta.propagate_res) \
                    or not np.all(np.isfinite(points[:, :n, :len(g)])):
                for idx, r in zip(g, self._run_lanes([jobs[idx] for idx in g])):
                    results[idx] = r
                continue
            share = (_time.perf_counter() - clock) / B
            for j, idx in enumerate(g):
                results[idx] = _grid_result(grid[:, j], points[:, :n, j], lanes_run[j],
                                            self.ta.propagate_res[j][3], share)
        return results

    def _grid_event(self, choose, d_sgn, j) -> bool:
        """A guard crossed in lane j of :meth:`_run_grid`: its flag changes written and noted (False, stopping the
        group: the event cap exceeded or a halt flag set; the lane loop then runs the group).  The flags after a
        crossing depend only on the surface, the crossing's sign and the flags before: looked up once each."""
        lane = self.grid_lanes[j]
        key = (choose, d_sgn, lane.key)
        got = self.grid_rules.get(key)
        if got is None:
            got = self.grid_rules[key] = self._grid_rule(choose, d_sgn, lane.flags)
        if got is _PASS:
            return True
        lane.count += 1
        if lane.count > lane.cap or got is _HALT:
            self.grid_stop = True
            return False
        if got is _OBSERVED:
            return True
        flags, fkey, writes = got
        pars = self.pars
        for row, v in writes:
            pars[row, j] = v
        lane.flags, lane.key = flags, fkey
        lane.log.append((self.time.item(j), flags, fkey))
        return True

    def _grid_rule(self, choose, d_sgn, flags):
        """What a crossing of sign ``d_sgn`` does to lanes in ``flags``: _PASS (no guard acts), _OBSERVED (an
        event that changes nothing), _HALT (a halt flag set), else (the flags after, their key, the pars rows
        written)."""
        guard = choose(d_sgn, flags)
        if guard is None:
            return _PASS
        changes = {k: v for k, v in (guard.then or {}).items() if flags.get(k) != v}
        if not changes:
            return _OBSERVED
        after = dict(flags, **changes)
        if tr.halted(self.system, after):
            return _HALT
        return after, self._flag_key(after), [(self.i_flag[k], v) for k, v in changes.items()]

    def _flag_key(self, flags) -> tuple:
        return tuple(flags.get(f) for f in self.system.flag_names)

    def _run_lanes(self, jobs: list[OrbitJob]) -> list[OrbitResult]:
        """The lane loop: every job, clock instants and samples as terminal events (module docstring)."""
        hy, ta, B = self.hy, self.ta, self.B
        results = [OrbitResult() for _ in jobs]
        waiting = deque(range(len(jobs)))
        lanes = self.lanes = [None] * B
        target = np.array(self.time, dtype=float)
        success = int(hy.taylor_outcome.success)
        j0 = jobs[0]     # what a lane without a job holds: a valid state and parameters, and no motion
        parked = np.concatenate([np.asarray(j0.y0, dtype=float), np.zeros(self.state.shape[0] - self.n)])
        flags0 = tr.start_flags(self.system, 0.0, parked, j0.params, j0.flags)
        parked_pars = self.system.par_vector(j0.params, flags0) + [_FAR, 1.0 / j0.period]

        def refill():
            """Load waiting jobs into free lanes; park the rest (finite state, no motion)."""
            hi, lo = (np.array(a, dtype=float) for a in ta.dtime)
            for j in range(B):
                while lanes[j] is None and waiting:
                    i = waiting.popleft()
                    self._load(j, jobs[i], results[i], target, hi, lo)
                    if lanes[j].done:           # ended at its start (escape, nothing to record)
                        self._close(j)
                if lanes[j] is None:
                    if not math.isfinite(hi[j]):                # left by a failed lane
                        hi[j] = 0.0
                    lo[j] = 0.0
                    target[j] = hi[j]
                    self.state[:, j] = parked
                    self.pars[:, j] = parked_pars
            ta.set_dtime(hi, lo)

        refill()
        while any(lane is not None for lane in lanes):
            ta.propagate_until(target)
            freed = False
            for j, (outcome, _, _, nst) in enumerate(ta.propagate_res):
                lane = lanes[j]
                if lane is None:
                    continue
                lane.res.n_steps += nst
                # success, or (code >= 0) an event whose callback let the lane go on
                code = int(outcome)
                if not lane.done and code != success and code < 0:
                    t = float(self.time[j])
                    self._end(j, lane, "failed", f"integration stopped at t = {t:.9g} s: {outcome!r} "
                                                 f"(non-finite state or step failure)", t)
                if lane.done:
                    self._close(j)
                    freed = True
            if freed:
                refill()
        return results

    def _close(self, j):
        lane = self.lanes[j]
        lane.res.seconds = (_time.perf_counter() - lane.start_clock) / self.B
        self.lanes[j] = None


class _Callback:
    """An event callback bound to its engine (heyoka deep-copies callbacks: copies are itself)."""

    def __init__(self, eng):
        self.eng = eng

    def __deepcopy__(self, memo):
        return self

    def __copy__(self):
        return self

    def __call__(self, ta, d_sgn, j):  # pragma: no cover - interface
        """heyoka's entry: a free or finished lane stops (returns False); otherwise the event acts."""
        raise NotImplementedError


class _ClockCallback(_Callback):
    """Lane j reached its next clock instant: the periodic switch and/or a sample.

    The hot path of a sweep (two calls per relay period and lane): the switch instant and the
    next sample time are computed inline here, with the same formulas as
    :meth:`PeriodicSwitch.instants` and :meth:`OrbitJob.sample_time`."""

    def __init__(self, eng):
        super().__init__(eng)
        self.sw, self.system = eng.sw, eng.system
        self.i_flag = eng.i_flag[eng.sw.flag] if eng.sw is not None else None
        self.may_settle = tr.settle_gate(eng.system)

    def _settle(self, eng, lane, j, t) -> bool:
        """The system's settle after the switch (maps.transitions.settle: NOTHING where it cannot act)."""
        y = eng.state[:eng.n, j]
        out = tr.settle(self.system, t, y, lane.flags, lane.params)
        if out is tr.NOTHING:
            return True
        y_now = y.copy() if lane.tangent else None
        if not eng._apply(j, lane, out, t):
            return False
        eng._tangent_transition(j, lane, out, t, None, y_now=y_now)
        return True

    def __call__(self, ta, d_sgn, j):      # heyoka's entry, inlined (two calls per relay period and lane)
        eng = self.eng
        lane = eng.lanes[j]
        if lane is None or lane.done:
            return False
        t_sw, t_k = lane.t_sw, lane.t_k
        t_next = t_sw if t_sw < t_k else t_k
        # a switch and a sample computed apart (n / (2 W) against k T) may differ by rounding:
        # instants this close are one instant (a later one would fall inside the event cooldown)
        close = t_next + _SAME_INSTANT * (t_next if t_next > 1.0 else 1.0)
        if t_sw <= close:
            sw, n = self.sw, lane.n_sw
            lane.flags[sw.flag] = v = sw.off_value if n % 2 else sw.on_value
            eng.pars[self.i_flag, j] = v
            if n % 2 == 0:
                lane.budget.in_period = 0             # a new relay period begins
            m = n + 1
            lane.n_sw = m
            lane.t_sw = (m // 2 + (sw.duty if m % 2 else 0.0)) / lane.W
            lane.res.n_switches += 1
            may = self.may_settle
            if may is not None and may(lane.flags, eng.state[:eng.n, j], lane.params) \
                    and not self._settle(eng, lane, j, t_sw):
                return False
        if t_k <= close:
            k = lane.k_next
            lane.k_next = k + 1
            job = lane.job
            lane.t_k = job.offset + ((k + 1) / job.rate if job.rate is not None else (k + 1) * job.period)
            lane.budget.in_period = 0
            if k >= lane.rec_k:
                t = float(eng.time[j])
                if job.reference is None:
                    if k == lane.rec_k:
                        lane.recording = job.log
                    eng._sample(j, lane, t)
                elif k > lane.rec_k and not eng._renormalise(j, lane, t, k - lane.rec_k):
                    if not lane.done:           # a failed stretch ends it as ok; a settle may have ended it already
                        eng._end(j, lane)
                    return False
                if lane.done:
                    return False
            if k >= lane.last:
                eng._end(j, lane)
                return False
        t_sw, t_k = lane.t_sw, lane.t_k
        eng.pars[eng.i_next, j] = t_sw if t_sw < t_k else t_k
        return True


class _GuardCallback(_Callback):
    """A guard surface crossed in lane j: the active guard's transition (maps.transitions)."""

    def __init__(self, eng, gi):
        super().__init__(eng)
        self.choose = eng.choices[gi]

    def __call__(self, ta, d_sgn, j):      # heyoka's entry, inlined (the hot path of every sweep)
        eng = self.eng
        if eng.grid_lanes is not None:
            return eng._grid_event(self.choose, d_sgn, j)
        lane = eng.lanes[j]
        if lane is None or lane.done:
            return False
        guard = self.choose(d_sgn, lane.flags)
        if guard is None:
            return True
        t = eng.time.item(j)
        out = tr.fire(eng.system, guard, t, eng.state[:eng.n, j], lane.flags, lane.params)
        if not lane.tangent or out is tr.NOTHING or (out.y is None and not out.changes):
            return eng._apply(j, lane, out, t)
        if out.projection is None:        # the hot path: one compiled saltation of u
            u = eng.derivatives.tangent_jump(guard, out.changes)(eng.state[:, j], eng.pars[:, j], t)
            if not eng._apply(j, lane, out, t):
                return False
            eng.state[eng.n:, j] = u
            return True
        before = dict(lane.flags)
        if not eng._apply(j, lane, out, t):
            return False
        eng._tangent_transition(j, lane, out, t, before, guard)
        return True



def _plain(job: OrbitJob) -> bool:
    """Whether a job asks for the samples only: no transient, event log, companion, tangent vector or timed mode."""
    return (job.transient == 0 and not job.log and job.reference is None and job.tangent is None
            and job.timed is None)


def _flags_only(system, groups) -> bool:
    """Whether every transition of ``system`` at its event surfaces ``groups`` only sets flags: no reset map, no
    callable or projecting ``then``, no settle rule or mode projection (the modified Lorenz-84 flow's sign flag,
    docs/howto/autonomous-flows.md): :meth:`BatchEngine._run_grid` can then run it."""
    return (system.settle is None and not system.mode_projections
            and all(g.reset is None and (g.then is None or isinstance(g.then, Mapping)) for grp in groups for g in grp))


def _grid_result(times, points, lane: _GridLane, steps: int, seconds: float) -> OrbitResult:
    """The :class:`OrbitResult` of one lane of :meth:`BatchEngine._run_grid`: its samples at ``times``, each with
    the flags after the last change before it (also as the array ``point_flags``)."""
    res = OrbitResult()
    at = np.searchsorted(np.array([t for t, _, _ in lane.log]), times, side="right")   # changes up to each sample
    flags = [lane.start] + [f for _, f, _ in lane.log]
    keys = np.array([lane.start_key] + [k for _, _, k in lane.log], dtype=float).reshape(len(flags), -1)
    res.times, res.points = times.copy(), points.copy()
    res.flags = [flags[i] for i in at]      # shared dicts, read only (maps.poincare reads them into an array)
    res.point_flags = keys[at]
    res.final_time = float(times[-1])
    res.final_state = points[-1].copy()
    res.final_flags = dict(flags[at[-1]])
    res.n_steps, res.n_events, res.seconds = int(steps), lane.count, seconds
    return res
