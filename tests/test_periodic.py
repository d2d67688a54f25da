"""Periodic orbits by multiple shooting against the closed-form 1:1 orbits of the restitution
oscillator (stable and unstable), a long simulation, and bad input."""
import math

import numpy as np
import pytest
from scipy.linalg import expm
from scipy.optimize import brentq

import maps
from bifurc.orbits.orbit import periodic_orbit
from bifurc.orbits.periodic import OrbitNotFound, find_periodic_orbit

BASE = dict(w0=1.0, zeta=0.05, F=0.5, Omega=2.5, e=0.2, r=0.7)


def free_flight(w0, zeta, F, Omega):
    """(A_lin, x_p): the free flight's matrix and its particular solution t -> (x_p, x_p') [m, m/s]."""
    Al = np.array([[0.0, 1.0], [-w0 * w0, -2 * zeta * w0]])
    D = (w0 * w0 - Omega * Omega) ** 2 + (2 * zeta * w0 * Omega) ** 2
    a, b = F * (w0 * w0 - Omega * Omega) / D, F * 2 * zeta * w0 * Omega / D
    return Al, lambda t: np.array([a * math.cos(Omega * t) + b * math.sin(Omega * t),
                                   Omega * (-a * math.sin(Omega * t) + b * math.cos(Omega * t))])


def closed_form_1_1(w0, zeta, F, Omega, e, r):
    """Every 1:1 impacting orbit (one impact per forcing period T = 2 pi / Omega), derived by hand:
    between impacts x = x_p(t) + homogeneous part, x_p = A cos(Omega t) + B sin(Omega t); the flight
    from (e, -r v) at t_i must return to (e, v) at t_i + T.  With Phi = expm(A_lin T) that is linear
    in v for a fixed impact phase: eliminate v, bracket the phase, brentq.  Returns
    [(impact time in [0, T), impact velocity v < 0, state at t = 0 mod T, multipliers)]."""
    T = 2 * math.pi / Omega
    Al = np.array([[0.0, 1.0], [-w0 * w0, -2 * zeta * w0]])
    D = (w0 * w0 - Omega * Omega) ** 2 + (2 * zeta * w0 * Omega) ** 2
    a, b = F * (w0 * w0 - Omega * Omega) / D, F * 2 * zeta * w0 * Omega / D

    def xp(t):
        return np.array([a * math.cos(Omega * t) + b * math.sin(Omega * t),
                         Omega * (-a * math.sin(Omega * t) + b * math.cos(Omega * t))])
    P = expm(Al * T)

    def v_of(th):
        x, u = xp(th / Omega)
        return ((P[0, 0] - 1) * (e - x) - P[0, 1] * u) / (P[0, 1] * r)

    def G(th):
        x, u = xp(th / Omega)
        v = v_of(th)
        return v - u - P[1, 0] * (e - x) - P[1, 1] * (-r * v - u)
    grid = np.linspace(0.0, 2 * math.pi, 3001)
    xg, ug = a * np.cos(grid) + b * np.sin(grid), Omega * (-a * np.sin(grid) + b * np.cos(grid))
    vg = ((P[0, 0] - 1) * (e - xg) - P[0, 1] * ug) / (P[0, 1] * r)
    Gg = vg - ug - P[1, 0] * (e - xg) - P[1, 1] * (-r * vg - ug)       # G on the grid, as arrays
    lam, V = np.linalg.eig(Al)                 # distinct eigenvalues (zeta != 1): expm(Al s) = V e^(lam s) V^-1
    out = []
    for lo, hi in zip(grid[:-1][Gg[:-1] * Gg[1:] < 0], grid[1:][Gg[:-1] * Gg[1:] < 0]):
        if G(lo) * G(hi) < 0:
            th = brentq(G, lo, hi, xtol=1e-15, rtol=1e-15)
            v, ti = v_of(th), th / Omega
            y_after = np.array([e, -r * v])
            s = np.linspace(0, T, 801)[1:-1]
            c = np.linalg.solve(V, y_after - xp(ti))
            t = ti + s
            flight = np.real((V[0] * c) @ np.exp(np.outer(lam, s))) + a * np.cos(Omega * t) + b * np.sin(Omega * t)
            if v >= 0 or flight.min() < e:
                continue                     # not an impact, or the flight passes through the stop
            force = F * math.cos(Omega * ti) - w0 * w0 * e
            am, ap = force - 2 * zeta * w0 * v, force + 2 * zeta * w0 * r * v
            S = np.array([[-r, 0.0], [(ap + r * am) / v, -r]])
            y0 = expm(Al * (T - ti)) @ (y_after - xp(ti)) + xp(T)
            out.append((ti, v, y0, np.linalg.eigvals(P @ S)))
    return out


