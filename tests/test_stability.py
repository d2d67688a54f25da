"""The stability suite's verdicts and bounds, sticking and escape against independent estimates."""
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import maps
from bifurc.cli import main
from bifurc.stability import CASES, QUICK, VERDICTS, run_case, run_suite


@pytest.fixture(scope="module")
def quick():
    return run_suite(quick=True, progress=False)


def test_quick_suite_verdicts_are_the_expected_ones(quick):
    assert list(quick.case.values) == QUICK
    got = [VERDICTS[int(v)] for v in quick.verdict.values]
    want = [VERDICTS[int(v)] for v in quick.expected.values]
    assert got == want


def test_double_agrees_with_extended_precision_within_the_bound(quick):
    ok = quick.where(quick.verdict == 0, drop=True)
    assert ok.sizes["case"] >= 7
    assert (ok.state_error <= ok.bound).all()
    assert (ok.event_count_difference == 0).all()
    assert float(ok.event_time_error.max()) < 1e-11


def test_stiff_stop_penetration_tends_to_the_linear_estimate(quick):
    """Max penetration v sqrt(m/k) for c = 0, up to the DC force's static offset ~ F/k."""
    r8 = quick.sel(case="stiff-k1e+08-c0")
    assert abs(float(r8.penetration_ratio) - 1) < 0.01
    r10 = quick.sel(case="stiff-k1e+10-c10")
    assert abs(float(r10.penetration_ratio) - 1) < 0.002
    for name in ("stiff-k1e+05-c0", "stiff-k1e+08-c0", "stiff-k1e+10-c10"):
        assert float(quick.sel(case=name).energy_balance_error) < 1e-12
        assert int(quick.sel(case=name).contacts) == 1
    # a stiffer stop costs no more steps per contact: heyoka adapts the step to the contact
    assert float(quick.sel(case="stiff-k1e+10-c10").steps_per_contact) <= 10


def test_chattering_ends_stuck_with_bounded_events(quick):
    r = quick.sel(case="chatter-stick")
    assert 0.3 < float(r.stick_time) < 0.5 and int(r.contacts) < 100 and int(r.steps) < 2000
    assert np.isnan(float(r.unstick_time))  # nothing pulls it away: it stays


def test_time_on_the_stop_matches_the_circuit_alone():
    """Held on the stop (x = e, v = 0) the circuit is a linear ODE; the bar leaves when the
    (listing-sign) AC push 0.5 |L'| i^2 first exceeds its weight."""
    case = next(c for c in CASES if c.name == "stuck-unstick")
    res = run_case(case)
    p = maps.get_scene("ac-stop").parameters(**case.params)
    xb = p["d_ac"]
    norm = p["A"] / (p["B"] * math.sqrt(math.pi / 2))
    gauss = math.exp(-2 * (xb / p["B"]) ** 2)
    L, dL = p["L0"] + norm * gauss, -4 * norm * xb / p["B"] ** 2 * gauss
    w = 2 * math.pi * p["f_mains"]

    def rhs(t, y):  # eq 4.16 with v = dv/dt = 0
        i, z = y
        return [z, (w * p["V"] * math.cos(w * t) - p["R"] * z - i / p["C"]) / L]

    def push(t, y):
        return 0.5 * abs(dL) * y[0] ** 2 - p["m"] * p["g"]
    push.terminal, push.direction = True, 1
    sol = solve_ivp(rhs, (0, 0.05), [0.0, 0.0], method="DOP853", rtol=1e-13, atol=1e-15, events=push)
    assert res["unstick_time"] == pytest.approx(sol.t_events[0][0], abs=1e-10)
    assert VERDICTS.index(res["verdict"]) == 0


def test_escape_is_detected_at_the_time_of_the_mechanics_alone():
    """Thrown up from the DC centre at 10 m/s, the bar leaves the model's domain 0.1 m above
    the centre; the AC force there is negligible, so the cubic alone gives the time."""
    case = next(c for c in CASES if c.name == "thrown-out")
    res = run_case(case)
    assert res["verdict"] == "escaped"
    p = maps.get_scene("thesis-1dof").parameters(preset="matlab-listing", **case.params)

    def rhs(t, y):
        xa = y[0] - p["d_dc"]
        return [y[1], (-p["a3"] * xa**3 + p["a2"] * xa**2 - p["a1"] * xa) / p["m"]]

    def out(t, y):
        return y[0] - (p["d_dc"] + 0.1)
    out.terminal, out.direction = True, 1
    sol = solve_ivp(rhs, (0, 1), [0.0625, 10.0], method="DOP853", rtol=1e-12, atol=1e-14, events=out)
    assert res["failure_time"] == pytest.approx(sol.t_events[0][0], abs=1e-5)


def test_non_finite_state_is_a_reported_failure_not_a_crash_nor_a_nan():
    ds = maps.simulate("dc-only", t_end=1.0, params={"a3": -1e300}, x0={"x": 0.1})
    assert ds.attrs["status"] == "failed" and "non-finite" in ds.attrs["failure"]
    assert np.isfinite(ds.attrs["failure_time"]) and np.all(np.isfinite(ds.attrs["failure_state"]))
    assert not np.isnan(ds.x.values).any()


def test_stability_command_writes_report_and_dataset(tmp_path, capsys):
    assert main(["stability", "--case", "stuck-held", "--case", "thrown-out", "-o", str(tmp_path)]) == 0
    text = (tmp_path / "stability.md").read_text()
    assert "| stuck-held |" in text and "escaped (escaped)" in text
    import xarray as xr
    ds = xr.open_dataset(tmp_path / "stability.nc")
    assert ds.sizes["case"] == 2 and ds.verdict.attrs["flag_meanings"].startswith("ok ill_conditioned")
    for name, var in ds.variables.items():
        assert "units" in var.attrs, name


@pytest.mark.slow
def test_full_suite_has_only_expected_verdicts():
    ds = run_suite(progress=False)
    bad = [str(c) for c, v, e in zip(ds.case.values, ds.verdict.values, ds.expected.values) if v != e]
    assert not bad, bad
