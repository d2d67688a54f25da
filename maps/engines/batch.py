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

