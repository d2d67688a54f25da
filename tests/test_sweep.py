"""Stroboscopic maps, sweeps, grazing, follow mode, resume and storage against independent truths."""
import math

import numpy as np
import pytest
import xarray as xr

import bifurc
import maps
from bifurc.storage import files, load as storage
from bifurc.labels.classify import CLASS_LABELS
from bifurc.sweeps.job import ValueJob
from bifurc.sweeps.sweep import sweep
from conftest import completed_values, kill_when_parts
from maps.impacts import impact_table

OSC = dict(w0=1.0, zeta=0.02, F=0.1, Omega=1.0, e=-1.0, r=0.8)


@pytest.fixture(scope="module")
def osc():
    return maps.forced_oscillator_with_stop()


def steady_state(p):
    """Analytic non-impacting steady state at t = k T: (x, v)."""
    w0, z, F, W = p["w0"], p["zeta"], p["F"], p["Omega"]
    X = F / math.hypot(w0**2 - W**2, 2 * z * w0 * W)
    phi = math.atan2(2 * z * w0 * W, w0**2 - W**2)
    return X * math.cos(phi), X * W * math.sin(phi), X


def test_stroboscopic_map_converges_to_the_analytic_steady_state(osc):
    p = dict(OSC, Omega=0.7, e=-5.0, zeta=0.1)
    smap = maps.StroboscopicMap(osc, p, tol=1e-14)
    assert smap.period == pytest.approx(2 * math.pi / 0.7)
    o = smap.orbit({"x": 0.0, "v": 0.0}, 5, transient=120)  # transient decays as exp(-zeta w0 t) ~ 1e-24
    x, v, X = steady_state(p)
    np.testing.assert_allclose(o.points[:, 0], x, atol=1e-12)
    np.testing.assert_allclose(o.points[:, 1], v, atol=1e-12)
    assert o.impacts_per_step.sum() == 0
    # smallest gap per period: the lowest point of the orbit, -X, measured from the stop e
    np.testing.assert_allclose(o.min_clearance_per_step, -X - p["e"], atol=1e-12)
    # step() from a recorded point gives the next one
    np.testing.assert_allclose(smap.step(o.points[0], k=120), o.points[1], atol=1e-13)
    J = smap.jacobian(o.points[0], k=120)  # linear flow: exp(-zeta w0 T) = |det J|^(1/2)
    assert abs(np.linalg.det(J)) == pytest.approx(math.exp(-2 * 0.1 * smap.period), rel=1e-6)


def test_map_impacts_equal_the_time_history():
    sc = maps.get_scene("thesis-1dof").with_options(dc_law="listing")
    p = sc.parameters(preset="matlab-listing", V=90, relay_hz=9)
    smap = maps.StroboscopicMap(sc, p, tol=1e-12)
    o = smap.orbit(sc.initial_state(), 18, transient=0)
    run = maps.run_scene("thesis-1dof", 2.0, preset="matlab-listing", params={"V": 90, "relay_hz": 9})
    ref = impact_table(run)
    assert o.impacts_per_step.sum() == ref["t"].size > 0
    np.testing.assert_allclose(o.impact_time, ref["t"], atol=1e-12)
    np.testing.assert_allclose(o.impact_velocity, ref["velocity"], atol=1e-9)
    np.testing.assert_allclose(o.points[-1], run.y, atol=1e-10)
    assert np.all((o.impact_phase >= 0) & (o.impact_phase < 1))
    assert smap.forcing_period_steps == 9  # 9 relay periods hold 50 mains cycles


def test_grazing_located_where_the_analytic_amplitude_reaches_the_stop(osc):
    W, e = 0.7, -1.0
    F_graze = abs(e) * math.hypot(1 - W**2, 2 * 0.02 * W)  # X(F) = |e|
    xtol = 1e-7
    ds = sweep(osc, "F", np.linspace(0.9, 1.1, 5) * F_graze, params=dict(OSC, Omega=W, e=e), transient=300,
               record=30, tol=1e-13, lyapunov=False, error_sample=0, grazing_xtol=xtol, progress=False)
    assert ds.sizes["grazing"] == 1
    assert abs(float(ds.grazing_value[0]) - F_graze) <= xtol + 1e-9
    sub = ds.sel(branch="independent")
    assert list(sub.class_code.values[:2]) == [CLASS_LABELS.index("periodic-no-impact")] * 2
    assert list(sub.impacts_per_period.values[-2:]) == [1, 1]


