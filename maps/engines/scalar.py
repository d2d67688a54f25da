"""The scalar engine: one trajectory at a time on a heyoka ``taylor_adaptive``.

:class:`HybridRun` integrates one trajectory: every guard surface is a terminal event whose
callback applies the transition rules of :mod:`maps.transitions` at the crossing, and every
relay switch ends ``propagate_until`` at its exact instant, so no Taylor step crosses a mode
change.  :class:`ScalarEngine` runs :class:`~maps.engines.base.OrbitJob` s with it, one after
the other (transients without the stops at observation-only guards).
"""
from __future__ import annotations

import copy
import math
import time as _time
import weakref
from typing import Callable, Mapping

import heyoka as hy
import numpy as np

from .. import transitions as tr
from ..hybrid import (_FP_TYPES, Escaped, EventRecord, HybridState, HybridSystem,
                      IntegrationFailure, _fp, _np_dtype, validate_tol)
from ..parameters import ParameterError, validate_value
from ..progression import time_in_mode
from ..tangent import renormalise, tangent_sample
from .base import Engine, OrbitJob, OrbitResult

_TIME_LIMIT = int(hy.taylor_outcome.time_limit)
_NF_STATE = int(hy.taylor_outcome.err_nf_state)

class HybridRun:
    """One trajectory of a :class:`HybridSystem`, advanced through guards and switches.

    Relay switches end ``propagate_until`` at their exact instants; a guard's transition is
    applied in its event's callback, inside ``propagate_until`` (as the batch engine does), and
    the integration goes on unless it must end there (a halt, a ``stop_roles`` guard, a cap).

    >>> run = HybridRun(system, params, x0, tol=1e-12)
    >>> run.advance(2.0)          # to t = 2 s
    >>> run.t, run.y, run.events  # time, state, list of EventRecord
    """

    def __init__(self, system: HybridSystem, params: Mapping[str, float], x0, t0: float = 0.0,
                 flags: Mapping[str, float] | None = None, tol: float = 1e-12, fp_type=float,
                 max_events: int | None = 100_000, record_events: bool = True,
                 max_events_per_period: int | None = None, observations: bool = True,
                 steps_by_mode: bool = False):
        """``x0`` is a continuous state (mapping, array) or a :class:`HybridState`.
        ``max_events`` caps the events of the whole run, ``max_events_per_period`` those of
        any one period of the first switch (a relay period); more raise :class:`EventCap`.
        ``max_period_events`` reports the most events seen in one such period.
        ``observations=False``: no stop (and no record) at guards that change neither flags nor
        state (e.g. the bar's turning points); the motion is the same (a transient).
        ``steps_by_mode``: ``propagate_until`` also ends at every transition, so that the Taylor
        steps of each mode are counted (:meth:`steps_where`); dense output (``on_segment``)
        does so too."""
        self.system = system
        self.observations = bool(observations)
        self.steps_by_mode = bool(steps_by_mode)
        self.params = system.validate(params)
        self.tol = validate_tol(tol)
        if fp_type not in _FP_TYPES:  # else a TypeError from deep inside heyoka
            raise ParameterError(f"'fp_type' = {fp_type!r} is not supported; allowed: float, "
                                 f"numpy.longdouble, heyoka.real128 (numpy.float32 also runs)")
        self.fp_type = fp_type
        self._n = len(system.states)
        self.ta, self.compile_seconds = self._integrator(tol, fp_type)
        self.record_events = record_events
        if max_events is not None:
            max_events = int(validate_value("max_events", max_events, 1, math.inf))
        self.max_events = max_events
        if max_events_per_period is not None:
            max_events_per_period = int(validate_value("max_events_per_period", max_events_per_period, 1, math.inf))
        self.max_events_per_period = max_events_per_period
        surfaces = tr.event_surfaces(system, self.observations)
        self._choices = [tr.GuardChoice(g) for g in surfaces]
        self._may_settle = tr.settle_gate(system)     # after a switch: settle only where it can act
        self._bind()
        self._flag_slots = {k: i for k, i in system._flag_index.items() if i < len(self._pars_view)}
        self._roles = {g.role for grp in surfaces for g in grp}
        self._stop_on: frozenset = frozenset()     # stop_roles of the advance under way
        self._stop_each = self.steps_by_mode      # end propagate_until after every transition
        self._pending = None        # an exception raised in an event callback, re-raised by advance()
        self.stopped_by = None
        self.reset(t0, x0, flags)

    def _bind(self):
        """Live views of this run's integrator buffers (heyoka never reallocates them: the hot loop
        writes through them) and its event callbacks bound to this run (a weak reference)."""
        self._state_view, self._pars_view = self.ta.state, self.ta.pars
        self._y_view = self._state_view[:self._n]
        me = weakref.ref(self)
        for ev in (self.ta.t_events if self.ta.with_events else ()):
            ev.callback.run = me

    def __deepcopy__(self, memo):
        """A copy that integrates on its own: its integrator's views and callbacks are its own."""
        new = self.__class__.__new__(self.__class__)
        memo[id(self)] = new
        for k, v in self.__dict__.items():
            setattr(new, k, copy.deepcopy(v, memo))
        new._bind()
        return new

    def reset(self, t0: float, x0, flags: Mapping[str, float] | None = None) -> "HybridRun":
        """Restart this run at time ``t0`` [s] from state ``x0`` (no recompilation).

        Flags: ``flags``, else those of a :class:`HybridState` ``x0``, else the system's rule
        (:func:`maps.transitions.start_flags`), with switches at their value at ``t0``; the
        event log, counters and heyoka's event cooldowns are cleared.
        """
        system = self.system
        if not math.isfinite(float(t0)):  # a NaN start time would make advance() a silent no-op
            raise ParameterError(f"'t0' must be a finite time [s], got {t0}")
        if isinstance(x0, HybridState):
            flags = x0.flags if flags is None else flags
            x0 = x0.y
        y0 = system.state_vector(x0)
        self.flags = tr.start_flags(system, t0, y0, self.params, flags)
        if system.mode_projections:
            y0 = system.on_mode_set(y0, self.params, self.flags, float(t0))
        self.ta.time = _fp(t0, self.fp_type)
        self._y_view[:] = np.asarray(y0, dtype=_np_dtype(self.fp_type))
        if self.ta.with_events:          # a system without guards or switches has no event
            self.ta.reset_cooldowns()
        self._load_pars()
        self._start_sensitivities(t0)
        self.events = []
        self._pending = None
        self.n_switches = 0
        self.budget = tr.EventBudget(self.max_events, self.max_events_per_period)
        self.flag_log = [(t0, dict(self.flags))]
        self._log_steps = [0]       # Taylor steps taken in each flag_log entry's mode
        self._next_switch = {sw.flag: sw.index_at(t0, self.params[sw.frequency]) + 1 for sw in system.switches}
        self._apply(tr.settle(system, t0, self.y, self.flags, self.params), t0)
        return self

    # ----- state access ---------------------------------------------------
    @property
    def t(self) -> float:
        return float(self.ta.time)

    def _integrator(self, tol, fp_type):
        return self.system.integrator(tol, fp_type, observations=self.observations, callbacks=True)

    def _start_sensitivities(self, t0):
        """Hook: a run that carries derivatives starts them here (see VariationalRun)."""

    #: hook ``(switch, t, flags_before)``: a periodic switch at ``t`` has just changed the flags
    #: (None: nothing to do; see VariationalRun)
    _on_switch = None

    @property
    def y(self) -> np.ndarray:
        return np.array(self._y_view, dtype=float)

    @property
    def state(self) -> HybridState:
        """The hybrid state now: continuous state and flags."""
        return HybridState(self.y, dict(self.flags))

    @property
    def n_steps(self) -> int:
        """Taylor steps taken since the reset."""
        return sum(self._log_steps)

    @property
    def n_events(self) -> int:
        return self.budget.total

    @property
    def max_period_events(self) -> int:
        return self.budget.busiest

    def __getitem__(self, name):
        return float(self.ta.state[self.system.state_names.index(name)])

    @property
    def mode_steps(self) -> dict:
        """Taylor steps per mode: {tuple of flag values (system order): steps} since the reset
        (a run built with ``steps_by_mode=True``)."""
        self._need_steps_by_mode()
        out: dict = {}
        for (_, fl), n in zip(self.flag_log, self._log_steps):
            key = tuple(fl.values())
            out[key] = out.get(key, 0) + n
        return out

    def steps_where(self, **flags) -> int:
        """Taylor steps taken in modes with these flag values, e.g. ``steps_where(contact=1)``
        (a run built with ``steps_by_mode=True``)."""
        self._need_steps_by_mode()
        return sum(n for (_, fl), n in zip(self.flag_log, self._log_steps)
                   if all(fl.get(k) == v for k, v in flags.items()))

    def _need_steps_by_mode(self):
        if not self.steps_by_mode:
            raise ParameterError("steps per mode are counted by a run built with steps_by_mode=True "
                                 "(transitions then end each propagate_until)")

    def set_params(self, **values):
        """Change parameter values in place (no recompilation)."""
        merged = dict(self.params, **values)
        self.params = self.system.validate(merged)
        self._load_pars()

    def _load_pars(self):
        n = len(self._pars_view)
        self._pars_view[:] = np.asarray(self.system.par_vector(self.params, self.flags)[:n],
                                        dtype=_np_dtype(self.fp_type))

    def _set_flags(self, changed: Mapping[str, float], t: float):
        if not changed:
            return
        flags, pars, slots = self.flags, self._pars_view, self._flag_slots
        for k, v in changed.items():
            flags[k] = v
            i = slots.get(k)
            if i is not None:       # a flag no expression uses (a halt flag) lives only here
                pars[i] = v
        self.flag_log.append((t, dict(flags)))
        self._log_steps.append(0)

    def _apply(self, out: tr.Outcome, t: float, guard=None, y_minus=None):
        """Write a transition's outcome into the integrator, count and log its records.
        ``guard`` (a state event: crossed in ``y_minus`` under the flags before ``out``) or None
        (a transition at a fixed time) matters only to runs that carry derivatives."""
        if out.y is not None:
            self._y_view[:] = out.y
        if out.changes:
            self._set_flags(out.changes, t)
        for name, y_minus, y_plus, flags in out.records:   # arrays and dicts of the transition's own
            cap = self.budget.count(name, t)
            if cap is not None:
                cap.state = self.y
                raise cap
            if self.record_events:
                self.events.append(EventRecord(t, name, y_minus, y_plus, flags))

    # ----- integration ------------------------------------------------------
    def next_switch_time(self):
        return tr.next_switch(self.system, self.params, self._next_switch)

    def _on_event(self, gi: int, sign) -> bool:
        """heyoka's callback of terminal event ``gi`` (its surface crossed with ``sign``), at the
        event, inside ``propagate_until``: the chosen guard's transition (:func:`maps.transitions.fire`).
        True: integrate on; False: ``propagate_until`` returns (a halt or an exception, kept in
        ``_pending`` for :meth:`advance` to raise; a ``stop_roles`` guard; ``_stop_each``).
        Nothing may be raised through heyoka."""
        try:
            guard = self._choices[gi](sign, self.flags)
            if guard is None:
                return True                 # a crossing no guard acts on
            t = float(self.ta.time)
            out = tr.fire(self.system, guard, t, self._y_view, self.flags, self.params)
            if out is tr.NOTHING:
                return True
            self._apply(out, t, guard, out.records[0][1])   # the state the guard met, fire's copy
            if out.halted:
                self._pending = Escaped(f"{guard.name}: the state left the model's domain at t = {t:.9g} s",
                                        t, self.y)
                return False
            if guard.role in self._stop_on:
                self.stopped_by = guard.name
                return False
            return not self._stop_each
        except Exception as exc:            # noqa: BLE001 - re-raised by advance() once heyoka returned
            self._pending = exc
            return False

    def advance(self, t_end: float, on_segment: Callable | None = None, stop_roles: tuple = ()) -> "HybridRun":
        """Integrate to ``t_end`` [s] through every guard and switch.

        ``on_segment(c_output, t_start, t_stop)`` receives heyoka's continuous
        output of each smooth segment (dense output; requested only when given).
        ``stop_roles``: return right after the transition of the first guard with one of these
        roles (e.g. ``("impact",)``: the impact map), which ``stopped_by`` then names (else None).
        Raises :class:`IntegrationFailure` on a non-finite state, :class:`EventCap` beyond
        the event caps and :class:`Escaped` when a halt flag is set.
        """
        self._check_advance(t_end, stop_roles)
        # The hot loop of every scalar run: it runs once per relay switch (guards act in callbacks);
        # names are bound once, the state is read through a live view and copied only where kept.
        ta, sys, params, flags = self.ta, self.system, self.params, self.flags
        propagate, y_view, fp = ta.propagate_until, self._y_view, self.fp_type
        c_out = on_segment is not None
        n_groups, may_settle, on_switch = len(self._choices), self._may_settle, self._on_switch
        first_switch = sys.switches[0] if sys.switches else None
        self.stopped_by = None
        self._stop_on = frozenset(stop_roles)
        self._stop_each = self.steps_by_mode or c_out     # smooth segments: one per propagate_until
        t_sw, sw = self.next_switch_time()
        log_steps, flag_log = self._log_steps, self.flag_log    # reset() rebinds them, never advance()
        slots, pars = self._flag_slots, self._pars_view
        t = float(ta.time)
        while t < t_end:
            t_stop = t_end if t_end < t_sw else t_sw
            if t_stop > t:
                t_start, y_start = t, y_view.copy()   # heyoka leaves a non-finite state after a failed step
                mode = len(log_steps) - 1             # the mode the segment starts in
                target = t_stop if fp is float else _fp(t_stop, fp)
                # c_output only when asked: a keyword argument costs heyoka's binding 0.75 us a call
                res = propagate(target, c_output=True) if c_out else propagate(target)
                code = int(res[0])
                log_steps[mode] += res[3]   # exact per mode where each transition ends propagate_until
                if c_out and res[4] is not None:
                    on_segment(res[4], t, float(ta.time))     # the segment up to a failed transition too
                if self._pending is not None:
                    exc, self._pending = self._pending, None
                    raise exc
                t = float(ta.time)
            else:
                code = _TIME_LIMIT
            if code == _TIME_LIMIT:
                if sw is not None and t_stop == t_sw:
                    counters = self._next_switch
                    n = counters[sw.flag]
                    counters[sw.flag] = n + 1
                    self.n_switches += 1
                    if sw is first_switch and n % 2 == 0:
                        self.budget.in_period = 0      # a new relay period begins
                    if on_switch is not None:
                        flags_before = dict(flags)
                        self._set_flags({sw.flag: sw.off_value if n % 2 else sw.on_value}, t_sw)
                        on_switch(sw, t_sw, flags_before)
                    else:                              # _set_flags of one flag, inline
                        flags[sw.flag] = value = sw.off_value if n % 2 else sw.on_value
                        slot = slots.get(sw.flag)
                        if slot is not None:
                            pars[slot] = value
                        flag_log.append((t_sw, dict(flags)))
                        log_steps.append(0)
                    if may_settle is not None and may_settle(flags, y_view, params):
                        self._apply(tr.settle(sys, t_sw, y_view, flags, params), t_sw)
                    if len(counters) == 1:             # one switch: its next instant, inline
                        n += 1
                        t_sw = (n // 2 + (sw.duty if n % 2 else 0.0)) / params[sw.frequency]
                    else:
                        t_sw, sw = self.next_switch_time()
                continue
            if -n_groups - 1 < code < 0:       # a callback ended propagate_until after its transition
                if self.stopped_by is not None:
                    return self
                continue
            raise self._failure(code, res, t_start, y_start)
        return self

    def _check_advance(self, t_end, stop_roles) -> None:
        if not math.isfinite(float(t_end)):  # NaN: silent no-op; inf: ValueError inside heyoka
            raise ParameterError(f"'t_end' must be a finite time [s], got {t_end}")
        if stop_roles and not self._roles.issuperset(stop_roles):
            raise ParameterError(f"stop_roles {tuple(stop_roles)}: allowed roles here: {', '.join(sorted(self._roles))}")

    def _failure(self, code, res, t_start, y_start) -> IntegrationFailure:
        """The failure of a propagate_until that ended with ``code`` (a non-finite state: the last
        finite one, at the segment's start ``t_start``)."""
        if code == _NF_STATE:
            y_start = np.array(y_start, dtype=float)
            return IntegrationFailure(f"non-finite state in the step after t = {t_start:.9g} s "
                                      f"(last finite state {np.array2string(y_start, precision=6)})",
                                      t_start, y_start)
        return IntegrationFailure(f"integration stopped with {res[0]} at t = {float(self.ta.time):.9g} s",
                                  float(self.ta.time), self.y)


class VariationalRun(HybridRun):
    """A :class:`HybridRun` that also carries the sensitivities Y = dy/d(y0, p) (n x (n + m)):
    heyoka's variational equations between events, the saltation rule of
    :func:`maps.transitions.saltation` at every state event, the projection's Jacobian where a
    settle transition projects the state.  Double precision; ``wrt`` names the parameters p.

    A switch frequency W among ``wrt`` (the relay's) moves every switch instant t_s = n/(2W):
    each switch adds (f- - f+) dt_s/dW to its column, with dt_s/dW = -t_s/W, and a run started at
    a switch instant t0 starts its column at f(t0, y0) t0/W (the start moves with the schedule).
    The end time's own term belongs to the caller that fixes the end (the map: f(t1) dt1/dW).
    ``event_time_row`` is dt_e/d(y0, p) of the last state event (the impact map's moving end)."""

    def __init__(self, system, params, x0, *, wrt: tuple = (), **kw):
        from ..variational import Derivatives
        self.wrt = tuple(wrt)
        self.derivatives = Derivatives(system, self.wrt)
        self._freq_cols = {sw.flag: len(system.states) + self.wrt.index(sw.frequency)
                           for sw in system.switches if sw.frequency in self.wrt}
        if not self._freq_cols:
            self._on_switch = None      # no switch instant moves: advance's inline switch path
        super().__init__(system, params, x0, **kw)

    def _integrator(self, tol, fp_type):
        if fp_type is not float:
            raise ParameterError("exact Jacobians run in double precision (fp_type=float)")
        if not self.observations:
            raise ParameterError("runs with sensitivities stop at every guard (observations=True)")
        from ..variational import variational_integrator
        return variational_integrator(self.system, tol, self.wrt)

    def _start_sensitivities(self, t0):
        self.event_time_row = None
        n, m = self._n, len(self.wrt)
        Y = np.eye(n, n + m)             # [I | 0]
        if self._freq_cols:
            d = self.derivatives
            f = d.rhs(t0, self.y, d.pars(self.params, self.flags))
            for sw in self.system.switches:
                col = self._freq_cols.get(sw.flag)
                if col is not None:
                    Y[:, col] = f * (t0 / self.params[sw.frequency])
        for (flag, value), name in self.system.mode_projections.items():
            if self.flags.get(flag) == value:     # started on a mode's set: perturbations projected onto it
                P_y, P_p, _ = self.derivatives.projection(name, t0, self.y, self.params, self.flags)
                Y = tr.projected(Y, P_y, P_p)
                break
        self._state_view[n:] = Y.ravel()

    def _on_switch(self, sw, t, flags_before):
        col = self._freq_cols.get(sw.flag)
        if col is None:
            return
        d, y = self.derivatives, self.y
        jump = d.rhs(t, y, d.pars(self.params, flags_before)) - d.rhs(t, y, d.pars(self.params, self.flags))
        Y = self.sensitivities
        Y[:, col] += jump * (-t / self.params[sw.frequency])
        self._state_view[self._n:] = Y.ravel()

    def end_time_term(self, t1: float, dt1: dict) -> np.ndarray:
        """Sensitivities of the state at an end time t1 that moves with parameters: Y + f(t1) dt1/dp
        for ``dt1`` {parameter: dt1/dp}."""
        Y = self.sensitivities
        if dt1:
            d = self.derivatives
            f = d.rhs(t1, self.y, d.pars(self.params, self.flags))
            for name, dt in dt1.items():
                Y[:, self._n + self.wrt.index(name)] += f * dt
        return Y

    @property
    def sensitivities(self) -> np.ndarray:
        """dy/d(y0, p) now: n x (n + m), the state's columns first."""
        n = self._n
        return np.array(self._state_view[n:], dtype=float).reshape(n, n + len(self.wrt))

    def _apply(self, out, t, guard=None, y_minus=None):
        if out is tr.NOTHING or (out.y is None and not out.changes):
            super()._apply(out, t, guard, y_minus)
            return
        if guard is not None and out.projection is None and not self.wrt:   # dy/dy0 alone: one compiled call
            d, n, state = self.derivatives, self._n, self._state_view
            # state: (y-, Y-) at the crossing (nothing is written before this), Y n x n, a tangent n x 1
            jump = d.matrix_jump(guard, out.changes, len(state) // n - 1)
            pars = self._pars_view      # the flags before the transition (written below)
            if len(pars) < jump.nparams:        # a reset reads parameters the integrator does not
                pars = d.pars(self.params, self.flags)
            Y, dt, rate = jump(state, pars, t)
            if rate != 0.0 and math.isfinite(rate):
                self.event_time_row = dt
                super()._apply(out, t, guard, y_minus)
                state[n:] = Y.ravel()
                return          # else a grazing crossing: the general rule below says so
        Y, dt = self.derivatives.transition(self.sensitivities, out, t, self.params, dict(self.flags),
                                            dict(self.flags, **out.changes), guard, y_minus, self.y)
        if dt is not None:
            self.event_time_row = dt
        super()._apply(out, t, guard, y_minus)
        self._state_view[self._n:] = Y.ravel()


class TangentRun(VariationalRun):
    """A :class:`HybridRun` that carries one tangent vector u (u' = (df/dy) u between events, the
    saltation rule and projections of :class:`VariationalRun` applied to it), zero until the caller
    starts it (:func:`maps.tangent.tangent_sample`)."""

    def __init__(self, system, params, x0, **kw):
        super().__init__(system, params, x0, wrt=(), **kw)

    def _integrator(self, tol, fp_type):
        if fp_type is not float:
            raise ParameterError("tangent vectors run in double precision (fp_type=float)")
        if not self.observations:
            raise ParameterError("runs with sensitivities stop at every guard (observations=True)")
        from ..variational import tangent_integrator
        return tangent_integrator(self.system, tol)

    def _start_sensitivities(self, t0):
        self.event_time_row = None
        self._state_view[self._n:] = 0.0

    @property
    def tangent(self) -> np.ndarray:
        """The tangent vector's live view (n,)."""
        return self._state_view[self._n:]

    def _apply(self, out, t, guard=None, y_minus=None):
        if self._state_view[self._n:].any():       # a zero vector (not started) stays zero
            super()._apply(out, t, guard, y_minus)
        else:
            HybridRun._apply(self, out, t, guard, y_minus)

    @property
    def sensitivities(self) -> np.ndarray:
        return np.array(self._state_view[self._n:], dtype=float).reshape(self._n, 1)


class ScalarEngine(Engine):
    """Runs jobs one after the other on one :class:`HybridRun` (any system, any sampling).

    As the batch engine does, a transient and a companion run without stops at observation-only
    guards (nothing of them is kept); a window whose crossings are logged runs with them."""

    name = "scalar"

    def __init__(self, system, tol: float, *, max_events_per_period: int = 10_000,
                 observations: bool = True, fp_type=float):
        super().__init__(system, tol, max_events_per_period=max_events_per_period, observations=observations)
        self.fp_type = fp_type
        self._run: HybridRun | None = None
        self._quiet_run: HybridRun | None = None
        self._tangent_run: TangentRun | None = None

    def hybrid_run(self, params, observations: bool = True) -> HybridRun:
        """This engine's reusable run, with ``params`` loaded (compiled once per structure);
        ``observations=False`` (or an engine built without them): the run that takes no stop at
        observation-only guards."""
        if observations and self.observations:
            self._run = self._reuse(self._run, HybridRun, params, fp_type=self.fp_type)
            return self._run
        self._quiet_run = self._reuse(self._quiet_run, HybridRun, params, fp_type=self.fp_type, observations=False)
        return self._quiet_run

    def tangent_run(self, params) -> TangentRun:
        """This engine's reusable run with a tangent vector (compiled on first use)."""
        self._tangent_run = self._reuse(self._tangent_run, TangentRun, params)
        return self._tangent_run

    def _reuse(self, run, cls, params, **kw):
        """``run`` with ``params`` loaded, or a new ``cls`` run if there is none yet."""
        if run is None:
            return cls(self.system, params, np.zeros(len(self.system.states)), tol=self.tol, max_events=None,
                       max_events_per_period=self.max_events_per_period, **kw)
        if run.params != params:
            run.set_params(**params)
        return run

    @property
    def compile_seconds(self) -> float:
        return sum(r.compile_seconds for r in (self._run, self._quiet_run) if r is not None)

    def run(self, jobs: list[OrbitJob]) -> list[OrbitResult]:
        return [self._one(job) for job in jobs]

    def _one(self, job: OrbitJob) -> OrbitResult:
        clock = _time.perf_counter()
        res = OrbitResult()
        tangent = job.tangent is not None
        run = self.hybrid_run(job.params, observations=False) if job.transient or not job.log else \
            self.hybrid_run(job.params)
        run.record_events = False
        k = job.k0
        before = [0, 0, 0]           # steps, events and switches of the runs handed over
        try:
            run.reset(job.sample_time(k), job.y0, job.flags)
            end_transient = k + job.transient
            while k < end_transient:     # period by period: the event cap counts per period
                k += 1
                run.advance(job.sample_time(k))
                run.budget.new_period()
            if tangent:                  # the record carries a tangent vector: its run takes over here
                run = self._hand_over(run, self.tangent_run(job.params), job.sample_time(k), before)
                tangent = tangent_sample(run.tangent, res.tangent, job.tangent, job.shift)
            elif job.log and not run.observations:     # the logged window records every guard
                run = self._hand_over(run, self.hybrid_run(job.params), job.sample_time(k), before)
            if job.reference is None:
                self._sample(res, run)
            run.record_events = job.log
            for i in range(job.record):
                run.events = []
                k += 1
                run.advance(job.sample_time(k))
                run.budget.new_period()
                if tangent:
                    tangent = tangent_sample(run.tangent, res.tangent, shift=job.shift)
                if job.reference is None:
                    self._sample(res, run)
                    if job.log:
                        res.period_events.append([(ev.name, ev.t, ev.y_minus) for ev in run.events])
                else:
                    z, stretch = renormalise(job.reference[i + 1], run.y, job.d0, job.scale, job.shift)
                    res.stretch.append(stretch)
                    if not math.isfinite(stretch):
                        break
                    run.reset(run.t, z)          # flags by the system's rule, as a bare map step
        except Escaped as exc:
            res.status, res.failure, res.failure_time = "escaped", str(exc), exc.t
        except IntegrationFailure as exc:
            res.status, res.failure, res.failure_time = "failed", str(exc), exc.t
        if job.timed is not None and job.reference is None and res.times:
            res.mode_time = time_in_mode(run.flag_log, res.times, job.timed).tolist()
        if job.log and res.status != "ok":
            res.tail_events = [(ev.name, ev.t, ev.y_minus) for ev in run.events]
        run.events = []
        res.final_time, res.final_state, res.final_flags = run.t, run.y, dict(run.flags)
        res.n_steps, res.n_events, res.n_switches = (run.n_steps + before[0], run.n_events + before[1],
                                                     run.n_switches + before[2])
        res.seconds = _time.perf_counter() - clock
        return res

    @staticmethod
    def _hand_over(run: HybridRun, other: HybridRun, t: float, before: list) -> HybridRun:
        """``other`` restarted at ``t`` [s] in ``run``'s hybrid state; ``before`` accumulates
        ``run``'s steps, events and switches."""
        before[0] += run.n_steps
        before[1] += run.n_events
        before[2] += run.n_switches
        other.record_events = False
        other.reset(t, run.state)
        return other

    @staticmethod
    def _sample(res: OrbitResult, run: HybridRun):
        res.times.append(run.t)
        res.points.append(run.y)
        res.flags.append(dict(run.flags))
