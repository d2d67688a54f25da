"""The three DC-force laws of the thesis (MODEL.md section 1), each against an independent truth:
Table 4.1 read here from the CSV, a least-squares cubic computed here with numpy, listing C.9's
expression typed here as printed, closed-form free fall, and the energy balance."""
import numpy as np
import pytest

import maps
from maps.engines.scalar import HybridRun
from maps.impacts import impact_table
from maps.model import dc_region_flags, measured_dc_regions
from maps.parameters import ParameterError



def _table():
    """Table 4.1 straight from the shipped CSV: |xa| [m], pull toward the centre [N] (20 V DC)."""
    from importlib import resources
    text = resources.files("maps").joinpath("data", "dc_force_table_4_1.csv").read_text()
    rows = np.array([[float(v) for v in ln.split(",")] for ln in text.splitlines()[2:] if ln.strip()])
    return rows[:, 0], rows[:, 1]


def _dc_only(law):
    sc = maps.get_scene("dc-only").with_options(dc_law=law)
    return sc, sc.system, sc.parameters()


def _force(system, p, xa, flags=None):
    """The compiled F_dc [N] at xa [m] (bar at rest), with the law's region flags from the state."""
    y = np.array([p["d_dc"] + xa, 0.0])
    fl = dict(system.flag_defaults, **(flags if flags is not None else dc_region_flags(system.options, y, p)))
    return float(system.evaluate(["F_dc"], y, p, fl)[0])


def test_measured_law_passes_through_every_table_point_from_both_sides():
    """Each region's cubic, evaluated at both of its ends, is -sign(xa) x the table value."""
    x, T = _table()
    sc, system, p = _dc_only("measured")
    regions = measured_dc_regions()
    table = dict(zip(np.round(x, 6), T))
    checked = 0
    for k, (lo, hi, *_rest) in enumerate(regions):
        if abs(lo) > 0.0291 or abs(hi) > 0.0291:
            continue                                     # the two outer regions: tested below
        flags = maps.model._region_flags(k)
        for xa in (lo, hi):
            want = -np.sign(xa) * table[round(abs(xa), 6)]
            assert abs(_force(system, p, xa, flags) - want) < 1e-12, (k, xa)
            checked += 1
    assert checked == 2 * 16
    for xa, Tk in zip(x, T):   # and through the one rule that picks the region from the state
        assert abs(_force(system, p, -xa) - Tk) < 1e-12 or xa == 0.029


def test_measured_law_is_odd_monotone_between_the_points_and_zero_beyond_29_mm():
    x, T = _table()
    sc, system, p = _dc_only("measured")
    xs = np.linspace(0.0, 0.02899, 2000)
    pull = np.array([-_force(system, p, xa) for xa in xs])
    assert np.all(np.diff(pull) >= -1e-12)                       # monotone
    assert pull.min() >= -1e-12 and pull.max() <= T.max() + 1e-12  # within the table's range
    push = np.array([_force(system, p, -xa) for xa in xs])
    np.testing.assert_allclose(push, pull, rtol=0, atol=1e-12)  # odd: F(-xa) = -F(xa)
    for xa in (0.02901, 0.0291, 0.035, 0.09, -0.02901, -0.03, -0.0625):
        assert _force(system, p, xa) == 0.0


def test_a_bar_released_35_mm_above_the_dc_centre_falls_freely():
    """Measured law, V = 0: no DC force beyond 29 mm, no AC force, no weight offset:
    x(t) = x0 - g t^2 / 2 until the bar reaches xa = 29 mm (t = sqrt(2 * 6 mm / g))."""
    p = maps.get_scene("thesis-1dof").parameters(V=0.0)
    x0 = p["d_dc"] + 0.035
    t_edge = np.sqrt(2 * 0.006 / p["g"])
    t = np.linspace(0.0, 0.99 * t_edge, 50)
    ds = maps.simulate("thesis-1dof", t_end=t_edge * 0.99, t_eval=t, dc_law="measured", params={"V": 0.0},
                       x0={"x": x0, "v": 0.0}, tol=1e-15)
    assert ds.attrs["dc_law"] == "measured" and ds.attrs["status"] == "ok"
    np.testing.assert_allclose(ds.x.values, x0 - 0.5 * p["g"] * t**2, rtol=0, atol=1e-12)


