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

Guards carry a *role* (impact, release, flight_minimum, deepest, escape, stick,
unstick, slip, observation, other) that analysis reads instead of guard names.
The distance to the stop (``gap``) is declared: by default it is the surface of
the guard whose role is "impact", signed so that > 0 is clear, whichever side
of the mass the stop is on.

This module only declares.  The rules applied at a transition live in
:mod:`maps.transitions`; the integrators (:class:`~maps.engines.scalar.HybridRun`,
the batch engine) in :mod:`maps.engines`.  Compiled integrators are cached per
system structure, tolerance and floating-point type.
"""
from __future__ import annotations

import functools
import inspect
import math
import os
import time as _time
from dataclasses import dataclass, field
from typing import Callable, Mapping, Sequence

import heyoka as hy
import numpy as np

from .parameters import Parameter, ParameterError, validate_value

#: heyoka's log levels, quietest last
HEYOKA_LOG_LEVELS = ("trace", "debug", "info", "warning", "error", "critical")


def quiet_heyoka(level: str | None = None) -> str:
    """Set heyoka's log level (default: the environment's ``BIFURC_HEYOKA_LOG``, else "error"); returns it.

    heyoka writes its warnings to stdout, where they reach notebooks as raw lines. The one the models here
    provoke is benign: "polynomial root finding during event detection returned a nonzero errno with message
    'Numerical argument out of domain'" (a guard's Taylor polynomial evaluated out of a function's domain
    while its roots are isolated; the event is still located). ``BIFURC_HEYOKA_LOG=warning`` shows them."""
    level = level or os.environ.get("BIFURC_HEYOKA_LOG", "error")
    if level not in HEYOKA_LOG_LEVELS:
        level = "error"
    getattr(hy, f"set_logger_level_{level}")()
    return level


quiet_heyoka()


#: what a guard crossing means, for analysis (impact logs, clearance, signatures):
#: impact (contact onset), release (contact ends), flight_minimum (a free-flight minimum of the
#: gap), deepest (deepest point of a contact), escape (leaves the model's domain), stick /
#: unstick / slip (sticking modes), observation (recorded only), other
ROLES = ("impact", "release", "flight_minimum", "deepest", "escape", "stick", "unstick", "slip",
         "observation", "other")
#: roles of today's guard names, for guards declared without a role
ROLE_OF_NAME = {"contact": "impact", "lowest": "flight_minimum", "deepest": "deepest",
                "release": "release", "escape": "escape", "stick": "stick", "unstick": "unstick"}

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
    callable ``then(t, y, flags, params) -> dict``, or ``-> (dict, y)`` to enter the new
    mode with the state projected (declare the projection's expressions in
    ``system.projections[name]`` for exact Jacobians).  ``reset`` maps the state
    at the crossing to the state after it (``None``: continuous): a list of heyoka
    expressions, one per state (e.g. ``[s.x, -s.r * s.v]``, differentiable
    symbolically; ``sym.t`` for a reset that depends on time, e.g. a moving stop), or a
    Python function ``reset(y, params) -> y`` or ``reset(y, params, t) -> y`` (traced on heyoka
    symbols where it can be, see :meth:`HybridSystem.reset_expressions`).  The guard's
    surface and the reset are evaluated at the crossing's instant.  A guard with ``then=None`` and ``reset=None`` only records
    the crossing (an observation, e.g. the deepest point of a contact).
    ``role`` (one of :data:`ROLES`) says what the crossing means; without it the
    name decides ("contact": impact, "lowest": flight_minimum, ...; else
    observation or other).
    """

    name: str
    expr: object
    direction: int = 0
    when: Mapping[str, float] = field(default_factory=dict)
    then: Mapping[str, float] | Callable | None = None
    reset: Callable | None = None
    role: str | None = None

    def __post_init__(self):
        if self.direction not in (-1, 0, 1):
            raise ValueError(f"guard {self.name!r}: direction {self.direction!r}; allowed: -1, 0, +1")
        role = self.role
        if role is None:
            role = ROLE_OF_NAME.get(self.name, "observation" if self.then is None and self.reset is None
                                    else "other")
        if role not in ROLES:
            raise ValueError(f"guard {self.name!r}: role {role!r}; allowed: {', '.join(ROLES)}")
        object.__setattr__(self, "role", role)

    @property
    def observes_only(self) -> bool:
        """True for a guard that changes neither flags nor state (a recorded crossing)."""
        return self.then is None and self.reset is None

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


