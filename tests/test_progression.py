"""Progression measures (maps.progression) in time histories and sweeps."""
import math

import numpy as np
import pytest

import bifurc
import maps
from maps.progression import MEASURES, TARGET_DEPTH, held_time, progression_measures


def test_measures_of_a_steady_advance_are_its_closed_forms():
    v, W, m1 = 0.05, 6.0, 0.155                     # 50 mm/s, relay 6 Hz
    t = np.linspace(0.0, 10.0, 1001)
    x2 = 0.01 - v * t                                # starts at x2 = 0.01 m
    imp_t = np.array([0.5, 4.9, 5.5, 9.0])           # two inside the window [5, 10]
    imp_v = np.array([-3.0, -2.0, -1.0, -0.5])
    m = progression_measures(t, x2, x2_start=0.01, relay_hz=W, impact_time=imp_t, impact_velocity=imp_v,
                             m1=m1, held=1.25, window=(5.0, 10.0))
    assert m["progression_rate"] == pytest.approx(v, rel=1e-12)
    assert m["progression_per_period"] == pytest.approx(v / W, rel=1e-12)
    assert m["time_to_depth"] == pytest.approx(TARGET_DEPTH / v, rel=1e-12)
    assert m["impact_energy_per_period"] == pytest.approx(0.5 * m1 * (1.0 + 0.25) / (5.0 * W), rel=1e-12)
    assert m["stuck_fraction"] == pytest.approx(0.25, rel=1e-12)
    slow = progression_measures(t, 0.01 - 0.001 * t, x2_start=0.01, relay_hz=None, m1=m1)
    assert math.isnan(slow["time_to_depth"]) and math.isnan(slow["progression_per_period"])


def test_held_time_integrates_the_flag_log():
    log = [(0.0, {"stuck": 1.0}), (1.0, {"stuck": 0.0}), (1.5, {"stuck": 1.0}), (4.0, {"stuck": 0.0})]
    assert held_time(log, 0.5, 5.0, ("stuck", 1.0)) == pytest.approx(0.5 + 2.5)
    assert held_time(log, 0.5, 5.0, None) == 0.0


def test_viscous_rate_obeys_the_momentum_balance():
    """m1 dv1/dt + m2 dv2/dt = -F_static - soil_c v2 (internal forces cancel), so over the window
    soil_c (x2(t_a) - x2(t_b)) = F_static (t_b - t_a) + [m1 v1 + m2 v2]_(t_a)^(t_b): the stored rate
    is F_static/soil_c plus the momentum change over soil_c and the window."""
    ds = maps.simulate("thesis-2dof", t_end=2.0, transient=0.5, params={"V": 90.0, "relay_hz": 9.0})
    p = {k: ds.attrs[f"param_{k}"] for k in ("m1", "m2", "F_static", "soil_c")}
    a, b = ds.sel(t=0.5), ds.isel(t=-1)
    dP = float(p["m1"] * (b.v1 - a.v1) + p["m2"] * (b.v2 - a.v2))
    expected = (p["F_static"] * 1.5 + dP) / (p["soil_c"] * 1.5)
    assert float(ds.progression_rate) == pytest.approx(expected, rel=1e-9)
    assert float(ds.stuck_fraction) == 0.0                       # viscous soil never holds the rig
    for name, (units, long_name) in MEASURES.items():
        assert ds[name].attrs["units"] == units and ds[name].attrs["long_name"] == long_name
    assert list(ds.attrs["progression_window"]) == [0.5, 2.0]


def test_coulomb_stuck_fraction_is_the_time_the_flag_holds():
    ds = maps.simulate("prototype", periods=12)
    t = ds.t.values
    half = t >= t[-1] / 2
    sampled = float(np.mean(ds.rig_stuck.values[half]))          # the flag on the sampling grid
    assert float(ds.stuck_fraction) == pytest.approx(sampled, abs=2e-3)
    assert 0.0 < float(ds.stuck_fraction) <= 1.0


