"""The DC well (maps/well.py, issue 46): each DC law's rest height and stiffness against closed forms
derived here from the law's own printed formula (numpy roots of the cubic, the catalogue's tanh pair
solved by brentq, Table 4.1 through scipy's PCHIP), setting the well by dc_rest / dc_stiffness, the
C.14 law, and the numbers reaching datasets and `bifurc params`."""
import math

import numpy as np
import pytest
from numpy.polynomial import Polynomial as Poly
from scipy.interpolate import PchipInterpolator
from scipy.optimize import brentq

import maps
from bifurc.cli import main
from maps.parameters import ParameterError
from maps.well import well

TABLE_4_1 = [(0.000, 0.0), (0.005, 0.0), (0.010, 0.2), (0.015, 0.4), (0.020, 0.9), (0.025, 1.5),
             (0.027, 2.1), (0.028, 2.9), (0.029, 3.6)]          # |xa| [m], pull [N] at 20 V DC
LAWS = ("listing", "fit", "measured", "catalogue", "dynamics-script")


def _pb(law, **params):
    return maps.problem("thesis-1dof", preset="matlab-listing", dc_law=law, params=params)


def _well(pb):
    return well(pb.options, pb.values)


def _cubic(law, p):
    """The law's cubic in xa at dc_scale 1 as printed (C.9 / eq 4.7 / C.14), lowest degree first."""
    a1, a2, a3 = p["a1"], p["a2"], p["a3"]
    return Poly([0.0, -a1, a2, -a3]) if law in ("listing", "dynamics-script") else Poly([0.0, a1, -a2, -a3])


@pytest.mark.parametrize("law", ["listing", "fit", "dynamics-script"])
@pytest.mark.parametrize("params", [{}, {"dc_scale": 0.3}])
def test_cubic_laws_rest_and_stiffness_are_the_cubics_roots(law, params):
    """+m g cancels the weight: the rest is a real root of the cubic where it falls through zero, of
    lowest potential (fit: its double well's two roots, equal to 1e-20 J: the one nearer the stop);
    the stiffness is -dc_scale F'(root); depth and range from the quartic potential."""
    pb = _pb(law, **params)
    p, s = pb.values, pb.values["dc_scale"]
    F = _cubic(law, p)
    roots = [r.real for r in F.roots() if abs(r.imag) < 1e-12 and F.deriv()(r.real) < 0]
    U = -F.integ()
    lowest = min(U(r) for r in roots)
    xa = min(r for r in roots if U(r) <= lowest + 1e-15)
    w = _well(pb)
    rest = max(p["d_dc"] + xa, 0.0)
    assert w["dc_rest"] == pytest.approx(rest, abs=1e-12)
    assert w["dc_stiffness"] == pytest.approx(-s * F.deriv()(xa), rel=1e-9)
    if law == "listing":
        assert xa == 0.0 and w["dc_stiffness"] == pytest.approx(15.38 * s, rel=1e-12)
        # the odd quartic potential regains its value on the stop at the mirror height: x_max = 2 d_dc
        assert w["dc_range"] == pytest.approx(2 * p["d_dc"], abs=1e-9)
        assert w["dc_depth"] == pytest.approx(s * (U(-p["d_dc"]) - U(0.0)), rel=1e-9)
    if law == "fit":   # the double well's lower minimum: xa = -(a2 + sqrt(a2^2 + 4 a1 a3)) / (2 a3)
        a1, a2, a3 = p["a1"], p["a2"], p["a3"]
        assert xa == pytest.approx(-(a2 + math.sqrt(a2 * a2 + 4 * a1 * a3)) / (2 * a3), rel=1e-12)
        assert w["dc_rest"] == pytest.approx(0.0625 - 0.010219, abs=1e-6)
    if law == "dynamics-script":    # C.14: centred at the stop, the bar rests on it
        assert w["dc_rest"] == 0.0 and w["dc_depth"] == 0.0 and w["dc_range"] == 0.0
        assert w["dc_stiffness"] == pytest.approx(15.38 * s, rel=1e-12)


def _catalogue(p):
    Fs, u, sd = p["F_dc_sat"], p["u_dc"], p["s_dc"]
    F = lambda xa: -0.5 * Fs * (math.tanh((xa - u) / (2 * sd)) + math.tanh((xa + u) / (2 * sd)))  # noqa: E731
    dF = lambda xa: -Fs / (4 * sd) * (1 / math.cosh((xa - u) / (2 * sd)) ** 2  # noqa: E731
                                      + 1 / math.cosh((xa + u) / (2 * sd)) ** 2)
    return F, dF