def test_no_grazing_search_between_two_unconverged_values():
    """Without a periodic orbit on either side (e.g. intermittent chaos with lyapunov=False, where
    every non-periodic value is not-converged) there is no branch to follow: nothing is integrated."""
    from types import SimpleNamespace

    from bifurc.sweeps.grazing import locate_grazing_values

    class Forbidden:
        def __getattr__(self, name):
            raise AssertionError("no evaluation expected")

    def r(code, n):
        return SimpleNamespace(status=0, class_code=code, n_impacts=n, record_used=100)
    values = np.array([2.0, 2.01, 2.02])
    results = {"independent": [r(4, 0), r(4, 37), r(4, 0)]}
    assert locate_grazing_values(results, values, Forbidden(), 1e-6) == []


def test_follow_mode_finds_coexisting_attractors(osc):
    """Impacts harden the oscillator: above w0 an impacting 1:1 orbit coexists with the
    small non-impacting one; sweeping up follows the first, sweeping down the second."""
    values = np.linspace(0.9, 1.3, 9)
    ds = sweep(osc, "Omega", values, mode="follow", params=OSC, transient=150, record=30, tol=1e-12,
               lyapunov=False, error_sample=0, grazing=False, progress=False)
    up, down = ds.sel(branch="up"), ds.sel(branch="down")
    both = (up.class_code == 0) & (up.impacts_per_period == 1) & (down.class_code == 1)
    coexist = values[both.values]
    assert coexist.size >= 3 and coexist.min() > 1.0
    # the non-impacting one is the analytic linear response
    for W in coexist:
        x, v, X = steady_state(dict(OSC, Omega=W))
        assert X < abs(OSC["e"])
        assert float(down.x.sel(Omega=W).isel(sample=-1)) == pytest.approx(x, abs=1e-8)


_completed = completed_values


def test_interrupted_batch_sweep_resumes_to_the_same_dataset(tmp_path, monkeypatch):
    """Batch mode saves each completed chunk: after an interruption only the rest runs."""
    args = dict(preset="matlab-listing", params={"V": 90}, transient=20, record=10, grazing=False,
                error_sample=0, progress=False, chunk_size=2)
    values = np.linspace(4, 9, 6)
    path = tmp_path / "d.nc"
    original = ValueJob.run_many
    seen = []

    def flaky(self, vals):
        if len(seen) == 4:
            raise KeyboardInterrupt
        seen.extend(vals)
        return original(self, vals)

    monkeypatch.setattr(ValueJob, "run_many", flaky)
    with pytest.raises(KeyboardInterrupt):
        sweep("thesis-1dof", "relay_hz", values, path=path, **args)
    assert not path.exists()
    assert _completed(tmp_path / "d.nc.parts") == 4
    seen.clear()
    monkeypatch.setattr(ValueJob, "run_many", lambda self, vals: seen.extend(vals) or original(self, vals))
    resumed = sweep("thesis-1dof", "relay_hz", values, path=path, **args)
    assert seen == list(values[4:])
    monkeypatch.setattr(ValueJob, "run_many", original)
    fresh = sweep("thesis-1dof", "relay_hz", values, **args)
    for name in ("x", "v", "i", "z", "impact_time", "class_code", "min_clearance", "lyapunov"):
        np.testing.assert_allclose(resumed[name].values, fresh[name].values, rtol=0, atol=1e-12, equal_nan=True)


