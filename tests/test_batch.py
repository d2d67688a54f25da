"""heyoka batch mode (maps.engines.batch) under the sweep: lanes, refills, companions.

Every comparison is against the scalar path (HybridRun through StroboscopicMap), which the
other test files check against analytic solutions, scipy and extended precision.  Horizons
are short: the two paths take different steps, and the chaotic regimes of the thesis scene
amplify round-off by ~e^0.2 per relay period.
"""
import math

import numpy as np
import pytest

import maps
from bifurc.sweeps.job import ValueJob
from bifurc.labels.lyapunov import exponent_interval, lyapunov_along
from bifurc.sweeps.sweep import sweep
from maps.engines import BatchEngine, OrbitJob, engine_for
from maps.hybrid import HybridSystem, PeriodicSwitch, State
from maps.parameters import Parameter
from maps.tangent import companion_start
from maps.parameters import ParameterError


@pytest.fixture(scope="module")
def base():
    return maps.get_scene("thesis-1dof").parameters(preset="matlab-listing", V=90.0)


def _compare(a, b, lyap_tol=1e-6):
    # lyap_tol: both paths integrate the tangent vector with the record (the exponents agree to
    # ~1e-8, measured); companions would agree to ~1e-3 only (their 1e-8 separation carries the
    # ~tol integration differences between the paths)
    for x, y in zip(a, b):
        assert x.status == y.status
        assert x.n_impacts == y.n_impacts
        assert x.label == y.label, (x.value, x.label, y.label)
        assert np.nanmax(np.abs(x.points - y.points) / np.maximum(1, np.abs(x.points))) < 1e-8
        assert abs(x.min_clearance - y.min_clearance) < 1e-9
        np.testing.assert_allclose(x.impact_time, y.impact_time, rtol=0, atol=1e-9)
        assert (math.isnan(x.lyapunov) and math.isnan(y.lyapunov)) or abs(x.lyapunov - y.lyapunov) < lyap_tol


@pytest.mark.parametrize("x0", [{}, {"x": 0.0}])
def test_sweep_point_batch_equals_scalar(base, x0):
    """11 values in 4 lanes (refilled 2-3 times each), 2 passes (transient, recorded window with
    every observation guard and the tangent vector); x0 = 0 starts on the stop.  A short horizon:
    the record is not extended (max_record)."""
    point = ValueJob(maps.problem("thesis-1dof", params=base, x0=x0), "relay_hz", transient=4, record=6, lyapunov_steps=6, max_record=6,
                     budget=10)
    values = np.linspace(2.0, 10.0, 11)
    scalar = [point(v) for v in values]
    batch = point.run_many(values)
    _compare(scalar, batch)
    assert sum(r.n_impacts for r in scalar) > 0
    assert all(np.isfinite(r.lyapunov) for r in batch if r.label not in ("periodic", "periodic-no-impact"))
    # steps: the same trajectories need nearly the same number of Taylor steps
    assert all(abs(b.n_steps / a.n_steps - 1) < 0.05 for a, b in zip(scalar, batch))


def test_escaping_lanes_end_and_are_refilled(base):
    """Sweeping V to 1000 V throws the bar out: a lane that ends early is refilled, and the escape
    time is the scalar one (a non-relay parameter swept: the relay frequency is fixed per lane)."""
    point = ValueJob(maps.problem("thesis-1dof", params=dict(base, relay_hz=5.0)), "V", transient=2, record=4, lyapunov_steps=4,
                     max_record=4, budget=6)
    values = np.linspace(600.0, 1000.0, 9)
    scalar = [point(v) for v in values]
    batch = point.run_many(values)
    assert [r.status for r in scalar] == [r.status for r in batch]
    assert 0 < sum(r.status == 1 for r in scalar) < values.size
    for a, b in zip(scalar, batch):
        if a.status == 1:
            assert abs(a.failure_time - b.failure_time) < 1e-7
            assert "left the model's domain" in b.failure and "left the model's domain" in a.failure
        else:   # hundreds of volts: strongly chaotic, round-off differences grow ~10x per period
            p, q = a.points[0], b.points[0]
            assert np.max(np.abs(p - q) / np.maximum(1, np.abs(p))) < 1e-8


