"""heyoka batch mode for sweeps: ``batch_size`` parameter values per SIMD pass.

:class:`BatchEngine` runs a list of :class:`LaneJob` s (one trajectory each: its own
parameter values, start, relay switch instants, flags and event handling) on one compiled
``taylor_adaptive_batch``.  What keeps the SIMD lanes busy and Python out of the way:

- the relay switch is a terminal *time event* ``(t - t_next) W = 0`` per lane, so lanes with
  different relay frequencies never wait for each other's switch;
- every transition (relay switch, contact, release, escape, ...) is handled in the event's
  callback, inside ``propagate_until``: a few microseconds of Python per event, and the
  batch returns to the loop only when a lane's trajectory ends;
- a lane whose trajectory ends is refilled at once with the next job.

The system's ``settle`` runs after every lane transition, as in
:class:`~maps.hybrid.HybridRun`.  Guards must set flags without a reset map (the model's
scenes); a system with reset maps uses the scalar path.

A *companion* job (Benettin's Lyapunov exponent) follows a recorded reference orbit: at
every period end it is moved back to ``d0`` from the reference state, exactly as
:func:`bifurc.lyapunov.lyapunov_along` does on the scalar path.
"""
from __future__ import annotations

import math
import time as _time
from collections import deque
from dataclasses import dataclass, field

import numpy as np

from maps.hybrid import settle_may_act
from maps.parameters import ParameterError

__all__ = ["LaneJob", "LaneResult", "BatchEngine", "engine_for", "unsupported"]


@dataclass
class LaneJob:
    """One trajectory: from ``y0`` at t = k0 / W, ``transient`` relay periods, then ``record`` more.

    The states at the end of the transient and of every recorded period are kept, and (if
    ``log``) the guard crossings of each recorded period as ``(name, t, y)``.  With
    ``reference`` (the ``record + 1`` states of another orbit at the same period ends) the
    job is a Benettin companion: after each recorded period it is renormalised to distance
    ``d0`` (norm scaled by ``scale``) from the reference and its exponent is returned.
    """

    params: dict
    y0: np.ndarray
    flags: dict
    k0: int = 0
    transient: int = 0
    record: int = 1
    log: bool = False
    reference: list | None = None
    d0: float = 1e-8
    scale: np.ndarray | None = None


@dataclass
class LaneResult:
    times: list = field(default_factory=list)          # [s] recorded period ends (first: end of transient)
    points: list = field(default_factory=list)         # states at those times
    period_events: list = field(default_factory=list)  # per recorded period: [(name, t, y)]
    tail_events: list = field(default_factory=list)    # logged crossings after the last complete period
    status: str = "ok"                                 # ok, escaped, failed
    failure: str = ""
    failure_time: float = math.nan
    final_time: float = 0.0
    final_state: np.ndarray | None = None
    final_flags: dict = field(default_factory=dict)
    n_steps: int = 0
    n_events: int = 0
    n_switches: int = 0
    seconds: float = 0.0                               # share of the batch's wall time
    lyapunov: float = math.nan                         # companion jobs: exponent per period


class _Lane:
    __slots__ = ("job", "res", "W", "n_sw", "last", "rec_k", "flags", "params", "k_done", "events",
                 "n_events_period", "lyap_sum", "lyap_n", "done", "start_clock")


def unsupported(system) -> str | None:
    """Why ``system`` cannot run in batch mode, or None if it can."""
    if any(g.reset is not None or callable(g.then) for g in system.guards):
        return (f"batch mode supports guards that set flags without a reset map; "
                f"{system.name!r} has others: use the scalar path")
    if "dc_region" in system.flag_names:
        return (f"batch mode starts lanes with flags that do not follow the state; {system.name!r} "
                f"derives flags from it (dc_law='measured'): use the scalar path")
    if len(system.switches) != 1:
        return (f"batch mode needs exactly one periodic switch (a relay); "
                f"{system.name!r} has {len(system.switches)}")
    return None


