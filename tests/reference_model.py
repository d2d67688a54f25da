"""The model's equations written again in plain numpy from docs/model.md, for the tests.

Independent of maps.model (no heyoka expression is reused): the charge ("kvl") circuit form
of the 1-DOF model with its energy quadratures and stored energy, and the 2-DOF horizontal
model (viscous soil, "thesis" circuit form, eq 4.16 on the relative position r = x1 - x2).
bifurc.verification.baselines.rhs_1dof covers the 1-DOF "thesis" form.
"""
from __future__ import annotations

import math


def _inductance(p, xb):
    """L [H], dL/dxb [H/m], d2L/dxb2 [H/m^2] of the Gaussian fit (eqs 4.13-4.15)."""
    A, B, L0 = p["A"], p["B"], p["L0"]
    g = A / (B * math.sqrt(math.pi / 2.0)) * math.exp(-2.0 * xb * xb / (B * B))
    return L0 + g, -4.0 * xb / (B * B) * g, (16.0 * xb * xb / B**4 - 4.0 / (B * B)) * g


def _dc_force(p, r):
    """Cubic DC force [N] along +r without the weight offset (listing C.9)."""
    xa = r - p["d_dc"]
    return p["dc_scale"] * (-p["a3"] * xa**3 + p["a2"] * xa**2 - p["a1"] * xa)


def rhs_1dof_kvl(p: dict, ac_sign: str = "physical"):
    """``f(t, y, relay, contact) -> dy`` for y = (x, v, q, i, W_src, E_R, E_c)."""
    w = 2.0 * math.pi * p["f_mains"]
    sign = 1.0 if ac_sign == "physical" else -1.0

    def f(t, y, relay, contact):
        x, v, q, i = y[:4]
        L, dL, _ = _inductance(p, x + p["d_ac"])
        F_c = (-p["k"] * (x - p["e"]) - p["c"] * v) if contact else 0.0
        F = _dc_force(p, x) + sign * 0.5 * dL * i * i + F_c  # the weight cancels the DC offset
        u = relay * p["V"] * math.sin(w * t)
        di = (u - p["R"] * i - q / p["C"] - dL * v * i) / L  # d(L i)/dt + R i + q/C = u
        return [v, F / p["m"], i, di, u * i, p["R"] * i * i, (p["c"] * v * v) if contact else 0.0]

    return f


def energy_1dof_kvl(p: dict, y, contact) -> float:
    """Kinetic + DC potential + magnetic + capacitor + stop elastic energy [J]."""
    x, v, q, i = y[:4]
    xa = x - p["d_dc"]
    U = p["dc_scale"] * (p["a3"] * xa**4 / 4 - p["a2"] * xa**3 / 3 + p["a1"] * xa**2 / 2)
    L, _, _ = _inductance(p, x + p["d_ac"])
    elastic = 0.5 * p["k"] * (x - p["e"]) ** 2 if contact else 0.0
    return 0.5 * p["m"] * v * v + U + 0.5 * L * i * i + 0.5 * q * q / p["C"] + elastic


def rhs_2dof_viscous(p: dict):
    """``f(t, y, relay, contact) -> dy`` for y = (x1, v1, x2, v2, i, z), horizontal, no gravity."""
    w = 2.0 * math.pi * p["f_mains"]

    def f(t, y, relay, contact):
        x1, v1, x2, v2, i, z = y
        r, rd = x1 - x2, v1 - v2
        L, dL, ddL = _inductance(p, r + p["d_ac"])
        F_c = (-p["k"] * (r - p["e"]) - p["c"] * rd) if contact else 0.0
        F_bar = _dc_force(p, r) + 0.5 * dL * i * i + F_c
        a1 = F_bar / p["m1"]
        a2 = (-F_bar - p["F_static"] - p["soil_c"] * v2) / p["m2"]
        rdd = a1 - a2
        dz = (relay * p["V"] * w * math.cos(w * t) - (p["R"] + 2.0 * dL * rd) * z
              - (1.0 / p["C"] + ddL * rd * rd + dL * rdd) * i) / L  # eq 4.16
        return [v1, a1, v2, a2, z, dz]

    return f
