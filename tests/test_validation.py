"""Bad input is refused with a message naming the parameter and its allowed range."""
import math

import numpy as np
import pytest

import maps
from maps import ParameterError


@pytest.mark.parametrize("kwargs, named", [
    (dict(params={"m": -1.0}), r"'m'.*\(0, inf\)"),
    (dict(params={"V": math.nan}), r"'V'.*finite"),
    (dict(params={"relay_hz": 0.0}), r"'relay_hz'.*\(0, 1000\]"),
    (dict(params={"k": math.inf}), r"'k'.*finite.*\(0, 1e\+14\] N m-1"),
    (dict(params={"mass": 1.0}), r"'mass'.*parameters are: m, g"),
    (dict(preset="best-guess"), r"'best-guess'.*thesis-text"),
    (dict(x0={"y": 1.0}), r"'y'.*states are: x, v, i, z"),
    (dict(tol=math.inf), r"'tol'.*finite.*\(0, 0.01\]"),
    (dict(tol=0.0), r"'tol'.*\(0, 0.01\]"),
    (dict(circuit="foo"), r"'circuit'.*thesis, kvl"),
    (dict(ac_sign="down"), r"'ac_sign'.*physical, listing"),
])
def test_simulate_refuses_bad_input(kwargs, named):
    with pytest.raises(ParameterError, match=named):
        maps.simulate("thesis-1dof", periods=1, **kwargs)


def test_unknown_scene_lists_the_scenes():
    with pytest.raises(ParameterError, match=r"'mole'.*thesis-1dof"):
        maps.simulate("mole", t_end=1.0)


def test_duration_must_be_given_once_and_positive():
    with pytest.raises(ParameterError, match="exactly one"):
        maps.simulate("thesis-1dof", periods=2, t_end=1.0)
    with pytest.raises(ParameterError, match="exactly one"):
        maps.simulate("thesis-1dof")
    with pytest.raises(ParameterError, match="'periods'"):
        maps.simulate("thesis-1dof", periods=-3)
    with pytest.raises(ParameterError, match="declares no clock"):
        maps.simulate("dc-only", periods=3)


def test_scene_parameters_validate_like_simulate():
    scene = maps.get_scene("thesis-2dof")
    with pytest.raises(ParameterError, match=r"'m2'"):
        scene.parameters(m2=0.0)
    with pytest.raises(ParameterError, match=r"'m'.*scene 'thesis-2dof'"):
        scene.parameters(m=0.1)  # 2-DOF scenes name their masses m1 and m2
    assert scene.parameters(m2=3.0)["m2"] == 3.0


def test_a_nonphysical_option_combination_is_refused():
    with pytest.raises(ParameterError, match="'energy'"):
        maps.ModelOptions(dof=2, energy=True)


@pytest.mark.parametrize("overrides, named", [
    (dict(m=-1.0), r"'m'.*-1 kg.*\(0, inf\) kg"),
    (dict(V=math.nan), r"'V'.*finite.*nan"),
    (dict(relay_hz=0.0), r"'relay_hz'.*\(0, 1000\]"),
    (dict(V="ninety"), r"'V'.*must be a number"),
    (dict(mass=1.0), r"'mass'.*parameters are: m, g"),
])
def test_scene_parameters_refuse_what_simulate_refuses(overrides, named):
    with pytest.raises(ParameterError, match=named):
        maps.get_scene("thesis-1dof").parameters(**overrides)
    with pytest.raises(ParameterError, match=named):
        maps.simulate("thesis-1dof", periods=1, params=overrides)


def test_scene_parameters_refuse_an_unknown_preset():
    with pytest.raises(ParameterError, match=r"'best-guess'.*matlab-listing"):
        maps.get_scene("thesis-1dof").parameters(preset="best-guess")


def test_options_are_named_with_their_allowed_values():
    with pytest.raises(ParameterError, match=r"'circuit' = 'foo'; allowed: thesis, kvl"):
        maps.ModelOptions(circuit="foo")
    with pytest.raises(ParameterError, match=r"'colour'.*options: dof"):
        maps.get_scene("thesis-1dof").with_options(colour="red")


