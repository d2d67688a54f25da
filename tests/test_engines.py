"""Engine conformance: every engine of maps.engines runs the same problems to the same event
sequence, flags and states.

The scalar engine is checked against closed forms, scipy and extended precision elsewhere
(test_oscillator, test_sticking, test_crosscheck, test_stability); here the batch engine must
reproduce it: the same events in the same order at the same instants (1e-9 s), the same flags
at every sample, states to 1e-8 relative.  Horizons are short (a few periods): the two engines
take different steps, and the chaotic thesis regimes amplify round-off.
"""
import math

import numpy as np
import pytest

import maps
from bifurc.verification.suite import CASES, case_scene
from maps.engines import ENGINES, OrbitJob, engine_for


def _case(name):
    return next(c for c in CASES if c.name == name)


def _problem(name):
    """(system, params, y0, flags, sampling period [s], periods, max events per period)."""
    if name == "measured-law":
        sc = maps.get_scene("thesis-1dof").with_options(dc_law="measured", ac_sign="listing")
        p = sc.parameters(preset="matlab-listing", V=90.0, relay_hz=7.0)
        y0 = sc.system.state_vector(sc.initial_state(x=0.0, v=0.0, i=0.1, z=0.0))
        return sc.system, p, y0, None, 1.0 / 7.0, 8, 10_000
    if name == "prototype-drift":
        sc = maps.get_scene("prototype").with_options(soil="drift")
        p = sc.parameters()
        return sc.system, p, sc.system.state_vector(sc.initial_state()), None, 1.0 / p["relay_hz"], 8, 10_000
    if name == "oscillator":
        system = maps.forced_oscillator_with_stop()
        p = system.validate(dict(w0=1.0, zeta=0.05, F=0.5, Omega=2.5, e=0.0, r=0.7))
        return system, p, system.state_vector({"x": 0.2, "v": 0.0}), None, 2 * math.pi / 2.5, 12, 10_000
    case = _case(name)
    sc, p = case_scene(case)
    y0 = sc.system.state_vector(sc.initial_state(**case.x0))
    periods = max(1, round(case.t_end * p["relay_hz"])) if "relay_hz" in p else 4
    return (sc.system, p, y0, case.flags or None, 1.0 / p["relay_hz"], min(periods, 8),
            case.max_events_per_period or 10_000)


PROBLEMS = {
    "graze-thesis": "thesis-1dof, 9 Hz, 90 V: contacts and relay switches",
    "chatter-relay": "a bar that chatters, sticks on the stop and leaves it (stick/unstick)",
    "thrown-out": "an escape",
    "chatter-no-stick": "the per-period event cap",
    "prototype-stick": "2-DOF, Coulomb soil (a reset map), the bar and the rig sticking",
    "prototype-drift": "2-DOF, drift soil: the slider state, elastic and progression modes (guards with callables)",
    "oscillator": "the restitution oscillator: a reset map, no relay, strobe period 2 pi / Omega",
    "measured-law": "the measured DC law: region modes set by the start rule and changed by guards",
}


def _run(method, name):
    system, p, y0, flags, T, periods, cap = _problem(name)
    eng = engine_for(system, 1e-12, method, max_events_per_period=cap, batch_size=4)
    job = OrbitJob(p, y0, flags, period=T, rate=p.get("relay_hz"), record=periods, log=True)
    return eng.run([job])[0]


@pytest.mark.parametrize("name", list(PROBLEMS))
def test_engines_agree(name):
    ref = _run("scalar", name)
    for method in ENGINES:
        if method == "scalar":
            continue
        got = _run(method, name)
        assert got.status == ref.status, (method, got.failure, ref.failure)
        if ref.status != "ok":
            assert got.failure_time == pytest.approx(ref.failure_time, abs=1e-9)
        assert len(got.points) == len(ref.points)
        assert got.flags == ref.flags
        for a, b in zip(got.points, ref.points):
            assert np.max(np.abs(a - b) / np.maximum(1.0, np.abs(b))) < 1e-8
        events = lambda r: [e for period in r.period_events + [r.tail_events] for e in period]  # noqa: E731
        ea, eb = events(got), events(ref)
        assert [e[0] for e in ea] == [e[0] for e in eb], method
        assert np.max(np.abs([x[1] - y[1] for x, y in zip(ea, eb)]), initial=0.0) < 1e-9
        assert got.final_flags == ref.final_flags


