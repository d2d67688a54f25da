"""Stroboscopic and impact maps against analytic solutions and the time history."""
import math

import numpy as np
import pytest

import maps
from maps.impacts import free_flight_minima, impact_table
from maps.poincare import forcing_period_steps

OSC = dict(w0=1.0, zeta=0.05, F=0.3, Omega=0.7, e=-10.0, r=0.8)


@pytest.fixture(scope="module")
def osc():
    return maps.forced_oscillator_with_stop()


@pytest.fixture(scope="module")
def scene():
    return maps.get_scene("thesis-1dof").with_options(dc_law="listing")  # matlab-listing runs


def linear_response(p, t):
    """Steady forced response of x'' + 2 zeta w0 x' + w0^2 x = F cos(Omega t): (x, v) at t."""
    w0, z, F, W = p["w0"], p["zeta"], p["F"], p["Omega"]
    X = F / math.hypot(w0**2 - W**2, 2 * z * w0 * W)
    phi = math.atan2(2 * z * w0 * W, w0**2 - W**2)
    return X * math.cos(W * t - phi), -X * W * math.sin(W * t - phi)


def test_linear_oscillator_map_converges_to_the_analytic_steady_state(osc):
    """Stop far away: the map is linear, contracts by exp(-zeta w0 T) per step and its
    fixed point is the analytic forced response sampled at the phase."""
    tol, phase = 1e-14, 0.3
    smap = maps.StroboscopicMap(osc, OSC, phase=phase, tol=tol)
    T = 2 * math.pi / OSC["Omega"]
    assert smap.period == pytest.approx(T, rel=1e-15) and smap.forcing_period_steps == 1
    transient = 100  # start error ~ 1 decays by exp(-zeta w0 100 T) ~ 3e-20
    o = smap.orbit({"x": 1.0, "v": 0.0}, 4, transient=transient)
    for k, (t, y) in enumerate(zip(o.times, o.points)):
        assert t == pytest.approx((transient + k + phase) * T, rel=1e-15)
        x, v = linear_response(OSC, t)
        assert abs(y[0] - x) / tol < 100 and abs(y[1] - v) / tol < 100
    assert o.impacts_per_step.sum() == 0 and o.impact_time.size == 0
    assert np.all(np.isinf(o.min_impact_speed_per_step))
    # the map is affine: its Jacobian has det = exp(-2 zeta w0 T) (Liouville)
    det = np.linalg.det(smap.jacobian(o.points[0], k=transient))
    assert det == pytest.approx(math.exp(-2 * OSC["zeta"] * OSC["w0"] * T), rel=1e-7)


def test_step_and_orbit_agree_through_impacts_and_contacts(scene):
    """step() from every recorded point (relay flag from the time, contact flag from the gap)
    lands on the next recorded point; 9 Hz: impacts, and a sample taken inside the stop."""
    p = scene.parameters(preset="matlab-listing", V=90, relay_hz=9)
    smap = maps.StroboscopicMap(scene, p, tol=1e-12)
    o = smap.orbit(scene.initial_state(), 18, transient=0)
    assert o.impacts_per_step.sum() > 5 and (o.points[:, 0] < 0).any()  # a sample in contact
    scale = np.max(np.abs(o.points), axis=0)
    err = max(np.max(np.abs(smap.step(o.points[k], k) - o.points[k + 1]) / scale) for k in range(o.n))
    assert err / 1e-12 < 100  # measured 3e-13
    assert smap.forcing_period_steps == 9


