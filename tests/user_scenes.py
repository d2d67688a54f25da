"""A user's system declared outside the toolkit, for the scene-registry tests: a linear oscillator
driven by a relay-switched square-wave force against a rigid stop with restitution.

    x'' + 2 zeta w0 x' + w0^2 x = F (2 P - 1),  P switched at t = n / (2 f_sw) (50 % duty),
    v -> -r v when x reaches e moving down.

Its switch frequency is named ``f_sw`` (not the thesis model's ``relay_hz``): the toolkit must
find its clock from the declared PeriodicSwitch.  The stop lies below the static deflection under
-F, so the mass never rests on it (no sticking mode needed).
"""
import math

import maps
from maps import Guard, HybridSystem, Parameter, PeriodicSwitch, State

PARAMETERS = [
    Parameter("w0", "rad s-1", "natural angular frequency", 0, math.inf, low_open=True),
    Parameter("zeta", "1", "damping ratio", 0, 10),
    Parameter("F", "m s-2", "square-wave force amplitude per unit mass", 0, math.inf),
    Parameter("f_sw", "Hz", "switch frequency", 0, 1e3, low_open=True),
    Parameter("e", "m", "stop position (x >= e is free)", -math.inf, math.inf),
    Parameter("r", "1", "coefficient of restitution", 0, 1),
]
DEFAULTS = {"w0": 2 * math.pi, "zeta": 0.05, "F": 30.0, "f_sw": 0.8, "e": -1.0, "r": 0.8}


def relay_oscillator() -> HybridSystem:
    """The system (states x [m], v [m/s]; flag P: the switch)."""

    def rhs(s):
        return [s.v, s.F * (2 * s.P - 1) - 2 * s.zeta * s.w0 * s.v - s.w0 * s.w0 * s.x]

    return HybridSystem(
        "relay-oscillator", states=[State("x", "m", "position"), State("v", "m s-1", "velocity")],
        parameters=PARAMETERS, rhs=rhs, flags={"P": 1.0},
        guards=lambda s: [Guard("contact", s.x - s.e, -1, reset=[s.x, -s.r * s.v], role="impact"),
                          Guard("lowest", s.v, +1, role="flight_minimum")],
        switches=[PeriodicSwitch("P", "f_sw")])


#: the scene: defaults and a start above the stop
SCENE = maps.Scene("relay-oscillator", "square-wave driven oscillator against a stop (tests/user_scenes.py)",
                   None, preset=None, overrides={k: (v, "tests/user_scenes.py") for k, v in DEFAULTS.items()},
                   x0={"x": 0.0, "v": 0.0}, builder=relay_oscillator)