@dataclass
class HybridState:
    """The state of a hybrid system: the continuous state ``y`` and the flags (the mode).

    Maps take and return it, so that a step restarts exactly from any stored point (a
    bar stuck on its stop, a rig stuck in the soil).  ``flags=None`` means "not known":
    the system's declared rule (:meth:`HybridSystem.mode_at`) decides once.
    """

    y: np.ndarray
    flags: dict | None = None

    def __post_init__(self):
        self.y = np.asarray(self.y, dtype=float) if not isinstance(self.y, np.ndarray) else self.y
        if self.flags is not None:
            self.flags = dict(self.flags)


_COMPILED: dict = {}


def settle_may_act(system, flags, y=None, params=None) -> bool:
    """False when ``system.settle_if`` rules out any change under ``flags`` (a callable one also
    reads the state ``y`` and ``params``)."""
    cond = system.settle_if
    if cond is None:
        return True
    if callable(cond):
        return bool(cond(flags, y, params))
    for k, v in cond:
        if flags[k] == v:
            return True
    return False


def _constant(value: float, params=None) -> float:
    """``value`` whatever the parameters (an autonomous flow's sampling step as its strobe period; picklable)."""
    return value


def _sample_step(name: str, step, strobe_period, switches, forcing) -> float | None:
    """The declared sampling step [s] of an autonomous flow, checked: positive and finite, and declared alone
    (a switch, a forcing or a strobe period is a clock of its own)."""
    if step is None:
        return None
    if strobe_period is not None or switches or forcing:
        raise ValueError(f"{name!r}: sample_step declares an autonomous flow's sampling step; it has a clock "
                         f"already (strobe_period, a switch or a forcing): declare one of them")
    step = float(step)
    if not (math.isfinite(step) and step > 0.0):
        raise ParameterError(f"sample_step = {step!r} of {name!r}: must be a finite time step above 0 [s]")
    return step