def _sorted(mu):
    return np.array(sorted(mu, key=lambda z: (round(abs(z), 12), z.imag)))


@pytest.mark.parametrize("zeta", [0.05, 0.0])
def test_stable_and_unstable_1_1_orbits_equal_the_closed_form(zeta):
    p = dict(BASE, zeta=zeta)
    orbits = closed_form_1_1(**p)
    system = maps.forced_oscillator_with_stop()
    T = 2 * math.pi / p["Omega"]
    found = {"stable": 0, "unstable": 0}
    for ti, v, y0, mu in orbits:
        guess = y0 + np.array([2e-3, -3e-3])
        ds = periodic_orbit(system, params=p, start=guess, period=1, error=False)
        assert np.max(np.abs(np.array([float(ds.x[0]), float(ds.v[0])]) - y0)) < 1e-10
        assert int(ds.impacts_per_period) == 1
        assert abs(float(ds.impact_velocity[0]) - v) < 1e-10
        assert abs(float(ds.impact_time[0]) - ti) < 1e-10 and abs(float(ds.impact_phase[0]) - ti / T) < 1e-10
        got = ds.multiplier_abs.values * np.exp(1j * ds.multiplier_arg.values)
        np.testing.assert_allclose(_sorted(got), _sorted(mu), rtol=0, atol=1e-9)
        found["stable" if bool(ds.stable) else "unstable"] += 1
        assert bool(ds.stable) == (np.max(np.abs(mu)) < 1)
    assert found == {"stable": 1, "unstable": 1}


def test_no_impacting_1_1_orbit_only_a_sticking_one():
    """Omega = 0.5: the closed form has no impacting 1:1 orbit (the free response, amplitude 0.67,
    would pass through the stop at e = 0.2).  What is there instead: every start chatters onto the
    stop within the period, sticks, and leaves at the phase where the forcing pulls it off, so the
    map is constant near it.  Newton returns that sticking orbit, never an impacting one: the point
    two simulations from different starts reach after one period (to 1e-12), multipliers 0 (the
    stick projects every perturbation away), and a release from the stop in every period.  (Newton
    once said "no convergence" here: it scaled the residual by the first guess's magnitude, and the
    guess at rest made v's scale atol = 1e-9, so the map's 1e-16 of round-off read 1e-7.)"""
    p = dict(BASE, Omega=0.5)
    assert closed_form_1_1(**p) == []
    smap = maps.StroboscopicMap(maps.forced_oscillator_with_stop(), p, tol=1e-12)
    orbit = find_periodic_orbit(smap, np.array([0.5, 0.0]), 1, max_iter=25)
    for start in ({"x": 0.5, "v": 0.0}, {"x": 0.3, "v": 0.1}):
        assert np.max(np.abs(smap.orbit(start, 1).points[-1] - orbit.nodes[0].y)) < 1e-12
    assert orbit.stable and np.max(np.abs(orbit.multipliers)) < 1e-12
    assert "unstick" in orbit.signatures[0]


def test_without_the_stick_mode_newton_refuses_the_zeno_cascade():
    """The same case without the stick mode (stick_speed = 0): the chattering cascade has infinitely
    many impacts before the forcing pulls the mass off, which no integration resolves; Newton must
    say it found no orbit, with the reason, never return one."""
    p = dict(BASE, Omega=0.5)
    smap = maps.StroboscopicMap(maps.forced_oscillator_with_stop(stick_speed=0.0), p, tol=1e-12,
                                max_events_per_period=2000)
    with pytest.raises(OrbitNotFound) as err:
        find_periodic_orbit(smap, np.array([0.5, 0.0]), 1, max_iter=25)
    assert err.value.reason