def test_interrupted_sweep_resumes_to_the_same_dataset(tmp_path, monkeypatch):
    args = dict(preset="matlab-listing", params={"V": 90}, transient=20, record=10, lyapunov=False,
                grazing=False, error_sample=0, progress=False, batch_size=1)
    values = np.linspace(4, 9, 6)
    path = tmp_path / "d.nc"
    calls = {"n": 0}
    original = ValueJob.__call__

    def flaky(self, value, start=None):
        if calls["n"] == 4:
            raise KeyboardInterrupt
        calls["n"] += 1
        return original(self, value, start)

    monkeypatch.setattr(ValueJob, "__call__", flaky)
    with pytest.raises(KeyboardInterrupt):
        sweep("thesis-1dof", "relay_hz", values, path=path, **args)
    assert not path.exists()
    assert _completed(tmp_path / "d.nc.parts") == 4
    monkeypatch.setattr(ValueJob, "__call__", original)
    calls["n"] = 0
    seen = []
    monkeypatch.setattr(ValueJob, "__call__", lambda self, v, s=None: seen.append(v) or original(self, v, s))
    resumed = sweep("thesis-1dof", "relay_hz", values, path=path, **args)
    assert seen == list(values[4:])  # only the missing values ran
    monkeypatch.setattr(ValueJob, "__call__", original)
    fresh = sweep("thesis-1dof", "relay_hz", values, **args)
    for name in ("x", "v", "i", "z", "impact_time", "class_code", "min_clearance"):
        np.testing.assert_allclose(resumed[name].values, fresh[name].values, rtol=0, atol=1e-12, equal_nan=True)
    assert not (tmp_path / "d.nc.parts").exists()
    with pytest.raises(maps.ParameterError, match="other arguments"):
        (tmp_path / "e.nc.parts").mkdir()
        (tmp_path / "e.nc.parts" / "manifest.json").write_text("{}")
        sweep("thesis-1dof", "relay_hz", values, path=tmp_path / "e.nc", **args)


def test_an_unreadable_resume_part_is_recomputed_with_a_warning(tmp_path, monkeypatch):
    from bifurc.run.parts import Parts
    args = dict(preset="matlab-listing", params={"V": 90}, transient=20, record=10, lyapunov=False, grazing=False,
                error_sample=0, progress=False, batch_size=1, workers=1, chunk_size=1)
    values = np.linspace(4, 9, 4)
    path = tmp_path / "d.nc"
    monkeypatch.setattr(Parts, "remove", lambda self: None)      # keep the parts, as after a late interruption
    first = sweep("thesis-1dof", "relay_hz", values, path=path, **args)
    parts = sorted((tmp_path / "d.nc.parts").glob("*.nc"))
    assert len(parts) == 4
    parts[1].write_bytes(parts[1].read_bytes()[:100])           # a truncated part
    path.unlink()
    seen, original = [], ValueJob.__call__
    monkeypatch.setattr(ValueJob, "__call__", lambda self, v, s=None: seen.append(v) or original(self, v, s))
    with pytest.warns(RuntimeWarning, match="discarding the unreadable resume part"):
        again = sweep("thesis-1dof", "relay_hz", values, path=path, **args)
    assert seen == [values[1]] and again.attrs["resumed_values"] == 3
    for name in ("x", "v", "i", "z", "impact_time", "class_code", "period", "min_clearance", "n_impacts", "status"):
        np.testing.assert_array_equal(again[name].values, first[name].values, err_msg=name)


