"""Generic hybrid (piecewise-smooth) dynamical systems on heyoka.

A :class:`HybridSystem` is declared with

- ``states``: the continuous state, each a :class:`State` with a unit;
- ``parameters``: named :class:`~maps.parameters.Parameter` s (heyoka runtime
  parameters: changing a value never recompiles);
- ``flags``: discrete mode variables (also runtime parameters).  A *mode* is
  an assignment of the flags; the right-hand side of each mode is ``rhs``
  with the flags at those values, e.g. ``contact * (-k*x - c*v)``;
- ``guards``: :class:`Guard` s, event expressions with a direction, the flags
  under which they are active, the next mode and an optional reset map;
- ``switches``: time-scheduled flag changes such as a relay
  (:class:`PeriodicSwitch`), hit exactly by integrating up to each instant.

:class:`HybridRun` integrates one trajectory: it stops on every guard and
switch, applies the transition and never steps across a mode change with one
smooth right-hand side.  Compiled integrators are cached per system structure,
tolerance and floating-point type.
"""
from __future__ import annotations

import math
import time as _time
from dataclasses import dataclass, field
from typing import Callable, Mapping, Sequence

import heyoka as hy
import numpy as np

from .parameters import Parameter, ParameterError, validate_value

__all__ = ["State", "Guard", "PeriodicSwitch", "HybridSystem", "HybridRun", "EventRecord",
           "IntegrationFailure", "Escaped", "EventCap"]

#: explicit cooldown of every terminal event [s]; with heyoka's automatic one
#: an event that starts on its own zero (a bar starting on the stop) re-triggers.
EVENT_COOLDOWN = 1e-10


@dataclass(frozen=True)
class State:
    """One continuous state variable."""

    name: str
    unit: str
    long_name: str


@dataclass(frozen=True)
class Guard:
    """A switching surface ``expr = 0`` crossed in ``direction`` (-1, +1 or 0 for both).

    ``when`` lists flag values under which the guard is active (inactive
    crossings are passed over).  ``then`` gives the new flag values, or is a
    callable ``then(t, y, flags, params) -> dict``.  ``reset`` maps the state
    at the crossing to the state after it, ``reset(y, params) -> y`` (``None``:
    continuous).  A guard with ``then=None`` and ``reset=None`` only records
    the crossing (an observation, e.g. the deepest point of a contact).
    """

    name: str
    expr: object
    direction: int = 0
    when: Mapping[str, float] = field(default_factory=dict)
    then: Mapping[str, float] | Callable | None = None
    reset: Callable | None = None

    def heyoka_direction(self):
        return {-1: hy.event_direction.negative, 1: hy.event_direction.positive,
                0: hy.event_direction.any}[self.direction]


@dataclass(frozen=True)
class PeriodicSwitch:
    """A flag that is ``on_value`` for the first ``duty`` fraction of each period.

    The frequency is the parameter named ``frequency`` [Hz]: the flag switches
    at t = n / (2 W) for a 50 % duty, starting ON at t = 0 (thesis listing C.12).
    """

    flag: str
    frequency: str
    duty: float = 0.5
    on_value: float = 1.0
    off_value: float = 0.0

    def instants(self, freq: float, n: int) -> float:
        """Time of the n-th switch (n = 0 at t = 0, even n: ON, odd n: OFF)."""
        cycles, half = divmod(n, 2)
        return (cycles + (self.duty if half else 0.0)) / freq

    def index_at(self, t: float, freq: float) -> int:
        """Index of the last switch at or before ``t``."""
        cycles = math.floor(t * freq + 1e-12)
        n = 2 * cycles
        if t >= self.instants(freq, n + 1) * (1 - 1e-15) - 1e-15:
            n += 1
        return n

    def value_for_index(self, n: int) -> float:
        return self.off_value if n % 2 else self.on_value


class IntegrationFailure(RuntimeError):
    """The integration produced a non-finite state or could not continue."""

    def __init__(self, message, t=None, state=None):
        super().__init__(message)
        self.t = t
        self.state = state


