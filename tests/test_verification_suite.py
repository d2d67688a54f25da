"""The stability suite's verdicts and bounds, sticking and escape against independent estimates."""
import numpy as np
import pytest
from scipy.integrate import solve_ivp

import maps
from bifurc.cli import main
from bifurc.verification.suite import CASES, QUICK, VERDICTS, run_case, run_suite


@pytest.fixture(scope="module")
def quick():
    return run_suite(quick=True, progress=False)


def test_quick_suite_verdicts_are_the_expected_ones(quick):
    assert list(quick.case.values) == QUICK
    got = [VERDICTS[int(v)] for v in quick.verdict.values]
    want = [VERDICTS[int(v)] for v in quick.expected.values]
    assert got == want


def test_double_agrees_with_extended_precision_within_the_bound(quick):
    ok = quick.isel(case=np.flatnonzero(quick.verdict.values == 0))
    assert ok.sizes["case"] >= 10
    assert (ok.state_error <= ok.bound).all() and (ok.tight_state_error <= ok.bound).all()
    assert (ok.event_count_difference == 0).all() and (ok.tight_event_count_difference == 0).all()
    assert float(ok.event_time_error.max()) < 1e-10  # measured 4.7e-11 (relay chattering, 1 s)
    assert float(ok.state_error.max()) < 1e-10       # measured 4.2e-11 (relay 100 Hz, 355 steps at tol 1e-12)


def test_a_sensitive_orbit_diverges_late_and_agrees_over_a_short_horizon(quick):
    r = quick.sel(case="precision-long-9Hz")
    assert VERDICTS[int(r.verdict)] == "ill-conditioned" and float(r.state_error) > 1e3 * float(r.bound)
    assert float(r.short_horizon) == 3.0 and float(r.short_state_error) <= float(r.short_bound)


def test_grazes_are_neither_missed_nor_doubled(quick):
    """The DC well returns the bar 1 nm above or below its start on the stop: 1 nm above is a
    free-flight minimum every half period, never a contact; 1 nm below a contact every time."""
    miss, hit = quick.sel(case="graze-miss-1nm"), quick.sel(case="graze-hit-1nm")
    assert int(miss.contacts) == 0 and abs(float(miss.min_clearance) - 1e-9) < 1e-15
    assert int(hit.contacts) == 8 and int(hit.event_count_difference) == 0
    assert int(hit.tight_event_count_difference) == 0
    # a 1 nm-deep contact begins at ~7e-4 m/s: a position error d shifts its time by d / 7e-4
    assert float(hit.event_time_error) < 1e-10 and float(hit.tight_event_time_error) < 1e-10  # measured 1.7e-11


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
    assert int(r.sticks) == 1 and int(r.unsticks) == 0  # nothing pulls it away: it stays
    assert float(r.time_on_stop) == pytest.approx(float(r.t_end) - float(r.stick_time), abs=1e-15)
    relay = quick.sel(case="chatter-relay")  # sticks every OFF half, leaves every ON half
    assert int(relay.sticks) == 5 and int(relay.unsticks) == 4 and int(relay.max_period_events) < 100
    capped = quick.sel(case="chatter-no-stick")
    assert VERDICTS[int(capped.verdict)] == "event-cap" and float(capped.failure_time) < 0.2


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


def test_verify_command_writes_report_and_dataset(tmp_path, capsys):
    assert main(["verify", "--case", "stuck-held", "--case", "thrown-out", "-o", str(tmp_path)]) == 0
    text = (tmp_path / "stability.md").read_text()
    assert "| stuck-held |" in text and "escaped (escaped)" in text
    assert "[2/2] thrown-out ... escaped" in capsys.readouterr().err
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
