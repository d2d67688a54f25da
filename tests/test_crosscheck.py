"""Independent cross-checks: scipy at tight tolerance, extended precision, the equations themselves."""
import heyoka as hy
import numpy as np
import pytest

import maps
from bifurc.verification.baselines import rhs_1dof, solve_scipy
from maps.engines.scalar import HybridRun
from maps.impacts import impact_table

PARAMS = {"V": 90.0, "relay_hz": 9.0}


def test_contact_times_agree_with_scipy_dop853_at_rtol_1e12():
    """bifurc.verification.baselines writes the right-hand side again from docs/model.md (no heyoka) and restarts
    solve_ivp at every contact and relay switch."""
    scene = maps.get_scene("thesis-1dof").with_options(dc_law="listing")  # the reference writes C.9
    p = scene.parameters(preset="matlab-listing", **PARAMS)
    y0 = scene.system.state_vector(scene.initial_state())  # 1 mm above the stop, at rest
    run = maps.run_scene("thesis-1dof", 1.0, preset="matlab-listing", params=PARAMS, tol=1e-15)
    ref = solve_scipy(p, y0, 1.0, method="DOP853", tol=1e-12)
    mine = impact_table(run)["t"]
    assert ref.n_impacts == mine.size >= 1
    np.testing.assert_allclose(mine, ref.impact_times, rtol=0, atol=1e-9)
    np.testing.assert_allclose(run.y[:2], ref.y[:2], rtol=0, atol=1e-7)


def test_a_run_without_observation_stops_has_the_same_contacts_as_scipy():
    """``observations=False`` (a transient's run: no stop at the flight minima and deepest points)
    changes no motion: contact times against scipy DOP853 at rtol 1e-12 as the full run's
    (measured 2.6e-13 s, as the full run), the final state within 1.2e-12 of scipy's, and no observation
    is recorded."""
    scene = maps.get_scene("thesis-1dof").with_options(dc_law="listing")
    p = scene.parameters(preset="matlab-listing", **PARAMS)
    y0 = scene.system.state_vector(scene.initial_state())
    ref = solve_scipy(p, y0, 1.0, method="DOP853", tol=1e-12)
    full = HybridRun(scene.system, p, y0, tol=1e-15)
    quiet = HybridRun(scene.system, p, y0, tol=1e-15, observations=False)
    full.advance(1.0)
    quiet.advance(1.0)
    observed = {g.name for g in scene.system.guards if g.observes_only}
    assert observed & {ev.name for ev in full.events}          # the full run does stop there
    assert not observed & {ev.name for ev in quiet.events}
    assert [ev.name for ev in quiet.events] == [ev.name for ev in full.events if ev.name not in observed]
    mine = impact_table(quiet)["t"]
    assert ref.n_impacts == mine.size >= 1
    np.testing.assert_allclose(mine, ref.impact_times, rtol=0, atol=1e-11)
    np.testing.assert_allclose(quiet.y[:2], ref.y[:2], rtol=0, atol=1e-10)
    assert quiet.n_steps < full.n_steps      # no step ends at an observation
    with pytest.raises(maps.ParameterError, match="observations=True"):
        maps.engines.scalar.VariationalRun(scene.system, p, y0, observations=False)


@pytest.mark.parametrize("fp_type, tol, slow", [(np.longdouble, 1e-19, False), (hy.real128, 1e-28, True)])
def test_double_agrees_with_extended_precision(fp_type, tol, slow, request):
    """Double at tol 1e-15: each Taylor step commits at most ~tol (relative), the N steps add up,
    and 0.5 s (4.5 relay periods, largest Lyapunov exponent <~ 0.3 per period: growth e^1.35 ~ 4,
    plus 6 contacts) amplify by less than 10: the bound is 10 N tol (measured 1.3e-13 against
    2.9e-12 with N = 288).  The reference's own error (tol 1e-19 or 1e-28) is negligible."""
    if slow and not request.config.getoption("--runslow"):
        pytest.skip("real128 compiles for ~12 s: run with --runslow")
    scene = maps.get_scene("thesis-1dof").with_options(dc_law="listing")  # the reference writes C.9
    p = scene.parameters(preset="matlab-listing", **PARAMS)
    y0 = scene.system.state_vector(scene.initial_state(x=0.005, v=-3.0))
    a = HybridRun(scene.system, p, y0, tol=1e-15)
    a.advance(0.5)
    yx = np.array([fp_type(float(v)) for v in y0], dtype=fp_type if fp_type is np.longdouble else hy.real128)
    b = HybridRun(scene.system, p, yx, tol=tol, fp_type=fp_type)
    b.advance(0.5)
    ta, tb = impact_table(a)["t"], impact_table(b)["t"]
    assert ta.size == tb.size >= 3
    np.testing.assert_allclose(ta, tb, rtol=0, atol=1e-12)
    yb = np.array([float(v) for v in b.ta.state])
    assert np.max(np.abs(a.y - yb) / np.maximum(1, np.abs(yb))) < 10 * a.n_steps * 1e-15