class Escaped(IntegrationFailure):
    """The state left the model's domain (a guard set a halt flag)."""


class EventCap(IntegrationFailure):
    """More events than the run's cap (per run or per relay period): chattering or a runaway."""


@dataclass
class EventRecord:
    """One guard crossing: time, guard name, state before and after the reset."""

    t: float
    name: str
    y_minus: np.ndarray
    y_plus: np.ndarray
    flags: dict


_COMPILED: dict = {}


def settle_may_act(system, flags) -> bool:
    """False when ``system.settle_if`` rules out any change under ``flags``."""
    cond = system.settle_if
    if cond is None:
        return True
    for k, v in cond:
        if flags[k] == v:
            return True
    return False


class HybridSystem:
    """A piecewise-smooth system: states, parameters, flags, rhs, guards, switches."""

    #: flag -> {value: event name}: a ``settle`` that sets the flag to the value is logged as
    #: an event of that name (e.g. ``{"stuck_bar": {1.0: "stick", 0.0: "unstick"}}``)
    settle_events: Mapping[str, Mapping[float, str]] = {}
    #: ``((flag, value), ...)``: ``settle`` can act only while one of these flags has that
    #: value, so elsewhere it is not called (it runs after every transition); None: always
    settle_if: tuple | None = None
    #: ``state_flags(y, params, flags, given) -> dict``: flags that follow from the state at a start
    #: (the region of a piecewise force law, contact); ``flags``: those so far, ``given``: the names
    #: the caller set.  Applied by ``initial_flags(..., y=)`` at every run start; None: none
    state_flags: Callable | None = None

    def __init__(self, name: str, states: Sequence[State], parameters: Sequence[Parameter],
                 rhs: Callable, flags: Mapping[str, float] | None = None,
                 guards: Callable | Sequence[Guard] = (), switches: Sequence[PeriodicSwitch] = (),
                 settle: Callable | None = None, outputs: Callable | None = None,
                 structure: tuple = (), halt_flags: Sequence[str] = (), gap: Callable | None = None):
        """``rhs(sym) -> list of expressions`` and ``guards(sym) -> list of Guard`` receive a
        :class:`Symbols` giving ``sym.x``/``sym['x']`` for states, parameters and flags,
        and ``sym.t`` for time.  ``settle(t, y, flags, params) -> flags`` makes the flags
        consistent after any transition (e.g. stick/slip).  ``outputs(sym) -> dict`` names
        derived expressions (forces) evaluated on demand; ``settle`` may also return
        ``(flags, y)`` to enter a mode with a projected state (e.g. a bar stuck on its
        stop: x = e, v = 0).  A guard that sets one of
        ``halt_flags`` to a non-zero value ends the run with :class:`Escaped`.
        ``gap(y, params) -> (gap [m], gap rate [m/s])`` gives the signed distance to the
        stop (> 0: clear) for impact logs and clearance; by default the state ``x``
        (or ``x1 - x2``) less the parameter ``e`` (0 if absent).
        """
        self.name = name
        self.states = tuple(states)
        self.parameters = tuple(parameters)
        self.flag_defaults = dict(flags or {})
        self.switches = tuple(switches)
        self.settle = settle
        self.halt_flags = tuple(halt_flags)
        self.gap = gap if gap is not None else _default_gap(tuple(s.name for s in states))
        self.structure = (name,) + tuple(structure)
        names = [s.name for s in self.states] + [p.name for p in self.parameters] + list(self.flag_defaults)
        if len(set(names)) != len(names):
            raise ValueError(f"duplicate names among states, parameters and flags of {name!r}")
        self.state_names = tuple(s.name for s in self.states)
        self.param_names = tuple(p.name for p in self.parameters)
        self.flag_names = tuple(self.flag_defaults)
        self._param_index = {p: i for i, p in enumerate(self.param_names)}
        self._flag_index = {f: len(self.param_names) + i for i, f in enumerate(self.flag_names)}
        self.sym = Symbols(self)
        self.rhs = list(rhs(self.sym))
        if len(self.rhs) != len(self.states):
            raise ValueError(f"rhs of {name!r} has {len(self.rhs)} components for {len(self.states)} states")
        self.guards = tuple(guards(self.sym) if callable(guards) else guards)
        self.outputs = dict(outputs(self.sym)) if outputs else {}
        for sw in self.switches:
            if sw.flag not in self.flag_defaults or sw.frequency not in self._param_index:
                raise ValueError(f"switch {sw} names an unknown flag or parameter")
        self._groups = self.event_groups()
        self._mixed = [len({g.direction for g in grp}) > 1 for grp in self._groups]
        self._cfuncs: dict = {}

    # ----- parameters -------------------------------------------------
    def parameter(self, name: str) -> Parameter:
        for p in self.parameters:
            if p.name == name:
                return p
        raise ParameterError(f"unknown parameter {name!r} for {self.name!r}; "
                             f"its parameters are: {', '.join(self.param_names)}")

    def validate(self, values: Mapping[str, float]) -> dict:
        """Validated full parameter dict; every parameter must be given."""
        out = {}
        for k in values:
            if k not in self._param_index:
                self.parameter(k)  # raises with the list of names
        for p in self.parameters:
            if p.name not in values:
                raise ParameterError(f"parameter {p.name!r} ({p.long_name}) has no value")
            out[p.name] = p.validate(values[p.name])
        return out

    def par_vector(self, params: Mapping[str, float], flags: Mapping[str, float]) -> list:
        return [params[p] for p in self.param_names] + [flags[f] for f in self.flag_names]

    def state_vector(self, x0: Mapping[str, float] | Sequence[float]) -> np.ndarray:
        """Initial state as an array (double, or the input's own extended dtype)."""
        if isinstance(x0, np.ndarray) and x0.dtype != float and x0.shape == (len(self.states),):
            for n, v in zip(self.state_names, x0):  # extended precision: checked like doubles
                if not math.isfinite(float(v)):
                    raise ParameterError(f"initial state {n!r} must be finite, got {v}")
            return x0.copy()
        if isinstance(x0, Mapping):
            unknown = set(x0) - set(self.state_names)
            if unknown:
                raise ParameterError(f"unknown state {sorted(unknown)[0]!r} for {self.name!r}; "
                                     f"its states are: {', '.join(self.state_names)}")
            y = np.array([float(x0.get(n, 0.0)) for n in self.state_names])
        else:
            y = np.asarray(x0, dtype=float).copy()
            if y.shape != (len(self.states),):
                raise ParameterError(f"initial state of {self.name!r} needs {len(self.states)} "
                                     f"components ({', '.join(self.state_names)}), got {y.shape}")
        for n, v in zip(self.state_names, y):
            if not math.isfinite(v):
                raise ParameterError(f"initial state {n!r} must be finite, got {v}")
        return y

    # ----- compilation ---------------------------------------------------
    def heyoka_system(self):
        return list(zip(self.sym.state_vars, self.rhs))

    def event_groups(self) -> list[list[Guard]]:
        """Guards grouped by identical expression: one heyoka event per surface.

        Guards that share a surface must not be separate events: a tie between two
        terminal events at the same instant can lose the active one (the free-flight
        minimum and the deepest point of a contact are both ``rdot = 0`` upward), and
        in long double a surface left exactly at 0.0 by one direction's event hides
        every later crossing of the other direction's event (contact onset after a
        release: the bar passed through the stop).  A surface whose guards have
        different directions is one event of direction "any"; the crossing's sign,
        recorded by a callback, selects the guard.
        """
        groups: dict = {}
        for g in self.guards:
            groups.setdefault(str(g.expr), []).append(g)
        return list(groups.values())

    def heyoka_events(self, fp_type=float):
        kw = {} if fp_type is float else {"fp_type": fp_type}
        events = []
        for grp in self._groups:
            extra = dict(direction=hy.event_direction.any, callback=_record_crossing) if len(
                {g.direction for g in grp}) > 1 else \
                dict(direction=grp[0].heyoka_direction())
            events.append(hy.t_event(grp[0].expr, cooldown=_fp(EVENT_COOLDOWN, fp_type), **extra, **kw))
        return events

    def integrator(self, tol: float = 1e-12, fp_type=float, compact_mode: bool = False):
        """A heyoka integrator for this system, compiled once per (structure, tol, fp_type).

        Returns a fresh deep copy so that several runs never share state.
        """
        key = (self.structure, float(tol), fp_type, compact_mode)
        proto = _COMPILED.get(key)
        if proto is None:
            t0 = _time.perf_counter()
            y0 = np.zeros(len(self.states), dtype=_np_dtype(fp_type))
            kw = {}
            if fp_type is not float:
                kw["fp_type"] = fp_type
            # heyoka sizes its parameter array to the highest index used; a flag used
            # by no expression (a halt flag) lives only on the Python side.
            proto = hy.taylor_adaptive(self.heyoka_system(), y0, tol=_fp(tol, fp_type),
                                       t_events=self.heyoka_events(fp_type),
                                       compact_mode=compact_mode, **kw)
            proto.compile_seconds = _time.perf_counter() - t0
            _COMPILED[key] = proto
        import copy
        ta = copy.deepcopy(proto)
        return ta, getattr(proto, "compile_seconds", 0.0)

    def cfunc(self, names: Sequence[str], fp_type=float):
        """Compiled evaluator of named outputs or guard expressions: f(y, pars, t) -> values."""
        key = (tuple(names), fp_type)
        if key not in self._cfuncs:
            exprs = [self.outputs[n] if n in self.outputs else self._guard_expr(n) for n in names]
            kw = {} if fp_type is float else {"fp_type": fp_type}
            self._cfuncs[key] = hy.cfunc(exprs, vars=self.sym.state_vars, compact_mode=True, **kw)
        return self._cfuncs[key]

    def evaluate(self, names: Sequence[str], y, params, flags, t=0.0) -> np.ndarray:
        """Evaluate named outputs at one state (numpy, double precision)."""
        f = self.cfunc(tuple(names))
        pars = np.asarray(self.par_vector(params, flags), dtype=float)[:f.nparams]
        kw = {"time": float(t)} if f.is_time_dependent else {}
        return f(np.asarray(y, dtype=float), pars=pars, **kw)

    def _guard_expr(self, name):
        for g in self.guards:
            if g.name == name:
                return g.expr
        raise KeyError(f"no output or guard named {name!r}")

    def guard_gradient(self, name: str):
        """d(guard)/d(state) as heyoka expressions (for saltation matrices)."""
        expr = self._guard_expr(name)
        return [hy.diff(expr, v) for v in self.sym.state_vars]

    def initial_flags(self, t: float, params: Mapping[str, float], overrides=None, y=None) -> dict:
        """Flags at a start at time ``t``: defaults, switches at their value at t, ``overrides``,
        then (given the state ``y``) those that ``state_flags`` derives from it."""
        flags = dict(self.flag_defaults)
        for sw in self.switches:
            flags[sw.flag] = sw.value_for_index(sw.index_at(t, params[sw.frequency]))
        flags.update(overrides or {})
        if y is not None and self.state_flags is not None:
            flags.update(self.state_flags(np.asarray(y, dtype=float), params, flags, tuple(overrides or ())))
        return flags

    def __repr__(self):
        return (f"HybridSystem({self.name!r}, states={list(self.state_names)}, "
                f"flags={list(self.flag_names)}, guards={[g.name for g in self.guards]})")