class BatchEngine:
    """A compiled batch integrator for one system structure and tolerance, and its lane loop."""

    def __init__(self, system, tol: float, batch_size: int = 4, observations: bool = False,
                 max_events_per_period: int = 10_000):
        import heyoka as hy
        from maps.hybrid import EVENT_COOLDOWN
        reason = unsupported(system)
        if reason:
            raise ParameterError(reason)
        if batch_size < 1:
            raise ParameterError(f"batch_size = {batch_size}: need at least 1 lane")
        self.system, self.B, self.hy, self.tol = system, int(batch_size), hy, tol
        self.max_events_per_period = max_events_per_period
        # one event per surface (direction "any" where its guards differ), dispatched on the
        # crossing's sign and the lane's flags; guards that only observe (no new flags) need
        # no stop unless asked for
        by_surface: dict = {}
        for g in system.guards:
            if observations or g.then is not None:
                by_surface.setdefault(str(g.expr), []).append(g)
        groups = list(by_surface.values())
        self.sw = sw = system.switches[0]
        self.i_next = len(system.param_names) + len(system.flag_names)     # next switch instant [s]
        i_W = system._param_index[sw.frequency]
        self.i_flag = dict(system._flag_index)     # every flag is a runtime parameter (below i_next)
        # per group: [(name, direction, [(flag, value) when], {flag: value} then)]
        self.groups = [[(g.name, g.direction, [(k, float(v)) for k, v in g.when.items()],
                         {k: float(v) for k, v in (g.then or {}).items()}) for g in grp] for grp in groups]
        events = [hy.t_event_batch(grp[0].expr, cooldown=EVENT_COOLDOWN, callback=_GuardCallback(self, gi),
                                   direction=grp[0].heyoka_direction() if len({g.direction for g in grp}) == 1
                                   else hy.event_direction.any) for gi, grp in enumerate(groups)]
        events.append(hy.t_event_batch((hy.time - hy.par[self.i_next]) * hy.par[i_W],
                                       direction=hy.event_direction.positive, cooldown=EVENT_COOLDOWN,
                                       callback=_RelayCallback(self)))
        n = len(system.states)
        self.ta = hy.taylor_adaptive_batch(system.heyoka_system(), np.zeros((n, self.B)), tol=tol,
                                           t_events=events)
        self.state, self.pars, self.time = self.ta.state, self.ta.pars, self.ta.time   # live views
        self.halt = tuple(system.halt_flags)
        self.flag_defaults = dict(system.flag_defaults, **{sw.flag: sw.on_value})   # at a period start
        self.lanes: list = [None] * self.B

    # ----- per-lane helpers -------------------------------------------------------
    def _set_flags(self, j, lane, new):
        pars, i_flag = self.pars, self.i_flag
        for k, v in new.items():
            lane.flags[k] = v
            i = i_flag.get(k)
            if i is not None:
                pars[i, j] = v

    def _settle(self, j, lane, t):
        settle = self.system.settle
        if settle is None:
            return
        if not settle_may_act(self.system, lane.flags):
            return
        new = settle(t, self.state[:, j], lane.flags, lane.params)
        if isinstance(new, tuple):
            new, y = new
            self.state[:, j] = y
        if new:
            self._set_flags(j, lane, new)

    def _sample(self, j, lane, t):
        """Record the state at a period end inside the recorded window."""
        res = lane.res
        res.times.append(t)
        res.points.append(self.state[:, j].copy())
        if lane.job.log and len(res.points) > 1:
            res.period_events.append(lane.events)
            lane.events = []

    def _renormalise(self, j, lane, t, k):
        """Benettin step: move the companion back to d0 from the reference; flags from its state."""
        job, state = lane.job, self.state
        y = job.reference[k - lane.rec_k]
        dz = state[:, j] - y
        d = dz / job.scale
        dist = math.sqrt(float(d @ d))
        if not math.isfinite(dist) or dist == 0.0:
            lane.lyap_n = -1                               # undetermined
            return
        if lane.lyap_n >= 0:
            lane.lyap_sum += math.log(dist / job.d0)
            lane.lyap_n += 1
        state[:, j] = z = y + dz * (job.d0 / dist)
        # as StroboscopicMap.step at a period start: default flags, the relay ON, contact from the gap
        flags = dict(self.flag_defaults)
        if "contact" in flags:
            flags["contact"] = 1.0 if self.system.gap(z, lane.params)[0] < 0 else 0.0
        self._set_flags(j, lane, flags)
        self.ta.reset_cooldowns(j)
        self._settle(j, lane, t)

    def _end(self, j, lane, status="ok", failure="", t=math.nan):
        """Close lane j's result (the lane is freed by the loop)."""
        res = lane.res
        res.status, res.failure = status, failure
        if status != "ok":
            res.failure_time = t
        res.final_time = float(self.time[j])
        res.final_state = self.state[:, j].copy()
        res.final_flags = dict(lane.flags)
        res.n_switches = lane.n_sw
        res.tail_events = lane.events if lane.job.log else []
        if lane.job.reference is not None:
            res.lyapunov = lane.lyap_sum / lane.lyap_n if lane.lyap_n == lane.job.record else math.nan
        lane.done = True

    def _load(self, j, job, res, target, hi, lo):
        """Put ``job`` into lane j (state, time, parameters, flags, first switch)."""
        sw = self.sw
        lane = _Lane()
        lane.job, lane.res = job, res
        lane.W = W = float(job.params[sw.frequency])
        lane.params, lane.flags = job.params, dict(job.flags)
        lane.n_sw = 2 * job.k0 + 1
        lane.rec_k = job.k0 + job.transient
        lane.last = 2 * (job.k0 + job.transient + job.record)
        lane.k_done, lane.events, lane.n_events_period = job.k0, [], 0
        lane.lyap_sum, lane.lyap_n, lane.done = 0.0, 0, False
        lane.start_clock = _time.perf_counter()
        t0 = job.k0 / W
        hi[j], lo[j] = t0, 0.0
        self.state[:, j] = job.y0
        self.pars[:, j] = self.system.par_vector(job.params, lane.flags) + [sw.instants(W, lane.n_sw)]
        self.ta.reset_cooldowns(j)
        target[j] = (job.k0 + job.transient + job.record + 1) / W   # never reached: the last switch ends it
        self.lanes[j] = lane
        self._settle(j, lane, t0)                                     # as HybridRun.reset
        if job.transient == 0 and job.reference is None:
            self._sample(j, lane, t0)

    # ----- the loop ---------------------------------------------------------------
    def run(self, jobs: list) -> list:
        """Integrate every job; returns one :class:`LaneResult` per job, in order."""
        hy, ta, B = self.hy, self.ta, self.B
        results = [LaneResult() for _ in jobs]
        waiting = deque(range(len(jobs)))
        lanes = self.lanes = [None] * B
        target = np.array(self.time, dtype=float)
        success = int(hy.taylor_outcome.success)
        if jobs:   # what a lane without a job holds: a valid state and parameters, and no motion
            j0 = jobs[0]
            parked = j0.y0
            parked_pars = self.system.par_vector(j0.params, j0.flags) + [self.sw.instants(j0.params[self.sw.frequency], 1)]

        def refill():
            """Load waiting jobs into free lanes; park the rest (finite state, no motion)."""
            hi, lo = (np.array(a, dtype=float) for a in ta.dtime)
            for j in range(B):
                if lanes[j] is not None:
                    continue
                if waiting:
                    i = waiting.popleft()
                    self._load(j, jobs[i], results[i], target, hi, lo)
                else:
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
                    lane.res.seconds = (_time.perf_counter() - lane.start_clock) / B
                    lanes[j] = None
                    freed = True
            if freed:
                refill()
        return results


