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

__all__ = ["forced_oscillator_with_stop", "OSCILLATOR_PARAMETERS"]

OSCILLATOR_PARAMETERS = [
    Parameter("w0", "rad s-1", "natural angular frequency", 0, math.inf, low_open=True),
    Parameter("zeta", "1", "damping ratio", 0, 10),
    Parameter("F", "m s-2", "forcing amplitude per unit mass", 0, math.inf),
    Parameter("Omega", "rad s-1", "forcing angular frequency", 0, math.inf, low_open=True),
    Parameter("e", "m", "stop position (x >= e is free)", -math.inf, math.inf),
    Parameter("r", "1", "coefficient of restitution", 0, 1),
]


def forced_oscillator_with_stop() -> HybridSystem:
    """The forced linear impact oscillator (states x [m], v [m/s]; parameters above).

    Guards: "contact" (x = e moving down; reset v -> -r v) and "lowest" (v = 0
    upward: a free-flight minimum, recorded for clearance).  Its stroboscopic
    period is the forcing period 2 pi / Omega.
    """

    def rhs(s):
        return [s.v, s.F * hy.cos(s.Omega * s.t) - 2 * s.zeta * s.w0 * s.v - s.w0**2 * s.x]

    def restitute(y, p):
        y = y.copy()
        y[1] = -p["r"] * y[1]
        return y

    def guards(s):
        return [Guard("contact", s.x - s.e, -1, reset=restitute),
                Guard("lowest", s.v, +1)]

    system = HybridSystem(
        "forced-oscillator-with-stop",
        states=[State("x", "m", "position"), State("v", "m s-1", "velocity")],
        parameters=OSCILLATOR_PARAMETERS, rhs=rhs, guards=guards)
    system.strobe_period = lambda p: 2 * math.pi / p["Omega"]
    return system