@pytest.mark.parametrize("dc_scale", [1.0, 0.5, 1.44])
def test_catalogue_rest_is_where_the_pull_equals_the_weight(dc_scale):
    """No weight offset: dc_scale F(xa) = m g on the monotone tanh pair (brentq at 1e-15)."""
    pb = _pb("catalogue", dc_scale=dc_scale)
    p = pb.values
    F, dF = _catalogue(p)
    W = p["m"] * p["g"]
    xa = brentq(lambda z: dc_scale * F(z) - W, -0.2, 0.0, xtol=1e-16, rtol=1e-15)
    w = _well(pb)
    assert w["dc_rest"] == pytest.approx(p["d_dc"] + xa, abs=1e-10)
    assert w["dc_stiffness"] == pytest.approx(-dc_scale * dF(xa), rel=1e-7)
    assert w["dc_stop_force"] == pytest.approx(dc_scale * F(-p["d_dc"]) - W, rel=1e-12)
    if dc_scale == 1.0:      # science review 4: parked at 38.3 mm, swings of about 96 mm
        assert w["dc_rest"] == pytest.approx(0.0383, abs=5e-5) and w["dc_range"] == pytest.approx(0.096, abs=1e-3)


def test_measured_law_leaves_the_bar_on_the_stop_and_places_a_well_through_pchip():
    """Table 4.1 reads 0 N beyond 29 mm: on the stop (xa = -62.5 mm) the bar feels only its weight
    and rests there.  Set to 5 mm, the rest is where dc_scale T(|xa|) = m g on the table's PCHIP."""
    w = _well(_pb("measured"))
    pb = _pb("measured")
    W = pb.values["m"] * pb.values["g"]
    assert w["dc_rest"] == 0.0 and w["dc_stop_force"] == pytest.approx(-W, rel=1e-12)
    T = PchipInterpolator(*map(np.array, zip(*TABLE_4_1)))
    for scale in (1.0, 2.0):
        pb = _pb("measured", dc_rest=0.005, **({"dc_scale": scale} if scale != 1.0 else {}))
        u = brentq(lambda z: scale * T(z) - W, 0.0051, 0.029, xtol=1e-16, rtol=1e-15)
        w = _well(pb)
        assert w["dc_rest"] == pytest.approx(0.005, abs=1e-9)
        assert pb.values["d_dc"] == pytest.approx(0.005 + u, abs=1e-9)
        assert w["dc_stiffness"] == pytest.approx(scale * float(T.derivative()(u)), rel=1e-6)


@pytest.mark.parametrize("law", LAWS)
@pytest.mark.parametrize("height", [0.0, 0.003, 0.005])
def test_dc_rest_moves_the_rest_to_that_height_and_the_model_feels_no_net_force_there(law, height):
    """The model's own net force (N_bar, AC current 0) vanishes at the set height and pulls back
    on both sides; the law's shape is kept (dc_scale, a1..a3 unchanged)."""
    base = _pb(law)
    pb = _pb(law, dc_rest=height)
    w = _well(pb)
    assert w["dc_rest"] == pytest.approx(height, abs=1e-9)
    assert pb.values["dc_scale"] == base.values["dc_scale"]
    system = pb.system
    fl = dict(system.flag_defaults)

    def N(x):
        y = np.array([x, 0.0, 0.0, 0.0])
        if law == "measured":
            fl.update(maps.model.dc_region_flags(pb.options, y, pb.values))
        return float(system.evaluate(["N_bar"], y, pb.values, fl)[0])

    K = w["dc_stiffness"]
    assert abs(N(height)) <= 1e-9 * max(K, 1.0) + 1e-12
    if height > 0:
        assert N(height - 1e-4) > 0 > N(height + 1e-4)
    assert "dc_rest = " in pb.provenance["d_dc"]


@pytest.mark.parametrize("law", ["listing", "catalogue", "dynamics-script", "fit"])
def test_dc_stiffness_sets_the_stiffness_keeping_the_rest(law):
    pb = _pb(law, dc_rest=0.004, dc_stiffness=120.0)
    w = _well(pb)
    assert w["dc_rest"] == pytest.approx(0.004, abs=1e-9)
    assert w["dc_stiffness"] == pytest.approx(120.0, rel=1e-7)
    if law in ("listing", "dynamics-script"):
        assert pb.values["dc_scale"] == pytest.approx(120.0 / 15.38, rel=1e-12)
        assert pb.values["d_dc"] == pytest.approx(0.004, abs=1e-15)