def test_a_resumed_value_keeps_the_time_spent_computing_it(tmp_path, monkeypatch, capsys):
    """Every value done before the interruption: the resumed dataset stores (and the command prints)
    the time spent on the values when they were computed, not the moment it took to load them."""
    from bifurc.cli import main
    from bifurc.run.parts import Parts
    argv = ["diagram", "--preset", "matlab-listing", "--set", "V=90", "--from", "4", "--to", "9", "--n", "4",
            "--transient", "1500", "--record", "20", "--no-lyapunov", "--quiet", "--workers", "1"]
    path = tmp_path / "d.nc"
    monkeypatch.setattr(Parts, "remove", lambda self: None)      # keep the parts, as after a late interruption
    assert main(argv + ["-o", str(path)]) == 0
    first = storage.read(path)
    out = capsys.readouterr().out
    path.unlink()
    from bifurc.sweeps.job import ValueJob
    for method in ("__call__", "run_many"):
        monkeypatch.setattr(ValueJob, method, lambda self, *a, **k: pytest.fail("computed a value again"))
    assert main(argv + ["-o", str(path)]) == 0       # workers=1 runs in this process: nothing computed again
    again = storage.read(path)
    np.testing.assert_array_equal(again.run_seconds.values, first.run_seconds.values)
    assert again.attrs["resumed_values"] == 4 and first.attrs["resumed_values"] == 0
    spent = float(first.run_seconds.sum())
    assert spent > 0.1 and again.attrs["values_seconds"] == pytest.approx(spent, rel=1e-12)
    printed = f"in {spent:.1f} s of computation"
    assert printed in out and printed in capsys.readouterr().out


def test_the_removed_mode_continuation_is_refused_in_one_line_naming_follow(osc):
    """"continuation" was a deprecated alias of "follow" up to 0.2.0 (CHANGELOG's migration table)."""
    with pytest.raises(maps.ParameterError, match="allowed: independent, follow"):
        sweep(osc, "Omega", [0.7, 0.8], mode="continuation", progress=False)


def test_netcdf_round_trip_is_lossless(tmp_path):
    ds = sweep("thesis-1dof", "relay_hz", np.array([5.0, 8.0]), preset="matlab-listing", params={"V": 90},
               transient=10, record=8, error_sample=2, progress=False)
    files.write_netcdf(ds, tmp_path / "s.nc")
    back = storage.read(tmp_path / "s.nc")
    xr.testing.assert_identical(back.drop_encoding() if hasattr(back, "drop_encoding") else back, ds)
    for name, var in ds.variables.items():
        assert back[name].dtype == var.dtype, name
        assert "units" in var.attrs, name
    assert back.class_code.attrs["flag_meanings"].split()[:2] == ["periodic", "periodic_no_impact"]
    assert "error_map_points_rel" in back.attrs and back.attrs["sweep_seconds"] > 0


def test_map_step_error_follows_the_tolerance_on_a_non_periodic_value():
    """The one-period error is small and shrinks with tol even where whole re-runs diverge
    (chaos, torus drift): the whole-run difference is reported apart, as sensitivity."""
    est = {}
    for tol in (1e-7, 1e-11):
        ds = sweep("thesis-1dof", "relay_hz", np.array([5.0]), preset="matlab-listing", params={"V": 90},
                   transient=60, record=40, tol=tol, grazing=False, error_sample=1, progress=False, budget=100)
        est[tol] = ds.attrs
    assert int(ds.class_code.values.ravel()[0]) in (2, 3, 4)  # not periodic (4: over 40 periods the exponent's
    #                                                          interval contains the chaos threshold)
    assert np.isnan(est[1e-11]["error_map_points_rel"])       # no periodic value sampled
    assert np.isnan(est[1e-11]["error_impact_time_s"])        # no contact time compared: unmeasured, not 0
    for tol, a in est.items():
        assert 0 < a["error_map_step_rel"] < 300 * tol, (tol, a["error_map_step_rel"])
    assert est[1e-7]["error_map_step_rel"] > 100 * est[1e-11]["error_map_step_rel"]


def test_bad_sweep_input_names_the_parameter():
    with pytest.raises(maps.ParameterError, match="relay_hz"):
        sweep("thesis-1dof", "relay_hz", [5.0, 0.0], transient=1, record=3, progress=False)
    with pytest.raises(maps.ParameterError, match="frequency"):
        sweep("thesis-1dof", "frequency", [5.0], transient=1, record=3, progress=False)
    with pytest.raises(maps.ParameterError, match="mode"):
        sweep("thesis-1dof", "relay_hz", [5.0], mode="sideways", progress=False)


