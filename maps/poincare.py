"""Poincare maps of hybrid systems: the stroboscopic map and the impact map.

The stroboscopic map samples the state at t_k = t0 + (k + phase) * T, T the
relay period 1/relay_hz (or a given period).  For the electro-vibro-impact
model the forcing P(t) V sin(2 pi f_mains t) repeats after T only when
f_mains/relay_hz is an integer; otherwise the map is not autonomous and its
forcing repeats after ``forcing_period_steps`` = q steps (q f_mains / relay_hz
integral).  A periodic orbit's period is then a multiple of q.
"""
from __future__ import annotations

import math
import time as _time
from dataclasses import dataclass, field

import numpy as np

from .hybrid import Escaped, HybridRun, HybridSystem, IntegrationFailure
from .parameters import ParameterError, validate_value

__all__ = ["StroboscopicMap", "MapOrbit", "ImpactMap", "forcing_period_steps", "orbit_from_periods"]


def forcing_period_steps(f_mains: float, relay_hz: float | None, max_steps: int = 1000,
                         period: float | None = None) -> int:
    """Smallest q <= max_steps after which the relay-switched mains forcing repeats, else 0.

    The forcing P(t) V sin(2 pi f_mains t) has period 1/relay_hz in P and 1/f_mains in
    the sine; sampled every ``period`` [s] (default 1/relay_hz) it repeats after q
    samples when q*period*f_mains and q*period*relay_hz are both integers (to 1e-9).
    0 means incommensurate within ``max_steps``: the map is not autonomous at all.
    Without a relay (``relay_hz`` None) only the mains period counts.
    """
    T = 1.0 / relay_hz if period is None else float(period)
    ratios = (T * f_mains,) if relay_hz is None else (T * f_mains, T * relay_hz)
    for q in range(1, max_steps + 1):
        if all(abs(q * r - round(q * r)) <= 1e-9 * max(1.0, q * r) for r in ratios):
            return q
    return 0


@dataclass
class MapOrbit:
    """Recorded iterates of a stroboscopic map and what happened between them.

    ``points[k]`` is the state at ``times[k]``; step k runs from ``times[k]`` to
    ``times[k+1]``.  Gaps are distances to the stop [m] (negative: penetration).
    ``min_gap_per_step`` is the smallest of the gaps at the step's ends, at its
    free-flight minima (guard "lowest") and, in contact, minus the deepest
    penetration: never NaN.  ``min_flight_gap_per_step`` keeps only the free-flight
    minima (inf where the step has none): it reaches 0 where a new impact is born
    (a grazing bifurcation), which the total ``min_gap`` does not show on an
    impacting orbit.
    """

    times: np.ndarray                 # (n+1,) [s]
    points: np.ndarray                # (n+1, d)
    impacts_per_step: np.ndarray      # (n,) contacts in (t_k, t_k+1]
    min_gap_per_step: np.ndarray      # (n,) [m] smallest gap in each step
    min_impact_speed_per_step: np.ndarray  # (n,) [m/s], inf where no contact
    impact_t: np.ndarray              # [s] contact onsets in the recorded window
    impact_velocity: np.ndarray       # [m/s] gap rate at onset (< 0)
    impact_phase: np.ndarray          # relay phase of each onset, in [0, 1)
    impact_penetration: np.ndarray    # [m] maximum penetration of each contact (>= 0)
    impact_duration: np.ndarray       # [s] contact duration (NaN: still in contact at the end)
    min_flight_gap_per_step: np.ndarray  # (n,) [m] lowest free-flight minimum per step, inf if none
    status: str = "ok"                # ok, escaped, failed
    failure: str = ""
    failure_time: float = math.nan
    n_steps: int = 0                  # Taylor steps
    run_seconds: float = 0.0
    final_state: np.ndarray | None = None
    final_flags: dict = field(default_factory=dict)

    @property
    def n(self) -> int:
        return len(self.impacts_per_step)


