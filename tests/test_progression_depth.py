"""The thesis' progression measure (0.2 m over the time to reach it, Tables 5.2-5.5; Fig 5.22's gradients):
studies/prototype_progression/depth.py against closed forms and against maps.simulate's own time_to_depth."""
import math

import numpy as np
import pytest

import maps
from studies.prototype_progression import depth


def test_first_time_and_gradients_on_closed_forms():
    t = np.linspace(0.0, 10.0, 61)                       # samples every 1/6 s
    d = 0.01 * t ** 2                                    # depth [m]: 0.2 m at sqrt(20) s
    got = depth.first_time(t, d, 0.2)
    assert got == pytest.approx(math.sqrt(20.0), abs=0.01)   # chord of a parabola: within 1/6 s^2 / 8 x 0.02 / slope
    assert math.isnan(depth.first_time(t, d, 5.0))
    assert depth.thesis_rate(25.0) == pytest.approx(8.0)      # 0.2 m in 25 s: 8 mm/s
    # two straight segments: 4 mm/s to 0.5 m, then 1 mm/s to 0.9 m
    tt = np.linspace(0.0, 525.0, 3151)
    dd = np.where(tt <= 125.0, 0.004 * tt, 0.5 + 0.001 * (tt - 125.0))
    g = depth.gradients({"t": tt, "depth": dd})
    assert g["deepest_m"] == pytest.approx(0.9) and g["seconds"] == pytest.approx(525.0, abs=1e-6)
    assert g["initial"] == pytest.approx(4.0, rel=1e-6) and g["final"] == pytest.approx(1.0, rel=1e-6)
    assert g["overall"] == pytest.approx(1e3 * 0.9 / 525.0, rel=1e-6)
    g = depth.gradients({"t": tt, "depth": dd}, target=0.5)        # a run past its target: measured to it
    assert g["deepest_m"] == 0.5 and g["seconds"] == pytest.approx(125.0, abs=1e-6)
    assert g["final"] == pytest.approx(4.0, rel=1e-6) and g["overall"] == pytest.approx(4.0, rel=1e-6)


def test_the_time_to_02_m_agrees_with_maps_simulate():
    """Viscous soil (the rig reaches 0.2 m in about 0.9 s): the run's interpolated time against the time
    history of maps.simulate, sampled every 0.2 ms by another path (its time_to_depth)."""
    run = depth.depth_run("viscous", relay_hz=6.0, v_amplitude=127.28, f_static=31.1, t_max=1.5, chunk=0.5)
    h = maps.simulate("prototype", t_end=1.5, soil="viscous", tol=1e-10,
                      params={"relay_hz": 6.0, "V": 127.28, "F_static": 31.1})
    ref = float(h.time_to_depth)
    assert run["status"] == "ok" and ref == pytest.approx(run["times"][0], abs=2e-3)
    # and the samples are the rig's position, 20 per relay period
    k = 60
    x2 = float(h.x2.sel(t=k / 120.0, method="nearest"))
    assert run["depth"][k] == pytest.approx(float(h.x2.values[0]) - x2, abs=2e-4 * 0.25)