def test_a_still_converging_transient_is_extended_until_it_decides(osc):
    """A lightly damped linear response decays by exp(-zeta w0 T) per period: after 20 periods it
    is not-converged at exactly that rate; with max_transient the sweep integrates on until the
    recurrence is within tolerance (about ln(1e-6)/ln(rate) ~ 300 periods)."""
    p = dict(OSC, Omega=0.7, e=-5.0, zeta=0.005)
    rate = math.exp(-0.005 * 1.0 * 2 * math.pi / 0.7)
    args = dict(params=p, transient=20, record=30, tol=1e-13, lyapunov=False, grazing=False, error_sample=0,
                progress=False)
    short = sweep(osc, "Omega", [0.7], budget=50, **args).isel(branch=0, Omega=0)   # no room to extend
    assert CLASS_LABELS[int(short.class_code)] == "not-converged"
    # the decaying free oscillation (w_d ~ w0) nearly repeats every 7 samples of T = 2 pi / 0.7,
    # the best candidate; its distance decays at the analytic rate per period
    assert float(short.convergence_rate) == pytest.approx(rate, rel=1e-3)
    assert int(short.period) == 0 and int(short.candidate_period) == 7  # not periodic: period 0
    assert int(short.transient_used) == 20 and int(short.budget_needed) > 50    # what would decide it
    # the default budget (anytime: the window doubles until the recurrence holds), and max_transient, the
    # former limit, which still raises the budget to max_transient + record
    for long in (sweep(osc, "Omega", [0.7], **args).isel(branch=0, Omega=0),
                 sweep(osc, "Omega", [0.7], max_transient=1000, budget=50, **args).isel(branch=0, Omega=0)):
        assert CLASS_LABELS[int(long.class_code)] == "periodic-no-impact" and int(long.period) == 1
        assert math.log(1e-6) / math.log(rate) < int(long.transient_used) + int(long.record_used) <= 1030
        assert int(long.budget_needed) == 0
        x, v, X = steady_state(p)
        assert float(long.x.isel(sample=-1)) == pytest.approx(x, abs=1e-5 * X)


KILL_SCRIPT = """
import sys, numpy as np
from bifurc.sweeps.sweep import sweep
sweep("thesis-1dof", "relay_hz", np.linspace(4, 9, 8), path=sys.argv[1], **{args})
"""


def test_killed_sweep_keeps_completed_values_and_resumes(tmp_path):
    """SIGKILL a sweep process part-way: the completed values stay on disk (no partial file), and
    the rerun computes only the rest and equals an uninterrupted sweep to 1e-12."""
    import sys
    args = dict(preset="matlab-listing", params={"V": 90.0}, transient=150, record=20, lyapunov=False,
                grazing=False, error_sample=0, progress=False, chunk_size=2)
    path = tmp_path / "k.nc"
    parts = tmp_path / "k.nc.parts"
    done = kill_when_parts([sys.executable, "-c", KILL_SCRIPT.format(args=repr(args)), str(path)], parts)
    if not 2 <= done < 8:
        pytest.skip(f"the kill came too late to test a resume ({done} values done)")
    assert not path.exists()  # a .tmp cut by the kill may remain: only whole .nc parts count
    seen = []
    original = ValueJob.run_many
    try:
        ValueJob.run_many = lambda self, vals: seen.extend(vals) or original(self, vals)
        resumed = sweep("thesis-1dof", "relay_hz", np.linspace(4, 9, 8), path=path, **args)
    finally:
        ValueJob.run_many = original
    assert len(seen) == 8 - done
    fresh = sweep("thesis-1dof", "relay_hz", np.linspace(4, 9, 8), **args)
    for name in ("x", "v", "i", "z", "impact_time", "impact_velocity", "class_code", "min_clearance", "n_impacts"):
        np.testing.assert_allclose(resumed[name].values, fresh[name].values, rtol=0, atol=1e-12, equal_nan=True)
    assert storage.read(path).sizes == resumed.sizes and not parts.exists()