@pytest.mark.parametrize("relay, contact", [(1.0, 0.0), (0.0, 0.0), (1.0, 1.0), (0.0, 1.0)])
def test_heyoka_rhs_equals_the_independent_numpy_rhs(relay, contact):
    """The compiled equations are docs/model.md's: forces, inductance derivatives, eq 4.16, contact law."""
    scene = maps.get_scene("thesis-1dof").with_options(dc_law="listing")  # the reference writes C.9
    system = scene.system
    p = scene.parameters(preset="matlab-listing", **PARAMS)
    f_ref = rhs_1dof(p)
    flags = dict(system.flag_defaults, P=relay, contact=contact)
    fn = hy.cfunc(system.rhs, vars=system.sym.state_vars)
    pars = np.asarray(system.par_vector(p, flags), float)[:fn.nparams]
    rng = np.random.default_rng(7)
    for _ in range(50):
        y = np.array([rng.uniform(-2e-3, 0.12), rng.uniform(-3, 3), rng.uniform(-2, 2), rng.uniform(-500, 500)])
        t = rng.uniform(0, 2)
        got = fn(y, pars=pars, time=t)
        want = np.array(f_ref(t, y, relay, contact))
        # dz/dt is a difference of terms up to the source's V w / L (~6e4 A s-2): round-off in
        # the phase w t (~1e-13 rad at t = 2 s) moves it by ~1e-9 however the product is ordered
        atol = 1e-12 * np.abs(want).max()
        scale = np.array([atol, atol, atol, 1e-13 * p["V"] * 2 * np.pi * p["f_mains"] / p["L0"]])
        assert np.all(np.abs(got - want) <= 1e-12 * np.abs(want) + np.maximum(atol, scale)), (got, want)


def _compiled_rhs(system, p, flags):
    fn = hy.cfunc(system.rhs, vars=system.sym.state_vars)
    pars = np.asarray(system.par_vector(p, dict(system.flag_defaults, **flags)), float)[:fn.nparams]
    return lambda y, t: fn(np.asarray(y, float), pars=pars, time=t)


@pytest.mark.parametrize("ac_sign", ["physical", "listing"])
@pytest.mark.parametrize("relay, contact", [(1.0, 0.0), (0.0, 0.0), (1.0, 1.0), (0.0, 1.0)])
def test_kvl_form_and_energy_equal_the_independent_numpy_model(relay, contact, ac_sign):
    """Charge form, its energy quadratures and the stored energy E_mech_el, against tests/reference_model."""
    from reference_model import energy_1dof_kvl, rhs_1dof_kvl
    scene = maps.get_scene("thesis-1dof").with_options(circuit="kvl", energy=True, ac_sign=ac_sign, dc_law="listing")
    system = scene.system
    p = scene.parameters(preset="matlab-listing", **PARAMS)
    f = _compiled_rhs(system, p, dict(P=relay, contact=contact))
    f_ref = rhs_1dof_kvl(p, ac_sign)
    rng = np.random.default_rng(11)
    for _ in range(50):
        y = np.r_[rng.uniform(-2e-3, 0.12), rng.uniform(-3, 3), rng.uniform(-0.05, 0.05), rng.uniform(-2, 2),
                  rng.uniform(-5, 5, 3)]
        t = rng.uniform(0, 2)
        want = np.array(f_ref(t, y, relay, contact))
        np.testing.assert_allclose(f(y, t), want, rtol=1e-12, atol=1e-12 * np.abs(want).max())
        E = system.evaluate(["E_mech_el"], y, p, dict(system.flag_defaults, P=relay, contact=contact), t)[0]
        assert abs(E - energy_1dof_kvl(p, y, contact)) <= 1e-12 * abs(E)


@pytest.mark.parametrize("relay, contact", [(1.0, 0.0), (0.0, 1.0)])
def test_two_dof_rhs_equals_the_independent_numpy_model(relay, contact):
    from reference_model import rhs_2dof_viscous
    scene = maps.get_scene("thesis-2dof")
    p = scene.parameters(preset="matlab-listing", **PARAMS)
    f = _compiled_rhs(scene.system, p, dict(P=relay, contact=contact))
    f_ref = rhs_2dof_viscous(p)
    rng = np.random.default_rng(5)
    for _ in range(50):
        x2 = rng.uniform(-0.5, 0.0)
        y = np.array([x2 + rng.uniform(-2e-3, 0.12), rng.uniform(-3, 3), x2, rng.uniform(-0.5, 0.5),
                      rng.uniform(-2, 2), rng.uniform(-500, 500)])
        t = rng.uniform(0, 2)
        want = np.array(f_ref(t, y, relay, contact))
        np.testing.assert_allclose(f(y, t), want, rtol=1e-12, atol=1e-12 * np.abs(want).max())