class Symbols:
    """Attribute/item access to the heyoka symbols of a system's states, parameters and flags."""

    def __init__(self, system: HybridSystem):
        self.state_vars = list(hy.make_vars(*system.state_names)) if len(system.state_names) > 1 \
            else [hy.make_vars(*system.state_names)]
        self._map = dict(zip(system.state_names, self.state_vars))
        for name, i in system._param_index.items():
            self._map[name] = hy.par[i]
        for name, i in system._flag_index.items():
            self._map[name] = hy.par[i]
        self.t = hy.time

    def __getitem__(self, name):
        return self._map[name]

    def __getattr__(self, name):
        try:
            return self.__dict__["_map"][name]
        except KeyError:
            raise AttributeError(name) from None


_CROSSING = [0]  # sign of the last crossing of a mixed-direction surface (set by its callback)


def _record_crossing(ta, d_sgn):
    """Terminal-event callback: remember the crossing direction, stop the integration."""
    _CROSSING[0] = int(d_sgn)
    return False


def _default_gap(names):
    if "x1" in names and "x2" in names:
        i1, v1, i2, v2 = (names.index(n) for n in ("x1", "v1", "x2", "v2"))
        return lambda y, p: (y[i1] - y[i2] - p.get("e", 0.0), y[v1] - y[v2])
    ix, iv = names.index("x") if "x" in names else 0, names.index("v") if "v" in names else 1
    return lambda y, p: (y[ix] - p.get("e", 0.0), y[iv])


