"""One problem object: a preset means the same model on every path; a system's clock comes from
what it declares; a user's system is a scene every command and worker process finds by name."""
import math
import os
import pickle
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

import bifurc
import maps
from maps import HybridSystem, Parameter, ParameterError, PeriodicSwitch, State

HERE = Path(__file__).parent
VALUES = {"V": 90.0, "relay_hz": 9.0}
N = 3   # relay periods: long enough for the DC laws to part (x = 0.107 m under fit, 0.073 m under listing)


@pytest.fixture(scope="module")
def listing_state():
    """The state after N relay periods under the listing law, chosen explicitly (the reference)."""
    sc = maps.get_scene("thesis-1dof").with_options(dc_law="listing")
    smap = maps.StroboscopicMap(sc, sc.parameters(preset="matlab-listing", **VALUES))
    return smap.orbit(sc.initial_state(), N).points[-1]


def test_the_readme_snippet_runs_the_presets_law(listing_state):
    """README: maps.StroboscopicMap("thesis-1dof", scene.parameters(preset="matlab-listing", ...)) ran
    the scene's default fit law while bifurc.sweep(..., preset="matlab-listing") ran listing."""
    scene = maps.get_scene("thesis-1dof")
    params = scene.parameters(preset="matlab-listing", **VALUES)
    assert params.options.dc_law == "listing" and params.preset == "matlab-listing"
    smap = maps.StroboscopicMap("thesis-1dof", params)
    assert smap.system.options.dc_law == "listing"
    y = smap.orbit(scene.initial_state(), N).points[-1]
    np.testing.assert_allclose(y, listing_state, rtol=0, atol=1e-12)
    fit = maps.get_scene("thesis-1dof").with_options(dc_law="fit")
    y_fit = maps.StroboscopicMap(fit, fit.parameters(preset="matlab-listing", **VALUES)).orbit(
        fit.initial_state(), N).points[-1]
    assert abs(y_fit[0] - y[0]) > 0.01     # the laws part by centimetres: the check can fail


def test_a_preset_means_the_same_model_on_every_path(tmp_path, listing_state):
    """maps.simulate, StroboscopicMap, bifurc.sweep, bifurc.periodic_orbit and the command line,
    each given only preset="matlab-listing", integrate the same model to 1e-12."""
    kw = dict(preset="matlab-listing", params=VALUES)
    t_end = N / VALUES["relay_hz"]
    ds = maps.simulate("thesis-1dof", t_eval=[t_end], t_end=t_end, **kw)
    states = maps.get_scene("thesis-1dof").system.state_names
    np.testing.assert_allclose([float(ds[s][-1]) for s in states], listing_state, rtol=0, atol=1e-12)
    assert ds.attrs["dc_law"] == "listing"

    p = maps.problem("thesis-1dof", **kw)
    np.testing.assert_allclose(maps.StroboscopicMap(p).orbit(dict(p.x0), N).points[-1], listing_state,
                               rtol=0, atol=1e-12)

    sw = bifurc.sweep("thesis-1dof", "relay_hz", [9.0], preset="matlab-listing", params={"V": 90.0},
                      transient=0, record=N, tol=1e-12, lyapunov=False, grazing=False, error_sample=0,
                      progress=False, workers=1, batch_size=1)
    np.testing.assert_allclose([float(sw[s].isel(branch=0, relay_hz=0, sample=N)) for s in states],
                               listing_state, rtol=0, atol=1e-12)
    assert sw.attrs["dc_law"] == "listing" and sw.attrs["scene"] == "thesis-1dof"

    # the orbit solver: its model's values, and its orbit against the same solve on the explicit listing map
    orb = bifurc.periodic_orbit("thesis-1dof", preset="matlab-listing", params={"V": 120.0, "relay_hz": 4.0},
                                transient=300, error=False)
    assert orb.attrs["dc_law"] == "listing" and orb.attrs["param_a3"] == maps.get_scene(
        "thesis-1dof").with_options(dc_law="listing").parameters(preset="matlab-listing")["a3"]
    sc = maps.get_scene("thesis-1dof").with_options(dc_law="listing")
    smap = maps.StroboscopicMap(sc, sc.parameters(preset="matlab-listing", V=120.0, relay_hz=4.0))
    start = smap.orbit(sc.initial_state(), 1, transient=300).state(0)
    ref = bifurc.find_periodic_orbit(smap, start, int(orb.period), k0=300)
    np.testing.assert_allclose(orb.isel(node=0)[list(states)].to_array().values, ref.nodes[0].y, rtol=0, atol=1e-12)

    out = tmp_path / "d.nc"
    subprocess.run([sys.executable, "-m", "bifurc", "diagram", "--scene", "thesis-1dof", "--preset",
                    "matlab-listing", "--set", "V=90", "--from", "9", "--to", "9", "--n", "1", "--transient", "0",
                    "--record", str(N), "--tol", "1e-12", "--no-lyapunov", "--workers", "1", "--batch-size", "1",
                    "--quiet", "-o", str(out)], check=True, capture_output=True)
    with xr.open_dataset(out) as cli:
        np.testing.assert_allclose([float(cli[s].isel(branch=0, relay_hz=0, sample=N)) for s in states],
                                   listing_state, rtol=0, atol=1e-12)
        assert cli.attrs["dc_law"] == "listing"


