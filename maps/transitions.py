"""The transition rules of a hybrid system: the one place every engine takes them from.

An engine (:mod:`maps.engines`) integrates smooth segments and stops at guard surfaces
and switch instants.  What happens there is decided here, the same way for every engine:

- :func:`event_surfaces`: guards grouped by surface, one integrator event per surface;
- :class:`GuardChoice`: which guard of a surface acts, by the crossing's sign and the flags;
- :func:`fire`: a guard's transition (reset map, new flags), then :func:`settle` (not after
  an observation: what an engine records never changes the motion);
- :func:`settle`: the system's consistency rule after any transition (stick/unstick, slip),
  which may project the state, and the names of the settle transitions it logs;
- :func:`halted`: a halt flag ends the run (an escape);
- :class:`EventBudget`: the caps on events per run and per relay period;
- :func:`start_flags`: the mode a run starts in (given flags, else the system's rule);
- :func:`next_switch`: the schedule of periodic switches;
- :func:`saltation`: how the sensitivities dy/d(y0, p) jump at a state event.

Relay switches happen at fixed times: they move no state and, since their instants do not
depend on the state, need no saltation for derivatives with respect to the state.
"""
from __future__ import annotations

import math
import operator
from dataclasses import dataclass, field
from typing import Mapping

import numpy as np

from .hybrid import EventCap, Guard, HybridSystem, settle_may_act

def event_surfaces(system: HybridSystem, observations: bool = True) -> list[list[Guard]]:
    """Guards grouped by identical surface, in declaration order: one integrator event each
    (:meth:`HybridSystem.event_groups`).

    ``observations=False`` leaves out guards that change neither flags nor state, so an
    engine that needs no record of them takes no stop there (a transient).  A surface whose
    guards have different directions is one event of direction "any" (see
    :meth:`HybridSystem.event_groups` for why surfaces are never split).
    """
    return system.event_groups(observations)


class GuardChoice:
    """Which guard of one surface acts on a crossing: the first whose direction matches the
    crossing's sign and whose ``when`` flags hold (None: the crossing is passed over).

    The answer depends only on the sign and the flags named in the ``when`` s, so it is
    looked up once per combination."""

    def __init__(self, group: list[Guard]):
        self.group = group
        self.mixed = len({g.direction for g in group}) > 1
        self.keys = tuple(sorted({k for g in group for k in g.when}))
        self._flags_of = operator.itemgetter(*self.keys) if self.keys else (lambda flags: ())
        self._cache: dict = {}

    def __call__(self, sign: int, flags: Mapping[str, float]) -> Guard | None:
        key = (int(sign) if self.mixed else 0, self._flags_of(flags))
        try:
            return self._cache[key]
        except KeyError:
            pass
        chosen = None
        for g in self.group:
            if (not self.mixed or g.direction in (0, sign)) and all(flags.get(k) == v for k, v in g.when.items()):
                chosen = g
                break
        self._cache[key] = chosen
        return chosen


@dataclass(slots=True)
class Outcome:
    """What a transition did: the state after it (None: unchanged), the flags that change,
    the log ``[(name, y_before, y_after, flags_after)]`` (the guard's own record first, then
    any settle transition it caused) and whether a halt flag is now set."""

    y: np.ndarray | None = None
    changes: dict = field(default_factory=dict)
    records: list = field(default_factory=list)
    halted: bool = False
    projection: str | None = None     # name of the settle transition that projected the state


#: the outcome of a transition that changes nothing (shared: never modify it)
NOTHING = Outcome()


def settle(system: HybridSystem, t: float, y: np.ndarray, flags: Mapping[str, float],
           params: Mapping[str, float]) -> Outcome:
    """The system's ``settle`` rule at time ``t`` in state ``y`` under ``flags``.

    Returns the projected state (if the rule projects), the flags it changes, and one record
    per change named in ``system.settle_events`` (e.g. "stick", "unstick"); :data:`NOTHING`
    when the rule cannot act or changes nothing."""
    if system.settle is None or not settle_may_act(system, flags, y, params):
        return NOTHING
    new = system.settle(t, np.array(y, dtype=float), dict(flags), params)
    if not new:                     # the common case after an event: nothing to settle
        return NOTHING
    out = Outcome()
    y_minus = np.array(y, dtype=float)
    if isinstance(new, tuple):      # (flags, state): a mode entered with a state projection
        new, y_plus = new
        out.y = np.asarray(y_plus, dtype=float)
        out.projection = "settle"
    if new:
        out.changes = {k: v for k, v in new.items() if flags.get(k) != v}
        named = system.settle_events
        after = dict(flags, **out.changes)
        for k, v in out.changes.items():
            if v in named.get(k, {}):
                out.records.append((named[k][v], y_minus, out.y if out.y is not None else y_minus, after))
    if out.y is None and not out.changes:
        return NOTHING
    if out.y is not None and out.records:
        out.projection = out.records[0][0]
    out.halted = halted(system, dict(flags, **out.changes))
    return out


