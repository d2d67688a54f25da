"""The scalar engine applies a guard's transition in its event callback, inside heyoka's
propagate_until: what that must not change (the motion, the step count, errors, the run's
isolation) and what it needs an option for (steps per mode)."""
import math
import weakref

import heyoka as hy
import numpy as np
import pytest

import maps
from maps.engines.scalar import HybridRun


def _thesis():
    sc = maps.get_scene("thesis-1dof").with_options(dc_law="listing")
    p = sc.parameters(preset="matlab-listing", V=90.0, relay_hz=9.0)
    return sc.system, p, sc.system.state_vector(sc.initial_state())


def test_ending_propagate_until_at_every_transition_changes_nothing():
    """A run whose callbacks end propagate_until after every transition (steps_by_mode, as the
    old loop did at every guard) and one that integrates on through them take the same Taylor
    steps from the same states: final states equal to the last bit, 8 contacts in 2 s."""
    system, p, y0 = _thesis()
    on = HybridRun(system, p, y0, tol=1e-12).advance(2.0)
    stops = HybridRun(system, p, y0, tol=1e-12, steps_by_mode=True).advance(2.0)
    assert np.array_equal(on.y, stops.y)
    assert on.n_steps == stops.n_steps
    assert [(e.name, e.t) for e in on.events] == [(e.name, e.t) for e in stops.events]
    assert sum(e.name == "contact" for e in on.events) == 8


def test_steps_per_mode_need_the_option_and_add_up():
    system, p, y0 = _thesis()
    run = HybridRun(system, p, y0, tol=1e-12).advance(1.0)
    with pytest.raises(maps.ParameterError, match="steps_by_mode=True"):
        run.steps_where(contact=1)
    run = HybridRun(system, p, y0, tol=1e-12, steps_by_mode=True).advance(1.0)
    inside, outside = run.steps_where(contact=1), run.steps_where(contact=0)
    assert inside > 0 and outside > 0
    assert inside + outside == run.n_steps == sum(run.mode_steps.values())


def _raising_system():
    """Free fall onto a stop at x = 0 whose restitution raises on the second impact."""
    calls = []

    def rhs(s):
        return [s.v, hy.expression(-9.81)]

    def bounce(y, p):
        calls.append(1)
        if len(calls) == 2:
            raise ValueError("restitution failed on purpose")
        y = y.copy()
        y[1] = -0.5 * y[1]
        return y

    def guards(s):
        return [maps.Guard("contact", s.x, -1, reset=bounce, role="impact")]

    system = maps.HybridSystem("falling", states=[maps.State("x", "m", "height"), maps.State("v", "m s-1", "speed")],
                               parameters=[], rhs=rhs, guards=guards)
    return system, calls


def test_an_error_in_a_transition_comes_out_of_advance_as_itself():
    """An exception inside a callback never crosses heyoka: advance() raises it once
    propagate_until has returned, at the second impact (t = 3 sqrt(2 h / g) for r = 1/2), and
    the run restarts cleanly afterwards."""
    system, calls = _raising_system()
    run = HybridRun(system, {}, {"x": 1.0, "v": 0.0}, tol=1e-14)
    with pytest.raises(ValueError, match="on purpose"):
        run.advance(5.0)
    t1 = math.sqrt(2 / 9.81)
    assert run.t == pytest.approx(t1 + 2 * 0.5 * 9.81 * t1 / 9.81, abs=1e-12)   # 1st flight + a bounce of v/2
    calls.clear()
    calls.append(1)        # the next bounce is the 2nd call again: fail at the 1st impact of the restart
    run.reset(0.0, {"x": 1.0, "v": 0.0})
    with pytest.raises(ValueError, match="on purpose"):
        run.advance(5.0)
    assert run.t == pytest.approx(t1, abs=1e-12)


def test_stop_roles_are_roles_of_this_run():
    system, p, y0 = _thesis()
    run = HybridRun(system, p, y0, tol=1e-12)
    with pytest.raises(maps.ParameterError, match="allowed roles here"):
        run.advance(1.0, stop_roles=("impakt",))
    run.advance(1.0, stop_roles=("impact",))
    assert run.stopped_by == "contact" and run.events[-1].name == "contact"


def test_runs_of_one_compiled_integrator_act_on_their_own_state():
    """Two runs share one compiled prototype (deep copies, each with callbacks bound to itself):
    advanced alternately, period by period, each ends exactly where it ends alone."""
    system, p, y0 = _thesis()
    q = dict(p, V=120.0)
    alone = [HybridRun(system, pp, y0, tol=1e-12).advance(1.0).y for pp in (p, q)]
    a, b = HybridRun(system, p, y0, tol=1e-12), HybridRun(system, q, y0, tol=1e-12)
    for k in range(1, 10):
        a.advance(k / 9.0)
        b.advance(k / 9.0)
    assert np.array_equal(a.y, alone[0]) and np.array_equal(b.y, alone[1])
    assert not np.array_equal(alone[0], alone[1])


def test_a_dropped_run_is_freed_at_once():
    """The callbacks hold their run by a weak reference: no cycle keeps an integrator alive."""
    system, p, y0 = _thesis()
    ref = weakref.ref(HybridRun(system, p, y0, tol=1e-12).advance(0.2))
    assert ref() is None


def test_a_deep_copy_of_a_run_integrates_on_its_own():
    """copy.deepcopy of a run midway: the copy's views and callbacks are its own, so both end where
    the original alone ends, and advancing one leaves the other where it was."""
    import copy
    system, p, y0 = _thesis()
    alone = HybridRun(system, p, y0, tol=1e-12).advance(1.0)
    run = HybridRun(system, p, y0, tol=1e-12).advance(0.5)
    twin = copy.deepcopy(run)
    twin.advance(1.0)
    assert run.t == 0.5 and np.array_equal(twin.y, alone.y)
    assert [e.name for e in twin.events] == [e.name for e in alone.events]
    run.advance(1.0)
    assert np.array_equal(run.y, alone.y)
