"""The drift soil law (Pavlovskaia, Wiercigroch and Grebogi, Phys. Rev. E 64, 056224, 2001):
a visco-elastic element (k_s, c_s) in series with a plastic slider of threshold P_max.

The rig alone on the soil (no solenoids, no stop: the bar exerts nothing) has closed forms:
under a constant force below the threshold it settles at the elastic deflection F/k_s with the
slider still; thrown into the soil at speed V with c_s V > P_max it progresses at once, the
element force held at P_max, until the slider's rate v2 + (P_max - k_s delta)/c_s reaches 0.
"""
import math

import pytest
from scipy.optimize import brentq

import maps
from maps import HybridRun, ModelOptions, build_system

RIG = ModelOptions(dof=2, dc=False, ac=False, stop=False, relay="none", soil="drift", energy=True)
P = dict(m1=0.155, m2=2.643, k_s=1e5, c_s=200.0, P_max=60.0)


def _rig(F_static, v2, t_end, tol=1e-15):
    system = build_system(RIG)
    run = HybridRun(system, dict(P, F_static=F_static), system.state_vector({"v2": v2}), tol=tol)
    run.advance(t_end)
    return system, run


def test_constant_force_below_threshold_deflects_the_element_and_leaves_the_slider():
    F = 20.0   # its overshoot from rest (at most 2F = 40 N) stays below P_max = 60 N
    system, run = _rig(F, 0.0, 3.0)   # decay rate c_s / (2 m2) = 37.8 s-1: e^-113 left after 3 s
    assert abs(run["d"]) <= 1e-15
    assert run["x2"] == pytest.approx(-F / P["k_s"], rel=1e-12)   # the soil lies toward -x
    assert not any(ev.name == "soil_yield" for ev in run.events)
    assert run.flags["soil_el"] == 1.0 and run.flags["soil_pl"] == 0.0


def test_a_single_impulse_advances_the_slider_by_the_closed_form():
    """Rig on the front (delta = 0) given v2 = -V by an impulse m2 V, no other force.  With
    c_s V > P_max it progresses from the start: m2 dv2/dt = P_max, so v2 = -V + P_max t / m2, and
    d(delta)/dt = (P_max - k_s delta)/c_s gives delta = P_max/k_s (1 - exp(-k_s t/c_s)).  Progression
    ends at t_e where dd/dt = v2 + (P_max - k_s delta)/c_s = -V + P_max t/m2 + P_max/c_s exp(-k_s t/c_s)
    = 0; the slider has then moved d = x2 + delta = -V t_e + P_max t_e^2/(2 m2) + delta(t_e), and
    it stays there (the element unloads, the rig leaves the front and flies off backward)."""
    V, m2, ks, cs, Pm = 1.0, P["m2"], P["k_s"], P["c_s"], P["P_max"]
    rate = lambda t: -V + Pm * t / m2 + Pm / cs * math.exp(-ks * t / cs)  # noqa: E731
    t_e = brentq(rate, 1e-6, 2 * V * m2 / Pm, xtol=1e-16, rtol=1e-15)
    d_e = -V * t_e + Pm * t_e**2 / (2 * m2) + Pm / ks * (1 - math.exp(-ks * t_e / cs))
    system, run = _rig(0.0, -V, 0.5)
    names = [ev.name for ev in run.events]
    assert names == ["soil_hold", "soil_leave"]
    assert run.events[0].t == pytest.approx(t_e, rel=1e-12)
    assert run["d"] == pytest.approx(d_e, rel=1e-12)
    assert run["v2"] > 0 and run["x2"] > run["d"]                # clear of the front, moving off


def test_soil_dissipation_is_plastic_work_plus_the_damper():
    """Energy: the kinetic energy the rig loses equals the slider's P_max x travel plus the
    damper's integral (quadrature states), the element unloaded at the end."""
    V = 1.0
    system, run = _rig(0.0, -V, 0.5)
    E_pl, E_damp = run["E_soil_plastic"], run["E_soil_damper"]
    assert E_pl == pytest.approx(P["P_max"] * -run["d"], rel=1e-10)
    lost = 0.5 * P["m2"] * (V**2 - run["v2"] ** 2)
    assert lost == pytest.approx(E_pl + E_damp, rel=1e-10)
    assert E_damp > 0.01 * E_pl                                  # both terms matter


def test_the_prototype_progresses_under_drift_soil_on_both_engines_with_the_same_start_mode():
    """The start rule puts a rig pressed on the front in contact; at the scene's defaults the
    rig advances with the slider (x2 - d stays within the element's deflection, P_max/k_s)."""
    sc = maps.get_scene("prototype").with_options(soil="drift")
    p = sc.parameters()
    run = maps.run_scene(sc, 1.0, params=p)
    assert run.status == "ok"
    assert {"soil_yield", "soil_hold"} <= {ev.name for ev in run.events}
    assert run["d"] < -1e-3
    assert abs(run["x2"] - run["d"]) < 2 * p["P_max"] / p["k_s"]


