"""A non-periodic set's mean lifetime (bifurc.attractors.lifetime) against closed forms.

The open map with a hole: on [0, 1) two full linear branches, [0, a) -> [0, 1) and [a, 1 - h) -> [0, 1), and the
hole [1 - h, 1) sent to the stable fixed point 2.  Every full-branch linear map carries Lebesgue measure to
(1 - h) times itself on [0, 1) (the preimage of an interval J has length (a + (1 - h - a)) |J|), so from a
uniform start P(still on the set after n steps) = (1 - h)^n exactly and the mean number of steps until the
trajectory sits on the fixed point is 1 / h.  The logistic map at r = 4 is conjugate to the tent map: its
chaos never ends.
"""
from __future__ import annotations

import math
import numpy as np
import pytest

from bifurc.attractors.lifetime import estimate_lifetime, fall_index, lifetime_interval
from one_dim_map import OneDimMap


def _hole_map(h: float) -> OneDimMap:
    a = 0.45 * (1.0 - h)          # unequal branches: no dyadic round-off collapse

    def f(x):
        if x < a:
            return x / a
        if x < 1.0 - h:
            return (x - a) / (1.0 - h - a)
        return 2.0
    return OneDimMap(f)


def _records_on_the_set(m, h, n, seed):
    """``n`` records of 48 points that stay on [0, 1 - h) (a census records a set only while on it)."""
    rng, out = np.random.default_rng(seed), []
    while len(out) < n:
        rec = m.orbits([{}], [np.array([rng.uniform(0.0, 1.0 - h)])], 48)[0]
        if rec.points.max() < 1.0 - h:
            out.append(rec)
    return out


@pytest.mark.parametrize("h", [0.01, 0.001])
def test_the_lifetime_interval_contains_the_closed_form(h):
    """Mean lifetime 1 / h (100 and 1000 steps, far below the 4000-step horizon): the interval contains it for
    at least 19 of 20 records (its level is 95 % or more) and every verdict is "saddle" or, for an unlucky
    draw, "long-lived" -- never "attractor"; at h = 0.01 every one is "saddle"."""
    m = _hole_map(h)
    got = [estimate_lifetime(m, rec, 0, 4000, seed=j) for j, rec in enumerate(_records_on_the_set(m, h, 20, 7))]
    assert sum(g.low <= 1.0 / h <= g.high for g in got) >= 19
    verdicts = [g.verdict(4000) for g in got]
    assert "attractor" not in verdicts
    if h == 0.01:
        assert set(verdicts) == {"saddle"}
    assert np.median([g.tau for g in got]) == pytest.approx(1.0 / h, rel=0.5)


def test_a_transient_as_long_as_the_horizon_is_never_called_an_attractor():
    """Mean lifetime 4000 steps = the horizon: 20 records, none is an attractor, and the interval contains 4000
    in at least 19."""
    h = 1.0 / 4000
    m = _hole_map(h)
    got = [estimate_lifetime(m, rec, 0, 4000, seed=j) for j, rec in enumerate(_records_on_the_set(m, h, 20, 8))]
    assert all(g.verdict(4000) != "attractor" for g in got)
    assert sum(g.low <= 4000 <= g.high for g in got) >= 19


def test_the_logistic_maps_chaos_at_r4_is_an_attractor():
    """At r = 4 no copy ever falls: the interval's lower end exceeds the horizon, the estimate is infinite."""
    m = OneDimMap(lambda x: 4.0 * x * (1.0 - x))
    rec = m.orbits([{}], [np.array([0.2345])], 48)[0]
    got = estimate_lifetime(m, rec, 0, 4000)
    assert got.verdict(4000) == "attractor" and got.falls == 0 and math.isinf(got.tau) and got.low > 4000


def test_no_falls_interval_in_closed_form():
    """With no falls the chi-square(2) quantile is -2 ln(1 - p): the lower end is T / -ln(a / 2), the upper one
    infinite; with d falls the estimate is T / d."""
    tau, low, high = lifetime_interval(1000.0, 0, 0.95)
    assert math.isinf(tau) and math.isinf(high)
    assert low == pytest.approx(1000.0 / -math.log(0.025), rel=1e-12)
    assert lifetime_interval(1000.0, 4, 0.95)[0] == pytest.approx(250.0, rel=1e-15)


def test_fall_index_is_where_the_repetition_starts():
    """Points chaotic up to index 30, then a period-3 cycle: the fall is at 30 (period 3 of candidates 1-4);
    still chaotic at the end: None."""
    rng = np.random.default_rng(0)
    cycle = np.tile([[0.1], [0.5], [0.9]], (20, 1))
    pts = np.vstack([rng.uniform(0, 1, (30, 1)), cycle])
    assert fall_index(pts, [1, 2, 3, 4], 16) == 30
    assert fall_index(np.vstack([cycle, rng.uniform(0, 1, (30, 1))]), [1, 2, 3, 4], 16) is None


def test_the_lifetime_is_stored_and_survives_a_resume_part():
    """A chaotic attractor's lifetime (inf, interval [5000, inf]) goes to the dataset's columns in strobe periods
    and through a resume part's JSON unchanged; a periodic one's stays NaN."""
    from bifurc.attractors.dataset import _columns
    from bifurc.attractors.identify import Attractor
    from bifurc.attractors.job import ValueCensus, decode, encode
    from bifurc.labels.codes import ClassCode
    chaos = Attractor(int(ClassCode.CHAOTIC), points=np.zeros((3, 2)), lifetime=math.inf,
                      lifetime_interval=(5000.0, math.inf))
    orbit = Attractor(int(ClassCode.PERIODIC), 1, points=np.zeros((1, 2)))
    from bifurc.attractors.fractions import census_fractions
    cols = _columns([1.0], [{0: chaos, 1: orbit}], [[0, 1, 0]], 2, {}, census_fractions([[0, 1, 0]], 2))
    assert math.isinf(cols["lifetime"][0, 0]) and cols["lifetime_low"][0, 0] == 5000.0
    assert np.isnan(cols["lifetime"][0, 1]) and np.isnan(cols["lifetime_high"][0, 2])
    back = decode(encode(ValueCensus([0], [chaos], [10]))).found[0]
    assert math.isinf(back.lifetime) and back.lifetime_interval == (5000.0, math.inf)
