"""The census of an autonomous flow sampled every ``sample_step`` (issue 47 section 3) against closed forms.

The Hopf normal form x' = mu x - w y - x (x^2 + y^2), y' = w x + mu y - y (x^2 + y^2) (in polar form r' = r (mu - r^2),
theta' = w): for mu < 0 the origin attracts every start, and the flow over one step dt has the Jacobian exp(A dt) at
it, A = [[mu, -w], [w, mu]], so the sampled map's multipliers are exp((mu +- i w) dt); for mu > 0 the circle r =
sqrt(mu) attracts every start but the origin, traversed in 2 pi / w, its samples turning by w dt about it each step.
The flow's divergence on the cycle is 2 mu - 4 r^2 = -2 mu: it dissipates, so no start is "neutral".
"""
from __future__ import annotations

import math

import numpy as np
import pytest

import bifurc
import maps
from bifurc.labels.codes import OUTCOMES
from bifurc.labels.codes import ClassCode
from maps import HybridSystem, Parameter, PeriodicSwitch, State
from maps.parameters import ParameterError

STEP, W = 0.3, 1.0


def hopf(step=STEP):
    return HybridSystem("hopf-normal-form", states=[State("x", "1", "first coordinate"), State("y", "1", "second")],
                        parameters=[Parameter("mu", "1", "growth rate", -10, 10),
                                    Parameter("w", "rad s-1", "angular frequency", 0, 100, low_open=True)],
                        rhs=lambda s: [s.mu * s.x - s.w * s.y - s.x * (s.x * s.x + s.y * s.y),
                                       s.w * s.x + s.mu * s.y - s.y * (s.x * s.x + s.y * s.y)],
                        sample_step=step)


HOPF = maps.Scene("hopf-normal-form", "x' = mu x - w y - x r^2, y' = w x + mu y - y r^2 (tests/test_census_flows.py)",
                  None, preset=None, overrides={"mu": (0.25, "tests/test_census_flows.py"),
                                                "w": (W, "tests/test_census_flows.py")},
                  x0={"x": 0.1, "y": 0.0}, builder=hopf, box={"x": (-1.5, 1.5), "y": (-1.5, 1.5)})


@pytest.fixture(scope="module")
def census():
    return bifurc.attractors(HOPF, "mu", [-0.5, 0.25], n_starts=16, seed=2, progress=False, workers=1)


def _present(ds, i) -> list:
    return [j for j in range(ds.sizes["attractor"] - len(OUTCOMES)) if ds.present.values[i, j]]


def test_the_stable_focus_is_a_fixed_point_with_multipliers_exp_of_its_eigenvalues_times_the_step(census):
    ds = census
    assert ds.attrs["sample_step"] == STEP
    (j,) = _present(ds, 0)
    assert float(ds.basin_fraction.values[0, j]) == 1.0
    assert int(ds.class_code.values[0, j]) == int(ClassCode.PERIODIC_NO_IMPACT) and int(ds.period.values[0, j]) == 1
    assert abs(float(ds.x.values[0, j, 0])) < 1e-9 and abs(float(ds.y.values[0, j, 0])) < 1e-9
    mu = -0.5
    assert np.allclose(ds.multiplier_abs.values[0, j], math.exp(mu * STEP), rtol=1e-8, atol=0)
    assert sorted(ds.multiplier_arg.values[0, j]) == pytest.approx([-W * STEP, W * STEP], abs=1e-8)
    df = ds.bifurc.table()
    assert list(df.loc[df["mu"] == -0.5, "description"]) == ["fixed point"]


def test_the_limit_cycle_has_its_radius_and_period(census):
    ds = census
    (j,) = _present(ds, 1)
    assert float(ds.basin_fraction.values[1, j]) == 1.0            # none neutral, none undecided
    assert int(ds.class_code.values[1, j]) == int(ClassCode.QUASI_PERIODIC)
    n = int(ds.n_points.values[1, j])
    r = np.hypot(ds.x.values[1, j, :min(n, ds.sizes["node"])], ds.y.values[1, j, :min(n, ds.sizes["node"])])
    assert np.allclose(r, math.sqrt(0.25), rtol=0, atol=1e-6)
    # the samples' centre is their mean, off the circle's centre by the part turn beyond whole ones (769 samples:
    # 36.7 turns): 5e-5 of the period
    assert float(ds.cycle_period.values[1, j]) == pytest.approx(2 * math.pi / W, rel=2e-4)
    assert float(ds.lyapunov_low.values[1, j]) <= 0.0 <= float(ds.lyapunov_high.values[1, j])
    assert float(ds.area_rate.values[1, j]) == pytest.approx(-2 * 0.25 * STEP, abs=1e-3)   # the divergence x dt
    from bifurc.attractors.dataset import census_lines
    assert "A" in census_lines(ds)[2] and "limit cycle" in census_lines(ds)[2]


def test_a_sample_step_is_declared_alone_and_positive():
    with pytest.raises(ParameterError, match="sample_step"):
        hopf(0.0)
    with pytest.raises(ValueError, match="sample_step"):
        HybridSystem("two-clocks", states=[State("x", "1", "x")], parameters=[Parameter("f", "Hz", "f", 0, 10)],
                     flags={"P": 1.0}, rhs=lambda s: [-s.x], switches=[PeriodicSwitch("P", "f")], sample_step=0.1)
    assert hopf().autonomous and hopf().strobe_period_of({"mu": 1.0, "w": 1.0}) == STEP