def test_grazing_of_an_impacting_orbit_where_a_new_impact_is_born(osc):
    """Stop at equilibrium, Omega = 0.44: a 1:5 orbit; lower down its lowest free-flight minimum
    touches the stop and more impacts appear.  The located graze is confirmed (the clearance
    shrank with the bracket), and the clearance of the 1:5 orbit, computed apart at three
    values above it, extrapolates (quadratic fit) to zero there."""
    p = dict(w0=1.0, zeta=0.05, F=1.0, Omega=1.0, e=0.0, r=0.8)
    kw = dict(params=p, transient=200, record=24, tol=1e-12, lyapunov=False, error_sample=0, progress=False)
    xtol = 1e-6
    ds = sweep(osc, "Omega", [0.42, 0.44], grazing_xtol=xtol, **kw)
    assert list(ds.period.values[0]) == [2, 1] and list(ds.impacts_per_period.values[0]) == [14, 5]
    assert ds.sizes["grazing"] == 1 and int(ds.grazing_confirmed[0]) == 1
    g = float(ds.grazing_value[0])
    assert 0.42 < g < 0.44 and float(ds.grazing_clearance[0]) < 1e-4
    d = np.array([2e-3, 4e-3, 8e-3])
    down = sweep(osc, "Omega", np.append(g + d, 0.44), mode="follow", grazing=False, **kw).sel(branch="down")
    assert list(down.impacts_per_period.values) == [5] * 4 and list(down.period.values) == [1] * 4
    root = min(np.roots(np.polyfit(d, down.min_flight_clearance.values[:3], 2)), key=abs)
    assert abs(root) < 20 * xtol  # measured 3.5e-6 (quadratic fit error)


def test_resume_refuses_parts_of_another_format(tmp_path):
    """Parts written by an older bifurc (pickles, manifest format 2) are not read as today's."""
    import json
    parts = tmp_path / "old.nc.parts"
    parts.mkdir()
    (parts / "manifest.json").write_text(json.dumps({"parts_format": 2, "mode": "independent"}))
    (parts / "independent-000000.pkl").write_bytes(b"\x80\x04N.")
    with pytest.raises(maps.ParameterError, match="format version 2"):
        sweep("thesis-1dof", "relay_hz", [5.0], transient=1, record=3, progress=False, path=tmp_path / "old.nc")
    assert (parts / "independent-000000.pkl").exists()     # nothing lost


def test_resume_refuses_parts_another_version_of_the_code_computed(tmp_path, monkeypatch):
    """Parts written by another version or commit of the code are not mixed with this one's results: the resume is
    refused in one line naming both, and the parts stay (a census resumed after a change of the code had kept 75
    values of the old code's)."""
    from bifurc.run import parts as resume
    args = dict(transient=1, record=3, lyapunov=False, grazing=False, error_sample=0, progress=False, batch_size=1,
                path=tmp_path / "d.nc")
    original = ValueJob.__call__

    def stop_at_the_second(self, value, start=None):
        if value > 5.0:
            raise KeyboardInterrupt
        return original(self, value, start)
    monkeypatch.setattr(ValueJob, "__call__", stop_at_the_second)
    with pytest.raises(KeyboardInterrupt):
        sweep("thesis-1dof", "relay_hz", [5.0, 6.0], **args)
    monkeypatch.setattr(ValueJob, "__call__", original)
    parts = sorted((tmp_path / "d.nc.parts").iterdir())
    assert _completed(tmp_path / "d.nc.parts") == 1
    monkeypatch.setattr(resume, "code_version", lambda: "bifurc 9.9.9, git 0000000")
    with pytest.raises(maps.ParameterError, match="code = .*this run has code = bifurc 9.9.9, git 0000000"):
        sweep("thesis-1dof", "relay_hz", [5.0, 6.0], **args)
    assert sorted((tmp_path / "d.nc.parts").iterdir()) == parts


