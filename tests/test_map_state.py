"""The map's state is the continuous state and the flags; guards carry roles; the gap is declared."""
import math

import heyoka as hy
import numpy as np
import pytest

import maps
from bifurc.verification.suite import CASES, case_scene
from maps import Guard, HybridState, HybridSystem, Parameter, ParameterError, State


def test_a_stored_stuck_point_restarts_exactly_in_its_stored_mode():
    """chatter-relay: the bar sticks on the stop in the first relay period and is stuck at every
    later sample.  Restarting a step from the stored hybrid state reproduces the next stored point
    (to 1e-10: a restart takes other Taylor steps than the continuous orbit; measured 2e-13).  A
    complete mode is taken as given, not re-inferred: the same state declared free and out of
    contact (stuck_bar = 0, contact = 0) is not held, and the step goes elsewhere."""
    case = next(c for c in CASES if c.name == "chatter-relay")
    sc, p = case_scene(case)
    smap = maps.StroboscopicMap(sc.system, p, tol=1e-12)
    o = smap.orbit(sc.initial_state(**case.x0), 6)
    stuck = [k for k in range(o.n) if o.state(k).flags["stuck_bar"] == 1]
    assert len(stuck) >= 4
    for k in range(o.n):
        nxt = smap.step(o.state(k), k)
        assert isinstance(nxt, HybridState)
        assert np.max(np.abs(nxt.y - o.points[k + 1]) / np.maximum(1, np.abs(o.points[k + 1]))) < 1e-10
        assert nxt.flags == o.state(k + 1).flags
    k = stuck[0]
    free = HybridState(o.points[k], dict(o.state(k).flags, stuck_bar=0.0, contact=0.0))
    try:
        other = smap.step(free, k)
        assert np.max(np.abs(other.y - o.points[k + 1])) > 1e-6
    except maps.IntegrationFailure:
        pass


def test_roles_default_from_the_old_names_and_are_checked():
    x = hy.make_vars("x")
    assert Guard("contact", x, -1).role == "impact" and Guard("lowest", x, 1).role == "flight_minimum"
    assert Guard("anything", x, 1).role == "observation"
    assert Guard("jump", x, 1, then={"a": 1}).role == "other"
    with pytest.raises(ValueError, match="role 'bounce'"):
        Guard("hit", x, -1, role="bounce")


def _ball(reset):
    """A ball under gravity above a floor at height h, restitution coefficient named e."""
    return HybridSystem(
        "ball", states=[State("y", "m", "height"), State("u", "m s-1", "velocity")],
        parameters=[Parameter("h", "m", "floor height"), Parameter("e", "1", "restitution", 0, 1)],
        rhs=lambda s: [s.u, hy.expression(-9.81)],
        guards=lambda s: [Guard("floor", s.y - s.h, -1, reset=reset(s), role="impact")])


def test_the_gap_comes_from_the_impact_guard_not_from_a_parameter_named_e():
    """Before, the default gap was 'x - e': a restitution coefficient named e read as a stop position."""
    ball = _ball(lambda s: [s.y, -s.e * s.u])
    p = dict(h=0.25, e=0.8)
    assert ball.gap([1.0, -2.0], p) == pytest.approx((0.75, -2.0))
    run = maps.HybridRun(ball, p, {"y": 1.0, "u": 0.0}, tol=1e-14)
    run.advance(0.5)
    hit = run.events[0]
    t_hit = math.sqrt(2 * 0.75 / 9.81)
    assert hit.t == pytest.approx(t_hit, abs=1e-12)
    assert hit.y_plus[1] == pytest.approx(0.8 * 9.81 * t_hit, rel=1e-12)   # reset from expressions
    assert abs(ball.gap(hit.y_minus, p)[0]) < 1e-12


def test_resets_are_traced_or_refused_by_name():
    osc = maps.forced_oscillator_with_stop()
    r = osc.reset_expressions(osc.guards[0])      # restitute(y, p) written with numpy indexing
    f = hy.cfunc(r, vars=osc.sym.state_vars)
    pars = np.array(osc.par_vector(dict(w0=1, zeta=0, F=0, Omega=1, e=0, r=0.7), {"stuck": 0}))[:f.nparams]
    np.testing.assert_allclose(f(np.array([0.0, -2.0]), pars=pars), [0.0, 1.4], rtol=1e-15)

    def opaque(y, p):
        return np.where(np.asarray(y, dtype=float) > 0, y, 0.0)    # needs numbers
    ball = _ball(lambda s: opaque)
    with pytest.raises(ParameterError, match="guard 'floor' cannot be traced"):
        ball.reset_expressions(ball.guards[0])


def test_a_sweep_stores_the_mode_at_every_sample_and_a_step_restarts_from_it():
    """chatter-relay as a one-value sweep: the stored states and flags at sample k restart the map
    and reproduce sample k + 1, including samples where the bar is stuck."""
    from bifurc.sweeps.sweep import sweep
    case = next(c for c in CASES if c.name == "chatter-relay")
    sc, p = case_scene(case)
    ds = sweep(sc.system, "V", [p["V"]], params=p, x0=case.x0, transient=0, record=4, progress=False,
               grazing=False, error_sample=0, lyapunov=False).isel(branch=0, V=0)
    names = sc.system.flag_names
    assert all(f"flag_{n}" in ds for n in names) and ds["flag_stuck_bar"].attrs["units"] == "1"
    assert (ds["flag_stuck_bar"].values[1:] == 1).all()
    smap = maps.StroboscopicMap(sc.system, p, tol=float(ds.attrs["tol"]))
    for k in range(4):
        y = np.array([float(ds[s].values[k]) for s in sc.system.state_names])
        flags = {n: float(ds[f"flag_{n}"].values[k]) for n in names}
        nxt = smap.step(HybridState(y, flags), k)
        want = np.array([float(ds[s].values[k + 1]) for s in sc.system.state_names])
        assert np.max(np.abs(nxt.y - want) / np.maximum(1, np.abs(want))) < 1e-10
