"""Continuation through a grazing (issue 28, section 3): the impact oscillator x'' + 2 zeta w0 x' + w0^2 x =
F cos(Omega t), stop at x = e, v -> -r v, with w0 = 1, zeta = 0.05, Omega = 0.8, e = -0.5, r = 0.7,
continued in F from 0.15 to 0.5.

Closed form: the non-impacting orbit is the linear forced response of amplitude
A = F / sqrt((w0^2 - Omega^2)^2 + (2 zeta w0 Omega)^2); it grazes the stop where A = |e|.  The impacting
branch beyond it is checked against a long scipy simulation (period 2 on one side of its period doubling,
period 1 on the other) and its impact speed against Nordmark's prediction from the exact Jacobians.
"""
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import bifurc
import maps
from bifurc.orbits.arclength import continue_branch
from bifurc.orbits.continuation import ContinuationProblem
from bifurc.orbits.nordmark import impact_speed, predict
from bifurc.orbits.periodic import find_periodic_orbit
from bifurc.storage.schema import SPECIAL_KINDS
from maps.poincare import StroboscopicMap

P = dict(w0=1.0, zeta=0.05, Omega=0.8, e=-0.5, r=0.7)
F_GRAZE = abs(P["e"]) * math.hypot(P["w0"] ** 2 - P["Omega"] ** 2, 2 * P["zeta"] * P["w0"] * P["Omega"])


@pytest.fixture(scope="module")
def ds():
    return bifurc.continue_orbit("impact-oscillator", "F", (0.15, 0.5), params=P, x0={"x": 0.0, "v": 0.0},
                                 transient=200)


@pytest.fixture(scope="module")
def branch():
    pb = maps.problem("impact-oscillator", params=dict(P, F=0.15), x0={"x": 0.0, "v": 0.0})
    smap = StroboscopicMap(pb, tol=1e-12)
    orbit = find_periodic_orbit(smap, smap.orbit({"x": 0.0, "v": 0.0}, 1, transient=200).state(0), 1, tol=1e-11)
    cp = ContinuationProblem(smap, "F", 1, 0, scale=orbit.scale, p_scale=0.35, p_ref=0.15, tol=1e-11)
    return cp, continue_branch(cp, orbit, 0.15, 0.5)


def _kinds(ds):
    return [SPECIAL_KINDS[int(k)] for k in ds.special_kind.values]


def test_grazing_located_at_the_closed_form_amplitude_and_passed(ds):
    kinds = _kinds(ds)
    g = kinds.index("grazing")
    assert abs(float(ds.special_value.values[g]) - F_GRAZE) < 1e-8
    # one point dimension: non-impacting points up to the grazing, impacting (1 per period) after it
    F, ipp = ds.F.values, ds.impacts_per_period.values
    i = int(ds.special_point.values[g])
    assert np.all(ipp[:i + 1] == 0) and np.all(ipp[i + 1:] == 1)
    assert F[i] <= F_GRAZE + 1e-8 < F[i + 1] < F_GRAZE + 1e-4
    assert F[-1] >= 0.5 and len(set(ds.branch_id.values)) == 1
    assert "continued from" in ds.attrs["branch_stop_reasons"]
    assert "Nordmark" in str(ds.special_note.values[g])


def _scipy_strobe(F, y0, periods, rtol=1e-11):
    """The impact oscillator by scipy (DOP853, the impact as a terminal event, v -> -r v), sampled every
    forcing period: the states at t = 2 pi k / Omega."""
    w0, z, W, e, r = P["w0"], P["zeta"], P["Omega"], P["e"], P["r"]
    T = 2 * math.pi / W

    def rhs(t, y):
        return [y[1], F * math.cos(W * t) - 2 * z * w0 * y[1] - w0 * w0 * y[0]]

    def hit(t, y):
        return y[0] - e
    hit.terminal, hit.direction = True, -1
    y, t, out = np.array(y0, float), 0.0, []
    for k in range(1, periods + 1):
        while True:
            sol = solve_ivp(rhs, (t, k * T), y, method="DOP853", rtol=rtol, atol=1e-13, events=hit)
            t, y = float(sol.t[-1]), sol.y[:, -1].copy()
            if sol.status != 1:
                break
            y = np.array([e, -r * y[1]])
        out.append(y.copy())
    return np.array(out)