def test_fit_law_is_the_least_squares_odd_cubic_of_the_table_negated():
    """Eq 4.6 = argmin over (a3, a1) of sum (a3 xa^3 - a1 xa - F)^2 (computed here), and the
    model's fit force is its negative (eq 4.7 less the weight offset, which cancels m g)."""
    x, T = _table()
    (a3, a1), *_ = np.linalg.lstsq(np.stack([x**3, -x], axis=1), T, rcond=None)
    sc, system, p = _dc_only("fit")
    assert abs(p["a3"] - a3) / a3 < 1e-3 and abs(p["a1"] - a1) / a1 < 1e-3
    for xa in (-0.0625, -0.02, 0.01, 0.029):
        want = -(a3 * xa**3 - a1 * xa)
        assert abs(_force(system, p, xa) - want) <= 1e-3 * (a3 * abs(xa)**3 + a1 * abs(xa))


def test_listing_law_is_listing_c9_as_printed():
    """C.9: F1 = -1.473E5*xa.^3 + 1.652E-14*xa.^2 - 15.38*xa + m*g; the weight -m g cancels its
    offset, so the net non-contact force of dc-only is F1 - m g."""
    sc, system, p = _dc_only("listing")
    m, g = p["m"], p["g"]
    for xa in (-0.0625, 0.012, 0.029):
        F1 = -1.473E5 * xa**3 + 1.652E-14 * xa**2 - 15.38 * xa + m * g
        y = np.array([p["d_dc"] + xa, 0.0])
        N = float(system.evaluate(["N_bar"], y, p, system.flag_defaults)[0])
        assert abs(N - (F1 - m * g)) <= 1e-12 * abs(F1)


def test_listing_overestimates_the_table_by_its_sign_not_by_the_fit():
    """Over 10-28 mm C.9 gives 1.26-1.82x the spring balance; eq 4.6 (same magnitudes, the linear
    term's sign flipped back) stays within 0.45 N of every reading."""
    x, T = _table()
    _, sl, pl = _dc_only("listing")
    _, sf, pf = _dc_only("fit")
    inside = (x >= 0.01) & (x <= 0.028)
    ratio = np.array([-_force(sl, pl, xa) for xa in x[inside]]) / T[inside]
    assert 1.25 < ratio.min() and ratio.max() < 1.85
    fit = np.array([-_force(sf, pf, xa) for xa in x])
    assert np.max(np.abs(fit - T)) < 0.46


@pytest.mark.parametrize("law, x0, v0", [("listing", 0.005, -3.0), ("fit", 0.005, -3.0),
                                         ("measured", 0.0625 - 0.02, 0.9)])
def test_kvl_energy_audit_closes_under_each_law(law, x0, v0):
    """d/dt(kinetic + law's potential [+ m g x for measured] + L i^2/2 + q^2/2C + stop elastic)
    = u i - R i^2 - c v^2; the measured law's potential is the piecewise integral, continuous at
    every knot and at the edge: the region changes below would otherwise break the balance."""
    scene = maps.get_scene("thesis-1dof").with_options(circuit="kvl", energy=True, dc_law=law)
    p = scene.parameters(preset="matlab-listing", V=90, relay_hz=9)
    run = HybridRun(scene.system, p, scene.initial_state(x=x0, v=v0), tol=1e-15)
    E0 = float(run.system.evaluate(["E_mech_el"], run.y, run.params, run.flags, 0.0)[0])
    names = run.system.state_names
    worst = 0.0
    for k in range(1, 11):
        run.advance(k / 9.0)
        y = run.y
        W, ER, Ec = (y[names.index(n)] for n in ("W_src", "E_R", "E_c"))
        E = float(run.system.evaluate(["E_mech_el"], y, run.params, run.flags, run.t)[0])
        throughput = abs(W) + ER + Ec
        worst = max(worst, abs((E - E0) - (W - ER - Ec)) / throughput)
    assert throughput > 0.1
    if law == "measured":
        assert sum(ev.name in ("dc_up", "dc_down") for ev in run.events) >= 10
    else:
        assert impact_table(run)["t"].size >= 5
    assert worst < 1e-8


def test_under_the_measured_law_a_bar_at_rest_on_the_stop_never_leaves_it():
    """The finding of issue 14: the stop (xa = -62.5 mm) lies outside Table 4.1, so no DC force
    acts there; the physical AC force pulls down and the weight acts: from the listings' start
    (on the stop at rest, i = 0.1 A) at 90 V the bar never rises above the stop in 3 s."""
    ds = maps.simulate("thesis-1dof", t_end=3.0, dt=1e-3, preset="matlab-listing", dc_law="measured",
                       params={"V": 90.0, "relay_hz": 5.0}, x0={"x": 0.0, "v": 0.0, "i": 0.1})
    assert ds.attrs["status"] == "ok" and ds.attrs["dc_law"] == "measured"
    assert float(ds.x.max()) <= 0.0
    assert float(ds.x.min()) > -1e-3         # pressed in by its weight and the AC pull: micrometres