def test_the_exponent_uses_the_whole_recorded_window_with_an_interval_and_reasons():
    """record = 200: the exponent is the mean over all 200 recorded periods (the same tangent stretch
    series recomputed here by the exact one-period Jacobians at the stored points, each an exact
    restart with its mode), its interval brackets it, and every not-converged value says why."""
    ds = sweep("thesis-1dof", "relay_hz", np.array([5.0, 9.0]), preset="matlab-listing", params={"V": 90},
               transient=50, record=200, grazing=False, error_sample=0, progress=False, batch_size=1,
               budget=250).isel(branch=0)     # one window of 200 periods, one trajectory
    assert ds.attrs["lyapunov_steps"] == 200 and "batch means" in ds.attrs["lyapunov_interval_method"]
    lam, lo, hi = ds.lyapunov.values, ds.lyapunov_low.values, ds.lyapunov_high.values
    assert np.all(np.isfinite(lam)) and np.all((lo <= lam) & (lam <= hi))
    sc = maps.get_scene("thesis-1dof").with_options(dc_law="listing")
    smap = maps.StroboscopicMap(sc, sc.parameters(preset="matlab-listing", V=90.0, relay_hz=9.0), tol=1e-10)
    pts = np.column_stack([ds[s].values[1] for s in ("x", "v", "i", "z")])
    scale = np.maximum(np.nanmax(np.abs(pts), axis=0), 1e-9)
    flags = np.column_stack([ds[f"flag_{f}"].values[1] for f in sc.system.flag_names])
    u, st = maps.tangent.start_direction(4), []
    for k in range(200):
        J = smap.linearize(maps.HybridState(pts[k], dict(zip(sc.system.flag_names, flags[k]))),
                           int(ds.transient_used.values[1]) + k).J
        w = J @ u
        st.append(np.log(np.linalg.norm(w / scale) / np.linalg.norm(u / scale)))
        u = w / np.linalg.norm(w)
    assert ds.attrs["lyapunov_method"].startswith("tangent")
    assert abs(float(np.mean(st)) - lam[1]) < 1e-9          # measured 1.6e-11
    for code, reason in zip(ds.class_code.values, ds.class_reason.values):
        assert (str(reason) != "") == (int(code) == 4)


@pytest.mark.parametrize("offset", [0.0, -1e-9])
def test_a_grid_value_on_the_graze_is_a_graze(osc, offset):
    """The grid holds the closed-form grazing amplitude itself (or a value within the bisection
    tolerance of it): the graze is located there, to xtol, and confirmed as a graze, not a jump."""
    W, e = 0.7, -1.0
    F_graze = abs(e) * math.hypot(1 - W**2, 2 * 0.02 * W)  # X(F) = |e|
    xtol = 1e-7
    values = np.array([0.9, 1.0 + offset, 1.1]) * F_graze
    ds = sweep(osc, "F", values, params=dict(OSC, Omega=W, e=e), transient=300, record=30, tol=1e-13,
               lyapunov=False, error_sample=0, grazing_xtol=xtol, progress=False)
    assert ds.sizes["grazing"] == 1 and int(ds.grazing_confirmed[0]) == 1
    assert abs(float(ds.grazing_value[0]) - F_graze) <= xtol + 1e-9


def test_periods_are_searched_among_multiples_of_the_forcing_period():
    """8.5 Hz at 90 V (listing law): the forcing repeats after q = 17 relay periods; with the default
    search (multiples of q up to 100 relay periods) the sweep finds the period-17 orbit with 12
    impacts (before, periods stopped at 16 and the value read quasi-periodic).  At 8.537 Hz the
    forcing never repeats (q = 0): no period is searched, and without an exponent the value is
    not-converged with that reason stored."""
    from bifurc.labels.classify import candidate_periods
    from bifurc.labels.codes import ClassCode
    assert candidate_periods(17, 100) == [17, 34, 51, 68, 85] and candidate_periods(0, 100) == []
    assert candidate_periods(1, 5) == [1, 2, 3, 4, 5]
    kw = dict(preset="matlab-listing", params={"V": 90}, grazing=False, error_sample=0, progress=False)
    ds = sweep("thesis-1dof", "relay_hz", np.array([8.5]), **kw).isel(branch=0, relay_hz=0)
    assert int(ds.forcing_period) == 17 and int(ds.period) == 17 and int(ds.impacts_per_period) == 12
    assert ClassCode(int(ds.class_code)) == ClassCode.PERIODIC and ds.attrs["max_period"] == 100
    q0 = sweep("thesis-1dof", "relay_hz", np.array([8.537]), lyapunov=False, transient=20, record=40,
               **kw).isel(branch=0, relay_hz=0)
    assert int(q0.forcing_period) == 0 and ClassCode(int(q0.class_code)) == ClassCode.NOT_CONVERGED
    assert "no candidate period" in str(q0.class_reason.values) and int(q0.period) == 0


