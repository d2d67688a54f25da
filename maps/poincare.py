"""Poincare maps of hybrid systems: the stroboscopic map and the impact map.

The stroboscopic map samples the state at t_k = t0 + (k + phase) * T, T the
relay period 1/relay_hz (or a given period).  For the electro-vibro-impact
model the forcing P(t) V sin(2 pi f_mains t) repeats after T only when
f_mains/relay_hz is an integer; otherwise the map is not autonomous and its
forcing repeats after ``forcing_period_steps`` = q steps (q f_mains / relay_hz
integral).  A periodic orbit's period is then a multiple of q.
"""
from __future__ import annotations

import functools
import math
import time as _time
from dataclasses import dataclass, field, replace

import numpy as np

from .engines import engine_for, unsupported
from .engines.base import OrbitJob
from .engines.scalar import ScalarEngine
from .hybrid import HybridState, HybridSystem, IntegrationFailure, commensurate_steps, validate_tol
from .impacts import impact_log
from .parameters import ParameterError, validate_value
from .problem import problem
from .progression import held_mode
from .translation import translation_basis

def _period_slope(system, params: dict, name: str) -> float:
    """dT/dp of the system's declared clock T (strobe_period, switch or forcing) at ``params``."""
    p = float(params[name])
    h = 1e-20 * max(1.0, abs(p))
    if system.strobe_period is not None:
        try:
            T = system.strobe_period(dict(params, **{name: complex(p, h)}))
            return float(np.imag(T) / h) if isinstance(T, complex) else 0.0
        except (TypeError, ValueError, ZeroDivisionError):
            pass
    h = 1e-6 * max(1.0, abs(p))
    try:
        up, down = system.strobe_period_of(dict(params, **{name: p + h})), system.strobe_period_of(dict(params, **{name: p - h}))
    except (ValueError, ZeroDivisionError, KeyError):
        return 0.0
    return 0.0 if up is None or down is None else (up - down) / (2 * h)


def forcing_period_steps(f_mains: float, relay_hz: float | None, max_steps: int = 1000,
                         period: float | None = None) -> int:
    """Smallest q <= max_steps after which a relay-switched mains forcing repeats, else 0
    (the thesis model's case of :meth:`~maps.hybrid.HybridSystem.forcing_q`).

    The forcing P(t) V sin(2 pi f_mains t) has period 1/relay_hz in P and 1/f_mains in
    the sine; sampled every ``period`` [s] (default 1/relay_hz) it repeats after q
    samples when q*period*f_mains and q*period*relay_hz are both integers (to 1e-9).
    Without a relay (``relay_hz`` None) only the mains period counts.
    """
    T = 1.0 / relay_hz if period is None else float(period)
    return commensurate_steps((f_mains,) if relay_hz is None else (f_mains, relay_hz), T, max_steps)