def test_a_stable_orbit_is_the_attractor_of_a_long_simulation():
    system = maps.forced_oscillator_with_stop()
    smap = maps.StroboscopicMap(system, BASE, tol=1e-14)
    o = smap.orbit({"x": 0.5, "v": 0.0}, 2, transient=600)
    orbit = find_periodic_orbit(smap, np.array([0.4, 0.3]), 1)
    assert orbit.stable
    assert np.max(np.abs(o.points[-1] - orbit.nodes[0].y)) < 1e-10


def test_period_17_of_thesis_1dof_at_8_5_hz_by_multiple_shooting():
    """The orbit a long sweep found with --max-period 17 (12 impacts): Newton from a simulated
    point converges, and the conditioning single shooting would face is reported."""
    sc = maps.get_scene("thesis-1dof").with_options(dc_law="listing")   # matlab-listing's law (C.9)
    p = sc.parameters(preset="matlab-listing", V=90.0, relay_hz=8.5)
    smap = maps.StroboscopicMap(sc, p, tol=1e-10)
    assert smap.forcing_period_steps == 17
    o = smap.orbit(sc.initial_state(), 2, transient=300)
    orbit = find_periodic_orbit(smap, o.state(0), 17, k0=300)
    assert orbit.residual < 1e-10 and orbit.impacts_per_period == 12
    c = orbit.conditioning
    assert c["single_shooting_growth"] > 1 and math.isfinite(c["multiple_shooting"])
    # the same orbit found again from its sample 5 periods on (another node of the same cycle)
    again = find_periodic_orbit(smap, orbit.nodes[5], 17, k0=305)
    assert np.max(np.abs(again.nodes[12].y - orbit.nodes[0].y) / orbit.scale) < 1e-8


def test_bad_input_is_one_line_naming_the_argument():
    sc = maps.get_scene("thesis-1dof")
    kw = dict(preset="matlab-listing", error=False)
    with pytest.raises(maps.ParameterError, match=r"period = 5 .* not a multiple of the forcing period q = 17"):
        periodic_orbit("thesis-1dof", params={"V": 90, "relay_hz": 8.5}, period=5, **kw)
    with pytest.raises(maps.ParameterError, match="q = 0"):
        periodic_orbit("thesis-1dof", params={"V": 90, "relay_hz": 8.537}, period=3, **kw)
    with pytest.raises(maps.ParameterError, match="'x' must be finite"):
        periodic_orbit("thesis-1dof", params={"V": 90, "relay_hz": 5}, start={"x": math.nan}, **kw)
    with pytest.raises(maps.ParameterError, match="'V'"):
        periodic_orbit("thesis-1dof", params={"V": "ninety"}, **kw)
    with pytest.raises(maps.ParameterError, match="period.*whole number"):
        periodic_orbit("thesis-1dof", params={"V": 90, "relay_hz": 5}, period="two", **kw)
    assert sc.name == "thesis-1dof"


def test_orbit_command_prints_and_writes_the_orbit(tmp_path, capsys):
    from bifurc.cli import main
    import xarray as xr
    out = tmp_path / "orbit.nc"
    argv = ["orbit", "--preset", "matlab-listing", "--set", "V=90", "--relay-hz", "8.5", "--tol", "1e-10",
            "--no-error", "-o", str(out)]
    assert main(argv) == 0
    text = capsys.readouterr().out
    assert "period 17" in text and "12 impacts per period" in text and "stable" in text
    ds = xr.open_dataset(out)
    assert int(ds.period) == 17 and ds.sizes["node"] == 17 and ds.sizes["multiplier"] == 4
    assert ds.multiplier_abs.attrs["units"] == "1" and ds.attrs["Conventions"].startswith("CF")
    assert all(s.split(",")[0] in ("impact", "flight_minimum", "stick", "release", "deepest", "unstick", "")
               for s in ds.signature.values)
    assert main(argv) == 2 and "--force" in capsys.readouterr().err