def settle_gate(system: HybridSystem):
    """A fast predicate ``may(flags, y, params) -> bool``: whether :func:`settle` can act under
    ``flags`` in state ``y`` (``system.settle_if``), or None when the system has no settle rule.
    For an engine's hot path (a relay switch, twice per period): it calls :func:`settle` only
    where this is True."""
    if system.settle is None:
        return None
    cond = system.settle_if
    if cond is None:
        return lambda flags, y, params: True
    if callable(cond):
        return cond
    if len(cond) == 1:
        (k1, v1), = cond
        return lambda flags, y, params: flags[k1] == v1
    if len(cond) == 2:
        (k1, v1), (k2, v2) = cond
        return lambda flags, y, params: flags[k1] == v1 or flags[k2] == v2
    return lambda flags, y, params: settle_may_act(system, flags, y, params)


def fire(system: HybridSystem, guard: Guard, t: float, y: np.ndarray, flags: Mapping[str, float],
         params: Mapping[str, float]) -> Outcome:
    """The transition of ``guard`` crossed at ``t`` in state ``y``: its reset map, its new
    flags (and the projection its ``then`` may return), then :func:`settle`.  Every guard, an
    observation too, gets one record, except a guard whose callable ``then`` declined and after
    which nothing changed (e.g. the model's "stick" crossed by a bar pulled off the stop):
    :data:`NOTHING`, no event.

    An observation (a guard that changes neither flags nor state) is NOT followed by
    :func:`settle`: an engine may skip its stop (a transient does), so a rule applied there
    would make the motion depend on what is observed."""
    y_minus = np.array(y, dtype=float)
    if guard.then is None and guard.reset is None:      # an observation: a record, nothing else
        return Outcome(None, {}, [(guard.name, y_minus, y_minus, dict(flags))], False)
    y_guard = None
    if guard.reset is not None:
        y_guard = np.asarray(system.reset_function(guard)(y_minus.copy(), params, t), dtype=float)
    here = y_minus if y_guard is None else y_guard
    changes: dict = {}
    projected = None
    if guard.then is not None:
        new = guard.then(t, here.copy(), dict(flags), params) if callable(guard.then) else guard.then
        if isinstance(new, tuple):  # (flags, state): the guard's mode entered with a projection
            new, projected = new[0], np.asarray(new[1], dtype=float)
        if new:
            changes = {k: v for k, v in new.items() if flags.get(k) != v}
    flags_guard = dict(flags, **changes) if changes else flags
    y_next = here if projected is None else projected
    s = settle(system, t, y_next, flags_guard, params)
    if s is NOTHING and callable(guard.then) and y_guard is None and projected is None and not changes:
        return NOTHING              # a conditional transition that did not happen: no event
    if s is NOTHING and projected is None:   # the common case: the guard's own transition only
        # (flags_guard is this call's own dict where the guard changed a flag: no copy needed)
        return Outcome(y_guard, changes, [(guard.name, y_minus, here, flags_guard if changes else dict(flags))],
                       halted(system, flags_guard))
    if projected is not None and s.projection is not None:
        raise ValueError(f"guard {guard.name!r} projects the state and settle projects it again: "
                         f"one projection per transition")
    y_after = s.y if s.y is not None else (projected if projected is not None else y_guard)
    out = Outcome(y=None if y_after is None else np.asarray(y_after, dtype=float),
                  changes=dict(changes, **s.changes) if s.changes else changes,
                  projection=guard.name if projected is not None else s.projection)
    # the guard's record shows the state and flags it left (before any settle transition)
    if s.records:
        out.records.append((guard.name, y_minus, here, dict(flags_guard)))
        out.records.extend(s.records)
    else:
        after = dict(flags_guard, **s.changes) if s.changes else dict(flags_guard)
        out.records.append((guard.name, y_minus, out.y if out.y is not None else y_minus, after))
    out.halted = halted(system, {**flags, **out.changes})
    return out


def halted(system: HybridSystem, flags: Mapping[str, float]) -> bool:
    """True when a halt flag (e.g. "escaped") is set: the state left the model's domain."""
    for f in system.halt_flags:
        if flags.get(f):
            return True
    return False