class _Callback:
    """An event callback bound to its engine.  heyoka deep-copies callbacks into the
    integrator; copies of this one are itself, so every copy sees the engine's live lanes."""

    def __init__(self, eng):
        self.eng = eng

    def __deepcopy__(self, memo):
        return self

    def __copy__(self):
        return self

    def __call__(self, ta, d_sgn, j):
        """heyoka's entry: a free or finished lane stops; otherwise :meth:`fire` decides."""
        lane = self.eng.lanes[j]
        if lane is None or lane.done:
            return False
        return self.fire(self.eng, lane, d_sgn, j)


class _RelayCallback(_Callback):
    """Lane j reached its relay switch: flip the relay, sample at a period end; False ends the lane."""

    def __init__(self, eng):
        super().__init__(eng)
        sw = eng.sw
        self.on, self.off, self.duty, self.flag = sw.on_value, sw.off_value, sw.duty, sw.flag
        self.i_flag = eng.i_flag.get(sw.flag)

    def fire(self, eng, lane, d_sgn, j):
        n = lane.n_sw
        t = float(eng.time[j])
        lane.flags[self.flag] = v = self.off if n % 2 else self.on
        if self.i_flag is not None:
            eng.pars[self.i_flag, j] = v
        eng._settle(j, lane, t)
        lane.n_sw = m = n + 1
        eng.pars[eng.i_next, j] = (m // 2 + (self.duty if m % 2 else 0.0)) / lane.W
        if n % 2:
            return True
        k = lane.k_done = n // 2
        lane.n_events_period = 0
        if k >= lane.rec_k:
            if lane.job.reference is None:
                eng._sample(j, lane, t)
            elif k > lane.rec_k:
                eng._renormalise(j, lane, t, k)
        if n >= lane.last:
            eng._end(j, lane)
            return False
        return True


class _GuardCallback(_Callback):
    """A guard surface crossed in lane j: the active guard's transition; False ends the lane.
    Which guard is active depends only on the crossing sign and the flags in its ``when``s,
    so the choice is looked up once per combination."""

    def __init__(self, eng, gi):
        super().__init__(eng)
        self.group = eng.groups[gi]
        self.keys = tuple(sorted({k for _, _, when, _ in self.group for k, _ in when}))
        self.choice: dict = {}

    def _active(self, d_sgn, flags):
        for guard in self.group:
            _, direction, when, _ = guard
            if (direction == 0 or direction == d_sgn) and all(flags[k] == v for k, v in when):
                return guard
        return None

    def fire(self, eng, lane, d_sgn, j):
        flags = lane.flags
        key = (d_sgn, *[flags[k] for k in self.keys])
        try:
            guard = self.choice[key]
        except KeyError:
            guard = self.choice[key] = self._active(d_sgn, flags)
        if guard is None:
            return True
        name, _, _, then = guard
        t = float(eng.time[j])
        lane.res.n_events += 1
        lane.n_events_period += 1
        if lane.job.log and lane.k_done >= lane.rec_k:
            lane.events.append((name, t, eng.state[:, j].copy()))
        if then:
            eng._set_flags(j, lane, then)
            eng._settle(j, lane, t)
            if any(flags[h] for h in eng.halt):
                eng._end(j, lane, "escaped", f"escaped at t = {t:.9g} s ({name})", t)
                return False
        if lane.n_events_period > eng.max_events_per_period:
            eng._end(j, lane, "failed", f"more than {eng.max_events_per_period} events in one relay "
                                        f"period at t = {t:.9g} s (chattering?)", t)
            return False
        return True


_ENGINES: dict = {}


def engine_for(system, tol: float, batch_size: int = 4, observations: bool = False) -> BatchEngine:
    """The process-wide engine for a system structure, tolerance, width and event set (compiled once)."""
    key = (system.structure, float(tol), int(batch_size), bool(observations))
    eng = _ENGINES.get(key)
    if eng is None:
        eng = _ENGINES[key] = BatchEngine(system, tol, batch_size, observations)
    return eng