@dataclass
class MapOrbit:
    """Recorded iterates of a stroboscopic map and what happened between them.

    ``points[k]`` is the state at ``times[k]``, with the flags ``point_flags[k]`` (columns
    ``flag_names``; :meth:`state` gives the hybrid state); step k runs from ``times[k]`` to
    ``times[k+1]``.  Gaps are distances to the stop [m] (negative: penetration).
    ``min_clearance_per_step`` is the smallest of the gaps at the step's ends, at its impacts
    (0 at the onset), at its free-flight minima (role "flight_minimum") and, in contact,
    minus the deepest penetration: never NaN.  ``min_flight_clearance_per_step`` keeps only the free-flight
    minima (inf where the step has none): it reaches 0 where a new impact is born
    (a grazing bifurcation), which the total ``min_clearance`` does not show on an
    impacting orbit.  A system without a declared gap has NaN gaps.
    """

    times: np.ndarray                 # (n+1,) [s]
    points: np.ndarray                # (n+1, d)
    impacts_per_step: np.ndarray      # (n,) contacts in (t_k, t_k+1]
    min_clearance_per_step: np.ndarray      # (n,) [m] smallest gap in each step
    min_impact_speed_per_step: np.ndarray  # (n,) [m/s], inf where no contact
    impact_time: np.ndarray              # [s] contact onsets in the recorded window
    impact_velocity: np.ndarray       # [m/s] gap rate at onset (< 0)
    impact_phase: np.ndarray          # relay phase of each onset, in [0, 1)
    impact_penetration: np.ndarray    # [m] maximum penetration of each contact (>= 0)
    impact_duration: np.ndarray       # [s] contact duration (NaN: still in contact at the end)
    min_flight_clearance_per_step: np.ndarray  # (n,) [m] lowest free-flight minimum per step, inf if none
    status: str = "ok"                # ok, escaped, failed
    failure: str = ""
    failure_time: float = math.nan
    n_steps: int = 0                  # Taylor steps
    run_seconds: float = 0.0
    final_state: np.ndarray | None = None
    final_flags: dict = field(default_factory=dict)
    flag_names: tuple = ()
    point_flags: np.ndarray | None = None   # (n+1, len(flag_names)) flags at each point
    signature: list = field(default_factory=list)  # per step: the ordered roles of its events
    tangent_start: np.ndarray | None = None   # (d,) unit tangent vector at points[0] (None: none integrated)
    tangent: np.ndarray | None = None         # (m, d) the tangent vector at the end of each step, m <= n
    tangent_shift: tuple | None = None        # the translation removed from it after each step (2-DOF)
    mode_time: np.ndarray | None = None       # (n+1,) [s] time in the soil's holding mode from points[0] to each
                                              # point (maps.progression.held_mode; None: the system has none)

    @property
    def n(self) -> int:
        return len(self.impacts_per_step)

    def tangent_stretch(self, scale=None) -> np.ndarray | None:
        """Log stretch [per step] of the tangent vector integrated with the flow, in the norm scaled
        by ``scale`` (:func:`maps.tangent.tangent_stretch`); NaN after it ended; None: none integrated."""
        if self.tangent_start is None:
            return None
        out = np.full(self.n, np.nan)
        if self.tangent is not None and len(self.tangent):
            from .tangent import tangent_stretch
            m = min(len(self.tangent), self.n)
            out[:m] = tangent_stretch(self.tangent_start, self.tangent[:m], scale, self.tangent_shift)
        return out

    def then(self, more: "MapOrbit") -> "MapOrbit":
        """This orbit followed by ``more``, which starts where this one ended (its first point is
        this one's last; its tangent vector, if any, continues this one's direction)."""
        cat = np.concatenate
        tangent = None
        if self.tangent is not None and more.tangent is not None:
            tangent = np.vstack([self.tangent, more.tangent])
        mode_time = None
        if self.mode_time is not None and more.mode_time is not None:
            mode_time = cat([self.mode_time, self.mode_time[-1] + more.mode_time[1:]])
        flags = None if self.point_flags is None or more.point_flags is None else \
            np.vstack([self.point_flags, more.point_flags[1:]])
        return replace(
            more, times=cat([self.times, more.times[1:]]), points=np.vstack([self.points, more.points[1:]]),
            impacts_per_step=cat([self.impacts_per_step, more.impacts_per_step]),
            min_clearance_per_step=cat([self.min_clearance_per_step, more.min_clearance_per_step]),
            min_impact_speed_per_step=cat([self.min_impact_speed_per_step, more.min_impact_speed_per_step]),
            impact_time=cat([self.impact_time, more.impact_time]),
            impact_velocity=cat([self.impact_velocity, more.impact_velocity]),
            impact_phase=cat([self.impact_phase, more.impact_phase]),
            impact_penetration=cat([self.impact_penetration, more.impact_penetration]),
            impact_duration=cat([self.impact_duration, more.impact_duration]),
            min_flight_clearance_per_step=cat([self.min_flight_clearance_per_step, more.min_flight_clearance_per_step]),
            n_steps=self.n_steps + more.n_steps, run_seconds=self.run_seconds + more.run_seconds,
            point_flags=flags, signature=list(self.signature) + list(more.signature),
            tangent_start=self.tangent_start, tangent=tangent, mode_time=mode_time)

    def since(self, k: int) -> "MapOrbit":
        """The orbit from its point ``k`` on (steps k, k+1, ...; the impacts after times[k])."""
        if k <= 0:
            return self
        keep = self.impact_time > self.times[k]
        tangent_start, tangent = self.tangent_start, self.tangent
        if tangent is not None and len(tangent) >= k:
            last = tangent[k - 1]
            tangent_start, tangent = last / np.linalg.norm(last), tangent[k:]
        return replace(
            self, times=self.times[k:], points=self.points[k:], impacts_per_step=self.impacts_per_step[k:],
            min_clearance_per_step=self.min_clearance_per_step[k:],
            min_impact_speed_per_step=self.min_impact_speed_per_step[k:],
            impact_time=self.impact_time[keep], impact_velocity=self.impact_velocity[keep],
            impact_phase=self.impact_phase[keep], impact_penetration=self.impact_penetration[keep],
            impact_duration=self.impact_duration[keep],
            min_flight_clearance_per_step=self.min_flight_clearance_per_step[k:],
            point_flags=None if self.point_flags is None else self.point_flags[k:],
            signature=list(self.signature)[k:], tangent_start=tangent_start, tangent=tangent,
            mode_time=None if self.mode_time is None else self.mode_time[k:] - self.mode_time[k])

    @property
    def tangent_direction(self) -> np.ndarray | None:
        """The unit tangent vector at the orbit's end (to continue it), or None."""
        if self.tangent is None or not len(self.tangent):
            return None
        last = np.asarray(self.tangent[-1], dtype=float)
        norm = np.linalg.norm(last)
        return last / norm if np.isfinite(norm) and norm > 0 else None

    def state(self, k: int) -> HybridState:
        """The hybrid state (continuous state and flags) at point k (negative: from the end)."""
        flags = None if self.point_flags is None else dict(zip(self.flag_names, self.point_flags[k]))
        return HybridState(self.points[k].copy(), flags)

    @property
    def final(self) -> HybridState:
        """The hybrid state where the orbit ended (to continue it exactly)."""
        return HybridState(np.asarray(self.final_state, dtype=float), dict(self.final_flags))