class StroboscopicMap:
    """The state sampled once per period T of a scene or hybrid system.

    >>> smap = StroboscopicMap("thesis-1dof", params)          # T = 1/relay_hz
    >>> orbit = smap.orbit(x0, n=100, transient=300)
    >>> y1 = smap.step(y0, k=0)                                # one period from t = phase*T

    The period T is ``period`` if given, else 1/relay_hz, else the system's
    ``strobe_period(params)`` (e.g. 2 pi / Omega for a harmonically forced system).
    """

    def __init__(self, system_or_scene, params: dict, *, period: float | None = None, phase: float = 0.0,
                 tol: float = 1e-12, fp_type=float, max_events_per_period: int = 10_000):
        if isinstance(system_or_scene, HybridSystem):
            self.system, self.scene = system_or_scene, None
        else:
            from .scenes import get_scene
            self.scene = get_scene(system_or_scene)
            self.system = self.scene.system
        self.phase = validate_value("phase", phase, 0.0, 1.0, high_open=True, long_name="sampling phase")
        self.max_events_per_period = max_events_per_period
        self._period_given = period
        self._run = HybridRun(self.system, params, np.zeros(len(self.system.states)), tol=tol,
                              fp_type=fp_type, max_events=None)
        self.set_params(**params)

    # ----- parameters ----------------------------------------------------------
    @property
    def params(self) -> dict:
        return self._run.params

    @property
    def tol(self) -> float:
        return self._run.tol

    def set_params(self, **values) -> "StroboscopicMap":
        """Change parameter values (no recompilation); the period follows relay_hz."""
        self._run.set_params(**values)
        p = self._run.params
        if self._period_given is not None:
            self.period = validate_value("period", self._period_given, 0.0, math.inf, low_open=True, unit="s")
        elif "relay_hz" in p:
            self.period = 1.0 / p["relay_hz"]
        elif getattr(self.system, "strobe_period", None) is not None:
            self.period = float(self.system.strobe_period(p))
        else:
            raise ParameterError("this system has no 'relay_hz' nor a strobe_period(params): "
                                 "give the stroboscopic 'period' [s]")
        # q: the forcing repeats every q samples (0: never).  A system without a mains
        # parameter is taken to be forced with the sampling period (q = 1).
        self.forcing_period_steps = (forcing_period_steps(p["f_mains"], p.get("relay_hz"), period=self.period)
                                     if "f_mains" in p else 1)
        return self

    def sample_time(self, k: int, t0: float = 0.0) -> float:
        return t0 + (k + self.phase) * self.period

    def _flags_for(self, y, t) -> dict | None:
        """Flags consistent with a state given at time t: in contact if it starts inside the stop."""
        if "contact" in self.system.flag_names:
            return {"contact": 1.0 if self.system.gap(np.asarray(y, float), self.params)[0] < 0 else 0.0}
        return None

    # ----- iteration -------------------------------------------------------------
    def step(self, y, k: int = 0, t0: float = 0.0) -> np.ndarray:
        """The state one period after ``y`` given at the k-th sample time t0 + (k + phase) T.

        The relay flag follows that time; the contact flag is inferred from the gap.
        """
        run = self._run
        ta = self.sample_time(k, t0)
        run.record_events = False
        run.max_events = self.max_events_per_period
        run.reset(ta, y, self._flags_for(y, ta))
        run.advance(self.sample_time(k + 1, t0))
        return run.y

    def jacobian(self, y, k: int = 0, *, eps: float | None = None, t0: float = 0.0) -> np.ndarray:
        """d(step)/dy by central differences (d x d), steps ``eps`` (default 1e-6 |y_j|, >= 1e-9).

        A placeholder for the variational Jacobian with saltation matrices at every
        contact and relay event; valid only where no event is grazed within +-eps.
        """
        y = np.asarray(y, dtype=float)
        d = y.size
        J = np.empty((d, d))
        for j in range(d):
            h = eps if eps is not None else 1e-6 * max(1e-3, abs(y[j]))
            e = np.zeros(d)
            e[j] = h
            J[:, j] = (self.step(y + e, k, t0) - self.step(y - e, k, t0)) / (2 * h)
        return J

    def orbit(self, x0, n: int, *, transient: int = 0, t0: float = 0.0, flags: dict | None = None) -> MapOrbit:
        """Start from ``x0`` at ``t0`` [s], discard the samples before k = ``transient``, record ``n`` steps.

        ``points[0]`` is the state at t0 + (transient + phase) T.  ``flags`` (e.g. the
        ``final_flags`` of a previous orbit) default to those consistent with ``x0``.
        Failures (escape, non-finite state, more than ``max_events_per_period`` events
        in a period) end the orbit early with ``status`` set and never raise; arrays
        then hold only the completed steps.
        """
        n = int(validate_value("n", n, 1, 1e8))
        transient = int(validate_value("transient", transient, 0, 1e8))
        run = self._run
        params = self.params
        clock = _time.perf_counter()
        run.record_events = False
        run.max_events = self.max_events_per_period * max(1, transient)
        run.reset(t0, x0, flags if flags is not None else self._flags_for(self.system.state_vector(x0), t0))
        times, points, period_events = [], [], []
        status, failure, t_fail = "ok", "", math.nan
        try:
            run.advance(self.sample_time(transient, t0))
            times.append(run.t)
            points.append(run.y)
            run.record_events = True
            for k in range(transient, transient + n):
                run.events = []
                run.max_events = run.n_events + self.max_events_per_period
                run.advance(self.sample_time(k + 1, t0))
                times.append(run.t)
                points.append(run.y)
                period_events.append([(ev.name, ev.t, ev.y_minus) for ev in run.events])
        except Escaped as exc:
            status, failure, t_fail = "escaped", str(exc), exc.t
        except IntegrationFailure as exc:
            status, failure, t_fail = "failed", str(exc), exc.t
        run.events = []
        if not points:
            points, times = [np.asarray(self.system.state_vector(x0), float)], [t0]
        return orbit_from_periods(self.system, params, params.get("relay_hz", 1.0 / self.period), times, points, period_events,
                                  status=status, failure=failure, failure_time=t_fail, n_steps=run.n_steps,
                                  run_seconds=_time.perf_counter() - clock, final_state=run.y,
                                  final_flags=dict(run.flags))


