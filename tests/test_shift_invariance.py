"""Shift-invariant analysis of the 2-DOF scenes (maps.translation): classification, exponents and
Jacobians in the reduced coordinates, so that an orbit repeating while the rig advances is
"period-n with progression d per period".

The case: the prototype under the drift soil at relay 5 Hz, a period-1 orbit in which bar, rig
and soil front advance by the same 2.944 mm every relay period (found by a sweep, then solved by
Newton in reduced coordinates as the independent reference).
"""
import math

import numpy as np
import pytest

import bifurc
import maps
from bifurc.labels.classify import ClassCode, classify_orbit, state_scale
from maps.poincare import StroboscopicMap
from maps.translation import advance_per_step, reduce_jacobian, reduce_points, translation_basis


def _orbit(n=30, transient=100):
    sc = maps.get_scene("prototype").with_options(soil="drift")
    smap = StroboscopicMap(sc, sc.parameters(relay_hz=5.0))
    return sc.system, smap, smap.orbit(sc.system.state_vector(sc.initial_state()), n, transient=transient)


def test_translation_basis_and_reduction():
    system = maps.get_scene("prototype").with_options(soil="drift").system
    e, a = translation_basis(system)
    assert system.state_names[a] == "d" and e.tolist() == [1, 0, 1, 0, 0, 0, 1]
    y = np.arange(7.0)
    r = reduce_points(system, y[None, :])[0]
    assert r[a] == 0.0 and r[0] == y[0] - y[a] and r[1] == y[1]
    assert translation_basis(maps.get_scene("thesis-1dof").system) is None


def test_a_progressing_orbit_is_periodic_in_reduced_coordinates_only():
    system, smap, o = _orbit()
    adv = advance_per_step(system, o.points)
    assert np.ptp(adv) < 1e-9 and adv.mean() < -2e-3                   # a steady 2.9 mm per period
    full = classify_orbit(o.points, o.impacts_per_step, max_period=10)
    red = classify_orbit(reduce_points(system, o.points), o.impacts_per_step, max_period=10)
    assert full["label"] != "periodic"                                  # the absolute state never repeats
    assert red["label"] == "periodic" and red["period"] == 1 and red["impacts_per_period"] >= 1


def test_exponent_in_reduced_coordinates_is_negative_where_the_full_one_is_neutral():
    """The shift is a neutral direction (multiplier 1): along it the full-coordinate companion
    neither grows nor shrinks, so its exponent tends to 0; removed, the exponent is the
    contraction of the stable orbit."""
    system, smap, o = _orbit(n=40)
    s = state_scale(reduce_points(system, o.points), 1e-9)
    reduced = smap.stretch([o.points], [{}], k0=[100], scales=[s], method="scalar")[0].mean()
    saved, system.translation = system.translation, None
    try:
        full = smap.stretch([o.points], [{}], k0=[100], scales=[state_scale(o.points, 1e-9)],
                            method="scalar")[0].mean()
    finally:
        system.translation = saved
    assert reduced < -1.5 and abs(full) < 0.05


def test_sweep_labels_the_progressing_orbit_periodic_with_its_progression():
    ds = bifurc.sweep("prototype", "relay_hz", np.array([5.0]), transient=100, record=30, soil="drift",
                      workers=1, progress=False, grazing=False, error_sample=0)
    assert ds.class_code.values[0, 0] == ClassCode.PERIODIC and ds.period.values[0, 0] == 1
    system, _, o = _orbit()
    assert float(ds.progression_per_period[0, 0]) == pytest.approx(-advance_per_step(system, o.points).mean(),
                                                                     rel=1e-7)
    text = bifurc.class_at(ds, 5.0)["text"]
    assert text.startswith("period-1,") and f"progression {1e3 * float(ds.progression_per_period[0, 0]):.4g} mm" in text
    assert "soil drift" in bifurc.classification_report(ds)


def test_reduced_exponent_and_jacobian_agree_with_newtons_multipliers():
    """Newton in reduced coordinates (bifurc.orbits.periodic) gives the multipliers; the companion's
    exponent is ln of the largest, and the reduced one-period Jacobian has the same spectrum
    while the full one adds the shift's multiplier 1."""
    orb = bifurc.periodic_orbit("prototype", soil="drift", params={"relay_hz": 5.0}, transient=100, error=False)
    mu = np.sort(orb.multiplier_abs.values)[::-1]
    system, smap, o = _orbit(n=40)
    s = state_scale(reduce_points(system, o.points), 1e-9)
    lam = smap.stretch([o.points], [{}], k0=[100], scales=[s], method="scalar")[0].mean()
    assert lam == pytest.approx(math.log(mu[0]), abs=0.02)
    J = smap.jacobian(o.state(-1), k=130)
    full = np.sort(np.abs(np.linalg.eigvals(J)))[::-1]
    red = np.sort(np.abs(np.linalg.eigvals(reduce_jacobian(system, J))))[::-1]
    assert np.min(np.abs(full - 1.0)) < 1e-8
    np.testing.assert_allclose(red[:3], mu[:3], rtol=1e-5)


def test_description_names_the_progression_per_period():
    from bifurc.labels.classify import describe
    assert describe(ClassCode.PERIODIC, 2, 3, progression=0.001) == "period-2, 3 impacts (2:3), progression 2 mm per period"
    assert describe(ClassCode.PERIODIC, 1, 1) == "period-1, 1 impact (1:1)"


def test_the_tangent_vector_exponent_is_taken_in_reduced_coordinates():
    """The tangent vector (the sweeps' default) loses its component along the translation after
    every step: its exponent equals ln of Newton's largest reduced multiplier, on both engines,
    where the full-coordinate vector would tend to the neutral 0."""
    orb = bifurc.periodic_orbit("prototype", soil="drift", params={"relay_hz": 5.0}, transient=100, error=False)
    mu0 = float(np.max(orb.multiplier_abs.values))
    system, smap, o = _orbit(n=40)
    for method in ("scalar", "batch"):
        t = smap.orbits([{}], o.points[0], 40, tangent=True, method=method)[0]   # k = 100: the same phase
        s = state_scale(reduce_points(system, t.points), 1e-9)
        lam = float(np.nanmean(t.tangent_stretch(s)[10:]))
        assert lam == pytest.approx(math.log(mu0), abs=0.02), method