@dataclass
class MapLinearization:
    """One map step and its derivatives: the next state, J = d(step)/dy, J_p = d(step)/dp
    (columns in the order asked), the step's event roles, compile time [s]; ``rank``: the
    numerical rank of J, computed when first asked (an SVD)."""

    state: HybridState
    J: np.ndarray
    J_p: np.ndarray
    signature: tuple
    compile_seconds: float = 0.0
    events: tuple = ()          # the step's EventRecords (time, guard, state before and after)

    @functools.cached_property
    def rank(self) -> int:
        """Singular values of J above 1e-10 of the largest (deficient where a settle projection,
        e.g. a bar that sticks, collapses directions)."""
        sv = np.linalg.svd(self.J, compute_uv=False)
        return int(np.sum(sv > sv[0] * 1e-10)) if sv.size and sv[0] > 0 else 0


@dataclass
class ImpactLinearization:
    """The next impact from a state given at a fixed time t0, with its exact derivatives: the
    impact time ``t`` [s], the hybrid state just after the impact's transition, J = d(that
    state)/dy0 (d x d) and ``dt_dy`` = dt/dy0 (d,) [s per state unit], the event roles on the
    way (the impact last), compile time [s]."""

    t: float
    state: HybridState
    J: np.ndarray
    dt_dy: np.ndarray
    signature: tuple
    compile_seconds: float = 0.0


def _central_differences(end, state, eps):
    """d end(state)/dy by central differences with steps ``eps`` (default 1e-6 |y_j|, >= 1e-9); the
    mode of a HybridState is kept (a test oracle: valid where no event is grazed within +-eps)."""
    y, flags, _ = _split(state)
    y = np.asarray(y, dtype=float)
    J = np.empty((y.size, y.size))
    for j in range(y.size):
        h = eps if eps is not None else 1e-6 * max(1e-3, abs(y[j]))
        e = np.zeros(y.size)
        e[j] = h
        ends = [np.asarray(end(HybridState(y + s * e, flags) if flags is not None else y + s * e), dtype=float)
                for s in (1, -1)]
        J[:, j] = (ends[0] - ends[1]) / (2 * h)
    return J


def _split(state):
    """(continuous state, flags or None, was a HybridState) of a map argument."""
    if isinstance(state, HybridState):
        return state.y, state.flags, True
    return state, None, False


