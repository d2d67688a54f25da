"""Independent baselines for the 1-DOF scene: scipy ``solve_ivp`` and the thesis' RK4.

The right-hand side here is written again from docs/model.md section 1 in plain
Python floats (no heyoka): the thesis circuit (eq 4.16), physical AC sign, SSR
relay.  Every baseline integrates the same hybrid problem as the toolkit:

- relay switches at t = n / (2 W), computed exactly as the engine does
  (:meth:`maps.hybrid.PeriodicSwitch.instants`), so every method solves the
  same problem down to the last bit of the switch instants;
- contact onset (x = e, downward, while free) and release (x = e, upward,
  while in contact) switch the right-hand side; each integration segment is
  smooth and ends at an event or a relay switch.

:func:`solve_scipy` restarts ``solve_ivp`` at every event and switch with a
terminal event; :func:`solve_rk4_bisection` is the thesis' approach (listings
C.7, C.8, C.13): fixed-step RK4 and bisection on the crossing time.
Each returns a :class:`BaselineResult` (final state, impact times, run time).
"""
from __future__ import annotations

import math
import time as _time
from dataclasses import dataclass, field

import numpy as np

from maps.hybrid import PeriodicSwitch
from maps.parameters import ParameterError

SCIPY_METHODS = ("DOP853", "RK45", "Radau", "LSODA")
_RELAY = PeriodicSwitch("P", "relay_hz")


@dataclass
class BaselineResult:
    """Outcome of one baseline run."""

    method: str
    tol: float                      # rtol = atol for scipy; the step h [s] for RK4
    y: np.ndarray                   # final state (x, v, i, z) [m, m/s, A, A/s]
    impact_times: np.ndarray        # contact onset times [s]
    run_seconds: float              # wall time of the integration [s]
    n_rhs: int = 0                  # right-hand side evaluations
    status: str = "ok"
    extra: dict = field(default_factory=dict)

    @property
    def n_impacts(self) -> int:
        return int(self.impact_times.size)


#: what the baselines implement: option -> allowed values (thesis-1dof, thesis circuit, no optional element)
SUPPORTED = {"dof": (1,), "dc": (True,), "ac": (True,), "stop": (True,), "relay": ("ssr",), "circuit": ("thesis",),
             "ac_sign": ("physical",), "energy": (False,), "dc_law": ("listing", "fit", "catalogue"),
             "air_damping": (False,), "rear_stop": (False,), "dc_delay": (False,)}


def check_supported(scene):
    """Raise :class:`~maps.ParameterError` unless the scene is a model the baselines implement
    (:data:`SUPPORTED`), naming the options that differ."""
    o = scene.options
    if o is None:
        raise ParameterError(f"the baselines implement only thesis-1dof; scene {scene.name!r} is not a thesis model")
    off = [f"{k}={getattr(o, k)!r} (allowed: {', '.join(map(str, v))})" for k, v in SUPPORTED.items()
           if getattr(o, k) not in v]
    if off:
        raise ParameterError(f"the baselines do not implement scene {scene.name!r} with {'; '.join(off)}")


def _dc_force(p: dict, dc_law: str):
    """F_dc(xa) [N] minus the weight where the law does not carry it (the cubics' + m g cancels it)."""
    s_dc = p["dc_scale"]
    if dc_law == "catalogue":
        F, u, w, mg = p["F_dc_sat"], p["u_dc"], 2.0 * p["s_dc"], p["m"] * p["g"]
        return lambda xa: -0.5 * s_dc * F * (math.tanh((xa - u) / w) + math.tanh((xa + u) / w)) - mg
    sl = 1.0 if dc_law == "listing" else -1.0     # the fit flips the signs of a2 and a1
    a1, a2, a3 = p["a1"], p["a2"], p["a3"]
    return lambda xa: s_dc * (-a3 * xa * xa * xa + sl * a2 * xa * xa - sl * a1 * xa)


def rhs_1dof(p: dict, dc_law: str = "listing"):
    """``f(t, y, relay, contact) -> [dx, dv, di, dz]`` for the 1-DOF thesis model (floats);
    ``dc_law`` "listing" (C.9), "fit" (eqs 4.6-4.7) or "catalogue" (two tanh steps, the weight acting)."""
    dc_force = _dc_force(p, dc_law)
    m, k, c, e = p["m"], p["k"], p["c"], p["e"]
    d_dc = p["d_dc"]
    R, C, V, d_ac, L0, A, B = p["R"], p["C"], p["V"], p["d_ac"], p["L0"], p["A"], p["B"]
    w = 2.0 * math.pi * p["f_mains"]
    norm = A / (B * math.sqrt(math.pi / 2.0))
    exp, cos = math.exp, math.cos

    def f(t, y, relay, contact):
        x, v, i, z = y[0], y[1], y[2], y[3]
        xa = x - d_dc
        F_dc = dc_force(xa)
        xb = x + d_ac
        gauss = exp(-2.0 * (xb / B) ** 2)
        L = L0 + norm * gauss
        dL = -4.0 * norm * xb / (B * B) * gauss
        ddL = -4.0 * norm / (B * B) * (1.0 - 4.0 * xb * xb / (B * B)) * gauss
        F_ac = 0.5 * dL * i * i
        F_c = -k * (x - e) - c * v if contact else 0.0
        acc = (F_dc + F_ac + F_c) / m
        du = relay * V * w * cos(w * t)
        dz = (du - (R + 2.0 * dL * v) * z - (1.0 / C + ddL * v * v + dL * acc) * i) / L
        return [v, acc, z, dz]

    return f


