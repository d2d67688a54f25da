"""Small hybrid systems declared through the public API, to copy and to test against.

:func:`forced_oscillator_with_stop` is a harmonically forced linear oscillator
against a rigid stop with Newtonian restitution:

    x'' + 2 zeta w0 x' + w0^2 x = F cos(Omega t)   while x > e,
    v -> -r v                                      when x reaches e moving down.

Between impacts its motion is known in closed form, which makes it the
reference for the engine's event handling, maps, classification and grazing.
"""
from __future__ import annotations

import math

import heyoka as hy

from .hybrid import Guard, HybridSystem, State
from .parameters import Parameter

OSCILLATOR_PARAMETERS = [
    Parameter("w0", "rad s-1", "natural angular frequency", 0, math.inf, low_open=True),
    Parameter("zeta", "1", "damping ratio", 0, 10),
    Parameter("F", "m s-2", "forcing amplitude per unit mass", 0, math.inf),
    Parameter("Omega", "rad s-1", "forcing angular frequency", 0, math.inf, low_open=True),
    Parameter("e", "m", "stop position (x >= e is free)", -math.inf, math.inf),
    Parameter("r", "1", "coefficient of restitution", 0, 1),
]

#: [m/s] a rebound slower than this while the forcing presses the mass on the stop ends
#: the cascade of ever shorter bounces (r < 1 accumulates infinitely many impacts in a
#: finite time): the mass sticks until the forcing pulls it away.
STICK_SPEED = 1e-5


def _pull_at_rest(t, p):
    """Acceleration [m/s^2] of the mass held at rest on the stop (> 0: pulled away)."""
    return p["F"] * math.cos(p["Omega"] * t) - p["w0"] ** 2 * p["e"]


def forced_oscillator_with_stop(stick_speed: float = STICK_SPEED) -> HybridSystem:
    """The forced linear impact oscillator (states x [m], v [m/s]; parameters above).

    Guards: "contact" (x = e moving down; reset v -> -r v), "lowest" (v = 0
    upward: a free-flight minimum, recorded for clearance) and "unstick" (the
    forcing starts pulling a stuck mass away).  The flag "stuck" (mass held at
    x = e, v = 0) is entered by ``settle`` when the mass is on the stop slower
    than ``stick_speed`` [m/s] and pressed on it.  Its stroboscopic period is the
    forcing period 2 pi / Omega.
    """

    def rhs(s):
        free = 1 - s.stuck
        return [free * s.v, free * (s.F * hy.cos(s.Omega * s.t) - 2 * s.zeta * s.w0 * s.v - s.w0**2 * s.x)]

    def restitute(y, p):
        y = y.copy()
        y[1] = -p["r"] * y[1]
        return y

    def guards(s):
        return [Guard("contact", s.x - s.e, -1, when={"stuck": 0}, reset=restitute, role="impact"),
                Guard("lowest", s.v, +1, when={"stuck": 0}, role="flight_minimum"),
                Guard("unstick", s.F * hy.cos(s.Omega * s.t) - s.w0**2 * s.e, +1,
                      when={"stuck": 1}, then={"stuck": 0}, role="unstick")]

    def settle(t, y, flags, p):
        on_stop = abs(y[0] - p["e"]) <= 1e-12 * max(1.0, abs(p["e"]))
        pressed = _pull_at_rest(t, p) < -1e-12 * (p["F"] + p["w0"] ** 2 * abs(p["e"]))  # not at the unstick instant
        if flags["stuck"] == 0 and on_stop and abs(y[1]) < stick_speed and pressed:
            y = y.copy()
            y[0], y[1] = p["e"], 0.0
            return {"stuck": 1.0}, y
        if flags["stuck"] == 1 and _pull_at_rest(t, p) > 0:
            return {"stuck": 0.0}
        return None

    system = HybridSystem(
        "forced-oscillator-with-stop",
        states=[State("x", "m", "position"), State("v", "m s-1", "velocity")],
        parameters=OSCILLATOR_PARAMETERS, rhs=rhs, flags={"stuck": 0.0}, guards=guards,
        settle=settle, structure=("stick", stick_speed),
        strobe_period=_forcing_period, forcing=_forcing_frequency,
        # the stick projection (x = e, v = 0) as expressions, for exact Jacobians through a stick
        projections={"settle": _stick_projection}, mode_projections={("stuck", 1.0): "settle"})
    return system


def _forcing_period(p) -> float:
    """The forcing period 2 pi / Omega [s]: the oscillator's stroboscopic period."""
    return 2 * math.pi / p["Omega"]


def _forcing_frequency(p) -> tuple:
    """The forcing frequency Omega / (2 pi) [Hz]."""
    return (p["Omega"] / (2 * math.pi),)


def _stick_projection(s, flags) -> list:
    """The stuck mass's state (x = e, v = 0) as heyoka expressions."""
    return [s.e, hy.expression(0.0)]