_FP_TYPES = (float, np.float64, np.longdouble, np.float32) + ((hy.real128,) if hasattr(hy, "real128") else ())


def _fp(value, fp_type):
    """A Python float as a scalar of heyoka's floating-point type."""
    return value if fp_type is float else fp_type(value)


def _np_dtype(fp_type):
    if fp_type is float:
        return float
    if fp_type is np.longdouble:
        return np.longdouble
    return fp_type


class HybridRun:
    """One trajectory of a :class:`HybridSystem`, advanced through guards and switches.

    >>> run = HybridRun(system, params, x0, tol=1e-12)
    >>> run.advance(2.0)          # to t = 2 s
    >>> run.t, run.y, run.events  # time, state, list of EventRecord
    """

    def __init__(self, system: HybridSystem, params: Mapping[str, float], x0, t0: float = 0.0,
                 flags: Mapping[str, float] | None = None, tol: float = 1e-12, fp_type=float,
                 max_events: int | None = 100_000, record_events: bool = True,
                 max_events_per_period: int | None = None):
        """``max_events`` caps the events of the whole run, ``max_events_per_period`` those of
        any one period of the first switch (a relay period); more raise :class:`EventCap`.
        ``max_period_events`` reports the most events seen in one such period."""
        self.system = system
        self.params = system.validate(params)
        self.tol = validate_tol(tol)
        if fp_type not in _FP_TYPES:  # else a TypeError from deep inside heyoka
            raise ParameterError(f"'fp_type' = {fp_type!r} is not supported; allowed: float, "
                                 f"numpy.longdouble, heyoka.real128 (numpy.float32 also runs)")
        self.fp_type = fp_type
        self.ta, self.compile_seconds = system.integrator(tol, fp_type)
        self.record_events = record_events
        if max_events is not None:
            max_events = int(validate_value("max_events", max_events, 1, math.inf))
        self.max_events = max_events
        if max_events_per_period is not None:
            max_events_per_period = int(validate_value("max_events_per_period", max_events_per_period, 1, math.inf))
        self.max_events_per_period = max_events_per_period
        self.reset(t0, x0, flags)

    def reset(self, t0: float, x0, flags: Mapping[str, float] | None = None) -> "HybridRun":
        """Restart this run at time ``t0`` [s] from state ``x0`` (no recompilation).

        Flags default to the system's defaults with switches at their value at ``t0``;
        the event log, counters and heyoka's event cooldowns are cleared.
        """
        system = self.system
        if not math.isfinite(float(t0)):  # a NaN start time would make advance() a silent no-op
            raise ParameterError(f"'t0' must be a finite time [s], got {t0}")
        self.ta.time = _fp(t0, self.fp_type)
        self.ta.state[:] = np.asarray(system.state_vector(x0), dtype=_np_dtype(self.fp_type))
        self.ta.reset_cooldowns()
        self.flags = system.initial_flags(t0, self.params, flags, y=self.ta.state)
        self._load_pars()
        self.events = []
        self.n_events = self.n_steps = self.n_switches = 0
        self.period_events = self.max_period_events = 0  # events in the current / busiest relay period
        self.mode_steps: dict = {}  # Taylor steps per mode (tuple of flag values, system order)
        self.flag_log = [(t0, dict(self.flags))]
        self._next_switch = {sw.flag: sw.index_at(t0, self.params[sw.frequency]) + 1 for sw in system.switches}
        self._settle(t0)
        return self

    # ----- state access ---------------------------------------------------
    @property
    def t(self) -> float:
        return float(self.ta.time)

    @property
    def y(self) -> np.ndarray:
        return np.array(self.ta.state, dtype=float)

    def __getitem__(self, name):
        return float(self.ta.state[self.system.state_names.index(name)])

    def steps_where(self, **flags) -> int:
        """Taylor steps taken in modes with these flag values, e.g. ``steps_where(contact=1)``."""
        names = list(self.flags)
        return sum(n for key, n in self.mode_steps.items()
                   if all(key[names.index(k)] == v for k, v in flags.items()))

    def set_params(self, **values):
        """Change parameter values in place (no recompilation)."""
        merged = dict(self.params, **values)
        self.params = self.system.validate(merged)
        self._load_pars()

    def _load_pars(self):
        n = len(self.ta.pars)
        self.ta.pars[:] = np.asarray(self.system.par_vector(self.params, self.flags)[:n],
                                     dtype=_np_dtype(self.fp_type))

    def _set_flags(self, new: Mapping[str, float], t: float):
        if not new:
            return
        changed = {k: v for k, v in new.items() if self.flags.get(k) != v}
        if not changed:
            return
        self.flags.update(changed)
        n = len(self.ta.pars)
        for k, v in changed.items():
            if self.system._flag_index[k] < n:
                self.ta.pars[self.system._flag_index[k]] = v
        self.flag_log.append((t, dict(self.flags)))

    def _settle(self, t, log: bool = True) -> list:
        """Make the flags consistent; transitions named in ``system.settle_events`` are
        logged as events (after the guard's own record when ``log`` is False: returned)."""
        records = []
        if self.system.settle is not None and settle_may_act(self.system, self.flags):
            y_minus = np.array(self.ta.state, dtype=float)
            new = self.system.settle(t, y_minus.copy(), dict(self.flags), self.params)
            if isinstance(new, tuple):  # (flags, state): a mode entered with a state projection
                new, y = new
                self.ta.state[:] = np.asarray(y, dtype=_np_dtype(self.fp_type))
            if new:
                named = self.system.settle_events
                for k, v in new.items():
                    if self.flags.get(k) != v and v in named.get(k, {}):
                        records.append((named[k][v], y_minus))
                self._set_flags(new, t)
        out = []
        for name, y_minus in records:
            self._count_event(name)
            if self.record_events:
                out.append(EventRecord(t, name, y_minus, np.array(self.ta.state, dtype=float), dict(self.flags)))
        if log:
            self.events.extend(out)
        return out

    def _count_event(self, name: str):
        self.n_events += 1
        self.period_events += 1
        self.max_period_events = max(self.max_period_events, self.period_events)
        if self.max_events is not None and self.n_events > self.max_events:
            raise EventCap(f"more than {self.max_events} events by t = {self.t:.9g} s "
                           f"(last: {name}); chattering or a runaway", self.t, self.y)
        if self.max_events_per_period is not None and self.period_events > self.max_events_per_period:
            raise EventCap(f"more than {self.max_events_per_period} events in one relay period, "
                           f"by t = {self.t:.9g} s (last: {name}); chattering or a runaway", self.t, self.y)

    # ----- integration ------------------------------------------------------
    def next_switch_time(self) -> tuple[float, PeriodicSwitch | None]:
        best, which = math.inf, None
        for sw in self.system.switches:
            ts = sw.instants(self.params[sw.frequency], self._next_switch[sw.flag])
            if ts < best:
                best, which = ts, sw
        return best, which

    def advance(self, t_end: float, on_segment: Callable | None = None) -> "HybridRun":
        """Integrate to ``t_end`` [s], stopping on every guard and switch.

        ``on_segment(c_output, t_start, t_stop)`` receives heyoka's continuous
        output of each smooth segment (dense output; requested only when given).
        Raises :class:`IntegrationFailure` on a non-finite state or on more than
        ``max_events`` events.
        """
        if not math.isfinite(float(t_end)):  # NaN: silent no-op; inf: ValueError inside heyoka
            raise ParameterError(f"'t_end' must be a finite time [s], got {t_end}")
        ta = self.ta
        sys = self.system
        c_out = on_segment is not None
        while float(ta.time) < t_end:
            t_sw, sw = self.next_switch_time()
            t_stop = min(t_end, t_sw)
            t_start = float(ta.time)
            y_start = np.array(ta.state, dtype=float)
            if t_stop > t_start:
                res = ta.propagate_until(_fp(t_stop, self.fp_type), c_output=c_out)
                outcome, nsteps = res[0], res[3]
                self.n_steps += nsteps
                key = tuple(self.flags.values())
                self.mode_steps[key] = self.mode_steps.get(key, 0) + nsteps
                if c_out and res[4] is not None:
                    on_segment(res[4], t_start, float(ta.time))
            else:
                outcome = hy.taylor_outcome.time_limit
            if outcome == hy.taylor_outcome.time_limit:
                if sw is not None and t_stop == t_sw:
                    n = self._next_switch[sw.flag]
                    self._next_switch[sw.flag] = n + 1
                    self.n_switches += 1
                    if sw is self.system.switches[0] and n % 2 == 0:
                        self.period_events = 0  # a new relay period begins
                    self._set_flags({sw.flag: sw.value_for_index(n)}, t_sw)
                    self._settle(t_sw)
                continue
            code = int(outcome)
            if -len(sys._groups) - 1 < code < 0:
                group, mixed = sys._groups[-code - 1], sys._mixed[-code - 1]
                for g in group:
                    if (not mixed or g.direction in (0, _CROSSING[0])) and \
                            all(self.flags.get(k) == v for k, v in g.when.items()):
                        self._on_guard(g)
                        break
                continue
            state = np.array(ta.state, dtype=float)
            if outcome == hy.taylor_outcome.err_nf_state:
                raise IntegrationFailure(f"non-finite state in the step after t = {t_start:.9g} s "
                                         f"(last finite state {np.array2string(y_start, precision=6)})",
                                         t_start, y_start)
            raise IntegrationFailure(f"integration stopped with {outcome} at t = {float(ta.time):.9g} s",
                                     float(ta.time), state)
        return self

    def _on_guard(self, g: Guard):
        self._count_event(g.name)
        t = self.t
        y_minus = np.array(self.ta.state, dtype=float) if self.record_events else None
        if g.reset is not None:
            self.ta.state[:] = g.reset(np.array(self.ta.state), self.params)
        if g.then is not None:
            new = g.then(t, np.array(self.ta.state, dtype=float), dict(self.flags), self.params) \
                if callable(g.then) else g.then
            self._set_flags(new, t)
        y_guard = np.array(self.ta.state, dtype=float) if self.record_events else None
        flags_guard = dict(self.flags)
        settled = self._settle(t, log=False)
        if self.record_events:  # the guard's record, then any settle transition it caused
            self.events.append(EventRecord(t, g.name, y_minus, y_guard if settled else
                                           np.array(self.ta.state, dtype=float),
                                           flags_guard if settled else dict(self.flags)))
            self.events.extend(settled)
        for f in self.system.halt_flags:
            if self.flags.get(f):
                raise Escaped(f"{g.name}: the state left the model's domain at t = {t:.9g} s",
                              t, np.array(self.ta.state, dtype=float))


def validate_tol(tol) -> float:
    from .parameters import validate_value
    return validate_value("tol", tol, 0.0, 1e-2, low_open=True, long_name="integration tolerance")
