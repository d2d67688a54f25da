"""Chaotic transients in the census (outcome "transient") and where they go (bifurc.attractors.eventual), against
closed forms and an independent iteration of the same starts.

The open map with a hole as a kicked flow: on [0, 1) two full linear branches, [0, a) -> [0, 1) and [a, 1 - h) ->
[0, 1), a = 0.45 (1 - h); the hole's first part [1 - h, 1 - h + h1) is sent to 2.2 and the rest [1 - h + h1, 1) to
3.2, and x -> 2 + (x - 2) / 2 below 2.5, 3 + (x - 3) / 2 above: two stable fixed points, x = 2 and x = 3 (multiplier
1/2).  Both branches carry Lebesgue measure to (1 - h) times itself on [0, 1), so the chaotic set is a saddle with
mean lifetime exactly 1 / h steps, and a trajectory that has stayed on it enters the hole uniformly: it goes to 2 with
probability h1 / h.  The second state y' = 1 - y decays to 1 (multiplier exp(-1)) and only slows nothing.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

import bifurc
import maps
from bifurc.labels.codes import OUTCOMES
from bifurc.attractors.eventual import eventual_fractions, saddle_groups
from maps import HybridSystem, Parameter, State

H, H1 = 1e-3, 3e-4


def _kicked_hole():
    import heyoka as hy

    def kick(s):
        x, h, h1 = s.x, s.h, s.h1
        a = 0.45 * (1.0 - h)
        inner = hy.select(hy.lt(x, a), x / a, (x - a) / (1.0 - h - a))
        hole = hy.select(hy.lt(x, 1.0 - h + h1), 2.2 + 0.0 * x, 3.2 + 0.0 * x)
        out = hy.select(hy.lt(x, hy.expression(2.5)), 2.0 + 0.5 * (x - 2.0), 3.0 + 0.5 * (x - 3.0))
        return hy.select(hy.lt(x, 1.0 - h), inner, hy.select(hy.lt(x, hy.expression(1.0)), hole, out))
    return HybridSystem(
        "kicked-hole", states=[State("x", "1", "kicked coordinate"), State("y", "1", "relaxing coordinate")],
        parameters=[Parameter("h", "1", "hole width", 0, 0.5), Parameter("h1", "1", "hole's part sent to 2", 0, 0.5)],
        rhs=lambda s: [0.0 * s.x, 1.0 - s.y],
        guards=lambda s: [maps.Guard("kick", hy.sin(2 * math.pi * s.t), -1, reset=[kick(s), s.y], role="other")],
        strobe_period=lambda p: 1.0)


HOLE = maps.Scene("kicked-hole", "the open map with a hole as a kicked flow (tests/test_eventual.py)", None,
                  preset=None,
                  overrides={"h": (H, "tests/test_eventual.py"), "h1": (H1, "tests/test_eventual.py")},
                  x0={"x": 0.3, "y": 1.0}, builder=_kicked_hole, box={"x": (0.05, 0.95), "y": (0.5, 1.5)})


def _iterate(x, steps):
    """The same map in numpy: (fall step of each start, None if on the set throughout; where it ends)."""
    a = 0.45 * (1.0 - H)
    x = np.array(x, dtype=float)
    fall = np.full(len(x), -1)
    for k in range(steps):
        fell = (fall < 0) & (x >= 1.0 - H)
        fall[fell] = k
        x = np.where(x < 1.0 - H, np.where(x < a, x / a, (x - a) / (1.0 - H - a)),
                     np.where(x < 1.0, np.where(x < 1.0 - H + H1, 2.2, 3.2),
                              np.where(x < 2.5, 2.0 + 0.5 * (x - 2.0), 3.0 + 0.5 * (x - 3.0))))
    return fall, x


@pytest.fixture(scope="module")
def hole_census():
    return bifurc.attractors(HOLE, "h", [H], n_starts=300, seed=3, budget=800, progress=False, workers=1,
                             link=False)


def test_starts_still_on_the_saddle_at_the_budget_are_transient(hole_census):
    """The fraction of starts the census calls "transient" at 800 periods has an interval containing the fraction of
    the same starts that numpy finds still on the set after 800 steps (about exp(-0.8) = 0.45); none is
    "not_converged"; the transient entry's lifetime interval contains the closed form 1 / h = 1000 steps."""
    ds = hole_census
    labels = list(ds.attractor_label.values)
    t, nc = labels.index("transient"), labels.index("not_converged")
    fall, _ = _iterate(ds.start_x.values, 800)
    on = float(np.mean(fall < 0))
    assert 0.3 < on < 0.6
    assert ds.basin_fraction_low.values[0, t] <= on <= ds.basin_fraction_high.values[0, t]
    assert ds.basin_count.values[0, nc] == 0
    assert ds.lifetime_low.values[0, t] <= 1.0 / H <= ds.lifetime_high.values[0, t]


