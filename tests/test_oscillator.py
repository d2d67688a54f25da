"""The forced impact oscillator against its closed-form free flight, solved independently."""
import math

import numpy as np
import pytest
from scipy.optimize import brentq

import maps
from maps.engines.scalar import HybridRun


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
    """First t > t0 with x(t) = e moving down.

    Scan a grid of 1/400 of the shortest period; inside each cell, a sign change of v from
    - to + is a minimum, located by brentq on v: if it lies below e the cell holds a crossing
    even when both ends are above e (a shallow dip), so no crossing is skipped.  The crossing
    itself is then bracketed between the cell start and that minimum and found by brentq.
    """
    x, v = free_flight(p, t0, x0, v0)
    e = p["e"]
    h = 2 * math.pi / max(p["w0"], p["Omega"]) / 400
    root = lambda a, b: brentq(lambda s: x(s) - e, a, b, xtol=1e-15, rtol=4 * np.finfo(float).eps)  # noqa: E731
    t = t0 + 1e-12
    for _ in range(10**6):
        t_next = t + h
        if x(t) - e > 0 >= x(t_next) - e:
            ti = root(t, t_next)
            return ti, v(ti)
        if v(t) < 0 < v(t_next):
            t_min = brentq(v, t, t_next, xtol=1e-15)
            if x(t_min) < e:
                ti = root(t, t_min)
                return ti, v(ti)
        t = t_next
    raise AssertionError("no impact within 10^6 grid cells")


@pytest.mark.parametrize("zeta", [0.05, 0.0])
def test_twenty_impacts_match_the_closed_form(zeta):
    """A 1:1 impacting motion (one impact per forcing period, settling on the period-1 orbit;
    with zeta = 0 only the restitution dissipates).  Measured: 1.4e-14 s and 1.8e-14 m/s."""
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
    # the case is the period-1 impacting motion it claims to be: intervals of one forcing period
    intervals = np.diff(times[:20]) / (2 * math.pi / p["Omega"])
    assert np.all(np.abs(intervals - 1) < 0.1)
    assert abs(intervals[-1] - 1) < 1e-3


def test_restitution_reset_is_applied_exactly():
    system = maps.forced_oscillator_with_stop()
    p = dict(w0=1.0, zeta=0.05, F=0.5, Omega=0.8, e=-0.6, r=0.7)
    run = HybridRun(system, p, {"x": 0.0, "v": 0.0}, tol=1e-15)
    run.advance(20.0)
    for ev in (ev for ev in run.events if ev.name == "contact"):
        assert ev.y_plus[1] == -p["r"] * ev.y_minus[1]
        assert abs(ev.y_minus[0] - p["e"]) < 1e-14


def test_restitution_never_lets_the_mass_below_the_stop():
    system = maps.forced_oscillator_with_stop()
    p = dict(w0=1.0, zeta=0.0, F=0.5, Omega=0.8, e=-0.6, r=0.7)
    run = HybridRun(system, p, {"x": 0.0, "v": 0.0}, tol=1e-15)
    lowest = []
    run.advance(60.0, on_segment=lambda c, a, b: lowest.append(c(np.linspace(a, b, 50))[:, 0].min()))
    assert min(lowest) >= p["e"] - 1e-13


@pytest.mark.parametrize("zeta, Omega", [(0.1, 0.7), (0.3, 1.4)])
def test_stroboscopic_map_without_impacts_converges_to_the_steady_amplitude(zeta, Omega):
    """Stop far away: the forcing-period map converges to the fixed point of the steady state
    X cos(Omega t - phi), X = F / sqrt((w0^2 - Omega^2)^2 + (2 zeta w0 Omega)^2); the transient
    decays as exp(-zeta w0 t), below 1e-13 of X after the transient periods used here."""
    system = maps.forced_oscillator_with_stop()
    p = dict(w0=1.0, zeta=zeta, F=0.4, Omega=Omega, e=-50.0, r=0.7)
    T = 2 * math.pi / Omega
    transient = math.ceil(32 / (zeta * p["w0"] * T))  # exp(-32) ~ 1e-14
    smap = maps.StroboscopicMap(system, p, period=T, tol=1e-15)
    orbit = smap.orbit({"x": 0.3, "v": -0.2}, 4, transient=transient)
    X = p["F"] / math.hypot(p["w0"] ** 2 - Omega**2, 2 * zeta * p["w0"] * Omega)
    amplitude = np.hypot(orbit.points[:, 0], orbit.points[:, 1] / Omega)  # harmonic: sqrt(x^2 + (v/W)^2)
    assert orbit.impacts_per_step.sum() == 0
    np.testing.assert_allclose(amplitude, X, rtol=1e-10)
    np.testing.assert_allclose(np.diff(orbit.points, axis=0), 0.0, atol=1e-10 * X)  # a fixed point
    # and the transient really was there: one period from the start is far from it
    first = smap.step([0.3, -0.2], k=0)
    assert abs(math.hypot(first[0], first[1] / Omega) - X) > 1e-3