def _switched(name="f_sw"):
    """A mass on a spring pushed by a relay on the parameter ``name`` (no thesis name anywhere)."""
    params = [Parameter("w0", "rad s-1", "natural angular frequency", 0, math.inf, low_open=True),
              Parameter(name, "Hz", "switch frequency", 0, 1e3, low_open=True),
              Parameter("f_drive", "Hz", "sinusoidal drive frequency", 0, 1e3, low_open=True)]
    return HybridSystem("switched", states=[State("x", "m", "position"), State("v", "m s-1", "velocity")],
                        parameters=params, flags={"P": 1.0},
                        rhs=lambda s: [s.v, s.P - s.w0 * s.w0 * s.x], switches=[PeriodicSwitch("P", name)],
                        forcing=("f_drive",))


def test_the_clock_comes_from_the_declared_switch_whatever_its_name():
    smap = maps.StroboscopicMap(_switched(), {"w0": 3.0, "f_sw": 4.0, "f_drive": 48.0})
    assert smap.period == 0.25
    assert smap.forcing_period_steps == 1                 # 48 Hz: 12 cycles in every 1/4 s
    smap.set_params(f_drive=50.0)
    assert smap.forcing_period_steps == 2                 # 12.5 cycles per sample
    smap.set_params(f_drive=51.0)
    assert smap.forcing_period_steps == 4                 # 12.75 cycles per sample
    smap.set_params(f_drive=50.0 * math.sqrt(2))
    assert smap.forcing_period_steps == 0                 # incommensurate
    other = maps.StroboscopicMap(_switched("rate"), {"w0": 3.0, "rate": 2.5, "f_drive": 50.0})
    assert other.period == 0.4 and other.forcing_period_steps == 1
    # a step lands on the switch instants: 1/(2 f) is a sample-exact half period
    y = smap.set_params(f_drive=50.0).step(np.array([0.0, 0.0]))
    # closed form of x'' = P - w0^2 x from rest: P = 1 for the first half period, 0 for the second
    w, h = 3.0, 0.125
    x1, v1 = (1 - math.cos(w * h)) / w**2, math.sin(w * h) / w
    x2 = x1 * math.cos(w * h) + v1 / w * math.sin(w * h)
    v2 = -x1 * w * math.sin(w * h) + v1 * math.cos(w * h)
    np.testing.assert_allclose(y, [x2, v2], rtol=0, atol=1e-13)


def test_a_system_without_a_clock_asks_for_the_period():
    s = HybridSystem("free", states=[State("x", "m", "position")], parameters=[], rhs=lambda s: [0.0 * s.x + 1.0])
    with pytest.raises(ParameterError, match="declares no clock"):
        maps.StroboscopicMap(s, {})
    assert maps.StroboscopicMap(s, {}, period=0.5).step(np.array([0.0]))[0] == pytest.approx(0.5, abs=1e-14)


def test_problem_resolves_once_and_travels():
    p = maps.problem("thesis-1dof", preset="matlab-listing", params={"V": 120}, dc_law="measured")
    assert p.options.dc_law == "measured"               # a chosen law is not the preset's
    assert p.provenance["V"] == "set by user" and p.provenance["m"].startswith("matlab-listing")
    assert p.strobe_period() == pytest.approx(1 / p.values["relay_hz"], rel=1e-15)
    q = pickle.loads(pickle.dumps(p))
    assert q.options == p.options and dict(q.values) == dict(p.values) and dict(q.x0) == dict(p.x0)
    assert p.with_values(V=100).values["V"] == 100 and p.values["V"] == 120
    with pytest.raises(ParameterError, match="'V'"):
        p.with_values(V=-5)
    with pytest.raises(ParameterError, match="fixed"):
        maps.problem(p, preset="thesis-text")
    with pytest.raises(ParameterError, match="unknown option 'dc_lw'"):
        maps.problem("thesis-1dof", dc_lw="fit")
    a = p.attrs()
    assert a["dc_law"] == "measured" and a["param_V_source"] == "set by user" and a["param_V_units"] == "V"


