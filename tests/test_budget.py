"""The sweep's budgets: the time budget cuts extensions (and says so), the progress bar counts the relay
periods integrated and grows as values are extended."""
import numpy as np

import bifurc
from bifurc.labels.codes import ClassCode
from bifurc.report import undecided_summary
from bifurc.run.progress import PeriodBar as _PeriodBar


def test_a_spent_time_budget_leaves_undecided_values_not_converged_with_that_reason():
    """7.3, 7.5 and 9 Hz at 90 V (matlab-listing) are undecided after their first record (100 transient +
    100 recorded periods, extended to three forcing periods where q is long): with a time budget already
    spent they are not extended further, and each says it was cut; without it they are extended."""
    kw = dict(preset="matlab-listing", params={"V": 90.0}, transient=100, record=100, grazing=False,
              error_sample=0, progress=False, workers=1)
    values = [7.3, 7.5, 9.0]
    cut = bifurc.sweep("thesis-1dof", "relay_hz", values, time_budget=1e-3, **kw).isel(branch=0)
    free = bifurc.sweep("thesis-1dof", "relay_hz", values, budget=1000, **kw).isel(branch=0)
    for i in range(len(values)):
        assert ClassCode(int(cut.class_code[i])) == ClassCode.NOT_CONVERGED
        assert "cut by the sweep's time budget" in str(cut.class_reason.values[i])
        assert int(cut.periods_integrated[i]) <= 320 < int(free.periods_integrated[i])
    assert "time_budget_deadline" in cut.attrs and "time_budget_deadline" not in free.attrs
    lines = undecided_summary(cut)
    assert any("time budget" in line and "raise --time-budget" in line for line in lines), lines


class _Bar:
    def __init__(self, total):
        self.total, self.n, self.postfix = total, 0, ""

    def update(self, n):
        self.n += n

    def set_postfix_str(self, text, refresh=True):
        self.postfix = text


class _R:
    def __init__(self, periods):
        self.periods_integrated = periods


def test_the_progress_bar_grows_with_the_planned_work():
    """Three values of 400 planned periods: the first chunk used 400 and 2000 (an extension), so the
    value to come is planned at their mean, 1200 (total 3600); when it uses 400 the bar ends at 2800."""
    bar = _Bar(3 * 400)
    p = _PeriodBar(bar, 3, 400, "values")
    p.done([_R(400), _R(2000)])
    assert (bar.total, bar.n, bar.postfix) == (3600, 2400, "2/3 values")
    p.done([_R(400)])
    assert (bar.total, bar.n, bar.postfix) == (2800, 2800, "3/3 values")
    assert np.isclose(bar.n / bar.total, 1.0)


def _undecided(needs, reasons, budget=6000, seconds=10.0, periods=1000):
    """A diagram's fields undecided_summary reads: every value not-converged with its budget_needed."""
    import xarray as xr
    n = len(needs)
    return xr.Dataset({"class_code": ("v", np.full(n, int(ClassCode.NOT_CONVERGED))),
                       "class_reason": ("v", np.array(reasons, dtype=object)),
                       "budget_needed": ("v", np.array(needs, np.int64)),
                       "periods_integrated": ("v", np.full(n, periods // n, np.int64))},
                      attrs={"budget_periods": budget, "values_seconds": seconds})


THRESHOLD = "4 of 4 trajectories' exponent intervals contain a threshold +-0.01 (widest [0, 0.02])"


def test_no_budget_is_suggested_where_the_evidence_says_a_longer_one_cannot_decide():
    """The main job's 8 values near the threshold ask for 433207 periods, 72 budgets: beyond the 4 budgets
    past which the sweep stops extending (anytime.HOPELESS), so no --budget is suggested (as README and
    `bifurc map` say)."""
    lines = undecided_summary(_undecided([433207] * 8, [THRESHOLD] * 8))
    assert lines[1].startswith("  8: exponent undecided") and "unlikely to decide" in lines[1], lines
    assert "--budget" not in "".join(lines)


def test_a_suggested_budget_is_within_reach_and_carries_its_time():
    """Two values asking 12000 and 18000 periods (within 4 budgets of 6000) and one asking 10**7: --budget 18000
    for the two. Each integrated 2000 periods (copies included) in 10 s / 6000 periods: at 3x the budget each
    integrates 6000, 2 x 6000 x 10 / 6000 = 20 s."""
    lines = undecided_summary(_undecided([12000, 18000, 10**7], [THRESHOLD] * 3, seconds=10.0, periods=6000))
    assert lines[1] == ("  3: exponent undecided: a trajectory's interval contains the chaos threshold; try --budget "
                        "18000 (about 20 s of computation for 2 values); 1 more unlikely to be decided by a longer "
                        "budget"), lines