def test_the_undamped_swing_from_the_stop_reaches_dc_range_and_damping_parks_it_at_dc_rest():
    """Integration against the well's root-finding: dc-only, released at rest on the stop."""
    for law, params in (("listing", {}), ("listing", {"dc_rest": 0.01}), ("catalogue", {"dc_rest": 0.008})):
        pb = maps.problem("dc-only", preset="matlab-listing", dc_law=law, params=params, x0={"x": 0.0, "v": 0.0})
        w = well(pb.options, pb.values)
        ds = maps.simulate(pb, t_end=0.4, dt=1e-4)
        assert float(ds.x.max()) == pytest.approx(w["dc_range"], abs=2e-5)
    pb = maps.problem("dc-only", preset="matlab-listing", dc_law="listing", params={"dc_rest": 0.005, "c_air": 0.5},
                      x0={"x": 0.0, "v": 0.0})
    ds = maps.simulate(pb, t_end=8.0, dt=1e-2)
    assert float(ds.x[-1]) == pytest.approx(0.005, abs=1e-5)


def test_datasets_record_the_well():
    ds = maps.simulate("thesis-1dof", preset="matlab-listing", t_end=0.01, params={"dc_rest": 0.005})
    assert ds.attrs["dc_rest"] == pytest.approx(0.005, abs=1e-12) and ds.attrs["dc_rest_units"] == "m"
    assert ds.attrs["dc_stiffness"] == pytest.approx(15.38, rel=1e-9) and ds.attrs["dc_stiffness_units"] == "N m-1"
    assert ds.attrs["dc_range"] == pytest.approx(0.01, abs=1e-9)
    assert "dc_depth" in ds.attrs and "dc_stop_force" in ds.attrs and "dc_well_definition" in ds.attrs
    assert "dc_rest = 0.005" in ds.attrs["param_d_dc_source"]
    assert "dc_rest" not in maps.simulate("ac-only", t_end=0.01).attrs


def test_dynamics_script_law_is_c14s_cubic_centred_at_the_stop():
    pb = _pb("dynamics-script")
    p = pb.values
    assert (p["a1"], p["a2"], p["a3"], p["d_dc"]) == (15.38, 1.652e-14, 1.4735, 0.0)
    assert "C.14" in pb.provenance["a3"] and "C.14" in pb.provenance["d_dc"]
    assert "C2*(u - x)" in maps.laws.DC_LAWS["dynamics-script"]
    system = pb.system
    for x in (0.0, 0.003, 0.02):   # F_dc without the weight offset: the printed Fspr at s = x
        F = float(system.evaluate(["F_dc"], np.array([x, 0.0, 0.0, 0.0]), p, dict(system.flag_defaults))[0])
        assert F == pytest.approx(-1.4735 * x**3 + 1.652e-14 * x**2 - 15.38 * x, abs=1e-15)


def test_api_and_cli_accept_the_same_names_with_the_same_one_line_errors(capsys):
    assert main(["params", "--scene", "thesis-1dof", "--dc-law", "dynamics-script", "--set", "dc_rest=0.005"]) == 0
    out = capsys.readouterr().out
    rows = {line.split()[0]: line.split()[1] for line in out.splitlines() if line.strip()}
    assert float(rows["dc_rest"]) == pytest.approx(0.005) and float(rows["dc_stiffness"]) == pytest.approx(15.38)
    assert float(rows["d_dc"]) == pytest.approx(0.005)
    for bad, want in (({"dc_rest": 0.7}, "outside its allowed range [0, 0.5] m"),
                      ({"dc_rest": 0.02}, "dc_law measured can give"),
                      ({"dc_stiffness": -1}, "outside its allowed range (0, 1e+06] N m-1"),
                      ({"dc_rest": 0.01, "d_dc": 0.01}, "give one of them, not both")):
        with pytest.raises(ParameterError) as api:
            _pb("measured", **bad)
        assert want in str(api.value) and "\n" not in str(api.value)
        argv = ["params", "--scene", "thesis-1dof", "--preset", "matlab-listing", "--dc-law", "measured"]
        for k, v in bad.items():
            argv += ["--set", f"{k}={v}"]
        assert main(argv) == 2
        err = capsys.readouterr().err.strip()
        assert err.endswith(str(api.value)) and len(err.splitlines()) == 1
    with pytest.raises(ParameterError, match="no DC solenoid"):
        maps.problem("ac-only", params={"dc_rest": 0.01})


def test_with_values_places_the_well_too():
    pb = _pb("listing").with_values(dc_rest=0.007, relay_hz=5.0)
    assert pb.values["d_dc"] == pytest.approx(0.007) and pb.values["relay_hz"] == 5.0
    assert _well(pb)["dc_rest"] == pytest.approx(0.007, abs=1e-12)