class StroboscopicMap:
    """The state sampled once per period T of a scene or hybrid system.

    >>> smap = StroboscopicMap("thesis-1dof", params)          # T = 1/relay_hz
    >>> orbit = smap.orbit(x0, n=100, transient=300)
    >>> y1 = smap.step(y0, k=0)                                # one period from t = phase*T
    >>> s1 = smap.step(orbit.state(-1), k=400)                 # hybrid state in, hybrid state out
    >>> many = smap.orbits([{"relay_hz": f} for f in (5, 6)], x0, n=100, transient=300)

    The period T is ``period`` if given, else the system's declared clock: its ``strobe_period``
    (e.g. 2 pi / Omega for a harmonically forced system), else the period of its first
    :class:`~maps.hybrid.PeriodicSwitch` (1/relay_hz for the thesis model), else of its first
    forcing frequency.
    The map's state is the continuous state and the flags (:class:`~maps.hybrid.HybridState`);
    a bare continuous state starts in the mode the system's rule gives it.  Orbits are
    integrated by an engine of :mod:`maps.engines` (the scalar one here; :meth:`orbits` and
    :meth:`stretch` use the batch engine for many parameter sets).
    """

    def __init__(self, system_or_scene, params: dict | None = None, *, period: float | None = None,
                 phase: float = 0.0, tol: float = 1e-12, fp_type=float, max_events_per_period: int = 10_000):
        if isinstance(system_or_scene, HybridSystem):
            self.system, self.scene, self.problem = system_or_scene, None, None
            if params is None:
                raise ParameterError(f"give the parameter values of system {system_or_scene.name!r} (params=...)")
        else:   # a Problem, or a scene with values (which may carry their model: Scene.parameters)
            self.problem = problem(system_or_scene, params=params)
            self.scene, self.system, params = self.problem.scene, self.problem.system, dict(self.problem.values)
        self.phase = validate_value("phase", phase, 0.0, 1.0, high_open=True, long_name="sampling phase")
        self.max_events_per_period = max_events_per_period
        self.fp_type = fp_type
        self._period_given = period
        self._engine = ScalarEngine(self.system, tol, max_events_per_period=max_events_per_period, fp_type=fp_type)
        self._var_runs: dict = {}
        self._tol = validate_tol(tol)
        self._params = self.system.validate(params)
        self.set_params(**params)

    # ----- parameters ----------------------------------------------------------
    @property
    def params(self) -> dict:
        return self._params

    @property
    def tol(self) -> float:
        return self._tol

    @property
    def compile_seconds(self) -> float:
        """Seconds heyoka took to compile this map's scalar integrator (0: cached, or not needed yet)."""
        return self._engine.compile_seconds

    @property
    def _run(self):
        """The scalar engine's run with this map's parameters (compiled on first use only: a
        sweep on the batch engine never needs it)."""
        return self._engine.hybrid_run(self._params)

    def at(self, params: dict | None = None, *, phase: float | None = None) -> "StroboscopicMap":
        """This map at other parameter values (changes to its own) and/or another sampling ``phase``, as a new light
        value: it shares the compiled integrators (the engines and their runs) and leaves this map unchanged."""
        view = object.__new__(type(self))
        view.__dict__.update(self.__dict__)      # a shallow copy: the engines and their caches are shared
        if phase is not None:
            view.phase = validate_value("phase", phase, 0.0, 1.0, high_open=True, long_name="sampling phase")
        if params:
            view.set_params(**params)
        return view

    def set_params(self, **values) -> "StroboscopicMap":
        """Change parameter values (no recompilation); the period follows the declared clock."""
        self._params = self.system.validate(dict(self._params, **values))
        self.period = self.period_for(self._params)
        self.forcing_period_steps = self.forcing_period_for(self._params)
        return self

    def period_for(self, p: dict) -> float:
        """The sampling period T [s] under parameter values ``p``: ``period`` if given, else the
        system's declared clock (:meth:`~maps.hybrid.HybridSystem.strobe_period_of`)."""
        if self._period_given is not None:
            return validate_value("period", self._period_given, 0.0, math.inf, low_open=True, unit="s")
        T = self.system.strobe_period_of(p)
        if T is None:
            raise ParameterError(f"system {self.system.name!r} declares no clock (no periodic switch, forcing or "
                                 f"strobe_period): give the stroboscopic 'period' [s]")
        return T

    def forcing_period_for(self, p: dict) -> int:
        """q: the declared forcing repeats every q samples (0: never; 1 for a system that declares
        neither a forcing nor a switch)."""
        return self.system.forcing_q(p, self.period_for(p))

    def _rate(self, p: dict) -> float | None:
        """Samples per second when the period is the first switch's (exact switch instants), else None."""
        return self.system.strobe_rate(p) if self._period_given is None else None

    def sample_time(self, k: int, t0: float = 0.0) -> float:
        """t0 + (k + phase) T [s]; k / relay_hz exactly as the relay's switch instants when T = 1/relay_hz."""
        rate = self._rate(self.params)
        if rate is not None and self.phase == 0.0:
            return t0 + k / rate
        return t0 + (k + self.phase) * self.period

    def _job(self, params, y0, flags, k0, transient, record, t0=0.0, **kw) -> OrbitJob:
        T = self.period_for(params)
        rate = self._rate(params) if self.phase == 0.0 else None
        return OrbitJob(params, np.asarray(y0, dtype=float), flags, period=T, offset=t0 + self.phase * T,
                        rate=rate, k0=k0, transient=transient, record=record, **kw)

    # ----- iteration -------------------------------------------------------------
    def step(self, state, k: int = 0, t0: float = 0.0):
        """The state one period after ``state`` given at the k-th sample time t0 + (k + phase) T.

        ``state`` is a :class:`~maps.hybrid.HybridState` (returned as one, with the flags at
        the end) or a bare continuous state (returned bare; its mode from the system's rule).
        Raises :class:`~maps.hybrid.IntegrationFailure` (or Escaped, EventCap) if the step fails.
        """
        y, flags, hybrid = _split(state)
        run = self._run
        run.record_events = False
        run.reset(self.sample_time(k, t0), y, flags)
        run.advance(self.sample_time(k + 1, t0))
        return HybridState(run.y, dict(run.flags)) if hybrid else run.y

    def linearize(self, state, k: int = 0, *, params=(), t0: float = 0.0, n: int = 1,
                  until: float | None = None) -> MapLinearization:
        """``n`` steps (default one) from ``state`` at sample k with their exact derivatives
        (variational equations with saltation at every state event, :mod:`maps.variational`).

        Returns the next hybrid state, J = d(step)/dy (d x d), J_p = d(step)/d(params) (d x m,
        at a fixed sample index and start time), the numerical rank of J (deficient where a
        settle projection, e.g. a bar that sticks, collapses directions) and the step's
        signature (its events' roles in order).

        With respect to ``relay_hz`` the derivative is taken at a fixed sample index k, with all
        three effects: the start t_k = k/W and end t_{k+n} move, every relay switch n/(2W) moves,
        and so does the mains phase at the start (the forcing is in absolute time).

        ``until`` [s, absolute time, inside the first period]: stop there instead (the state and
        its derivatives at a fixed time, e.g. a grazing instant; not with ``relay_hz``).
        """
        y, flags, _ = _split(state)
        params = tuple(params)
        run = self._variational(params, y)
        run.reset(self.sample_time(k, t0), y, flags)
        n = int(validate_value("n", n, 1, 1e6))
        clock = self.system.strobe_parameter
        periodic = {} if self._rate(self.params) is not None else \
            {p: dT for p in params if (dT := self.period_derivative(p)) != 0.0}
        if periodic:       # the start t_k = t0 + (k + phase) T moves: d y(t1) / d t_k = -Phi f(t_k, y_k)
            d = run.derivatives
            f_start = d.rhs(self.sample_time(k, t0), np.asarray(y, float), d.pars(self.params, run.flags))
        if until is not None:
            if clock is not None and clock in params:
                raise ParameterError(f"linearize(until=...) takes no derivative with respect to {clock}")
            n, t1 = 1, validate_value("until", until, self.sample_time(k, t0), self.sample_time(k + 1, t0), unit="s")
            run.advance(t1)
        for j in range(1, n + 1 if until is None else 1):
            run.advance(self.sample_time(k + j, t0))
            run.budget.new_period()
        t1 = self.sample_time(k + n, t0) if until is None else t1
        moving = {} if self._rate(self.params) is None or clock not in params else \
            {clock: -(t1 - t0) / self.params[clock]}      # t_k = t0 + k / W
        if until is None:      # the end t_{k+n} = t0 + (k + n + phase) T moves with T
            moving.update({p: (k + n + self.phase) * dT for p, dT in periodic.items()})
        Y = run.end_time_term(t1, moving)
        n = Y.shape[0]
        J = Y[:, :n]
        for p, dT in periodic.items():
            Y[:, n + params.index(p)] -= J @ f_start * ((k + self.phase) * dT)
        signature = tuple(self.system.role_of(ev.name) for ev in run.events)
        events, run.events = tuple(run.events), []
        return MapLinearization(HybridState(run.y, dict(run.flags)), J, Y[:, n:], signature,
                                run.compile_seconds, events)

    def period_derivative(self, name: str) -> float:
        """dT/d``name`` [s per parameter unit] of the declared clock at the current values (0 when
        the period is given or does not depend on ``name``): a complex step of ``strobe_period``
        (exact for analytic formulas such as 2 pi / Omega), else a central difference."""
        if self._period_given is not None or name not in self.params:
            return 0.0
        cache = self.__dict__.setdefault("_dT", {})
        key = (name, tuple(sorted(self.params.items())))
        if key not in cache:
            cache.clear()
            cache[key] = _period_slope(self.system, self.params, name)
        return cache[key]

    def _variational(self, params: tuple, y):
        """This map's reusable VariationalRun with respect to the state and ``params`` (compiled
        once per parameter list; ``y``: a valid state to build it at), with the map's parameter
        values loaded and events recorded."""
        run = self._var_runs.get(params)
        if run is None:
            from .engines.scalar import VariationalRun
            run = self._var_runs[params] = VariationalRun(self.system, self.params, y, wrt=params, tol=self.tol, max_events=None,
                                                          max_events_per_period=self.max_events_per_period)
        elif run.params != self.params:
            run.set_params(**self.params)
        run.record_events = True
        return run

    def jacobian(self, state, k: int = 0, *, eps: float | None = None, t0: float = 0.0,
                 method: str = "exact") -> np.ndarray:
        """d(step)/dy (d x d) at the k-th sample.

        ``method="exact"``: from the variational equations with saltation (:meth:`linearize`).
        ``method="fd"``: central differences with steps ``eps`` (default 1e-6 |y_j|, >= 1e-9),
        a test oracle only: valid where no event is grazed within +-eps, and its accuracy
        depends on eps.  The mode of a :class:`~maps.hybrid.HybridState` is kept.
        """
        if method == "exact":
            return self.linearize(state, k, t0=t0).J
        if method != "fd":
            raise ParameterError(f"jacobian method {method!r}; allowed: exact, fd")
        return _central_differences(lambda s: _split(self.step(s, k, t0))[0], state, eps)

    def orbit(self, x0, n: int, *, transient: int = 0, t0: float = 0.0, flags: dict | None = None,
              tangent: bool = False) -> MapOrbit:
        """Start from ``x0`` at ``t0`` [s], discard the samples before k = ``transient``, record ``n`` steps.

        ``x0`` is a continuous state (mapping or array) or a :class:`~maps.hybrid.HybridState`;
        ``points[0]`` is the state at t0 + (transient + phase) T.  ``flags`` (e.g. the
        ``final_flags`` of a previous orbit) default to those of a HybridState, else to the
        system's rule.  Failures (escape, non-finite state, more than ``max_events_per_period``
        events in a period) end the orbit early with ``status`` set and never raise; arrays
        then hold only the completed steps.  ``tangent``: a tangent vector is integrated with the
        recorded window (:meth:`MapOrbit.tangent_stretch`).
        """
        n = int(validate_value("n", n, 1, 1e8))
        transient = int(validate_value("transient", transient, 0, 1e8))
        y0, given, _ = _split(x0)
        flags = flags if flags is not None else given
        y0 = self.system.state_vector(y0)
        job = self._job(self.params, y0, flags, 0, transient, n, t0, **self._recorded(tangent))
        res = self._engine.run([job])[0]
        return self._orbit_from(res, job)

    def orbits(self, overrides: list, x0, n, *, transient: int | list = 0, flags: dict | list | None = None,
               method: str = "auto", batch_size: int = 4, tangent: bool = False, k0: int | list = 0,
               tangent_start: list | None = None, events: bool = True) -> list[MapOrbit]:
        """One orbit per parameter set: ``overrides[i]`` (a dict) changes this map's parameters.

        Every orbit starts from ``x0`` (a state, or a list of one state per set) at sample ``k0``
        (an int, or one per set; t = the k0-th sample time), as :meth:`orbit`, and records ``n``
        steps (an int, or a list of one per set).  ``flags``: the start mode (a dict, or one per
        set; None: the system's rule or the hybrid states' own flags).  ``method``:
        "batch" (heyoka batch mode, ``batch_size`` SIMD lanes: the transient without stops at
        observation-only guards, then the recorded window with them), "scalar" (one after the
        other), "auto" (batch where the engine supports the system).  Results agree to
        round-off, amplified by chaotic dynamics.  ``tangent``: a tangent vector is integrated
        with each recorded window from :func:`maps.tangent.start_direction`, or from
        ``tangent_start[i]`` (a unit vector, to continue one) (:meth:`MapOrbit.tangent_stretch`).
        ``events=False`` (batch, no tangent): the strobe points only, as a transient runs (no stops at
        observation-only guards, no event log: impact counts and clearances are empty), the fastest ensemble.
        """
        m_sets = len(overrides)
        per_set = lambda v, name: v if isinstance(v, (list, tuple)) else [v] * m_sets  # noqa: E731
        lengths, starts_k, transients = per_set(n, "n"), per_set(k0, "k0"), per_set(transient, "transient")
        if not len(lengths) == len(starts_k) == len(transients) == m_sets:
            raise ParameterError(f"n, k0 and transient: one per parameter set ({m_sets}), got {len(lengths)}, "
                                 f"{len(starts_k)} and {len(transients)}")
        lengths = [int(validate_value("n", m, 1, 1e8)) for m in lengths]
        starts_k = [int(validate_value("k0", k, 0, 1e12)) for k in starts_k]
        transients = [int(validate_value("transient", t, 0, 1e8)) for t in transients]
        params = [self.system.validate(dict(self.params, **o)) for o in overrides]
        starts = x0 if isinstance(x0, list) else [x0] * len(params)
        modes = flags if isinstance(flags, list) else [flags] * len(params)
        jobs, recorded = [], self._recorded(tangent)
        for i, (p, s, m, k, tr) in enumerate(zip(params, starts, lengths, starts_k, transients)):
            y, given, _ = _split(s)
            kw = dict(recorded, tangent=np.asarray(tangent_start[i], dtype=float)) \
                if tangent and tangent_start is not None else recorded
            jobs.append(self._job(p, self.system.state_vector(y), modes[i] if modes[i] is not None else given,
                                  k, tr, m, **kw))
        method = self._method(method, batch_size)
        clock = _time.perf_counter()
        if method == "scalar":
            results = self._engine.run(jobs)
        else:
            full = self._batch_engine(batch_size, observations=True, tangent=tangent)
            if not events and not tangent:
                full, jobs = self._batch_engine(batch_size, observations=False), [replace(j, log=False) for j in jobs]
            if any(transients):
                first = self._batch_engine(batch_size, observations=False).run([replace(j, record=0, log=False) for j in jobs])
                second = full.run([replace(j, y0=r.final_state, flags=r.final_flags, k0=j.k0 + j.transient, transient=0)
                                   for j, r in zip(jobs, first)])
                results = []
                for pre, r in zip(first, second):
                    if pre.status != "ok":          # ended in the transient: nothing recorded
                        results.append(pre)
                    else:               # counts of the whole job, as the scalar engine's
                        r.n_steps += pre.n_steps
                        r.n_events += pre.n_events
                        r.n_switches += pre.n_switches
                        results.append(r)
            else:
                results = full.run(jobs)
        share = (_time.perf_counter() - clock) / max(1, len(jobs))
        out = []
        for job, r in zip(jobs, results):
            o = self._orbit_from(r, job)
            o.run_seconds = share
            out.append(o)
        return out

    def stretch(self, references: list, overrides: list, *, k0: list, scales: list, d0: float = 1e-8,
                method: str = "auto", batch_size: int = 4) -> list[np.ndarray]:
        """Tangent growth along recorded orbits (Benettin's companion, :mod:`maps.tangent`).

        ``references[i]`` are ``m + 1`` states of an orbit under ``overrides[i]``, the first at
        sample ``k0[i]``.  A companion starts ``d0`` from the first (norm scaled by
        ``scales[i]``), mode by the system's rule, and after each step is moved back to ``d0``
        from the next; returned: the log stretch of each step (NaN where it failed).
        A shift-invariant system (``system.translation``) is measured in its reduced coordinates
        (:mod:`maps.translation`): the neutral shift is removed at every renormalisation.
        """
        from .tangent import companion_start
        method = self._method(method, batch_size)
        shift = translation_basis(self.system)      # shift-invariant: the reduced coordinates' distance
        jobs = []
        for ref, o, k, s in zip(references, overrides, k0, scales):
            p = self.system.validate(dict(self.params, **o))
            z0 = companion_start(ref[0], d0, s, shift)
            jobs.append(self._job(p, z0, None, int(k), 0, len(ref) - 1, reference=list(ref), d0=d0, scale=s,
                                  shift=shift))
        if method == "scalar":
            results = self._engine.run(jobs)
        else:
            results = self._batch_engine(batch_size, observations=False).run(jobs)
        out = []
        for job, r in zip(jobs, results):
            st = np.full(job.record, np.nan)
            st[:len(r.stretch)] = r.stretch
            out.append(st)
        return out

    def _recorded(self, tangent: bool) -> dict:
        """The job keywords of a recorded orbit: its event log, the soil's holding mode timed
        (:func:`maps.progression.held_mode`) and, with ``tangent``, a tangent vector's start direction
        (:func:`maps.tangent.start_direction`) and the translation removed from it."""
        kw = dict(log=True, timed=held_mode(self.system))
        if tangent:
            from .tangent import start_direction
            shift = translation_basis(self.system)
            kw.update(tangent=start_direction(len(self.system.states), shift), shift=shift)
        return kw

    def _batch_engine(self, batch_size: int, observations: bool, tangent: bool = False):
        """The process-wide batch engine for this system, tolerance and event cap (compiled once)."""
        return engine_for(self.system, self.tol, "batch", observations=observations, batch_size=batch_size,
                          max_events_per_period=self.max_events_per_period, tangent=tangent)

    def _method(self, method, batch_size) -> str:
        if method not in ("auto", "batch", "scalar"):
            raise ParameterError(f"method {method!r}; allowed: auto, batch, scalar")
        batchable = unsupported(self.system) is None and self.fp_type is float
        if method == "batch" and not batchable:
            raise ParameterError(unsupported(self.system) or "the batch engine runs in double precision only")
        if method == "auto":
            return "batch" if batchable and batch_size > 1 else "scalar"
        return method

    def _orbit_from(self, r, job) -> MapOrbit:
        points, times, flags = r.points, r.times, r.flags
        if not len(points):     # failed before the first sample
            points = [np.asarray(job.y0, dtype=float)]
            times = [job.sample_time(job.k0)]
            flags = [r.final_flags or {}]
        names = self.system.flag_names
        point_flags = r.point_flags if r.point_flags is not None and len(r.points) else \
            np.array([[fl.get(f, np.nan) for f in names] for fl in flags], dtype=float)
        W = self.system.strobe_rate(job.params) or 1.0 / job.period
        extra = {} if job.tangent is None else dict(tangent_start=np.asarray(job.tangent, dtype=float),
                                                      tangent=np.array(r.tangent).reshape(-1, len(job.y0)),
                                                      tangent_shift=job.shift)
        if r.mode_time:
            extra["mode_time"] = np.asarray(r.mode_time, dtype=float)
        return orbit_from_periods(self.system, job.params, W, times, points, r.period_events, **extra,
                                  status=r.status, failure=r.failure, failure_time=r.failure_time,
                                  n_steps=r.n_steps, run_seconds=r.seconds, final_state=r.final_state,
                                  final_flags=dict(r.final_flags), flag_names=names, point_flags=point_flags)