def test_initial_states_are_checked_before_integration():
    with pytest.raises(ParameterError, match=r"unknown state 'y'.*states are: x, v, i, z"):
        maps.get_scene("thesis-1dof").initial_state(y=0.001)
    with pytest.raises(ParameterError, match=r"x0 must map state names.*x, v, i, z"):
        maps.simulate("thesis-1dof", periods=1, x0=[0.001, 0.0])
    with pytest.raises(ParameterError, match=r"initial state 'x' must be a number"):
        maps.simulate("thesis-1dof", periods=1, x0={"x": "high"})
    scene = maps.get_scene("dc-only")
    with pytest.raises(ParameterError, match=r"initial state 'x' must be finite"):
        maps.HybridRun(scene.system, scene.parameters(), np.array([np.nan, 0.0], dtype=np.longdouble),
                       fp_type=np.longdouble)


def test_engine_refuses_what_heyoka_would_fail_on_deep_inside():
    """Found by this test: fp_type=int and advance(inf) raised heyoka's TypeError/ValueError,
    a NaN start or end time made advance() a silent no-op."""
    scene = maps.get_scene("dc-only")
    p = scene.parameters()
    with pytest.raises(ParameterError, match=r"'fp_type'.*longdouble"):
        maps.HybridRun(scene.system, p, {"x": 0.01}, fp_type=int)
    with pytest.raises(ParameterError, match=r"'t0'.*finite"):
        maps.HybridRun(scene.system, p, {"x": 0.01}, t0=math.nan)
    run = maps.HybridRun(scene.system, p, {"x": 0.01})
    for t_end in (math.nan, math.inf):
        with pytest.raises(ParameterError, match=r"'t_end'.*finite"):
            run.advance(t_end)
    with pytest.raises(ParameterError, match=r"'fp_type'"):
        maps.run_scene("dc-only", 0.1, fp_type=int)


def test_strings_booleans_event_caps_and_sample_times_are_checked():
    with pytest.raises(ParameterError, match=r"'V'.*must be a number, got '90'"):
        maps.simulate("thesis-1dof", periods=1, params={"V": "90"})
    with pytest.raises(ParameterError, match=r"'V'.*must be a number, got True"):
        maps.simulate("thesis-1dof", periods=1, params={"V": True})
    with pytest.raises(ParameterError, match=r"'max_events'"):
        maps.run_scene("thesis-1dof", 0.1, max_events=0)
    with pytest.raises(ParameterError, match=r"t_eval must lie in \[0, t_end"):
        maps.simulate("thesis-1dof", t_end=0.1, t_eval=np.array([0.0, 0.2]))


def test_params_and_numeric_options_are_checked():
    """Found by this test: params given as a list raised a TypeError from Scene.parameters;
    a negative stick_speed or a string for a boolean option was accepted silently."""
    with pytest.raises(ParameterError, match=r"params must map parameter names"):
        maps.simulate("thesis-1dof", periods=1, params=[90.0, 9.0])
    with pytest.raises(ParameterError, match=r"'stick_speed' = -1 m s-1.*\[0, 1\] m s-1"):
        maps.ModelOptions(stick_speed=-1.0)
    with pytest.raises(ParameterError, match=r"'unstick_force' must be finite.*\[0, 1000\] N"):
        maps.get_scene("thesis-1dof").with_options(unstick_force=math.nan)
    with pytest.raises(ParameterError, match=r"option 'dc' = 'yes'; allowed: True, False"):
        maps.ModelOptions(dc="yes")


def test_dimensionless_ranges_are_printed_without_a_unit():
    with pytest.raises(ParameterError, match=r"'r' \(coefficient of restitution\) = 1.5 is outside "
                                             r"its allowed range \[0, 1\]$"):
        maps.HybridRun(maps.forced_oscillator_with_stop(), dict(w0=1.0, zeta=0.0, F=0.5, Omega=0.8,
                                                                e=-0.6, r=1.5), {"x": 0.0})
