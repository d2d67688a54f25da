"""The batch engine's run on the sampling grid (maps.engines.batch.BatchEngine._run_grid, issue 47 section 3): a
system without a clock whose guards only set flags, its samples taken by heyoka's propagate_grid, against scipy's
DOP853 at tight tolerance (an independent integrator, |z| written out) and against the lane loop.

The modified Lorenz-84 flow of docs/howto/autonomous-flows.md: x' = y - x, y' = -x z + b |z|, z' = x y - a, its
|z| a sign flag switched at z = 0 by two guards."""
from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import maps
from maps import Guard, HybridSystem, Parameter, State

A, B, STEP = 5.0, 0.1, 0.5


def lorenz84():
    def guards(s):
        return [Guard("z_falls", s.z, -1, when={"sgn": 1.0}, then={"sgn": -1.0}, role="other"),
                Guard("z_rises", s.z, +1, when={"sgn": -1.0}, then={"sgn": 1.0}, role="other")]

    def sign_of_z(y, params, flags, given):
        return {} if "sgn" in given else {"sgn": 1.0 if y[2] >= 0 else -1.0}

    return HybridSystem("modified-lorenz-84-test", states=[State("x", "1", "x"), State("y", "1", "y"),
                                                           State("z", "1", "z")],
                        parameters=[Parameter("a", "1", "a", -100, 100), Parameter("b", "1", "b", -100, 100)],
                        rhs=lambda s: [s.y - s.x, -s.x * s.z + s.b * s.sgn * s.z, s.x * s.y - s.a],
                        flags={"sgn": 1.0}, guards=guards, mode_rule=sign_of_z, sample_step=STEP)


SCENE = maps.Scene("modified-lorenz-84-test", "tests/test_batch_grid.py", None, preset=None,
                   overrides={"a": (A, "test"), "b": (B, "test")}, x0={"x": -4.0, "y": 5.0, "z": 0.0},
                   builder=lorenz84, box={"x": (-15.0, 15.0), "y": (-20.0, 20.0), "z": (-20.0, 20.0)})


@pytest.fixture(scope="module")
def smap():
    return maps.StroboscopicMap(maps.problem(SCENE), tol=1e-12)


def starts(n=7):       # 7: one group of 4 lanes and one of 3 (a spare lane)
    return list(np.random.default_rng(3).uniform([-15, -20, -20], [15, 20, 20], size=(n, 3)))


def exact(y0, k0, m):
    """scipy's DOP853 at rtol 1e-13 from sample k0 over m samples, |z| as written."""
    f = lambda t, u: [u[1] - u[0], -u[0] * u[2] + B * abs(u[2]), u[0] * u[1] - A]   # noqa: E731
    t = STEP * np.arange(k0, k0 + m + 1)
    return solve_ivp(f, (t[0], t[-1]), y0, method="DOP853", rtol=1e-13, atol=1e-12, t_eval=t).y.T


def test_the_grid_run_is_the_flow_sampled_every_step_with_its_sign_flag(smap):
    eng = smap._batch_engine(4, observations=False)
    assert eng.on_grid
    got = smap.orbits([{}] * 7, starts(), 12, k0=5, events=False)
    for y0, o in zip(starts(), got):
        assert o.status == "ok"
        np.testing.assert_allclose(o.times, STEP * np.arange(5, 18), rtol=0, atol=1e-12)
        truth = exact(y0, 5, 12)
        assert np.max(np.abs(o.points - truth)) < 1e-6 * np.max(np.abs(truth))
        np.testing.assert_array_equal(o.point_flags[:, 0], np.where(truth[:, 2] >= 0, 1.0, -1.0))
        assert o.final_flags == {"sgn": 1.0 if truth[-1, 2] >= 0 else -1.0}


def test_the_grid_run_and_the_lane_loop_agree_to_the_tolerance(smap):
    eng = smap._batch_engine(4, observations=False)
    grid = smap.orbits([{}] * 7, starts(), 12, k0=5, events=False)
    eng.on_grid = False
    try:
        lanes = smap.orbits([{}] * 7, starts(), 12, k0=5, events=False)
    finally:
        eng.on_grid = True
    for g, ll in zip(grid, lanes):
        assert np.max(np.abs(g.points - ll.points)) < 1e-7
        np.testing.assert_array_equal(g.point_flags, ll.point_flags)
        np.testing.assert_allclose(g.final_state, ll.final_state, rtol=0, atol=1e-7)


def test_a_lane_that_blows_up_is_reported_by_the_lane_loop(smap):
    """A start that leaves every bound (a = 5 drives z' = x y - a; from x = y = 1e8 the flow blows up in finite
    time) ends failed, as on the lane loop, and its group's other lanes are unchanged."""
    y0 = starts(4)
    y0[2] = np.array([1e8, 1e8, 1e8])
    got = smap.orbits([{}] * 4, y0, 12, k0=5, events=False)
    assert got[2].status == "failed"
    for i in (0, 1, 3):
        truth = exact(y0[i], 5, 12)
        assert got[i].status == "ok" and np.max(np.abs(got[i].points - truth)) < 1e-6 * np.max(np.abs(truth))