def _no_events() -> dict:
    """The impact log of a window without guard crossings: :func:`maps.impacts.impact_log` of none."""
    f, i = np.zeros(0), np.zeros(0, dtype=np.int64)
    return {"time": f, "velocity": f.copy(), "penetration": f.copy(), "duration": f.copy(), "event": i,
            "flight_time": f.copy(), "flight_gap": f.copy(), "flight_event": i.copy(), "event_gap": f.copy(),
            "event_role": []}


def orbit_from_periods(system, params, W, times, points, period_events, **fields) -> MapOrbit:
    """A :class:`MapOrbit` from the sampled states and each period's guard crossings.

    ``period_events[k]`` lists ``(event name, t [s], state at the crossing)`` between
    ``times[k]`` and ``times[k+1]``; events are read by their role (impact, flight_minimum,
    deepest, release), never by name.  ``W`` [Hz] gives the relay phase of each onset.
    ``fields`` are MapOrbit's remaining fields (status, n_steps, final_state, ...).
    """
    gap = system.gap if system.gap is not None else (lambda y, p, t=0.0: (math.nan, math.nan))
    step_of = [k for k, events in enumerate(period_events) for _ in events]
    log = impact_log(system, params, ((name, t, y) for events in period_events for name, t, y in events)) \
        if step_of else _no_events()
    n = len(period_events)
    imp_step = np.array(step_of, dtype=np.int64)[log["event"]] if step_of else np.zeros(0, np.int64)
    imp_n = np.bincount(imp_step, minlength=n)
    ends = np.array([gap(y, params, t)[0] for y, t in zip(points[:n + 1], times[:n + 1])], dtype=float)
    min_clearance = np.minimum(ends[:-1], ends[1:]) if n else np.zeros(0)
    min_flight, min_speed = np.full(n, math.inf), np.full(n, math.inf)
    for k, g in zip(step_of, log["event_gap"]):       # impacts (0 at the onset), flight minima, deepest points
        if g == g:
            min_clearance[k] = min(min_clearance[k], g)
    for i, g in zip(log["flight_event"], log["flight_gap"]):
        min_flight[step_of[i]] = min(min_flight[step_of[i]], g)
    for k, rate in zip(imp_step, log["velocity"]):
        min_speed[k] = min(min_speed[k], abs(rate))
    signature, roles = [], iter(log["event_role"])
    for events in period_events:
        signature.append(tuple(next(roles) for _ in events))
    it = log["time"]
    return MapOrbit(
        times=np.array(times), points=np.array(points), impacts_per_step=imp_n.astype(np.int64),
        min_clearance_per_step=min_clearance, min_impact_speed_per_step=min_speed,
        impact_time=it, impact_velocity=log["velocity"], impact_phase=(it * W) % 1.0,
        impact_penetration=log["penetration"], impact_duration=log["duration"],
        min_flight_clearance_per_step=min_flight, signature=signature, **fields)


