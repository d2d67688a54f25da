"""Time histories: sampling, relay timing, mode bookkeeping and compile-once caching."""
import numpy as np
import pytest

import maps
from maps.engines.scalar import HybridRun

CASE = dict(preset="matlab-listing", params={"V": 90.0, "relay_hz": 9.0})


@pytest.fixture(scope="module")
def history():
    return maps.simulate("thesis-1dof", t_end=1.5, dt=1e-3, **CASE)


def test_dense_output_does_not_change_the_trajectory(history):
    run = maps.run_scene("thesis-1dof", 1.5, **CASE)  # no dense output requested
    assert history.attrs["status"] == run.status == "ok"
    # the same steps are taken with and without continuous output: identical to rounding
    np.testing.assert_allclose(history.isel(t=-1)[["x", "v", "i", "z"]].to_array().values,
                               run.y, rtol=1e-14, atol=1e-15)
    from maps.impacts import impact_table
    np.testing.assert_array_equal(history.impact_time.values, impact_table(run)["t"])
    assert history.impact.size >= 4


def test_sampling_grid_does_not_change_impacts(history):
    fine = maps.simulate("thesis-1dof", t_end=1.5, dt=1e-4, **CASE)
    np.testing.assert_array_equal(fine.impact_time.values, history.impact_time.values)
    np.testing.assert_allclose(fine.x.sel(t=history.t, method="nearest").values, history.x.values,
                               rtol=0, atol=1e-13)


def test_dense_output_matches_restarted_integration(history):
    """A sample from dense output equals the state of a separate run stopped at that instant."""
    t_probe = float(history.t[777])
    run = maps.run_scene("thesis-1dof", t_probe, **CASE)
    assert abs(float(history.x[777]) - run["x"]) < 1e-11
    assert abs(float(history.v[777]) - run["v"]) < 1e-9


def test_relay_switches_land_exactly_on_schedule():
    run = maps.run_scene("thesis-1dof", 1.0, **CASE)
    W = 9.0
    switch_times = [t for (t, fl), (_, prev) in zip(run.flag_log[1:], run.flag_log[:-1]) if fl["P"] != prev["P"]]
    expected = np.arange(1, len(switch_times) + 1) / (2 * W)
    assert len(switch_times) == int(np.floor(2 * W * 1.0 + 1e-9))  # switches in (0, 1] s
    np.testing.assert_allclose(switch_times, expected, rtol=0, atol=1e-15)
    # relay ON in the first half of every period
    for t, fl in run.flag_log:
        phase = (t * W) % 1.0
        if fl["P"] == 1.0:
            assert phase < 0.5 + 1e-9 or phase > 1 - 1e-9


def test_every_mode_change_is_an_event_or_a_switch():
    """The integrator never steps across a mode change: each change of the contact flag
    happens at a recorded guard crossing, where the gap is zero."""
    run = maps.run_scene("thesis-1dof", 1.5, **CASE)
    event_times = {ev.t: ev for ev in run.events}
    changes = [(t, fl) for (t, fl), (_, prev) in zip(run.flag_log[1:], run.flag_log[:-1])
               if fl["contact"] != prev["contact"]]
    assert len(changes) >= 8
    for t, fl in changes:
        ev = event_times[t]
        assert ev.name == ("contact" if fl["contact"] else "release")
        assert abs(ev.y_minus[0]) < 1e-14  # x - e = 0 at the crossing (e = 0)


def test_compiled_once_per_structure():
    scene = maps.get_scene("thesis-1dof")
    params = scene.parameters(**CASE["params"], preset="matlab-listing")
    a = HybridRun(scene.system, params, scene.initial_state())
    b = HybridRun(scene.system, dict(params, V=50.0), scene.initial_state())
    assert a.compile_seconds == b.compile_seconds  # the same cached prototype
    assert a.ta is not b.ta  # but independent integrators
    a.advance(0.3)
    b.advance(0.3)
    assert a.y[2] != b.y[2]  # different runtime parameters took effect without recompiling


def test_dc_only_scene_has_no_circuit_states():
    sysdc = maps.get_scene("dc-only").system
    assert sysdc.state_names == ("x", "v")
    assert not {"R", "C", "V", "relay_hz"} & set(sysdc.param_names)
    ds = maps.simulate("dc-only", t_end=0.2)
    assert set(ds.data_vars) >= {"x", "v", "contact"} and "i" not in ds


def test_every_variable_has_units(history):
    for name, var in history.variables.items():
        assert "units" in var.attrs, name
    for key in ("param_V", "param_V_units", "param_V_source", "tol", "heyoka_version", "run_seconds",
                "compile_seconds", "circuit"):
        assert key in history.attrs
    assert history.attrs["param_V_source"] == "set by user"
    assert history.attrs["param_R_source"].startswith("matlab-listing")


def test_escape_is_reported_with_time_and_truncated_grid():
    ds = maps.simulate("ac-only", t_end=1.0)  # 25 V cannot hold the bar against its weight
    assert ds.attrs["status"] == "escaped"
    t_fail = ds.attrs["failure_time"]
    # free fall from rest with a weak upward AC pull: no faster than g, 0.2 m in >= sqrt(2*0.2/g)
    assert np.sqrt(2 * 0.2 / 9.81) - 1e-9 <= t_fail < 1.0
    assert float(ds.t[-1]) <= t_fail
    assert not np.isnan(ds.x.values).any()


def test_per_period_event_cap_is_a_reported_failure():
    ds = maps.simulate("thesis-1dof", t_end=1.5, max_events_per_period=2, **CASE)
    assert ds.attrs["status"] == "failed" and "events" in ds.attrs["failure"]
    assert ds.attrs["failure_time"] < 1.5 and not np.isnan(ds.x.values).any()
    ok = maps.simulate("thesis-1dof", t_end=1.5, max_events_per_period=50, **CASE)
    assert ok.attrs["status"] == "ok" and ok.sizes["impact"] >= 4 > ds.sizes["impact"]