def test_momentum_is_conserved_clear_of_the_drift_soil():
    """The front far ahead (d = -1 m): no soil force, no static force, only internal forces."""
    sc = maps.get_scene("prototype").with_options(soil="drift")
    p = sc.parameters(F_static=0.0)
    run = maps.HybridRun(sc.system, p, sc.initial_state(v1=-1.0, d=-1.0), tol=1e-15)
    P0 = p["m1"] * run["v1"] + p["m2"] * run["v2"]
    run.advance(2.0)
    assert sum(ev.name == "contact" for ev in run.events) >= 5
    assert abs(p["m1"] * run["v1"] + p["m2"] * run["v2"] - P0) / p["m1"] < 1e-9
    assert run.flags["soil_el"] == 0.0 and run["d"] == -1.0


def test_soil_option_on_the_command_line_and_in_datasets():
    ds = maps.simulate("prototype", t_end=0.05, soil="drift")
    assert ds.attrs["soil"] == "drift" and "Pavlovskaia" in ds.attrs["soil_source"]
    assert ds.attrs["param_P_max_source"].split(": ", 1)[1].startswith("ASSUMPTION")
    with pytest.raises(maps.ParameterError, match="soil"):
        maps.simulate("thesis-1dof", t_end=0.05, soil="drift")
    with pytest.raises(maps.ParameterError, match="soil"):
        maps.simulate("prototype", t_end=0.05, soil="sand")


def test_coulomb_compaction_stops_the_rig_at_twice_the_balance_depth():
    """Compaction (R = R0 (1 + depth/L)): a rig pushed by F > R0 from rest at the surface obeys
    m2 z'' = F - R0 (1 + z/L) for its depth z = -x2, a harmonic motion about z* = L (F/R0 - 1):
    it comes to rest at 2 z* after pi sqrt(m2 L / R0) and stays stuck (R there is 2F - R0 > F)."""
    o = ModelOptions(dof=2, dc=False, ac=False, stop=False, relay="none", soil="coulomb", compaction=True)
    system = build_system(o)
    assert system.translation is None                  # depth-dependent: no shift invariance
    R0, L, F, m2 = 100.0, 0.16, 130.0, P["m2"]
    run = HybridRun(system, dict(m1=P["m1"], m2=m2, F_static=F, soil_friction=R0, soil_depth_scale=L),
                    system.state_vector({}), tol=1e-15)
    run.advance(1.0)
    z_star = L * (F / R0 - 1)
    stops = [ev for ev in run.events if ev.name == "rig_stop" and ev.t > 0]   # (one at the start, v2 = 0)
    assert len(stops) == 1 and stops[0].t == pytest.approx(math.pi * math.sqrt(m2 * L / R0), rel=1e-12)
    assert -run["x2"] == pytest.approx(2 * z_star, rel=1e-12)
    assert run.flags["stuck"] == 1.0


def test_compaction_default_is_fitted_to_fig_5_22():
    from maps.presets import COMMON
    L = COMMON["soil_depth_scale"][0]
    assert 4.3 / (1 + 0.9 / L) == pytest.approx(0.65, rel=1e-12)   # rate ~ 1 / resistance (the stated assumption)
    assert "FITTED" in COMMON["soil_depth_scale"][1]


def test_drift_compaction_plastic_work_is_the_integral_of_the_growing_threshold():
    """With compaction the slider's threshold is P_max (1 + depth/L), depth = -d: the plastic work
    over a travel D is P_max (D + D^2 / (2 L)), and the kinetic energy lost is still that plus the
    damper's integral."""
    o = ModelOptions(dof=2, dc=False, ac=False, stop=False, relay="none", soil="drift", energy=True, compaction=True)
    system = build_system(o)
    L, V = 0.002, 1.0                       # a 2 mm depth scale: the threshold grows noticeably over the travel
    run = HybridRun(system, dict(P, F_static=0.0, soil_depth_scale=L), system.state_vector({"v2": -V}), tol=1e-15)
    run.advance(0.5)
    D = -run["d"]
    assert D > 1e-3
    assert run["E_soil_plastic"] == pytest.approx(P["P_max"] * (D + D**2 / (2 * L)), rel=1e-10)
    lost = 0.5 * P["m2"] * (V**2 - run["v2"] ** 2)
    assert lost == pytest.approx(run["E_soil_plastic"] + run["E_soil_damper"], rel=1e-10)