def _switch_times(freq, t0, t_end):
    """Relay switch instants in (t0, t_end) and the relay value after each."""
    n = _RELAY.index_at(t0, freq) + 1
    out = []
    while True:
        ts = _RELAY.instants(freq, n)
        if ts >= t_end:
            return out
        out.append((ts, _RELAY.value_for_index(n)))
        n += 1


def solve_scipy(params: dict, y0, t_end: float, method: str = "DOP853", tol: float = 1e-10,
                t0: float = 0.0, dc_law: str = "listing") -> BaselineResult:
    """``scipy.integrate.solve_ivp`` with terminal contact events, restarted at each event
    and relay switch; ``rtol = atol = tol``."""
    from scipy.integrate import solve_ivp
    if method not in SCIPY_METHODS:
        raise ParameterError(f"method {method!r}; allowed: {', '.join(SCIPY_METHODS)}")
    f = rhs_1dof(params, dc_law)
    e = params["e"]
    y = np.array(y0, dtype=float)
    contact = 1.0 if y[0] < e else 0.0
    relay = _RELAY.value_for_index(_RELAY.index_at(t0, params["relay_hz"]))
    impacts, nfev = [], 0

    def gap(t, y, relay, contact):
        return y[0] - e

    start = _time.perf_counter()
    t = t0
    status = "ok"
    for t_stop, relay_next in _switch_times(params["relay_hz"], t0, t_end) + [(t_end, None)]:
        while t < t_stop:
            gap.terminal = True
            gap.direction = 1.0 if contact else -1.0
            sol = solve_ivp(f, (t, t_stop), y, method=method, rtol=tol, atol=tol, events=gap,
                            args=(relay, contact))
            nfev += sol.nfev
            if sol.status < 0:
                status = "failed"
                break
            if sol.status == 1 and sol.t_events[0].size:
                t, y = float(sol.t_events[0][0]), np.array(sol.y_events[0][0])
                if not contact:
                    impacts.append(t)
                contact = 0.0 if contact else 1.0
            else:
                t, y = t_stop, sol.y[:, -1].copy()
        if status != "ok":
            break
        if relay_next is not None:
            relay = relay_next
    seconds = _time.perf_counter() - start
    return BaselineResult(f"scipy-{method}", tol, y, np.array(impacts), seconds, nfev, status)


def _rk4_step(f, t, y, h, relay, contact):
    k1 = f(t, y, relay, contact)
    y2 = [a + 0.5 * h * b for a, b in zip(y, k1)]
    k2 = f(t + 0.5 * h, y2, relay, contact)
    y3 = [a + 0.5 * h * b for a, b in zip(y, k2)]
    k3 = f(t + 0.5 * h, y3, relay, contact)
    y4 = [a + h * b for a, b in zip(y, k3)]
    k4 = f(t + h, y4, relay, contact)
    return [a + h / 6.0 * (b1 + 2.0 * b2 + 2.0 * b3 + b4) for a, b1, b2, b3, b4 in zip(y, k1, k2, k3, k4)]


def solve_rk4_bisection(params: dict, y0, t_end: float, h: float = 1e-4, delta: float = 1e-14,
                        t0: float = 0.0, dc_law: str = "listing") -> BaselineResult:
    """Fixed-step RK4 (listing C.8) with bisection on the contact crossing (listing C.13).

    ``h`` [s] is the step; a step that crosses x = e is bisected on its length until the
    bracket is shorter than ``delta`` [s] (the thesis used 1e-6 m on x; a time bracket is the
    stricter reading).  Relay switches are hit exactly by shortening the last step before them.
    """
    f = rhs_1dof(params, dc_law)
    e = params["e"]
    y = [float(v) for v in y0]
    contact = 1.0 if y[0] < e else 0.0
    relay = _RELAY.value_for_index(_RELAY.index_at(t0, params["relay_hz"]))
    impacts, steps, bisections = [], 0, 0
    start = _time.perf_counter()
    t = t0
    for t_stop, relay_next in _switch_times(params["relay_hz"], t0, t_end) + [(t_end, None)]:
        while t < t_stop:
            step = min(h, t_stop - t)
            if t_stop - (t + step) < 1e-3 * h:   # no sliver step before the switch
                step = t_stop - t
            y_new = _rk4_step(f, t, y, step, relay, contact)
            steps += 1
            crossed = (y_new[0] < e) if not contact else (y_new[0] > e)
            if crossed:
                lo, hi = 0.0, step                   # bisection on the step length
                while hi - lo > delta:
                    mid = 0.5 * (lo + hi)
                    ym = _rk4_step(f, t, y, mid, relay, contact)
                    bisections += 1
                    if ((ym[0] < e) if not contact else (ym[0] > e)):
                        hi = mid
                    else:
                        lo = mid
                y = _rk4_step(f, t, y, hi, relay, contact)
                t = t + hi
                if not contact:
                    impacts.append(t)
                contact = 0.0 if contact else 1.0
                continue
            y = y_new
            t = t_stop if step == t_stop - t else t + step
        if relay_next is not None:
            relay = relay_next
    seconds = _time.perf_counter() - start
    return BaselineResult("rk4-bisection", h, np.array(y), np.array(impacts), seconds,
                          4 * (steps + bisections), "ok", {"steps": steps, "bisections": bisections})