def test_an_orbit_starts_from_a_stored_sweep_point_with_its_flags():
    """A one-value sweep at 8.5 Hz stores states and mode flags at every sample; the last one
    starts Newton (at its own sample index) and lands on the period-17 orbit."""
    from bifurc import sweep, sweep_point
    ds = sweep("thesis-1dof", "relay_hz", [8.5], preset="matlab-listing", params={"V": 90}, transient=300,
               record=20, progress=False, grazing=False, error_sample=0, lyapunov=False)
    start, k = sweep_point(ds, 8.5)
    assert k == 320 and start.flags is not None and set(start.flags) >= {"P", "contact", "stuck_bar"}
    orbit = periodic_orbit("thesis-1dof", preset="matlab-listing", params={"V": 90, "relay_hz": 8.5},
                           start=(start, k), tol=1e-10, error=False)
    assert int(orbit.period) == 17 and int(orbit.impacts_per_period) == 12 and orbit.attrs["k0"] == 320


def test_the_impact_oscillator_scene_runs_every_command(tmp_path, capsys):
    """The oscillator of maps.examples is a scene: simulate, diagram, orbit and params run on it as on
    the thesis scenes; its orbit through the CLI equals the closed-form stable 1:1 orbit, and the
    clearance of an impacting orbit is 0 (the impact itself), not the free flight's minimum."""
    from bifurc.cli import main
    import xarray as xr
    assert main(["params", "--scene", "impact-oscillator"]) == 0 and "Omega" in capsys.readouterr().out
    assert main(["simulate", "--scene", "impact-oscillator", "--t-end", "20", "-o", str(tmp_path / "s.nc")]) == 0
    assert main(["diagram", "--scene", "impact-oscillator", "--param", "Omega", "--from", "2.4", "--to", "2.6",
                 "--n", "3", "--transient", "100", "--record", "10", "--quiet", "-o", str(tmp_path / "d.nc")]) == 0
    d = xr.open_dataset(tmp_path / "d.nc")
    assert (d.class_code.values == 0).all() and (d.period.values == 1).all()
    assert np.max(np.abs(d.min_clearance.values)) < 1e-12
    assert main(["orbit", "--scene", "impact-oscillator", "--x0", "x=0.5", "--transient", "100", "--tol", "1e-13",
                 "-o", str(tmp_path / "o.nc")]) == 0
    o = xr.open_dataset(tmp_path / "o.nc")
    stable = [c for c in closed_form_1_1(**BASE) if np.max(np.abs(c[3])) < 1][0]
    assert abs(float(o.impact_velocity[0]) - stable[1]) < 1e-9 and abs(float(o.min_clearance)) < 1e-12
    assert main(["orbit", "--scene", "impact-oscillator", "--preset", "matlab-listing"]) == 2
    assert "no presets" in capsys.readouterr().err


def test_a_2dof_orbit_is_solved_in_relative_coordinates_with_its_advance():
    """The prototype at 5 Hz repeats its relative motion every relay period while the rig creeps
    into the soil.  In the full state Newton would be singular (the shift of bar and rig together
    has multiplier 1); in the reduced coordinates it converges, the multipliers are the reduced
    map's (5 of them, none at 1), and the advance per period equals the simulated rig's to 1e-12 m."""
    sc = maps.get_scene("prototype")
    p = sc.parameters(relay_hz=5.0, V=90 * 1.4142)
    smap = maps.StroboscopicMap(sc, p, tol=1e-10)
    o = smap.orbit(sc.initial_state(), 6, transient=400)
    orbit = find_periodic_orbit(smap, o.state(0), 1, k0=400)
    assert orbit.reduced == ("x1", "v1", "v2", "i", "z") and orbit.multipliers.size == 5
    assert np.min(np.abs(np.abs(orbit.multipliers) - 1)) > 0.5
    assert np.ptp(np.diff(o.points[:, 2])) < 1e-13             # the simulation repeats too
    assert abs(orbit.advance - float(np.diff(o.points[:, 2])[0])) < 1e-12 and orbit.advance < 0
    ds = periodic_orbit("prototype", params={"relay_hz": 5.0, "V": 90 * 1.4142}, transient=400, tol=1e-10,
                        error=False)
    assert ds.advance_per_period.attrs["units"] == "m" and abs(float(ds.advance_per_period) - orbit.advance) < 1e-12
    assert float(ds.x2[0]) == 0.0 and "x2 = 0" in ds.attrs["reduced_coordinates_note"]