def test_rest_5mm_c_air_0_5_at_90V_hammers_mechanical_period_1_at_5Hz():
    """Issue 46's check (dc_law listing, physical AC sign, the listings' start): with the well's rest
    5 mm above the stop and flight damping 0.5 N s/m, the bar hammers period-1 (mechanical and full
    state) with one or two impacts per relay period and a few-mm stroke at relay 5 Hz, 90 V."""
    import bifurc
    ds = bifurc.sweep("thesis-1dof", "relay_hz", np.array([5.0]), preset="matlab-listing", dc_law="listing",
                      params={"dc_rest": 0.005, "c_air": 0.5, "V": 90.0}, x0={"x": 0.0, "v": 0.0, "i": 0.1, "z": 0.0},
                      progress=False, workers=1, lyapunov=False, grazing=False).isel(branch=0, relay_hz=0)
    assert ds.attrs["dc_law"] == "listing" and ds.attrs["dc_rest"] == pytest.approx(0.005, abs=1e-12)
    assert int(ds.period_mechanical) == 1 and int(ds.impacts_per_period_mechanical) in (1, 2)
    x = ds.x.values[np.isfinite(ds.x.values)]
    assert x.size and 0.0 < x.max() < 0.010
    h = maps.simulate("thesis-1dof", preset="matlab-listing", dc_law="listing", periods=200, dt=1e-3,
                      params={"dc_rest": 0.005, "c_air": 0.5, "V": 90.0, "relay_hz": 5.0},
                      x0={"x": 0.0, "v": 0.0, "i": 0.1, "z": 0.0})
    late = h.x.values[h.t.values > 36.0]                  # the last 20 relay periods
    assert -0.001 < late.min() < 0.0 and 0.002 < late.max() < 0.006   # a 0-4 mm stroke (review 4: -0.18..3.6 mm)


def test_c14s_law_needs_the_listings_reversed_ac_sign():
    """dynamics-script, 25 V, the listings' start on the stop: with the physical AC sign the solenoid
    presses the bar (resting at the spring's centre, on the stop) onto the stop and nothing moves; with
    C.2's reversed sign it hammers, period-1 with one impact per relay period at 2 Hz, a few-mm stroke."""
    kw = dict(preset="matlab-listing", dc_law="dynamics-script", periods=40, dt=1e-3,
              params={"V": 25.0, "relay_hz": 2.0}, x0={"x": 0.0, "v": 0.0, "i": 0.1, "z": 0.0})
    still = maps.simulate("thesis-1dof", ac_sign="physical", **kw)
    assert np.abs(still.x.values).max() < 1e-6
    moving = maps.simulate("thesis-1dof", ac_sign="listing", **kw)
    late = moving.x.values[moving.t.values > 15.0]
    assert 0.003 < late.max() < 0.005
    hits = moving.impact_time.values
    hits = hits[np.isfinite(hits) & (hits > 15.0)]
    assert len(hits) == 10                                 # one per relay period over the last 10


def test_every_analysis_refuses_to_vary_a_well_input_and_names_what_moves_it(capsys):
    """dc_rest and dc_stiffness are set once; a diagram, map, census or branch in them is refused in one line,
    before anything runs, naming d_dc (or dc_scale) and the offset between rest and d_dc here: under `fit`
    the double well's lower root xa* = -(a2 + sqrt(a2^2 + 4 a1 a3)) / (2 a3) (derived here), so rest = d_dc + xa*."""
    import bifurc
    p = _pb("fit").values
    a1, a2, a3 = p["a1"], p["a2"], p["a3"]
    xa = -(a2 + math.sqrt(a2 * a2 + 4 * a1 * a3)) / (2 * a3)
    calls = [lambda: bifurc.sweep("thesis-1dof", "dc_rest", [0.005, 0.01], dc_law="fit"),
             lambda: bifurc.regime_map("thesis-1dof", "V", [80, 90], "dc_rest", [0.005, 0.01], dc_law="fit"),
             lambda: bifurc.attractors("thesis-1dof", "dc_rest", [0.005], dc_law="fit"),
             lambda: bifurc.continue_orbit("thesis-1dof", "dc_rest", (0.005, 0.01), dc_law="fit")]
    for call in calls:
        with pytest.raises(ParameterError) as err:
            call()
        msg = str(err.value)
        assert "\n" not in msg and "'dc_rest' is a DC-well input" in msg and "vary d_dc" in msg
        offset_mm = float(msg.split("d_dc + ")[1].split(" mm")[0])
        assert offset_mm == pytest.approx(xa * 1e3, rel=1e-5)
    with pytest.raises(ParameterError, match="vary dc_scale: the stiffness is"):
        bifurc.sweep("thesis-1dof", "dc_stiffness", [10.0, 20.0])
    assert main(["diagram", "--scene", "thesis-1dof", "--param", "dc_rest", "--from", "0.003", "--to", "0.02",
                 "--n", "3", "-o", "never.nc"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "vary d_dc" in err


def test_a_problem_gives_its_well():
    """``Problem.well()`` is the public form of the well's numbers: the listing cubic rests at d_dc (its root 0)."""
    pb = _pb("listing", d_dc=0.02)
    assert pb.well()["dc_rest"] == pytest.approx(0.02, abs=1e-12) and pb.well() == _well(pb)
    assert maps.problem("ac-only").well() == {}