def test_impacting_branch_stability_change_is_a_period_doubling_against_scipy(ds):
    kinds = _kinds(ds)
    assert kinds.count("period_doubling") == 1
    k = kinds.index("period_doubling")
    F_pd, i = float(ds.special_value.values[k]), int(ds.special_point.values[k])
    mu = ds.multiplier_abs.values
    impacting = ds.impacts_per_period.values == 1
    assert np.all(mu[impacting & (ds.F.values < F_pd - 1e-6), 0] > 1)       # unstable from the grazing on
    assert np.all(mu[impacting & (ds.F.values > F_pd + 1e-6), 0] < 1)       # then stable
    assert abs(float(ds.special_multiplier_abs.values[k, 0]) - 1.0) < 1e-6
    # scipy, 300 forcing periods: above F_pd one state per period; below it the samples alternate, the
    # period-2 split squared linear in F_pd - F and vanishing at F_pd
    splits = []
    for dF in (0.004, 0.008):
        x = _scipy_strobe(F_pd - dF, [0.0, 0.0], 300)[-20:]
        assert np.max(np.abs(x[2:] - x[:-2])) < 1e-7                       # period 2 ...
        splits.append(float(np.max(np.abs(x[1] - x[0]))))                 # ... not period 1
    assert min(splits) > 1e-3
    F0 = F_pd - 0.004 + splits[0] ** 2 * 0.004 / (splits[1] ** 2 - splits[0] ** 2)
    assert abs(F0 - F_pd) < 3e-4                      # measured 8.8e-5 at 400 periods
    x = _scipy_strobe(F_pd + 0.004, [0.0, 0.0], 300)[-20:]
    assert np.max(np.abs(x[1:] - x[:-1])) < 1e-6
    j = int(np.argmin(np.abs(ds.F.values - (F_pd + 0.004)) + 10 * (~impacting)))
    assert abs(ds.F.values[j] - (F_pd + 0.004)) < 0.02                    # a branch point near it


def test_impact_speed_near_grazing_follows_nordmarks_prediction(branch):
    cp, br = branch
    sp = [s for s in br.special if s.kind == "grazing"][0]
    pred = predict(cp, sp)
    assert pred.outcome in ("persistence", "period-adding", "chaos") and pred.K > 0
    # closed form of the feedback: the linear flow's monodromy E = exp(A T) at any section, n = (1, 0),
    # b = (0, 1 + r): K = (1 + r) [(I - E)^-1 E]_01; sigma = d(min gap)/dF = -1 / sqrt(D) (amplitude F / sqrt(D))
    from scipy.linalg import expm
    E = expm(np.array([[0.0, 1.0], [-P["w0"] ** 2, -2 * P["zeta"] * P["w0"]]]) * 2 * math.pi / P["Omega"])
    assert abs(pred.K - (1 + P["r"]) * np.linalg.solve(np.eye(2) - E, E)[0, 1]) < 1e-8
    assert abs(pred.sigma + abs(P["e"]) / F_GRAZE) < 1e-8
    assert abs(pred.a - P["Omega"] ** 2 * abs(P["e"])) < 1e-8          # the gap's acceleration at the touch
    # independent: the impacting orbit at F_g + dF by Newton from a first guess off the branch
    rows = []
    for pt in br.points:
        dF = pt.p - sp.p
        if 0 < dF < 0.02 and pt.impacts_per_period == 1:
            v = [abs(ev.y_minus[1]) for evs in pt.events for ev in evs if ev.name == "contact"][0]
            rows.append((dF, v, impact_speed(pred, dF)))
    rows = np.array(rows)
    assert len(rows) >= 4 and rows[0, 0] < 1e-4
    # the impacting orbit's impact speed is linear in F - F_g (v^2 is not: a fit of v^2 against dF has
    # no constant slope), with the slope |sigma| / K of the discontinuity map
    slope = np.polyfit(np.log(rows[:, 0]), np.log(rows[:, 1]), 1)[0]
    assert abs(slope - 1.0) < 0.03
    rel = np.abs(rows[:, 1] - rows[:, 2]) / rows[:, 1]
    assert np.all(rel < 20 * rows[:, 0] + 1e-3)                          # agreement to O(dF)
    assert abs(rows[0, 1] / rows[0, 0] - abs(pred.sigma / pred.K)) < 1e-3 * abs(pred.sigma / pred.K) + 1e-2


def test_stated_tolerances_bound_the_real_error_within_100x(ds):
    """Each located point's tolerance is measured (a re-location at tol/100): never below its real error
    against the closed form, at most 100 times it (the grazing here; the frequency response's period
    doubling against its closed form, tests/test_frequency_response.py)."""
    from scipy.optimize import brentq
    from test_frequency_response import P as P_FR, _nearest
    g = _kinds(ds).index("grazing")
    err, tol = abs(float(ds.special_value.values[g]) - F_GRAZE), float(ds.special_tolerance.values[g])
    assert err <= tol <= 100 * max(err, 1e-16 * F_GRAZE)             # measured: 5.4e-15 <= 2.4e-14
    fr = bifurc.continue_orbit("impact-oscillator", "Omega", (2.5, 3.5), params=P_FR)
    i = int(fr.special_point[0])
    y = np.array([float(fr.x[i, 0]), float(fr.v[i, 0])])

    def f(Om):
        return float(np.real(np.prod(_nearest(dict(P_FR, Omega=Om), float(fr.section_phase[i]), y)[1] + 1.0)))
    pd = brentq(f, float(fr.Omega[i]) - 0.02, float(fr.Omega[i + 1]) + 0.02, xtol=1e-15, rtol=1e-15)
    err, tol = abs(float(fr.special_value[0]) - pd), float(fr.special_tolerance[0])
    assert err <= tol <= 100 * err                                     # measured: 2.5e-12 <= 4.1e-12
