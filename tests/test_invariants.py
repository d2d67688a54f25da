"""Invariants of the model: momentum, energy balance, agreement of the two circuit forms."""
import numpy as np
import pytest

import maps
from maps.impacts import impact_table

HIT = {"x": 0.005, "v": -3.0}  # 5 mm above the stop, moving toward it against the DC pull
CASE = dict(preset="matlab-listing", params={"V": 90.0, "relay_hz": 9.0})


def test_two_dof_momentum_is_conserved_without_soil_and_static_force():
    """Internal forces only (solenoids and stop act equally on bar and rig)."""
    scene = maps.get_scene("thesis-2dof")
    p = scene.parameters(preset="matlab-listing", V=90, relay_hz=9, soil_c=0.0, F_static=0.0)
    run = maps.HybridRun(scene.system, p, scene.initial_state(v1=-1.0), tol=1e-15)
    P0 = p["m1"] * run["v1"] + p["m2"] * run["v2"]
    scale = p["m1"] * 1.0  # the bar's initial momentum magnitude [kg m/s]
    worst = 0.0
    for k in range(1, 21):  # 20 relay periods, checked at each
        run.advance(k / 9.0)
        worst = max(worst, abs(p["m1"] * run["v1"] + p["m2"] * run["v2"] - P0) / scale)
    assert sum(ev.name == "contact" for ev in run.events) >= 10
    assert worst < 1e-9


def _energy_residual(run, E0):
    y = run.y
    names = run.system.state_names
    W, ER, Ec = (y[names.index(n)] for n in ("W_src", "E_R", "E_c"))
    E = float(run.system.evaluate(["E_mech_el"], y, run.params, run.flags, run.t)[0])
    throughput = abs(W) + ER + Ec
    return abs((E - E0) - (W - ER - Ec)) / throughput, throughput


@pytest.mark.parametrize("ac_sign", ["physical", "listing"])
def test_kvl_energy_balance_closes_only_with_the_physical_force(ac_sign):
    """d/dt(kinetic + DC potential + L i^2/2 + q^2/2C + stop elastic) = u i - R i^2 - c v^2 in contact,
    exactly when the AC force is +dW_mag/dx; the listing's reversed sign breaks the balance."""
    scene = maps.get_scene("thesis-1dof").with_options(circuit="kvl", energy=True, ac_sign=ac_sign)
    p = scene.parameters(preset="matlab-listing", V=90, relay_hz=9)
    run = maps.HybridRun(scene.system, p, scene.initial_state(**HIT), tol=1e-15)
    E0 = float(run.system.evaluate(["E_mech_el"], run.y, run.params, run.flags, 0.0)[0])
    worst = 0.0
    for k in range(1, 11):  # 10 relay periods
        run.advance(k / 9.0)
        res, throughput = _energy_residual(run, E0)
        worst = max(worst, res)
    assert impact_table(run)["t"].size >= 5 and throughput > 1.0  # joules moved through the circuit
    if ac_sign == "physical":
        assert worst < 1e-8
    else:
        assert worst > 1e-3


def _pair(W, periods=4):
    out = []
    for circuit in ("thesis", "kvl"):
        out.append(maps.run_scene("thesis-1dof", periods / W, x0=HIT, circuit=circuit, tol=1e-15,
                                  preset="matlab-listing", params={"V": 90.0, "relay_hz": W}))
    return out


def test_circuit_forms_agree_when_switches_fall_on_zeros_of_the_source():
    """At 5 Hz every switch (t = n/10 s) is a zero of sin(2 pi 50 t): the derivative form loses nothing."""
    a, b = _pair(5.0)
    ia, ib = a.system.state_names.index("i"), b.system.state_names.index("i")
    assert impact_table(a)["t"].size >= 5
    np.testing.assert_allclose(a.y[:2], b.y[:2], rtol=0, atol=1e-9)
    assert abs(a.y[ia] - b.y[ib]) < 1e-9
    np.testing.assert_allclose(impact_table(a)["t"], impact_table(b)["t"], rtol=0, atol=1e-9)


def test_circuit_forms_differ_when_the_relay_cuts_the_source_mid_cycle():
    """At 6 Hz the switch at t = 1/12 s cuts sin(2 pi 50 t) at 0.5: the thesis form drops that jump."""
    a, b = _pair(6.0)
    ia, ib = a.system.state_names.index("i"), b.system.state_names.index("i")
    assert abs(a.y[0] - b.y[0]) > 1e-6 and abs(a.y[1] - b.y[1]) > 1e-6 and abs(a.y[ia] - b.y[ib]) > 1e-6


def test_odd_mains_half_cycles_per_relay_period_flip_the_current_not_the_motion():
    """When 100/W is odd (4 Hz: 25 half-cycles) the source changes sign from one relay period to
    the next; the circuit is linear in i and the force goes as i^2, so the flow maps
    (x, v, i, z) at t to (x, v, -i, -z) at t + 1/W. Checked by starting the second period from the
    mirrored state: it must reproduce the first period's motion with the opposite current."""
    scene = maps.get_scene("thesis-1dof")
    p = scene.parameters(preset="matlab-listing", V=90, relay_hz=4)
    y0 = scene.system.state_vector(scene.initial_state(**HIT))
    a = maps.HybridRun(scene.system, p, y0, tol=1e-15)
    a.advance(0.25)  # one relay period from t = 0
    mirrored = y0 * np.array([1, 1, -1, -1])
    b = maps.HybridRun(scene.system, p, mirrored, t0=0.25, tol=1e-15)
    b.advance(0.5)  # the next relay period, from the mirrored start
    assert impact_table(a)["t"].size >= 1
    np.testing.assert_allclose(b.y[:2], a.y[:2], rtol=0, atol=1e-9)
    np.testing.assert_allclose(b.y[2:], -a.y[2:], rtol=0, atol=1e-9 * max(1, np.abs(a.y[2:]).max()))
    np.testing.assert_allclose(impact_table(b)["t"] - 0.25, impact_table(a)["t"], rtol=0, atol=1e-9)