def test_transient_starts_apportioned_by_the_saddles_exits(hole_census):
    """Where every start eventually goes (numpy, 40000 steps: exp(-40) of them still on the set): for both fixed
    points the eventual fraction's interval contains the same starts' fraction, and the transient starts are all
    apportioned (eventual transient 0, fractions summing to 1).  The interval of x = 2 is informative: it excludes
    both extremes, every transient start sent to x = 3 and every one sent to x = 2 (h1 / h = 0.3 of them go to 2)."""
    ds = hole_census
    labels = list(ds.attractor_label.values)
    fall, end = _iterate(ds.start_x.values, 40000)
    assert np.all(fall >= 0)
    n_ids = len(labels) - len(OUTCOMES)
    at = {round(float(ds.x.values[0, j, 0])): j for j in range(n_ids) if ds.present.values[0, j]}
    assert sorted(at) == [2, 3]
    ev, lo, hi = (ds[k].values[0] for k in ("eventual_fraction", "eventual_fraction_low", "eventual_fraction_high"))
    for x in (2, 3):
        truth = float(np.mean(np.abs(end - x) < 1e-6))
        assert lo[at[x]] <= truth <= hi[at[x]], (x, truth, lo[at[x]], hi[at[x]])
    assert ev[labels.index("transient")] == 0.0 and ev.sum() == pytest.approx(1.0, abs=1e-12)
    direct, transient = ds.basin_fraction.values[0, at[2]], ds.basin_fraction.values[0, labels.index("transient")]
    assert direct < lo[at[2]] and hi[at[2]] < direct + transient


def test_saddles_sharing_a_cell_through_another_are_one_group():
    from bifurc.attractors.identify import Attractor
    from bifurc.labels.codes import ClassCode
    sets = [{(0, 0)}, {(5, 5)}, {(0, 0), (5, 5)}, {(9, 9)}]
    saddles = [Attractor(int(ClassCode.CHAOTIC), cells=c) for c in sets]
    assert saddle_groups(saddles) == [0, 0, 0, 3]


def test_eventual_fractions_by_hand():
    """100 starts: 50 on attractor 0, 30 on 1, 20 transient on saddle 0; of the 40 starts seen on saddle 0 that
    settled, 10 went to 0 and 30 to 1: eventual 50 + 20 x 1/4 = 55 and 30 + 20 x 3/4 = 45 of 100."""
    from bifurc.attractors.identify import Attractor
    from bifurc.labels.codes import ClassCode
    T = OUTCOMES["transient"]
    out = [0] * 50 + [1] * 30 + [T] * 20
    via = [0] * 10 + [-1] * 40 + [0] * 30 + [0] * 20
    keys = [0, 1] + list(OUTCOMES.values())
    ev, lo, hi = eventual_fractions(out, via, [Attractor(int(ClassCode.CHAOTIC), cells={(1, 1)})], keys)
    assert ev[:2] == pytest.approx([0.55, 0.45], abs=1e-12) and ev[keys.index(T)] == 0.0
    assert np.all(lo <= ev) and np.all(ev <= hi)


def test_a_set_whose_records_decide_nothing_is_transient_where_its_lifetime_says_so(monkeypatch):
    """The records made to decide nothing (identify returns None): after ``max_tries`` records of a start, the set's
    lifetime from copies started on it (closed form 1 / h = 1000 steps, below the 4000-step horizon) shows it to be a
    transient, so that its starts run on as on a saddle instead of being "not_converged" (the recorded start and every
    later start on its cells were, at a few hundred steps): the transient fraction at the 2000-step budget contains the
    fraction of the same starts numpy finds on the set (about exp(-2) = 0.14), and no start is "not_converged"."""
    from bifurc.attractors import census as C
    monkeypatch.setattr(C, "identify", lambda *args, **kw: None)
    ds = bifurc.attractors(HOLE, "h", [H], n_starts=300, seed=3, budget=2000, progress=False, workers=1,
                           link=False)
    labels = list(ds.attractor_label.values)
    t, nc = labels.index("transient"), labels.index("not_converged")
    on = float(np.mean(_iterate(ds.start_x.values, 2000)[0] < 0))
    assert 0.08 < on < 0.2
    assert ds.basin_count.values[0, nc] == 0
    assert ds.basin_fraction_low.values[0, t] <= on <= ds.basin_fraction_high.values[0, t]
    assert ds.lifetime_low.values[0, t] <= 1.0 / H <= ds.lifetime_high.values[0, t]


def test_the_report_names_the_transient_starts_and_their_eventual_fractions(hole_census):
    """`ds.bifurc.report()` of the census: the transient row says where those starts are (a chaotic saddle, with its
    mean lifetime), and the fixed points' rows carry their eventual fractions beside the basin fractions."""
    from bifurc.report import attractors_report
    ds = hole_census
    text = attractors_report(ds)
    row = next(line for line in text.splitlines() if "| transient |" in line)
    life = float(ds.lifetime.values[0, list(ds.attractor_label.values).index("transient")])
    assert f"on a chaotic saddle at the budget (mean lifetime {life:.0f} strobe periods)" in row
    for j, label in enumerate(ds.attractor_label.values[:2]):
        line = next(t for t in text.splitlines() if t.startswith(f"| {H:g} | {label} |"))
        assert f"{ds.eventual_fraction.values[0, j]:.3f} [{ds.eventual_fraction_low.values[0, j]:.3f}, " in line