def test_a_bar_resting_on_the_stop_is_a_stable_orbit_with_the_circuits_closed_form_multipliers():
    """thesis-1dof, measured DC law, 5 Hz, 100 V: the bar stays stuck on the stop (x = e, v = 0).
    Started in the stuck mode, a perturbation off the stop is not a state of that mode (the bar falls
    back and sticks again): the Jacobian projects it first, so x and v have multipliers 0, not a
    frozen offset's 1.  With the bar at rest the circuit (eq. 4.16, i'' + R/L i' + i/(LC) = u'/L,
    L = L(e) constant) is linear with constant coefficients: its two multipliers over T = 1/5 s have
    the product det expm(A T) = exp(-R T / L), a complex pair of modulus exp(-R T / (2 L)) here."""
    import math
    import bifurc
    ds = bifurc.periodic_orbit("thesis-1dof", preset="matlab-listing", params={"V": 100.0, "relay_hz": 5.0},
                               dc_law="measured", transient=100, period=1)
    assert float(ds.flag_stuck_bar.values[0]) == 1.0
    p = maps.get_scene("thesis-1dof").with_options(dc_law="measured").parameters(preset="matlab-listing")
    q = (p["e"] + p["d_ac"]) / p["B"]
    L = p["A"] / p["B"] * math.exp(-2 * q * q) / math.sqrt(math.pi / 2) + p["L0"]
    mod = np.sort(ds.multiplier_abs.values)
    assert np.all(mod[:2] < 1e-12)                                              # x, v: projected
    np.testing.assert_allclose(mod[2:], math.exp(-p["R"] * 0.2 / (2 * L)), rtol=1e-8)
    assert int(ds.stable) == 1


@pytest.mark.parametrize("n", [1, 7, 40, 100])
def test_multipliers_of_an_n_fold_orbit_are_mu_to_the_n(n):
    """The 1:1 orbit past its period doubling in Omega (multipliers -1.40 and -0.277, closed form)
    taken n times: the multipliers are mu^n to 1e-10 relative, the small one (|mu|^100 ~ 1e-56) too,
    which the eigenvalues of the product of the Jacobians lose (absolute error eps |mu_1|^n)."""
    p = dict(BASE, e=0.0, Omega=2.7)
    (_, _, y0, mu), = [o for o in closed_form_1_1(**p) if abs(o[1]) > 0.05]
    smap = maps.StroboscopicMap(maps.forced_oscillator_with_stop(), p, tol=1e-15)
    orbit = find_periodic_orbit(smap, [maps.HybridState(y0, {"stuck": 0.0})] * n, n, tol=1e-12)
    want, got = np.sort_complex(mu ** n), np.sort_complex(orbit.multipliers)
    assert np.min(np.abs(want)) < (1e-30 if n == 100 else 1.0)
    np.testing.assert_allclose(got, want, rtol=1e-10, atol=0)


def test_a_velocity_zero_at_every_sample_is_scaled_by_its_amplitude():
    """Undamped, far from the stop: the orbit is x_p = F cos(Omega t) / (w0^2 - Omega^2), whose velocity
    is 0 at every strobe sample t = k T.  Scaling v by max(|v|, 1e-9) at the samples made a
    well-conditioned problem 'singular'; by its amplitude over the period it is solved."""
    p = dict(BASE, zeta=0.0, e=-5.0, Omega=1.7)
    smap = maps.StroboscopicMap(maps.forced_oscillator_with_stop(), p, tol=1e-14)
    a = p["F"] / (p["w0"] ** 2 - p["Omega"] ** 2)
    orbit = find_periodic_orbit(smap, maps.HybridState(np.array([0.9 * a, 0.01]), {"stuck": 0.0}), 1, tol=1e-12)
    assert orbit.nodes[0].y[0] == pytest.approx(a, rel=1e-12)
    assert abs(orbit.nodes[0].y[1]) < 1e-12
    assert orbit.scale[1] == pytest.approx(abs(a) * p["Omega"], rel=0.05)       # the amplitude of v
    assert orbit.conditioning["multiple_shooting"] < 1e3