def test_the_law_follows_the_preset_and_is_recorded():
    a = maps.simulate("thesis-1dof", periods=0.2, dt=1e-3)
    b = maps.simulate("thesis-1dof", periods=0.2, dt=1e-3, preset="matlab-listing")
    c = maps.simulate("thesis-1dof", periods=0.2, dt=1e-3, preset="matlab-listing", dc_law="measured")
    assert (a.attrs["dc_law"], b.attrs["dc_law"], c.attrs["dc_law"]) == ("fit", "listing", "measured")
    assert "eqs 4.6-4.7" in a.attrs["dc_law_source"] and "C.9" in b.attrs["dc_law_source"]
    assert "Table 4.1" in c.attrs["dc_law_source"] and "param_a1" not in c.attrs
    assert "eq 4.7" in a.attrs["param_a2_source"] and a.attrs["param_a2"] == 1.625e-14
    assert "C.9" in b.attrs["param_a2_source"] and b.attrs["param_a2"] == 1.652e-14
    assert a.attrs["preset"] == "thesis-text" and "0.5625" in a.attrs["preset_notes"]
    assert "i = 0.1 A" in b.attrs["preset_notes"]


def test_an_unknown_law_is_a_one_line_error_naming_the_allowed_ones():
    with pytest.raises(ParameterError, match=r"dc_law.*allowed: listing, fit, measured"):
        maps.simulate("thesis-1dof", periods=1, dc_law="table")


def test_cli_and_sweep_record_the_law(tmp_path, capsys):
    """--dc-law reaches the compiled model through the CLI, and a sweep (whose workers get no preset)
    runs and records the law it was given; the batch engine hands the measured law to the scalar path."""
    from bifurc.cli import main
    from bifurc.sweeps.sweep import sweep
    nc = tmp_path / "s.nc"
    assert main(["simulate", "--preset", "matlab-listing", "--dc-law", "measured", "--set", "V=90",
                 "--relay-hz", "5", "--periods", "2", "--x0", "x=0,v=0,i=0.1", "-o", str(nc)]) == 0
    import xarray as xr
    ds = xr.open_dataset(nc)
    assert ds.attrs["dc_law"] == "measured" and float(ds.x.max()) <= 0.0
    d = sweep("thesis-1dof", "relay_hz", [5.0, 6.0], preset="matlab-listing", dc_law="measured", params={"V": 90.0},
              transient=2, record=3, progress=False, batch_size=4, lyapunov=False)
    assert d.attrs["dc_law"] == "measured" and "Table 4.1" in d.attrs["dc_law_source"]
    assert (d.class_code.values >= 0).all()
    d2 = sweep("thesis-1dof", "relay_hz", [5.0], preset="matlab-listing", params={"V": 90.0},
               transient=2, record=3, progress=False, lyapunov=False)
    assert d2.attrs["dc_law"] == "listing"
    assert main(["simulate", "--dc-law", "table"]) == 2      # one line naming the allowed laws
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "listing" in err[0] and "measured" in err[0]


@pytest.mark.parametrize("x0, v0", [(0.0775, 0.04), (0.0775, -0.04), (0.0915, 0.3)])
def test_a_bar_entering_a_region_at_its_apex_falls_back_through_it(x0, v0):
    """Started exactly on a knot (xa = 15 mm, 29 mm) and turning round inside the new region, the
    bar must leave it again: the region flags always contain xa (to the 1e-12 m overlap), checked
    at every region change and at the end; V = 0, so the free fall below the edge is closed form."""
    sc = maps.get_scene("thesis-1dof").with_options(dc_law="measured")
    p = sc.parameters(preset="matlab-listing", V=0.0)
    run = HybridRun(sc.system, p, sc.initial_state(x=x0, v=v0, i=0.0, z=0.0), tol=1e-13, max_events=None)
    run.advance(0.08)
    changes = [ev for ev in run.events if ev.name in ("dc_up", "dc_down")]
    assert len(changes) >= 3
    for y, fl in [(ev.y_plus, ev.flags) for ev in changes] + [(run.y, run.flags)]:
        xa = y[0] - p["d_dc"]
        assert fl["dc_lo"] - 2e-12 <= xa <= fl["dc_hi"] + 2e-12, (xa, fl["dc_lo"], fl["dc_hi"])


