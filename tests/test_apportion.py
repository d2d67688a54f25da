"""Apportioning a known chaotic saddle's starts by its copies' exits (``Census(apportion=True)``, issue 47 section 2):
the fractions' intervals against a Monte-Carlo of a fake saddle with known exit probabilities, and the census of the
open map with a hole (tests/test_eventual.py) against its closed form.
"""
from __future__ import annotations

import numpy as np
import pytest

import bifurc
from bifurc.attractors.eventual import apportioned_fractions, wilson
from bifurc.labels.codes import OUTCOMES
from test_eventual import H, H1, HOLE, _iterate

T = OUTCOMES["transient"]
KEYS = [0, 1] + list(OUTCOMES.values())


def _toy(rng, n, m, direct, on_saddle, exit_p):
    """One fake census: ``n`` starts, each directly on attractor 0 or 1 (probabilities ``direct``) or stopped on
    saddle 0 (``on_saddle``); the saddle's ``m`` copies exit to 0 or 1 with probabilities ``exit_p``."""
    kind = rng.choice(3, size=n, p=[direct[0], direct[1], on_saddle])
    out = np.where(kind == 2, T, kind)
    via = np.where(kind == 2, 0, -1)
    exits = [list(rng.choice(2, size=m, p=exit_p))]
    return out, via, exits


@pytest.mark.parametrize("n, m, exit_p", [(200, 30, (0.3, 0.7)), (400, 12, (0.1, 0.9)), (100, 48, (0.5, 0.5))])
def test_intervals_cover_the_true_fraction_95_percent_of_the_time(n, m, exit_p):
    """2000 fake censuses: 20 % of starts settle on attractor 0, 30 % on 1, 50 % stop on a saddle whose ``m`` copies exit
    to 0 with probability ``exit_p[0]``; the true basin fraction of 0 is 0.2 + 0.5 exit_p[0] (closed form).  The 95 %
    intervals contain it in 95 % of the censuses, within 3 binomial standard deviations of 2000 draws (+-1.5 %), for
    both attractors (with 12 copies at most 3.5 % above: the smoothed share's variance is conservative there).  The binomial interval of the starts alone (Wilson at n) covers far less where the copies are few:
    the copies' own sampling error is what the interval must carry."""
    rng = np.random.default_rng(47)
    direct, on = (0.2, 0.3), 0.5
    truth = [direct[0] + on * exit_p[0], direct[1] + on * exit_p[1]]
    reps, hit, naive = 2000, np.zeros(2), np.zeros(2)
    for _ in range(reps):
        out, via, exits = _toy(rng, n, m, direct, on, exit_p)
        f, lo, hi = apportioned_fractions(out, via, exits, KEYS)
        assert f.sum() == pytest.approx(1.0, abs=1e-12) and f[KEYS.index(T)] == 0.0
        for k in (0, 1):
            hit[k] += lo[k] <= truth[k] <= hi[k]
            wl, wh = wilson(f[k] * n, n)
            naive[k] += wl <= truth[k] <= wh
    tol = 3 * np.sqrt(0.95 * 0.05 / reps)
    # with few copies the share's smoothing errs on the safe side (12 copies of a share 0.1: 97 %)
    assert np.all(hit / reps >= 0.95 - tol) and np.all(hit / reps <= 0.95 + (tol if m >= 30 else 0.035)), hit / reps
    if m <= 30:
        assert np.all(naive / reps < 0.9), naive / reps


def test_without_measured_exits_nothing_is_apportioned():
    """A saddle whose copies gave no exits keeps its starts "transient", with the plain Wilson intervals."""
    out = np.array([0] * 50 + [T] * 50)
    via = np.array([-1] * 50 + [0] * 50)
    f, lo, hi = apportioned_fractions(out, via, [[]], KEYS)
    assert f[0] == 0.5 and f[KEYS.index(T)] == 0.5
    assert (lo[0], hi[0]) == pytest.approx(wilson(50, 100), abs=1e-12)


@pytest.fixture(scope="module")
def hole_apportioned():
    return bifurc.attractors(HOLE, "h", [H], n_starts=300, seed=3, budget=800, progress=False, workers=1,
                             link=False, apportion=True)


def test_the_hole_apportioned_by_its_copies_exits(hole_apportioned):
    """The open map with a hole: every box start is on the saddle, which it leaves into the hole uniformly, so that it
    goes to x = 2 with probability h1 / h = 0.3 exactly (closed form).  Apportioned, no start is left "transient", the
    fractions sum to 1, the interval of x = 2 contains 0.3 and the fraction of the same starts numpy sends there (40000
    steps), and is wider than the binomial interval of 300 starts (it carries the copies' error too); the starts stop
    where they meet the saddle: fewer than 400 periods per start on average (following them, the budget of 800 with
    the mean lifetime 1 / h = 1000 costs about 580)."""
    ds = hole_apportioned
    labels = list(ds.attractor_label.values)
    n_ids = len(labels) - len(OUTCOMES)
    at = {round(float(ds.x.values[0, j, 0])): j for j in range(n_ids) if ds.present.values[0, j]}
    assert sorted(at) == [2, 3]
    f, lo, hi = (ds[k].values[0] for k in ("basin_fraction", "basin_fraction_low", "basin_fraction_high"))
    assert f[labels.index("transient")] == 0.0 and f.sum() == pytest.approx(1.0, abs=1e-12)
    _, end = _iterate(ds.start_x.values, 40000)
    same = float(np.mean(np.abs(end - 2) < 1e-6))
    j = at[2]
    assert lo[j] <= H1 / H <= hi[j] and lo[j] <= same <= hi[j]
    wl, wh = wilson(f[j] * 300, 300)
    assert hi[j] - lo[j] > 1.2 * (wh - wl)
    assert ds.attrs["periods_per_start_mean"] < 400
    np.testing.assert_array_equal(ds.eventual_fraction.values, ds.basin_fraction.values)


def test_apportion_is_a_command_line_switch():
    """``bifurc attractors --apportion`` is generated from the method field (off by default, on with the switch)."""
    from bifurc.cli import build_parser
    assert bifurc.Census().apportion is False
    from bifurc.commands._options import settings_from_args
    args = build_parser().parse_args(["attractors", "-o", "c.nc", "--from", "80", "--to", "90", "--apportion"])
    assert args.apportion is True and settings_from_args(bifurc.Census, args).apportion is True
    args = build_parser().parse_args(["attractors", "-o", "c.nc", "--from", "80", "--to", "90"])
    assert args.apportion is False