class HybridSystem:
    """A piecewise-smooth system: states, parameters, flags, rhs, guards, switches; the whole
    declaration is the constructor's arguments (nothing is assigned afterwards).  Keyword-only:

    - ``settle_events``: ``{flag: {value: event name}}``: a ``settle`` that sets the flag to the
      value is logged as an event of that name (e.g. ``{"stuck_bar": {1.0: "stick"}}``).
    - ``settle_if``: ``((flag, value), ...)``: ``settle`` can act only while one of these flags has
      that value (it is not called elsewhere); or a cheap callable ``(flags, y, params) -> bool``,
      never False where ``settle`` could act; None: always.
    - ``projections``: ``{name: f(sym, flags) -> list of expressions}``: the state projection of the
      settle transition (or ``then`` callable) named ``name``, for exact Jacobians.
    - ``mode_projections``: ``{(flag, value): name}``: a mode whose states lie on a set reached by
      ``projections[name]`` (a bar stuck on its stop); an exact Jacobian started in that mode first
      projects its perturbations onto the set.
    - ``translation``: ``{state: coefficient}``: a direction along which the flow is invariant (the
      2-DOF scenes: bar and rig shifted together); orbits are solved in reduced coordinates.
    - ``strobe_period``: ``f(params) -> T`` [s], the stroboscopic period; by default the period of the
      first periodic switch (1 / its frequency), else of the first forcing frequency.
    - ``sample_step``: Δt [s], an autonomous flow's sampling step (no switch, no forcing, no
      ``strobe_period``): its map is the flow sampled every Δt, as Attractors.jl samples a flow
      (``system.autonomous`` is then True; a census names its attractors fixed points, limit cycles
      and chaotic sets of the flow).
    - ``forcing``: the forcing frequencies [Hz] in absolute time, as parameter names or
      ``f(params) -> frequencies``: with the switches they give the map's forcing period q.
    - ``options``: the structural options the system was built from (a model's), or None.
    - ``mechanical``: the mechanical states' names (default: all), whose period is reported beside
      the full state's (the thesis model: x and v, not the coil's current and charge).
    """

    def __init__(self, name: str, states: Sequence[State], parameters: Sequence[Parameter],
                 rhs: Callable, flags: Mapping[str, float] | None = None,
                 guards: Callable | Sequence[Guard] = (), switches: Sequence[PeriodicSwitch] = (),
                 settle: Callable | None = None, outputs: Callable | None = None,
                 structure: tuple = (), halt_flags: Sequence[str] = (), gap: Callable | None = None,
                 mode_rule: Callable | None = None, *, settle_events: Mapping | None = None,
                 settle_if: tuple | Callable | None = None, projections: Mapping | None = None,
                 mode_projections: Mapping | None = None, translation: Mapping[str, float] | None = None,
                 strobe_period: Callable | None = None, forcing: Sequence[str] | Callable | None = None,
                 options=None, mechanical: Sequence[str] | None = None, sample_step: float | None = None):
        """``rhs(sym) -> list of expressions`` and ``guards(sym) -> list of Guard`` receive a
        :class:`Symbols` giving ``sym.x``/``sym['x']`` for states, parameters and flags,
        and ``sym.t`` for time.  ``settle(t, y, flags, params) -> flags`` makes the flags
        consistent after any transition (e.g. stick/slip).  ``outputs(sym) -> dict`` names
        derived expressions (forces) evaluated on demand; ``settle`` may also return
        ``(flags, y)`` to enter a mode with a projected state (e.g. a bar stuck on its
        stop: x = e, v = 0).  A guard that sets one of
        ``halt_flags`` to a non-zero value ends the run with :class:`Escaped`.
        ``gap(y, params) -> (gap [m], gap rate [m/s])``, or ``gap(y, params, t)`` for a stop
        that moves, gives the signed distance to the stop (> 0: clear) and its rate (the
        relative approach speed, < 0 toward the stop) for impact logs and clearance;
        ``system.gap`` is always callable as ``gap(y, params, t=0.0)``.  By default it is
        declared by the guard whose role is "impact": its surface, signed so that the approach
        to the stop is a decrease (``direction=-1``: the surface itself; ``+1``: its negative),
        and its rate along the flow in the default mode (with the surface's own time derivative);
        without an impact guard there is no gap.
        ``mode_rule(y, params, flags, given) -> dict`` gives the flags that follow from the state
        at a start (e.g. in contact inside the stop); ``given``: names the caller set (left alone).
        By default: beyond an impact surface whose guard sets flags, those flags.  The keyword-only
        declarations: the class docstring.
        """
        self.name = name
        self.states = tuple(states)
        self.parameters = tuple(parameters)
        self.flag_defaults = dict(flags or {})
        self.switches = tuple(switches)
        self.settle = settle
        self.halt_flags = tuple(halt_flags)
        self._gap_given = gap
        self.mode_rule = mode_rule
        self.settle_events = dict(settle_events or {})
        self.settle_if = settle_if
        self.projections = dict(projections or {})
        self.mode_projections = dict(mode_projections or {})
        self.translation = dict(translation) if translation else None
        self.sample_step = _sample_step(name, sample_step, strobe_period, switches, forcing)
        self.strobe_period = strobe_period if sample_step is None else functools.partial(_constant,
                                                                                          self.sample_step)
        self.forcing = forcing
        self.options = options
        self.mechanical = tuple(mechanical) if mechanical is not None else None
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
        impacts = [g for g in self.guards if g.role == "impact"]
        self.impact_guard = impacts[0] if impacts else None
        self.gap = _with_time(gap) if gap is not None else (_guard_gap(self, self.impact_guard)
                                                           if self.impact_guard is not None else None)
        self._check_declarations()
        self._groups = self.event_groups()
        self._cfuncs: dict = {}

    def _check_declarations(self) -> None:
        """ValueError unless the switches, mechanical states and forcing name this system's own names."""
        for sw in self.switches:
            if sw.flag not in self.flag_defaults or sw.frequency not in self._param_index:
                raise ValueError(f"switch {sw} names an unknown flag or parameter")
        if self.mechanical is not None and not set(self.mechanical) <= set(self.state_names):
            raise ValueError(f"mechanical states {self.mechanical} of {self.name!r} are not all states")
        if self.forcing is not None and not callable(self.forcing):
            self.forcing = tuple(self.forcing)
            unknown = [f for f in self.forcing if f not in self._param_index]
            if unknown:
                raise ValueError(f"forcing frequency {unknown[0]!r} of {self.name!r} is not a parameter")

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

    @property
    def mechanical_index(self) -> list:
        """Indices of the mechanical states (every state when none are declared)."""
        names = self.mechanical if self.mechanical is not None else self.state_names
        return [self.state_names.index(n) for n in names]

    # ----- clock -------------------------------------------------------
    def strobe_period_of(self, params: Mapping[str, float]) -> float | None:
        """The declared stroboscopic period T [s] under ``params``: ``strobe_period(params)``, else
        1 / the first periodic switch's frequency, else 1 / the first forcing frequency; None when
        the system declares no clock."""
        if self.strobe_period is not None:
            return float(self.strobe_period(params))
        if self.switches:
            return 1.0 / params[self.switches[0].frequency]
        freqs = self.forcing_frequencies(params)
        return 1.0 / freqs[0] if freqs else None

    def strobe_rate(self, params: Mapping[str, float]) -> float | None:
        """Samples per second [Hz] when the strobe period is the first switch's period (its sample
        instants k / W are then exactly its switch instants), else None."""
        if self.strobe_period is None and self.switches:
            return params[self.switches[0].frequency]
        return None

    @property
    def autonomous(self) -> bool:
        """True for an autonomous flow sampled every ``sample_step`` (no switch, no forcing)."""
        return self.sample_step is not None

    @property
    def declares_clock(self) -> bool:
        """True when the system declares a strobe period (a switch, a forcing or ``strobe_period``)."""
        return self.strobe_period is not None or bool(self.switches) or bool(self.forcing)

    @property
    def strobe_parameter(self) -> str | None:
        """The parameter that sets the strobe period when it is a switch's frequency, else None."""
        return self.switches[0].frequency if self.strobe_period is None and self.switches else None

    def forcing_frequencies(self, params: Mapping[str, float]) -> tuple:
        """The declared forcing frequencies [Hz] (not the switches')."""
        if self.forcing is None:
            return ()
        if callable(self.forcing):
            return tuple(float(f) for f in self.forcing(params))
        return tuple(float(params[f]) for f in self.forcing)

    def forcing_q(self, params: Mapping[str, float], period: float, max_steps: int = 1000) -> int:
        """q: the forcing (declared frequencies and switches) repeats every q samples of period
        ``period`` [s]; 0 when incommensurate within ``max_steps``; 1 for a system that declares
        neither a forcing nor a switch (taken to be forced with the sampling period)."""
        freqs = self.forcing_frequencies(params) + tuple(params[sw.frequency] for sw in self.switches)
        return commensurate_steps(freqs, period, max_steps) if freqs else 1

    # ----- compilation ---------------------------------------------------
    def heyoka_system(self):
        return list(zip(self.sym.state_vars, self.rhs))

    def event_groups(self, observations: bool = True) -> list[list[Guard]]:
        """Guards grouped by identical expression: one heyoka event per surface, in declaration
        order.  ``observations=False`` leaves out guards that change neither flags nor state
        (and a surface left without a guard), for a run that records none of them.

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
        if observations:
            return list(groups.values())
        kept = ([g for g in grp if not g.observes_only] for grp in groups.values())
        return [grp for grp in kept if grp]

    def heyoka_events(self, fp_type=float, observations: bool = True, callbacks: bool = False):
        """heyoka's terminal events, one per surface of ``event_groups(observations)`` (same order).

        ``callbacks``: each event calls an :class:`EventCallback` (its surface's index), which a
        run binds to itself (the scalar engine applies the transition there); else an event just
        stops the integration (a mixed-direction surface's callback keeps the crossing's sign
        in ``_CROSSING``)."""
        kw = {} if fp_type is float else {"fp_type": fp_type}
        events = []
        for i, grp in enumerate(self._groups if observations else self.event_groups(False)):
            mixed = len({g.direction for g in grp}) > 1
            extra = dict(direction=hy.event_direction.any if mixed else grp[0].heyoka_direction())
            if callbacks:
                extra["callback"] = EventCallback(i)
            elif mixed:
                extra["callback"] = _record_crossing
            events.append(hy.t_event(grp[0].expr, cooldown=_fp(EVENT_COOLDOWN, fp_type), **extra, **kw))
        return events

    def integrator(self, tol: float = 1e-12, fp_type=float, compact_mode: bool = False,
                   observations: bool = True, callbacks: bool = False):
        """A heyoka integrator for this system, compiled once per (structure, tol, fp_type,
        observations, callbacks): its events are those of :meth:`heyoka_events`.

        Returns a fresh deep copy so that several runs never share state.
        """
        key = (self.structure, float(tol), fp_type, compact_mode, bool(observations), bool(callbacks))
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
                                       t_events=self.heyoka_events(fp_type, observations, callbacks),
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

    def on_mode_set(self, y, params, flags, t: float = 0.0) -> np.ndarray:
        """``y`` moved onto the set of its mode, where the mode has one (``mode_projections``: a bar stuck on its
        stop sits on it at rest), else ``y``: every run starts there, as its exact Jacobian assumes (it projects
        the perturbations onto that set).  A stuck state off the set would stay where it is, a fixed point for any
        position: Newton from a guess moved along a branch's tangent past a stick onset (thesis-1dof, 110.8 V)
        "converged" to the bar stuck 7 um inside the stop moving at 0.2 mm/s."""
        for (flag, value), name in self.mode_projections.items():
            if flags.get(flag) == value:
                key = ("mode set", name, tuple(sorted(flags.items())))
                if key not in self._cfuncs:
                    rows = self.projections[name](self.sym, flags)
                    self._cfuncs[key] = hy.cfunc(rows, vars=self.sym.state_vars, compact_mode=True)
                return call_cfunc(self._cfuncs[key], y, self.par_vector(params, flags), t)
        return np.asarray(y, dtype=float)

    def evaluate(self, names: Sequence[str], y, params, flags, t=0.0) -> np.ndarray:
        """Evaluate named outputs at one state (numpy, double precision)."""
        return call_cfunc(self.cfunc(tuple(names)), y, self.par_vector(params, flags), t)

    def _guard_expr(self, name):
        for g in self.guards:
            if g.name == name:
                return g.expr
        raise KeyError(f"no output or guard named {name!r}")

    def guard_gradient(self, name: str):
        """d(guard)/d(state) and d(guard)/dt as heyoka expressions (for saltation matrices)."""
        expr = self._guard_expr(name)
        return [hy.diff(expr, v) for v in self.sym.state_vars], time_derivative(expr)

    def reset_expressions(self, guard: Guard) -> list:
        """The reset map of ``guard`` as heyoka expressions of the state and parameters.

        Given as expressions, they are returned; a Python ``reset(y, params)`` or
        ``reset(y, params, t)`` is traced by calling it on the symbols (an object array of state
        variables, a dict of parameter symbols and heyoka's time).  Raises :class:`ParameterError` naming the guard when the
        function cannot be traced (then declare ``reset`` as expressions for an exact
        Jacobian).  No reset: the identity."""
        if guard.reset is None:
            return list(self.sym.state_vars)
        if not callable(guard.reset):
            return list(guard.reset)
        cache = self.__dict__.setdefault("_traced", {})
        if guard.name not in cache:
            y = np.empty(len(self.state_names), dtype=object)
            y[:] = self.sym.state_vars
            params = {p: self.sym[p] for p in self.param_names}
            try:
                out = self.reset_function(guard)(y, params, self.sym.t)
                exprs = [v if isinstance(v, hy.expression) else hy.expression(float(v)) for v in out]
            except Exception as exc:  # noqa: BLE001 - any failure means: not traceable
                raise ParameterError(f"the reset of guard {guard.name!r} cannot be traced on heyoka symbols "
                                     f"({type(exc).__name__}: {exc}); declare reset= as a list of heyoka "
                                     f"expressions for an exact Jacobian") from None
            if len(exprs) != len(self.state_names):
                raise ParameterError(f"the reset of guard {guard.name!r} returns {len(exprs)} components "
                                     f"for {len(self.state_names)} states")
            cache[guard.name] = exprs
        return cache[guard.name]

    def reset_function(self, guard: Guard) -> Callable:
        """``reset(y, params, t=0.0) -> y`` for ``guard`` at time ``t`` [s] of the crossing
        (compiled once when declared as expressions; a Python ``reset(y, params)`` that does not
        read time is called as it is, its arity looked up once); None without a reset."""
        if guard.reset is None:
            return None
        cache = self.__dict__.setdefault("_reset_cfuncs", {})
        if guard.name not in cache:
            if callable(guard.reset):
                cache[guard.name] = _with_time(guard.reset)
            else:
                f = hy.cfunc(list(guard.reset), vars=self.sym.state_vars, compact_mode=True)
                defaults = dict(self.flag_defaults)

                def reset(y, params, t=0.0, f=f):
                    return call_cfunc(f, y, self.par_vector(params, defaults), t)
                cache[guard.name] = reset
        return cache[guard.name]

    def lie_derivative(self, expr):
        """d(expr)/dt along the flow: grad(expr) . rhs + partial d(expr)/dt (heyoka expression)."""
        out = time_derivative(expr)
        for v, f in zip(self.sym.state_vars, self.rhs):
            out = out + hy.diff(expr, v) * f
        return out

    def initial_flags(self, t: float, params: Mapping[str, float], overrides=None) -> dict:
        """Default flags with every switch at its value at ``t``, then ``overrides``."""
        flags = dict(self.flag_defaults)
        for sw in self.switches:
            flags[sw.flag] = sw.value_for_index(sw.index_at(t, params[sw.frequency]))
        flags.update(overrides or {})
        return flags

    def mode_at(self, y, params: Mapping[str, float], flags: Mapping[str, float] | None = None,
                given: tuple = (), t: float = 0.0) -> dict:
        """Flags that follow from the state ``y`` at a start at time ``t`` [s], by the declared
        rule (those in ``given`` are the caller's and are left out)."""
        y = np.asarray(y, dtype=float)
        if self.mode_rule is not None:
            flags = dict(self.flag_defaults) if flags is None else dict(flags)
            out = self.mode_rule(y, params, flags, tuple(given)) or {}
        else:
            g = self.impact_guard
            beyond = (g is not None and self.gap is not None and isinstance(g.then, Mapping)
                      and self.gap(y, params, t)[0] < 0)
            out = dict(g.then) if beyond else {}
        return {k: v for k, v in out.items() if k not in given}

    def role_of(self, name: str) -> str:
        """The role of a guard or settle event by its name ("other" if unknown)."""
        roles = self.__dict__.get("_roles")
        if roles is None:
            roles = {g.name: g.role for g in self.guards}
            for names in self.settle_events.values():
                for ev in names.values():
                    roles.setdefault(ev, ROLE_OF_NAME.get(ev, "other"))
            self._roles = roles
        return roles.get(name, "other")

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


class EventCallback:
    """The callback of the terminal event of surface ``index``: returns
    ``run._on_event(index, sign)`` (True: integrate on) for the run bound to this integrator copy
    (``run``: a weak reference, set by the run); unbound, it stops the integration as
    :func:`_record_crossing` does.  heyoka deep-copies callbacks with the integrator: each copy
    gets a callback of its own, bound to no run."""

    __slots__ = ("index", "run")

    def __init__(self, index: int):
        self.index, self.run = index, None

    def __deepcopy__(self, memo):
        return EventCallback(self.index)

    def __call__(self, ta, d_sgn):
        run = self.run() if self.run is not None else None
        if run is None:
            return _record_crossing(ta, d_sgn)
        return run._on_event(self.index, d_sgn)


def commensurate_steps(frequencies, period: float, max_steps: int = 1000) -> int:
    """Smallest q <= max_steps with q * period * f an integer (to 1e-9) for every frequency f [Hz],
    else 0 (incommensurate within ``max_steps``)."""
    ratios = [float(period) * f for f in frequencies]
    for q in range(1, min(int(max_steps), 32) + 1):   # the common small q, without numpy's overhead
        if all(abs(q * r - round(q * r)) <= 1e-9 * max(1.0, q * r) for r in ratios):
            return q
    q = np.arange(33, int(max_steps) + 1)          # every larger candidate at once (a loop cost ~1 ms a value)
    whole = np.ones(q.size, dtype=bool)
    for r in ratios:
        x = q * r
        whole &= np.abs(x - np.round(x)) <= 1e-9 * np.maximum(1.0, x)
    hit = np.flatnonzero(whole)
    return int(q[hit[0]]) if hit.size else 0


def call_cfunc(f, y, pars, t: float = 0.0) -> np.ndarray:
    """A compiled function of the state (``hy.cfunc`` over the state variables) at state ``y``
    with the runtime-parameter vector ``pars`` (parameters then flags, as ``par_vector``) and
    time ``t`` [s] (used only when the function depends on time)."""
    kw = {"time": float(t)} if f.is_time_dependent else {}
    return f(np.ascontiguousarray(y, dtype=float), pars=np.ascontiguousarray(np.asarray(pars, dtype=float)[:f.nparams]),
             **kw)


def time_derivative(expr):
    """Partial derivative of a heyoka expression with respect to time (heyoka differentiates
    only by variables and parameters: time is swapped for a variable and back)."""
    tau = hy.make_vars("_time_")
    d = hy.diff(hy.subs(expr, {hy.time: tau}), tau)
    return hy.subs(d, {tau: hy.time})


def _guard_gap(system: "HybridSystem", guard: Guard):
    """``gap(y, params, t=0.0) -> (gap, rate)`` from the impact guard's surface, > 0 clear, at
    time ``t`` [s].

    The rate is taken along the flow in the default mode, with the surface's partial time
    derivative (a moving stop): the relative approach speed."""
    sign = -1.0 if guard.direction == 1 else 1.0
    g = guard.expr * sign
    f = hy.cfunc([g, system.lie_derivative(g)], vars=system.sym.state_vars, compact_mode=True)
    defaults = dict(system.flag_defaults)

    def gap(y, params, t=0.0):
        out = call_cfunc(f, y, system.par_vector(params, defaults), t)
        return float(out[0]), float(out[1])

    return gap


def _with_time(fn: Callable) -> Callable:
    """``fn(y, params)`` or ``fn(y, params, t)`` (a reset, a gap) as ``f(y, params, t=0.0)``: a
    function that does not take the time is wrapped, one that takes it with a default is returned
    as it is (no cost per call), one that takes it without a default gets the default 0.0.  The
    arity is read once, here."""
    try:
        sig = inspect.signature(fn)
    except (TypeError, ValueError):      # a builtin without a signature: the old form
        sig = None
    if sig is not None:
        kinds = [p.kind for p in sig.parameters.values()]
        pos = [p for p in sig.parameters.values() if p.kind in (p.POSITIONAL_ONLY, p.POSITIONAL_OR_KEYWORD)]
        if inspect.Parameter.VAR_POSITIONAL in kinds or (len(pos) > 2 and pos[2].default is not inspect.Parameter.empty):
            return fn
        if len(pos) > 2:
            def timed(y, params, t=0.0, fn=fn):
                return fn(y, params, t)
            timed.__wrapped__ = fn
            return timed

    def untimed(y, params, t=0.0, fn=fn):
        return fn(y, params)
    untimed.__wrapped__ = fn
    return untimed


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


def validate_tol(tol) -> float:
    return validate_value("tol", tol, 0.0, 1e-2, low_open=True, long_name="integration tolerance")