def test_sweep_and_time_history_measure_the_same_window_alike():
    """A sweep's record [transient, transient + record] relay periods against a time history over
    the same window (the batch engine against the scalar one)."""
    W, tr, rec = 9.0, 6, 12
    ds = bifurc.sweep("thesis-2dof", "relay_hz", np.array([W]), transient=tr, record=rec, workers=1,
                      progress=False, lyapunov=False, grazing=False, error_sample=0, params={"V": 90.0})
    h = maps.simulate("thesis-2dof", t_end=(tr + rec) / W, transient=tr / W, params={"V": 90.0, "relay_hz": W},
                      dt=1.0 / (W * 50))
    assert float(ds.progression_rate[0, 0]) == pytest.approx(float(h.progression_rate), rel=1e-7)
    assert float(ds.progression_per_period[0, 0]) == pytest.approx(float(h.progression_per_period), rel=1e-7)
    assert float(ds.impact_energy_per_period[0, 0]) == pytest.approx(float(h.impact_energy_per_period),
                                                                     rel=1e-6, abs=1e-12)
    # viscous soil: 0.2 m within the record (0.88 s); the sweep interpolates between relay periods
    assert float(h.time_to_depth) == pytest.approx(0.2 / 0.2304, rel=0.05)
    assert abs(float(ds.time_to_depth[0, 0]) - float(h.time_to_depth)) < 0.1 / W
    assert ds.progression_rate.attrs["units"] == "m s-1"


def test_command_line_soil_transient_and_measures(tmp_path, capsys):
    from bifurc.cli import main
    nc = tmp_path / "drift.nc"
    assert main(["simulate", "--scene", "prototype", "--soil", "drift", "--periods", "6", "--transient", "0.5",
                 "-o", str(nc)]) == 0
    out = capsys.readouterr().out
    assert "progression" in out and "mm/s over 0.5-1 s" in out
    import xarray as xr
    with xr.open_dataset(nc) as ds:
        assert ds.attrs["soil"] == "drift" and float(ds.progression_rate) > 0
        assert ds.progression_rate.attrs["units"] == "m s-1"
    assert main(["simulate", "--scene", "thesis-1dof", "--soil", "drift", "--periods", "2"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "soil" in err[0] and "2-DOF" in err[0]
    assert main(["params", "--scene", "prototype", "--soil", "drift"]) == 0
    assert "P_max" in capsys.readouterr().out


@pytest.mark.parametrize("soil", ["coulomb", "drift"])
def test_sweep_stuck_fraction_is_the_time_in_the_holding_mode(soil):
    """The sweep's stuck_fraction is the time the soil holds the rig (banked at each flag change,
    batch engine), not the share of relay-period samples that fall in that mode: it equals the time
    history's (scalar engine, integrated over its flag log) over the same window to 1e-7, on both
    engines, and a finely sampled flag to the sampling's resolution."""
    W, tr, rec = 6.0, 4, 12
    kw = dict(transient=tr, record=rec, workers=1, progress=False, lyapunov=False, grazing=False, error_sample=0,
              soil=soil, tol=1e-12, budget=tr + rec)     # the time history's tolerance and window
    h = maps.simulate("prototype", t_end=(tr + rec) / W, transient=tr / W, params={"relay_hz": W}, soil=soil,
                      dt=1.0 / (W * 2000))
    for batch_size in (4, 1):
        ds = bifurc.sweep("prototype", "relay_hz", np.array([W]), batch_size=batch_size, **kw)
        # measured: coulomb 1e-10; drift 1.7e-8: its transient amplifies the engines' round-off (the batch
        # transient takes no stops at observation guards) to ~3e-6 in the state at the record's start
        # (with no transient the two agree to 1e-15), and the converging orbit carries it into the times
        assert float(ds.stuck_fraction[0, 0]) == pytest.approx(float(h.stuck_fraction), rel=1e-7)
    held = h.rig_stuck.values == 1 if soil == "coulomb" else h.soil_mode.values != 2   # drift: the slider still
    sampled = float(np.mean(held[h.t.values >= tr / W][:-1]))
    assert 0.0 < float(h.stuck_fraction) < 1.0
    assert float(h.stuck_fraction) == pytest.approx(sampled, abs=2e-3)
