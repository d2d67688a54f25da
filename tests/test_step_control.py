"""heyoka sizes each Taylor step on the state *and* the event functions.

The infinity norm that switches its error control from absolute to relative includes the
event functions' Taylor coefficients, so an event function much larger than the state
silently loosens the tolerance.  Every guard of the model is therefore written in units
no larger than the state's (metres, metres per second, or a force divided by the stop
stiffness), and an inactive guard is a small constant rather than identically zero.
"""
import itertools

import heyoka as hy
import numpy as np
import pytest

import maps


def test_a_large_event_function_loosens_heyokas_tolerance():
    """The fact behind the rule: x'' = -x, 100 s, tol 1e-10, with and without x - 1e9 as an event."""
    x, v = hy.make_vars("x", "v")
    exact = np.array([0.5 * np.cos(100.0), -0.5 * np.sin(100.0)])
    errors, steps = [], []
    for events in ([], [hy.t_event(x - 1e9)]):
        ta = hy.taylor_adaptive([(x, v), (v, -x)], [0.5, 0.0], tol=1e-10, t_events=events)
        steps.append(ta.propagate_until(100.0)[3])
        errors.append(np.abs(ta.state - exact).max())
    assert errors[0] < 1e-10
    assert errors[1] > 1e-4 and steps[1] < steps[0] / 3


SCENES = [("thesis-1dof", {}), ("thesis-2dof", {}), ("thesis-2dof", {"soil": "coulomb"}),
          ("dc-only", {}), ("ac-only", {}), ("ac-stop", {}), ("prototype", {})]


@pytest.mark.parametrize("name, options", SCENES)
def test_every_guard_is_no_larger_than_the_state(name, options):
    sc = maps.get_scene(name)
    if options:
        sc = sc.with_options(**options)
    system = sc.system
    params = sc.parameters(preset="matlab-listing", **({"V": 90.0} if "V" in system.param_names else {}))
    ds = maps.simulate(sc, t_end=0.3, params={k: params[k] for k in ("V",) if k in params},
                       preset="matlab-listing", dt=1e-3, tol=1e-10)
    Y = np.stack([ds[n].values for n in system.state_names], axis=1)
    names = [g.name for g in system.guards]
    binary = [f for f in system.flag_names if f not in ("escaped",)]
    worst = 0.0
    for y, t in zip(Y[::10], ds["t"].values[::10]):
        bound = max(1.0, np.abs(y).max())
        for bits in itertools.product((0.0, 1.0), repeat=len(binary)):
            flags = dict(system.flag_defaults, **dict(zip(binary, bits)))
            if "slip_dir" in flags:
                flags["slip_dir"] = 1.0 if bits[binary.index("slip_dir")] else -1.0
            g = system.evaluate(names, y, params, flags, t)
            worst = max(worst, np.abs(g).max() / bound)
    assert worst <= 1.0