class ImpactMap:
    """The impact map: (relay phase, impact velocity) at each contact onset.

    >>> imap = ImpactMap("thesis-1dof", params)
    >>> phase, velocity, t = imap.iterate(x0, n_impacts=50, transient_periods=300)

    The phase is t * relay_hz mod 1 (for a system without a relay: t / period mod 1).
    """

    def __init__(self, system_or_scene, params: dict, *, tol: float = 1e-12, period: float | None = None,
                 fp_type=float):
        self.stroboscopic = StroboscopicMap(system_or_scene, params, tol=tol, period=period, fp_type=fp_type)

    def _to_impact(self, run, state, t0: float, max_periods: float):
        """Advance ``run`` from ``state`` at ``t0`` [s] to just after the next impact's transition."""
        y, flags, _ = _split(state)
        run.reset(t0, y, flags)
        run.advance(t0 + max_periods * self.stroboscopic.period, stop_roles=("impact",))
        if run.stopped_by is None:
            raise IntegrationFailure(f"no impact within {max_periods:g} periods of t0 = {t0:.9g} s", run.t, run.y)
        return run

    def step(self, state, t0: float = 0.0, *, max_periods: float = 1000) -> tuple[float, HybridState]:
        """(t [s], hybrid state just after the transition) of the next impact from ``state`` at ``t0``.
        Raises :class:`~maps.hybrid.IntegrationFailure` when none comes within ``max_periods`` periods."""
        run = self.stroboscopic._run
        run.record_events = False
        run = self._to_impact(run, state, t0, max_periods)
        return run.t, HybridState(run.y, dict(run.flags))

    def linearize(self, state, t0: float = 0.0, *, max_periods: float = 1000) -> ImpactLinearization:
        """The next impact from ``state`` at ``t0`` [s] with its exact Jacobian: the flow's
        sensitivities Phi (variational equations, saltation at the events on the way), projected
        onto the impact section g = 0 whose hitting time moves with y0, then the impact's transition:

            J = R_y (I - f- grad(g)^T / (grad(g) . f- + dg/dt)) Phi + R_t dt/dy0 = Y+ + f+ dt/dy0,

        Y+ the saltation-updated sensitivities compared at the impact instant (the state then
        moves with f+ while the end follows the impact), dt/dy0 = -grad(g) Phi / (grad(g) . f- + dg/dt).
        A grazing impact (denominator 0) has no Jacobian: ZeroDivisionError."""
        s = self.stroboscopic
        y, _, _ = _split(state)
        run = self._to_impact(s._variational((), y), state, t0, max_periods)
        n = len(s.system.states)
        d = run.derivatives
        f_plus = d.rhs(run.t, run.y, d.pars(run.params, run.flags))
        dt = run.event_time_row[:n]
        J = run.sensitivities[:, :n] + np.outer(f_plus, dt)
        signature = tuple(s.system.role_of(ev.name) for ev in run.events)
        run.events = []
        return ImpactLinearization(run.t, HybridState(run.y, dict(run.flags)), J, dt, signature,
                                   run.compile_seconds)

    def jacobian(self, state, t0: float = 0.0, *, method: str = "exact", eps: float | None = None,
                 max_periods: float = 1000) -> np.ndarray:
        """d(state just after the next impact)/dy0 (d x d) from ``state`` at ``t0`` [s]:
        ``method="exact"`` (:meth:`linearize`) or "fd", central differences with steps ``eps``
        (default 1e-6 |y_j|, >= 1e-9), a test oracle only."""
        if method == "exact":
            return self.linearize(state, t0, max_periods=max_periods).J
        if method != "fd":
            raise ParameterError(f"jacobian method {method!r}; allowed: exact, fd")
        return _central_differences(lambda s: self.step(s, t0, max_periods=max_periods)[1].y, state, eps)

    def iterate(self, x0, n_impacts: int, transient_periods: int = 0, *, max_periods: int = 100_000,
                chunk: int = 20):
        """Arrays (phase in [0, 1), velocity [m/s], time [s]) of the next ``n_impacts`` onsets
        after ``transient_periods`` periods; fewer if ``max_periods`` pass without them or the
        run fails (then ``self.status`` says why)."""
        n_impacts = int(validate_value("n_impacts", n_impacts, 1, 1e8))
        s = self.stroboscopic  # phase 0: samples at t = k T
        phases, vels, times = [], [], []
        o = s.orbit(x0, chunk, transient=transient_periods)
        k = transient_periods
        while True:
            phases.extend(o.impact_phase)
            vels.extend(o.impact_velocity)
            times.extend(o.impact_time)
            self.status = o.status
            k += o.n
            if o.status != "ok" or len(times) >= n_impacts or k >= transient_periods + max_periods:
                break
            # continue from the end of this chunk, the state at t = k T
            o = s.orbit(o.final_state, chunk, t0=k * s.period, flags=o.final_flags)
        m = min(n_impacts, len(times))
        return np.array(phases[:m]), np.array(vels[:m]), np.array(times[:m])