def test_record_extended_to_three_forcing_periods_up_to_max_record():
    """8.9 Hz at 90 V (listing law): the forcing repeats after q = 89 relay periods, so a 100-period
    record cannot test period 89 (it needs two whole periods).  The record is extended to 3 q = 267
    periods (under the default cap 3 x 100) and the period-89 orbit is found; with --max-record 150
    the extension stops at 150 (on the one-value path too) and the period is missed, as it is at 100."""
    from bifurc.labels.codes import ClassCode
    job = ValueJob(maps.problem("thesis-1dof"), "relay_hz", record=100, max_period=100)
    assert job.record_cap == 300 and job.record_for(89) == 267 and job.record_for(17) == 100
    assert job.record_for(0) == 100 and job.record_for(101) == 100     # nothing to search: no extension
    assert ValueJob(maps.problem("thesis-1dof"), "relay_hz", record=100, max_record=120).record_for(89) == 120
    method = bifurc.Diagram(record=100)                                  # the public form of the same rule
    assert [method.record_for(q) for q in (89, 17, 0, 101)] == [267, 100, 100, 100]
    assert bifurc.Diagram(record=100, max_record=120).record_for(89) == 120
    kw = dict(preset="matlab-listing", params={"V": 90}, grazing=False, error_sample=0, progress=False)
    ds = sweep("thesis-1dof", "relay_hz", np.array([8.9]), **kw)
    v = ds.isel(branch=0, relay_hz=0)
    assert int(v.forcing_period) == 89 and int(v.record_used) == 267 and ds.attrs["max_record_periods"] == 300
    assert ClassCode(int(v.class_code)) == ClassCode.PERIODIC and int(v.period) == 89
    assert ds.sizes["sample"] == 101 and np.all(np.isfinite(v.x.values))    # the stored window stays record + 1
    assert ds.record_used.attrs["units"] == "1" and "max_record" in ds.record_used.attrs["long_name"]
    for cap, batch in ((150, 1), (100, 4)):
        short = sweep("thesis-1dof", "relay_hz", np.array([8.9]), max_record=cap, batch_size=batch,
                      budget=300 + cap, **kw).isel(branch=0, relay_hz=0)
        assert int(short.record_used) == cap and int(short.period) == 0
        assert ClassCode(int(short.class_code)) != ClassCode.PERIODIC
    with pytest.raises(maps.parameters.ParameterError, match="max_record"):
        sweep("thesis-1dof", "relay_hz", np.array([8.9]), max_record=50, **kw)


def test_grids_and_period_counts_are_refused_in_one_line_not_reshaped():
    """Newcomer review, API corpus: a string grid, a 2-D grid and a fractional transient were accepted
    (flattened, truncated) or ended in a raw ValueError."""
    kw = dict(progress=False, grazing=False, error_sample=0)
    for bad, match in (("abc", "values must be numbers"), (np.ones((2, 2)), "1-D"), ([5.0, "x"], "values must be")):
        with pytest.raises(maps.ParameterError, match=match):
            sweep("thesis-1dof", "relay_hz", bad, **kw)
    with pytest.raises(maps.ParameterError, match="transient = 10.5: a whole number"):
        sweep("thesis-1dof", "relay_hz", [5.0], transient=10.5, **kw)
    with pytest.raises(maps.ParameterError, match="values2 must be a 1-D"):
        bifurc.regime_map("thesis-1dof", "relay_hz", [5.0], "V", np.ones((2, 2)), progress=False, error_sample=0)
