"""The forced impact oscillator against its closed-form free flight, solved independently."""
import math

import numpy as np
import pytest
from scipy.optimize import brentq

import maps
from maps.hybrid import HybridRun


def free_flight(p, t0, x0, v0):
    """x(t), v(t) of x'' + 2 z w0 x' + w0^2 x = F cos(W t) from (t0, x0, v0), in closed form."""
    w0, z, F, W = p["w0"], p["zeta"], p["F"], p["Omega"]
    D = (w0**2 - W**2) ** 2 + (2 * z * w0 * W) ** 2
    a, b = F * (w0**2 - W**2) / D, F * 2 * z * w0 * W / D   # particular: a cos(W t) + b sin(W t)
    xp = lambda t: a * np.cos(W * t) + b * np.sin(W * t)  # noqa: E731
    vp = lambda t: -a * W * np.sin(W * t) + b * W * np.cos(W * t)  # noqa: E731
    s, wd = z * w0, w0 * math.sqrt(1 - z * z)
    A, B = x0 - xp(t0), (v0 - vp(t0) + s * (x0 - xp(t0))) / wd
    x = lambda t: xp(t) + np.exp(-s * (t - t0)) * (A * np.cos(wd * (t - t0)) + B * np.sin(wd * (t - t0)))  # noqa: E731
    v = lambda t: vp(t) + np.exp(-s * (t - t0)) * ((-s * A + wd * B) * np.cos(wd * (t - t0))  # noqa: E731
                                                   + (-s * B - wd * A) * np.sin(wd * (t - t0)))
    return x, v


def next_impact(p, t0, x0, v0):
    """First t > t0 with x(t) = e moving down: scan on a fine grid, then brentq."""
    x, v = free_flight(p, t0, x0, v0)
    h = 2 * math.pi / max(p["w0"], p["Omega"]) / 400
    t = t0 + 1e-12
    g_prev = x(t) - p["e"]
    while True:
        t_next = t + h
        g = x(t_next) - p["e"]
        if g_prev > 0 >= g:
            ti = brentq(lambda s: x(s) - p["e"], t, t_next, xtol=1e-15, rtol=4 * np.finfo(float).eps)
            return ti, v(ti)
        t, g_prev = t_next, g


@pytest.mark.parametrize("zeta", [0.05, 0.0])
def test_twenty_impacts_match_the_closed_form(zeta):
    system = maps.forced_oscillator_with_stop()
    p = dict(w0=1.0, zeta=zeta, F=0.5, Omega=0.8, e=-0.6, r=0.7)
    run = HybridRun(system, p, {"x": 0.0, "v": 0.0}, tol=1e-16)
    times, speeds = [], []
    while len(times) < 20:
        run.advance(run.t + 5.0)
        times = [ev.t for ev in run.events if ev.name == "contact"]
    speeds = [ev.y_minus[1] for ev in run.events if ev.name == "contact"][:20]
    t, x0, v0 = 0.0, 0.0, 0.0
    for k in range(20):
        ti, vi = next_impact(p, t, x0, v0)
        assert abs(times[k] - ti) < 1e-10, (k, times[k] - ti)
        assert abs(speeds[k] - vi) < 1e-10, (k, speeds[k] - vi)
        t, x0, v0 = times[k], p["e"], -p["r"] * speeds[k]  # restart both from the same post-impact state


def test_restitution_reset_is_applied_exactly():
    system = maps.forced_oscillator_with_stop()
    p = dict(w0=1.0, zeta=0.05, F=0.5, Omega=0.8, e=-0.6, r=0.7)
    run = HybridRun(system, p, {"x": 0.0, "v": 0.0}, tol=1e-15)
    run.advance(20.0)
    for ev in (ev for ev in run.events if ev.name == "contact"):
        assert ev.y_plus[1] == -p["r"] * ev.y_minus[1]
        assert abs(ev.y_minus[0] - p["e"]) < 1e-14