@pytest.mark.parametrize("relay_hz", [6.0, 9.0])
def test_orbit_impacts_equal_the_time_history(scene, relay_hz):
    """Counts, times, velocities, penetrations and durations of the contacts per period, and the
    smallest gap per period, against maps.simulate / run_scene over the same span."""
    n = 30
    p = scene.parameters(preset="matlab-listing", V=90, relay_hz=relay_hz)
    o = maps.StroboscopicMap(scene, p, tol=1e-12).orbit(scene.initial_state(), n)
    run = maps.run_scene("thesis-1dof", n / relay_hz, params={"V": 90.0, "relay_hz": relay_hz},
                         preset="matlab-listing")
    ref = impact_table(run)
    sim = maps.simulate("thesis-1dof", periods=n, params={"V": 90.0, "relay_hz": relay_hz},
                        preset="matlab-listing")
    assert o.impacts_per_step.sum() == sim.sizes["impact"] == ref["t"].size > 0
    np.testing.assert_allclose(o.impact_time, sim.impact_time.values, rtol=0, atol=1e-12)
    np.testing.assert_allclose(o.impact_velocity, sim.impact_velocity.values, rtol=0, atol=1e-9)
    np.testing.assert_allclose(o.impact_penetration, ref["penetration"], rtol=0, atol=1e-12)
    np.testing.assert_allclose(o.impact_duration, ref["duration"], rtol=0, atol=1e-12)
    per_step = np.histogram(ref["t"], bins=np.arange(n + 1) / relay_hz)[0]
    np.testing.assert_array_equal(o.impacts_per_step, per_step)
    np.testing.assert_allclose(o.impact_phase, (ref["t"] * relay_hz) % 1.0, atol=1e-12)
    np.testing.assert_allclose(o.points[-1], run.y, rtol=0, atol=1e-10)
    # smallest gap per period: events against a dense grid through every sample instant
    T = 1.0 / relay_hz
    t_grid = np.union1d(np.linspace(0, n * T, 2000 * n + 1), o.times)
    x = maps.simulate("thesis-1dof", t_end=o.times[-1], t_eval=t_grid, params={"V": 90.0, "relay_hz": relay_hz},
                      preset="matlab-listing").x.values
    grid_min = np.array([x[(t_grid >= o.times[k]) & (t_grid <= o.times[k + 1])].min() for k in range(n)])
    excess = grid_min - o.min_clearance_per_step  # the grid can only miss the true minimum from above
    assert excess.min() > -1e-12 and excess.max() < 1e-6  # dt = T/2000: a dt^2/8 < 4e-7 m in contact
    lows = free_flight_minima(run)
    assert np.min(o.min_flight_clearance_per_step) == pytest.approx(lows["gap"].min(), abs=1e-15)


def test_forcing_period_in_relay_periods():
    """q relay periods hold a whole number of mains cycles (docs/model.md: 4 Hz: 2, 6: 3, 8: 4, 9: 9)."""
    for relay_hz, q in ((2, 1), (4, 2), (5, 1), (6, 3), (7, 7), (8, 4), (9, 9), (10, 1), (7.5, 3)):
        assert forcing_period_steps(50.0, relay_hz) == q, relay_hz
    assert forcing_period_steps(50.0, math.pi) == 0  # incommensurate: never repeats
    # sampled every half relay period the relay alternates: q = 2
    assert forcing_period_steps(50.0, 5.0, period=0.1) == 2 and forcing_period_steps(50.0, 5.0, period=0.4) == 1


def test_forcing_period_closed_form():
    """relay_hz = f_mains b / a: T f_mains = a / b, so q = b / gcd(a, b), the smallest q with q a / b whole
    (every pair a < 60, b < 1000 on a coarse grid; none within max_steps: 0)."""
    for a in range(1, 60, 7):
        for b in list(range(1, 60)) + [97, 331, 500, 997, 1001, 1500]:
            q = b // math.gcd(a, b)
            assert forcing_period_steps(50.0, 50.0 * b / a) == (q if q <= 1000 else 0), (a, b)
    assert forcing_period_steps(50.0, 50.0 / math.sqrt(2.0)) == 0
    assert forcing_period_steps(50.0, 50.0 * 7 / 3, max_steps=6) == 0 and forcing_period_steps(50.0, 50.0 * 7 / 3,
                                                                                               max_steps=7) == 7


