"""Starting exactly on the stop must not loop (heyoka needs an explicit event cooldown).

Every run here has a small ``max_events``: a regression that re-triggers an event at the
same instant raises IntegrationFailure instead of hanging.
"""
import math

import numpy as np
from scipy.integrate import quad
from scipy.optimize import brentq

import maps
from maps.engines.scalar import HybridRun


def _dc_potential(p):
    """The DC well's potential U(x) [J] as a polynomial (the weight offset cancels m g)."""
    xa = np.poly1d([1.0, -p["d_dc"]])
    return p["a3"] * xa**4 / 4 - p["a2"] * xa**3 / 3 + p["a1"] * xa**2 / 2


def _oscillation_period(p, U):
    """Period [s] of the free oscillation from rest at x = 0 by quadrature, independent of heyoka:
    T = 2 int_0^b dx / sqrt(2 (U(0) - U(x)) / m), U(0) - U(x) = x (b - x) Q(x), the endpoint
    square-root singularities taken by quad's algebraic weight."""
    P = np.poly1d(np.r_[-U.coeffs[:-1], U(0.0) - U.coeffs[-1]])
    b = brentq(P, 0.5 * p["d_dc"] + 1e-6, 4 * p["d_dc"], xtol=1e-17)  # the far turning point
    Q, _ = np.polydiv(P, np.poly1d([-1.0, b, 0.0]))
    half, _ = quad(lambda x: 1.0 / np.sqrt(2 * Q(x) / p["m"]), 0.0, b, weight="alg",
                   wvar=(-0.5, -0.5), epsabs=1e-16, epsrel=1e-14)
    return 2 * half


def test_dc_only_bar_starting_on_the_stop_runs_without_looping():
    """From rest on the stop the DC force (~37 N) throws the bar up; the well is symmetric
    about d_dc, so the bar comes back to the stop at rest: a graze every oscillation."""
    scene = maps.get_scene("dc-only").with_options(dc_law="listing")  # _dc_potential is C.9's
    p = scene.parameters()
    run = HybridRun(scene.system, p, {"x": 0.0, "v": 0.0}, tol=1e-15, max_events=200)
    U = _dc_potential(p)
    E0 = U(0.0)
    worst = []

    def energy_error(c, a, b):  # free flight: kinetic + DC potential, on the dense output
        if b > a:
            y = c(np.linspace(a, b, 25))
            worst.append(np.max(np.abs(0.5 * p["m"] * y[:, 1] ** 2 + U(y[:, 0]) - E0)) / E0)

    run.advance(1.0, on_segment=energy_error)
    contacts = [ev for ev in run.events if ev.name == "contact"]
    turns = [ev for ev in run.events if ev.name == "lowest" and ev.t > 0]
    # a graze every oscillation: a turning point within 1 nm of the stop, or a contact slower
    # than 1 mm/s (which one is decided by rounding at the exact graze)
    T = _oscillation_period(p, U)
    assert abs(len(contacts) + len(turns) - math.floor(1.0 / T)) <= 1
    assert all(abs(ev.y_minus[0]) < 1e-9 for ev in turns)
    assert all(abs(ev.y_minus[1]) < 1e-3 for ev in contacts)
    assert max(worst) < 1e-12
    if not contacts:  # the turning points recur with the quadrature period
        np.testing.assert_allclose(np.diff([0.0] + [ev.t for ev in turns]), T, rtol=0, atol=1e-10)


OSC = dict(w0=1.0, zeta=0.05, F=0.5, Omega=0.8, r=0.7)


def _run_oscillator(e, v0, t0=0.0, t_end=30.0):
    system = maps.forced_oscillator_with_stop()
    run = HybridRun(system, dict(OSC, e=e), {"x": e, "v": v0}, t0=t0, tol=1e-14, max_events=2000)
    lowest = []
    run.advance(t_end, on_segment=lambda c, a, b: lowest.append(c(np.linspace(a, b, 25))[:, 0].min()))
    assert min(lowest + [run.y[0]]) >= e - 1e-12  # never below the rigid stop
    return run


def test_oscillator_starting_on_the_stop_moving_away():
    run = _run_oscillator(e=0.0, v0=0.3)
    assert run.n_events < 200
    assert all(abs(ev.y_minus[0]) < 1e-12 for ev in run.events if ev.name == "contact")


def test_oscillator_pressed_on_the_stop_for_good_stays_there():
    """e = 1 > F/w0^2: the forcing can never pull the mass off: no event, x = e exactly."""
    run = _run_oscillator(e=1.0, v0=0.0)
    assert run.n_events == 0 and run.flags["stuck"] == 1
    assert run.y[0] == 1.0 and run.y[1] == 0.0


def test_oscillator_pressed_on_the_stop_leaves_when_the_forcing_pulls():
    """e = 0.3: stuck from t0 = 2.5 s until F cos(Omega t) = w0^2 e, i.e. Omega t = 2 pi k -
    arccos(w0^2 e / F); then it flies, bounces with r = 0.7 (a Zeno cascade) and sticks again
    before the next release, once per forcing period."""
    e = 0.3
    run = _run_oscillator(e=e, v0=0.0, t0=2.5, t_end=40.0)
    released = np.array([ev.t for ev in run.events if ev.name == "unstick"])
    k = np.arange(1, released.size + 1)
    expected = (2 * math.pi * k - math.acos(OSC["w0"] ** 2 * e / OSC["F"])) / OSC["Omega"]
    assert released.size == 5
    np.testing.assert_allclose(released, expected, rtol=0, atol=1e-12)
    stuck_again = [ev.t for ev in run.events if ev.flags["stuck"] == 1]
    assert len(stuck_again) == 4 and all(a < b for a, b in zip(stuck_again, released[1:]))
    assert run.n_events < 200  # the cascade ends after ~25 bounces per flight