def orbit_from_periods(system, params, W, times, points, period_events, **fields) -> MapOrbit:
    """A :class:`MapOrbit` from the sampled states and each period's guard crossings.

    ``period_events[k]`` lists ``(guard name, t [s], state at the crossing)`` between
    ``times[k]`` and ``times[k+1]``; ``W`` [Hz] gives the relay phase of each onset.
    ``fields`` are MapOrbit's remaining fields (status, n_steps, final_state, ...).
    """
    gap = system.gap
    imp_n, min_gap, min_flight, min_speed = [], [], [], []
    it, iv, iph, ipen, idur = [], [], [], [], []
    g_prev = gap(points[0], params)[0]
    for k, events in enumerate(period_events):
        g_end = gap(points[k + 1], params)[0]
        g_lo, g_flight = min(g_prev, g_end), math.inf
        count, speed = 0, math.inf
        for name, t, y in events:
            if name == "contact":
                g, rate = gap(y, params)
                count += 1
                speed = min(speed, abs(rate))
                it.append(t)
                iv.append(rate)
                iph.append((t * W) % 1.0)
                ipen.append(max(0.0, -g))
                idur.append(math.nan)
            elif name == "lowest":
                g = gap(y, params)[0]
                g_lo, g_flight = min(g_lo, g), min(g_flight, g)
            elif name == "deepest":
                g = gap(y, params)[0]
                g_lo = min(g_lo, g)
                if ipen:
                    ipen[-1] = max(ipen[-1], -g)
            elif name == "release" and idur and math.isnan(idur[-1]):
                idur[-1] = t - it[-1]
        imp_n.append(count)
        min_gap.append(g_lo)
        min_flight.append(g_flight)
        min_speed.append(speed)
        g_prev = g_end
    return MapOrbit(
        times=np.array(times), points=np.array(points), impacts_per_step=np.array(imp_n, dtype=np.int64),
        min_gap_per_step=np.array(min_gap), min_impact_speed_per_step=np.array(min_speed),
        impact_t=np.array(it), impact_velocity=np.array(iv), impact_phase=np.array(iph),
        impact_penetration=np.array(ipen), impact_duration=np.array(idur),
        min_flight_gap_per_step=np.array(min_flight), **fields)


class ImpactMap:
    """The impact map: (relay phase, impact velocity) at each contact onset.

    >>> imap = ImpactMap("thesis-1dof", params)
    >>> phase, velocity, t = imap.iterate(x0, n_impacts=50, transient_periods=300)

    The phase is t * relay_hz mod 1 (for a system without a relay: t / period mod 1).
    """

    def __init__(self, system_or_scene, params: dict, *, tol: float = 1e-12, period: float | None = None,
                 fp_type=float):
        self.stroboscopic = StroboscopicMap(system_or_scene, params, tol=tol, period=period, fp_type=fp_type)

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
            times.extend(o.impact_t)
            self.status = o.status
            k += o.n
            if o.status != "ok" or len(times) >= n_impacts or k >= transient_periods + max_periods:
                break
            # continue from the end of this chunk, the state at t = k T
            o = s.orbit(o.final_state, chunk, t0=k * s.period, flags=o.final_flags)
        m = min(n_impacts, len(times))
        return np.array(phases[:m]), np.array(vels[:m]), np.array(times[:m])