def test_non_autonomous_map_repeats_after_q_steps(scene):
    """At 6 Hz the sampled forcing repeats every 3 relay periods: step(y, k) depends on k mod 3."""
    p = scene.parameters(preset="matlab-listing", V=90, relay_hz=6)
    smap = maps.StroboscopicMap(scene, p, tol=1e-12)
    y = scene.system.state_vector(scene.initial_state())
    y0, y1, y3 = smap.step(y, 0), smap.step(y, 1), smap.step(y, 3)
    scale = np.maximum(np.abs(y0), 1e-9)
    assert np.max(np.abs(y3 - y0) / scale) < 1e-9  # same forcing, times differ by 3 T
    assert np.max(np.abs(y1 - y0) / scale) > 1e-3  # other mains phase at the relay switch


def test_impact_map_of_a_period_one_impacting_orbit(osc):
    """Stop at the equilibrium, forcing above resonance: a stable 1:1 impacting orbit; the impact
    map settles on one point (phase, velocity) and agrees with the stroboscopic record."""
    p = dict(OSC, e=0.0, zeta=0.05, F=0.5, Omega=2.5, r=0.7)
    imap = maps.ImpactMap(osc, p, tol=1e-13)
    phase, vel, t = imap.iterate({"x": 0.2, "v": 0.0}, 12, transient_periods=200, chunk=5)
    assert imap.status == "ok" and phase.size == 12
    assert np.ptp(phase) < 1e-9 and np.ptp(vel) < 1e-9 and vel[0] < 0
    T = 2 * math.pi / p["Omega"]
    np.testing.assert_allclose(np.diff(t), T, rtol=0, atol=1e-9)
    assert phase[0] == pytest.approx((t[0] / T) % 1.0, abs=1e-12)
    o = maps.StroboscopicMap(osc, p, tol=1e-13).orbit({"x": 0.2, "v": 0.0}, 12, transient=200)
    np.testing.assert_allclose(o.impact_time, t, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(o.impacts_per_step, 1)
    # restitution: the rebound speed is r times the impact speed, from the closed-form flight
    assert np.all(o.min_impact_speed_per_step == pytest.approx(abs(vel[0]), abs=1e-9))


def test_escape_ends_the_orbit_with_a_status(scene):
    """ac-only at 25 V escapes (MODEL/brief): the orbit stops, reports it and does not raise."""
    ac = maps.get_scene("ac-only")
    p = ac.parameters(preset="thesis-text")
    smap = maps.StroboscopicMap(ac, p, period=0.013, tol=1e-10)  # no relay: the period is given
    assert smap.forcing_period_steps == 20  # 20 samples hold 13 mains cycles
    o = smap.orbit(ac.initial_state(), 50)
    assert o.status == "escaped" and o.failure and math.isfinite(o.failure_time)
    assert o.points.shape[0] == o.n + 1 <= 50 and o.times[-1] <= o.failure_time


def test_the_map_at_other_parameters_is_a_light_value_equal_to_a_fresh_map():
    """``smap.at(params, phase=)`` leaves ``smap`` unchanged, shares its compiled engine, and steps exactly as a map
    built anew at those parameters and that phase (bit for bit)."""
    import maps
    sc = maps.get_scene("thesis-1dof").with_options(dc_law="listing")
    base = maps.StroboscopicMap(sc, sc.parameters(preset="matlab-listing", V=90.0, relay_hz=9.0), tol=1e-10)
    view = base.at({"V": 110.0, "relay_hz": 7.0}, phase=0.25)
    fresh = maps.StroboscopicMap(sc, sc.parameters(preset="matlab-listing", V=110.0, relay_hz=7.0), tol=1e-10,
                                 phase=0.25)
    assert base.params["V"] == 90.0 and base.phase == 0.0 and base.period == pytest.approx(1 / 9.0, rel=1e-15)
    assert view.params["V"] == 110.0 and view.period == pytest.approx(1 / 7.0, rel=1e-15) and view._engine is base._engine
    y0 = sc.initial_state()
    a, b = view.orbit(y0, 8, transient=20), fresh.orbit(y0, 8, transient=20)
    np.testing.assert_array_equal(a.points, b.points)
    np.testing.assert_array_equal(base.orbit(y0, 3).points, maps.StroboscopicMap(
        sc, sc.parameters(preset="matlab-listing", V=90.0, relay_hz=9.0), tol=1e-10).orbit(y0, 3).points)
