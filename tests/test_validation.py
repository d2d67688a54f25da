"""Bad input is refused with a message naming the parameter and its allowed range."""
import math

import pytest

import maps
from maps import ParameterError


@pytest.mark.parametrize("kwargs, named", [
    (dict(params={"m": -1.0}), r"'m'.*\(0, inf\)"),
    (dict(params={"V": math.nan}), r"'V'.*finite"),
    (dict(params={"relay_hz": 0.0}), r"'relay_hz'.*\(0, 1000\]"),
    (dict(params={"k": math.inf}), r"'k'"),
    (dict(params={"mass": 1.0}), r"'mass'.*parameters are: m, g"),
    (dict(preset="best-guess"), r"'best-guess'.*thesis-text"),
    (dict(x0={"y": 1.0}), r"'y'.*states are: x, v, i, z"),
    (dict(tol=math.inf), r"'tol'"),
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
    with pytest.raises(ParameterError, match="no relay"):
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