def test_companion_lane_equals_lyapunov_along(base):
    """The engine's Benettin companion and the scalar lyapunov_along give the same exponent."""
    point = ValueJob(maps.problem("thesis-1dof", params=base), "relay_hz", transient=5, record=8)
    smap = point.warm()
    system = smap.system
    exps = []
    for W in (3.0, 7.5):
        p = system.validate(dict(base, relay_hz=W))
        smap.set_params(**p)
        o = smap.orbit(point.x0_state(), 8, transient=5)
        scale = np.maximum(np.max(np.abs(o.points), axis=0), 1e-9)
        ref = lyapunov_along(smap.step, o.points, scale=scale, k0=5)
        z0 = companion_start(o.points[0], scale=scale)
        job = OrbitJob(p, z0, None, period=1 / W, rate=W, k0=5, record=8, reference=list(o.points), scale=scale)
        got = exponent_interval(engine_for(system, smap.tol, "batch").run([job])[0].stretch)[0]
        assert got == pytest.approx(ref, abs=1e-3)   # see _compare
        exps.append(got)
    assert all(np.isfinite(exps))


def test_batch_refuses_systems_it_cannot_run(base):
    two = HybridSystem("two-switches", [State("x", "m", "x")], [Parameter("f", "Hz", "f"), Parameter("h", "Hz", "h")],
                       rhs=lambda s: [s.a - s.b], flags={"a": 0.0, "b": 0.0},
                       switches=[PeriodicSwitch("a", "f"), PeriodicSwitch("b", "h")])
    with pytest.raises(ParameterError, match="at most one periodic switch"):
        BatchEngine(two, 1e-10)
    with pytest.raises(ParameterError, match="batch_size"):
        sweep("thesis-1dof", "relay_hz", [5.0], preset="matlab-listing", batch_size=0, progress=False)


def test_sweep_batch_and_scalar_datasets_agree():
    """sweep(batch_size=4) and sweep(batch_size=1) store the same diagram on a short horizon (a budget
    that allows no extension: chaos amplifies the paths' round-off over long windows)."""
    kw = dict(preset="matlab-listing", params={"V": 90.0}, transient=4, record=6, max_record=6, progress=False,
              grazing=False, error_sample=0, budget=10)
    values = np.linspace(3.0, 9.0, 7)
    a = sweep("thesis-1dof", "relay_hz", values, batch_size=1, **kw)
    b = sweep("thesis-1dof", "relay_hz", values, batch_size=4, **kw)
    assert np.array_equal(a.class_code.values, b.class_code.values)
    assert np.array_equal(a.n_impacts.values, b.n_impacts.values)
    for k in ("x", "v", "i", "z"):
        np.testing.assert_allclose(a[k].values, b[k].values, rtol=1e-8, atol=1e-10)


def test_values_still_converging_integrate_on_from_the_batch_orbit(base):
    """4 Hz is not-converged after 300 periods with a decaying recurrence: run_many hands it to the
    scalar extension (max_transient), which finds the period-2 orbit without impact as the scalar path."""
    point = ValueJob(maps.problem("thesis-1dof", params=base, dc_law="listing"), "relay_hz", transient=300, record=100,
                     max_transient=1000)
    a, b = point(4.0), point.run_many([4.0])[0]
    assert a.label == b.label == "periodic-no-impact"
    assert a.period == b.period == 2
    assert a.transient_used == b.transient_used > 300
    assert abs(a.min_clearance - b.min_clearance) < 1e-6 and b.min_clearance > 5e-4


def test_an_empty_ensemble_is_an_empty_list():
    """No job: no orbit (the batch engine used to fail on its parked lane, built from the first job)."""
    smap = maps.StroboscopicMap(maps.problem("impact-oscillator"))
    assert smap.orbits([], [], 10) == [] and smap.orbits([], [], 10, tangent=True) == []