class EventBudget:
    """Caps on the events of one run (``per_run``) and of any one relay period (``per_period``).

    :meth:`count` returns an :class:`~maps.hybrid.EventCap` to raise (or to end a lane with)
    when a cap is exceeded, else None; ``busiest`` is the most events seen in one period."""

    __slots__ = ("per_run", "per_period", "total", "in_period", "busiest")

    def __init__(self, per_run: int | None = None, per_period: int | None = None):
        self.per_run, self.per_period = per_run, per_period
        self.total = self.in_period = self.busiest = 0

    def new_period(self):
        self.in_period = 0

    def count(self, name: str, t: float, y=None) -> EventCap | None:
        self.total += 1
        self.in_period += 1
        if self.in_period > self.busiest:
            self.busiest = self.in_period
        if self.per_run is not None and self.total > self.per_run:
            return EventCap(f"more than {self.per_run} events by t = {t:.9g} s (last: {name}); "
                            f"chattering or a runaway", t, y)
        if self.per_period is not None and self.in_period > self.per_period:
            return EventCap(f"more than {self.per_period} events in one relay period, by t = {t:.9g} s "
                            f"(last: {name}); chattering or a runaway", t, y)
        return None


def start_flags(system: HybridSystem, t: float, y, params: Mapping[str, float],
                flags: Mapping[str, float] | None = None) -> dict:
    """The flags of a run starting at ``t`` [s] in state ``y``: defaults, every switch at its
    value at ``t``, the given ``flags``, and for every flag not given the system's rule
    (:meth:`HybridSystem.mode_at`: in contact when starting inside the stop or pressed on it,
    the region of a piecewise force law).  A complete mode (a stored HybridState's flags) is
    taken as it is."""
    given = dict(flags or {})
    base = system.initial_flags(t, params, given)
    if len(given) >= len(system.flag_names) and set(given) >= set(system.flag_names):
        return base
    base.update(system.mode_at(y, params, base, tuple(given), t=t))
    return base


def next_switch(system: HybridSystem, params: Mapping[str, float], counters: Mapping[str, int]):
    """``(time [s], switch)`` of the next periodic switch, given each switch's next index."""
    best, which = math.inf, None
    for sw in system.switches:
        ts = sw.instants(params[sw.frequency], counters[sw.flag])
        if ts < best:
            best, which = ts, sw
    return best, which


def saltation(Y: np.ndarray, f_minus, f_plus, grad, g_t: float, g_p, R_y, R_p, dt=None, R_t=None) -> np.ndarray:
    """Sensitivities after a state event: ``Y`` (n x (n + m)) holds dy/d(y0, p) just before it.

    A guard g(y, t; p) = 0 crossed at t_e moves with the perturbation: dt_e = -(grad g . dy +
    g_p dp) / (grad g . f- + dg/dt).  The state after the event, R(y-(t_e), t_e), compared at
    the same time, moves by R_y dy + R_p dp + (R_y f- + R_t - f+) dt_e, hence (Y's parameter
    columns carry dp = 1)

        Y+ = R_y Y- + [0 | R_p] + (f+ - R_y f- - R_t) (grad g . Y- + [0 | g_p]) / (grad g . f- + dg/dt).

    ``R`` is the whole transition: the guard's reset composed with any settle projection, ``R_t``
    its partial time derivative (None: 0, a reset that does not read time; a moving stop's does),
    and ``f+`` the vector field of the mode entered.  A grazing crossing (denominator 0) has no
    finite saltation: ZeroDivisionError.  ``dt``: :func:`event_time_row`, if already computed.
    """
    n = Y.shape[0]
    out = R_y @ Y
    out[:, n:] += R_p
    jump = f_plus - R_y @ f_minus if R_t is None else f_plus - R_y @ f_minus - R_t
    out -= np.outer(jump, event_time_row(Y, f_minus, grad, g_t, g_p) if dt is None else dt)
    return out


def event_time_row(Y: np.ndarray, f_minus, grad, g_t: float, g_p) -> np.ndarray:
    """dt_e/d(y0, p) (n + m,) of a state event g(y, t; p) = 0 reached with sensitivities ``Y``
    (n x (n + m)) just before it: -(grad g . Y- + [0 | g_p]) / (grad g . f- + dg/dt).  A grazing
    crossing (denominator 0): ZeroDivisionError."""
    rate = float(grad @ f_minus) + g_t
    if rate == 0.0:
        raise ZeroDivisionError("grazing event: grad(g) . f + dg/dt = 0, the saltation matrix is unbounded")
    row = grad @ Y
    row[Y.shape[0]:] += g_p
    return -row / rate


def projected(Y: np.ndarray, P_y, P_p) -> np.ndarray:
    """Sensitivities after a projection at a fixed time (a settle at a relay switch): P_y Y + [0 | P_p]."""
    n = Y.shape[0]
    out = P_y @ Y
    out[:, n:] += P_p
    return out