def test_register_scene_in_this_process():
    sys.path.insert(0, str(HERE))
    try:
        import user_scenes
        sc = maps.register_scene(user_scenes.relay_oscillator, name="relay-osc-api",
                                 defaults=user_scenes.DEFAULTS, x0={"x": 0.0}, replace=True)
        assert "relay-osc-api" in maps.scene_names()
        p = maps.problem("relay-osc-api", params={"f_sw": 0.8})
        assert p.strobe_period() == 1.25
        d = bifurc.sweep("relay-osc-api", "f_sw", [0.8, 1.0], transient=100, record=10, grazing=False,
                         error_sample=0, progress=False, workers=1)
        assert list(d.period.values[0]) == [1, 1] and list(d.impacts_per_period.values[0]) == [1, 1]
        assert pickle.loads(pickle.dumps(p)).system.name == "relay-oscillator"   # by its builder's reference
        with pytest.raises(ParameterError, match="already registered"):
            maps.register_scene(sc)
        with pytest.raises(ParameterError, match="built-in"):
            maps.register_scene(user_scenes.relay_oscillator, name="thesis-1dof")
    finally:
        sys.path.remove(str(HERE))
        if "relay-osc-api" in maps.registry._REGISTERED:
            maps.registry.unregister_scene("relay-osc-api")
    assert "relay-osc-api" not in maps.scene_names()


def test_a_users_system_runs_through_every_command_on_two_workers(tmp_path):
    """A fresh command-line process finds the user's system by its address and by an installed entry
    point; the diagram's two worker processes rebuild it from the address."""
    dist = tmp_path / "site" / "user_scenes_demo-0.1.dist-info"    # an installed distribution's entry point
    dist.mkdir(parents=True)
    (dist / "METADATA").write_text("Metadata-Version: 2.1\nName: user-scenes-demo\nVersion: 0.1\n")
    (dist / "entry_points.txt").write_text("[maps.scenes]\nrelay-oscillator-ep = user_scenes:SCENE\n")
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(HERE), str(tmp_path / "site")]), MPLBACKEND="Agg")

    def run(*argv):
        r = subprocess.run([sys.executable, "-m", "bifurc", *argv], cwd=tmp_path, env=env, capture_output=True,
                           text=True)
        assert r.returncode == 0, r.stderr
        return r.stdout

    assert "relay-oscillator-ep" in run("scenes")
    run("simulate", "--scene", "user_scenes:SCENE", "--periods", "5", "-o", "run.nc")
    run("diagram", "--scene", "relay-oscillator-ep", "--param", "f_sw", "--from", "0.5", "--to", "1.2", "--n", "8",
        "--transient", "100", "--record", "20", "--workers", "2", "--quiet", "-o", "d.nc")
    run("orbit", "--scene", "user_scenes:SCENE", "--transient", "100", "-o", "orbit.nc")
    run("continue", "--scene", "user_scenes:SCENE", "--param", "F", "--from", "30", "--to", "20", "-o", "branch.nc")
    with xr.open_dataset(tmp_path / "run.nc") as ds:
        assert ds.attrs["scene"] == "user_scenes:SCENE" and ds.sizes["impact"] == 5
    with xr.open_dataset(tmp_path / "d.nc") as d:
        assert d.attrs["workers"] == 2 and d.attrs["scene"] == "relay-oscillator-ep"
        assert np.all(d.class_code.values >= 0) and np.all(d.period.values == 1)
    with xr.open_dataset(tmp_path / "orbit.nc") as o:
        assert int(o.period) == 1 and int(o.impacts_per_period) == 1 and int(o.stable) == 1
        mu_orbit = np.sort(o.multiplier_abs.values)
    with xr.open_dataset(tmp_path / "branch.nc") as b:
        assert b.sizes["point"] > 5
        first = np.sort(b.multiplier_abs.isel(point=0).values)
    np.testing.assert_allclose(first, mu_orbit, rtol=1e-8)   # the branch starts on the orbit