def test_measured_replay_run_never_carries_a_region_past_its_bounds():
    """The thesis' start under the measured law with the listing's AC sign at 90 V, 7 Hz: the AC
    push throws the bar into the table's range and back; every region change leaves xa inside the
    new region and the run ends without escaping."""
    sc = maps.get_scene("thesis-1dof").with_options(dc_law="measured", ac_sign="listing")
    p = sc.parameters(preset="matlab-listing", V=90.0, relay_hz=7.0)
    run = HybridRun(sc.system, p, sc.initial_state(x=0.0, v=0.0, i=0.1, z=0.0), tol=1e-12, max_events=None)
    run.advance(3.0)
    changes = [ev for ev in run.events if ev.name in ("dc_up", "dc_down")]
    assert len(changes) >= 20 and max(ev.y_plus[0] for ev in changes) > p["d_dc"]
    for ev in changes:
        xa = ev.y_plus[0] - p["d_dc"]
        assert ev.flags["dc_lo"] - 2e-12 <= xa <= ev.flags["dc_hi"] + 2e-12


@pytest.mark.parametrize("law, v0", [("fit", -3.0), ("catalogue", -0.5)])
def test_fit_and_catalogue_law_trajectories_equal_the_scipy_baseline(law, v0):
    """The baselines write the rhs again without heyoka (bifurc.baselines, MODEL.md's fit signs, the
    catalogue's two tanh steps with the weight acting): 1 s at 90 V and 9 Hz from 5 mm above the stop
    moving down (at 3 m/s the catalogue's weaker pull lets the bar escape), DOP853 at 1e-12 against heyoka."""
    from bifurc.verification.baselines import solve_scipy
    sc = maps.get_scene("thesis-1dof").with_options(dc_law=law)
    p = sc.parameters(V=90.0, relay_hz=9.0)
    y0 = sc.system.state_vector(sc.initial_state(x=0.005, v=v0))
    run = HybridRun(sc.system, p, y0, tol=1e-15)
    run.advance(1.0)
    ref = solve_scipy(p, y0, 1.0, method="DOP853", tol=1e-12, dc_law=law)
    assert ref.n_impacts == impact_table(run)["t"].size >= 1
    np.testing.assert_allclose(impact_table(run)["t"], ref.impact_times, rtol=0, atol=1e-8)
    np.testing.assert_allclose(run.y[:2], ref.y[:2], rtol=0, atol=1e-6)


def test_measured_law_and_its_potential_equal_scipys_pchip_of_the_table():
    """scipy's PchipInterpolator through Table 4.1 is the independent truth: the compiled force
    equals -sign(xa) pchip(|xa|) inside the table, and the potential U(xa) = integral of the pull
    from 0 to |xa| (kvl energy output, bar at rest, no current) is continuous across every knot."""
    from scipy.interpolate import PchipInterpolator
    x, T = _table()
    pchip = PchipInterpolator(x, T)
    sc = maps.get_scene("thesis-1dof").with_options(dc_law="measured", circuit="kvl", energy=True)
    system = sc.system
    p = sc.parameters(preset="matlab-listing")
    xs = np.linspace(-0.0289, 0.0289, 577)
    _, dc_system, dc_p = _dc_only("measured")
    F = [_force(dc_system, dc_p, xa) for xa in xs]
    np.testing.assert_allclose(F, -np.sign(xs) * pchip(np.abs(xs)), rtol=0, atol=1e-12)

    def U(xa, flags=None):
        y = np.zeros(len(system.state_names))
        y[0] = p["d_dc"] + xa
        fl = dict(system.flag_defaults, **(flags if flags is not None else dc_region_flags(system.options, y, p)))
        return float(system.evaluate(["E_mech_el"], y, p, fl)[0]) - p["m"] * p["g"] * y[0]
    for xa in (0.012, -0.021, 0.0275, 0.035, -0.05):
        want = float(pchip.integrate(0.0, min(abs(xa), 0.029)))
        assert abs(U(xa) - want) < 1e-14
    for k, reg in enumerate(measured_dc_regions()[1:], start=1):   # both sides of every lower bound
        lo = reg[0]
        assert abs(U(lo, maps.model._region_flags(k)) - U(lo, maps.model._region_flags(k - 1))) < 1e-15