def test_problems_exercise_what_they_claim():
    """The conformance problems are not vacuous: each shows the behaviour it stands for."""
    names = lambda r: {e[0] for period in r.period_events + [r.tail_events] for e in period}  # noqa: E731
    r = _run("scalar", "graze-thesis")
    assert "contact" in names(r) and r.n_switches >= 8
    assert {"stick", "unstick"} <= names(_run("scalar", "chatter-relay"))
    assert _run("scalar", "thrown-out").status == "escaped"
    capped = _run("scalar", "chatter-no-stick")
    assert capped.status == "failed" and "events in one relay period" in capped.failure
    proto = _run("scalar", "prototype-stick")
    assert {"stick", "rig_stop"} <= names(proto)
    assert {"soil_yield", "soil_hold", "contact"} <= names(_run("scalar", "prototype-drift"))
    assert "contact" in names(_run("scalar", "oscillator"))
    assert {"dc_up", "contact", "unstick"} <= names(_run("scalar", "measured-law"))


def test_many_jobs_in_few_lanes_equal_one_by_one():
    """Nine parameter sets through 4 lanes (refilled as jobs end, one escaping) give each job's
    own result, in order."""
    system, p, y0, flags, T, _, cap = _problem("graze-thesis")
    jobs = []
    for W in np.linspace(3.0, 9.0, 9):
        q = dict(p, relay_hz=W, V=90.0 if W < 8 else 600.0)
        jobs.append(OrbitJob(system.validate(q), y0, None, period=1.0 / W, rate=W, transient=2, record=3, log=True))
    batch = engine_for(system, 1e-12, "batch", batch_size=4).run(jobs)
    scalar = engine_for(system, 1e-12, "scalar").run(jobs)
    assert [r.status for r in batch] == [r.status for r in scalar]
    assert len({r.status for r in batch}) == 2      # some escape, some not
    # both transients skip the observation stops; the logged windows have them again
    for results in (batch, scalar):
        assert any(e[0] in ("lowest", "deepest") for r in results for period in r.period_events for e in period)
    for a, b in zip(batch, scalar):
        assert len(a.points) == len(b.points)
        for x, y in zip(a.points, b.points):
            assert np.max(np.abs(x - y) / np.maximum(1.0, np.abs(y))) < 1e-8


@pytest.mark.parametrize("name", ["chatter-relay", "prototype-stick"])
def test_where_a_bar_comes_to_rest_does_not_depend_on_what_is_observed(name):
    """A transient (runs that skip the observation stops: flight minima, deepest points)
    and a logged record (every engine stopping at them) reach the same samples and modes.  The bar
    comes to rest on the compliant stop in both problems; the stick rule once acted at the deepest
    points, so a transient without them kept a resting bar in contact where a record stuck it."""
    system, p, y0, flags, T, periods, cap = _problem(name)
    kw = dict(period=T, rate=p.get("relay_hz"))
    for bare_method in ENGINES:       # both engines' transients skip the observation stops
        bare = engine_for(system, 1e-12, bare_method, observations=False, max_events_per_period=cap, batch_size=4)
        skipped = bare.run([OrbitJob(p, y0, flags, transient=periods, record=1, **kw)])[0]
        for method in ENGINES:
            seen = _run(method, name)
            assert "stick" in {e[0] for period in seen.period_events for e in period}
            assert skipped.status == seen.status == "ok"
            a, b = skipped.points[0], seen.points[periods]
            assert np.max(np.abs(a - b) / np.maximum(1.0, np.abs(b))) < 1e-8, (bare_method, method)
            assert skipped.flags[0] == seen.flags[periods], (bare_method, method)
