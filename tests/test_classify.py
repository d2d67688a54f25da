"""Classification, Lyapunov exponents and grazing bisection against known answers."""
import math

import numpy as np
import pytest

from bifurc.labels.classify import CLASS_LABELS, classify_orbit, describe, lyapunov_threshold
from bifurc.sweeps.grazing import locate_grazing
from bifurc.labels.lyapunov import largest_lyapunov
from maps.parameters import ParameterError


def logistic(r):
    return lambda y, k: r * y * (1 - y)


def iterate(step, y0, n, skip=0):
    y = np.atleast_1d(np.asarray(y0, float))
    out = []
    for k in range(skip + n):
        y = step(y, k)
        if k >= skip:
            out.append(y.copy())
    return np.array(out)


def test_logistic_two_cycle_is_period_2_with_its_impact_count():
    r = 3.2  # analytic 2-cycle: x = (r + 1 -+ sqrt((r - 3)(r + 1))) / (2 r)
    pts = iterate(logistic(r), [0.3], 60, skip=400)
    lo, hi = sorted(pts[-2:, 0])
    root = math.sqrt((r - 3) * (r + 1))
    assert lo == pytest.approx((r + 1 - root) / (2 * r), abs=1e-12)
    assert hi == pytest.approx((r + 1 + root) / (2 * r), abs=1e-12)
    impacts = np.tile([1, 2], 30)[:59]  # one impact then two: 3 per period
    c = classify_orbit(pts, impacts)
    assert (c["label"], c["period"], c["impacts_per_period"]) == ("periodic", 2, 3)
    assert c["recurrence"] <= 1.0
    assert describe(c["code"], c["period"], c["impacts_per_period"]) == "period-2, 3 impacts (2:3)"


def test_inconsistent_impacts_are_not_a_period():
    pts = iterate(logistic(3.2), [0.3], 60, skip=400)
    impacts = np.tile([1, 2], 30)[:59]
    impacts[30] = 0  # a graze missing once: the state repeats, the impact sequence does not
    c = classify_orbit(pts, impacts)
    assert c["label"] != "periodic" or c["period"] != 2


def test_no_impact_period_1():
    pts = np.tile([[0.5, -1.0]], (20, 1)) + 1e-12 * np.random.default_rng(1).standard_normal((20, 2))
    c = classify_orbit(pts, np.zeros(19, int))
    assert (c["label"], c["period"]) == ("periodic-no-impact", 1)


@pytest.mark.parametrize("max_period", [1, 4, 16, 50])
def test_quasi_periodic_rotation_is_never_periodic(max_period):
    golden = (math.sqrt(5) - 1) / 2
    k = np.arange(201)
    pts = np.column_stack([np.cos(2 * math.pi * golden * k), np.sin(2 * math.pi * golden * k)])
    c = classify_orbit(pts, np.zeros(200, int), max_period=max_period, lyapunov=0.0)
    assert c["label"] == "quasi-periodic"
    c = classify_orbit(pts, np.zeros(200, int), max_period=max_period)  # no Lyapunov: undecided
    assert c["label"] == "not-converged"


def test_decaying_transient_is_not_converged_with_its_rate():
    rho = 0.9
    k = np.arange(100)
    pts = np.column_stack([1 + rho ** k, np.full(k.size, 2.0)])  # -> a fixed point, slowly
    c = classify_orbit(pts, np.ones(99, int), rtol=1e-10, atol=1e-14)
    assert c["label"] == "not-converged"
    assert c["period"] == 1 and c["convergence_rate"] == pytest.approx(rho, rel=1e-6)


def test_positive_lyapunov_overrides_a_decaying_recurrence_fit():
    """A chaotic record whose recurrence distance trends down (here under an envelope 0.95^k) is
    not a converging transient once the exponent is positive; without one it stays undecided."""
    u = np.empty(120)
    u[0] = 0.3
    for k in range(119):
        u[k + 1] = 4.0 * u[k] * (1.0 - u[k])  # logistic map, lambda = ln 2
    k = np.arange(120)
    pts = np.column_stack([1.0 + 0.95 ** k * u, np.full(k.size, 2.0)])
    undecided = classify_orbit(pts, np.ones(119, int), rtol=1e-10, atol=1e-14)
    assert undecided["label"] == "not-converged" and undecided["convergence_rate"] < 0.98
    assert classify_orbit(pts, np.ones(119, int), rtol=1e-10, atol=1e-14, lyapunov=math.log(2))["label"] == "chaotic"
    assert classify_orbit(pts, np.ones(119, int), rtol=1e-10, atol=1e-14, lyapunov=-0.05)["label"] == "not-converged"


def test_escape_and_failure_pass_through():
    assert classify_orbit(np.zeros((3, 1)), np.zeros(2), status="escaped")["label"] == "escaped"
    assert classify_orbit(np.zeros((3, 1)), np.zeros(2), status="failed")["label"] == "failed"
    bad = np.ones((5, 2))
    bad[3, 1] = np.nan
    assert classify_orbit(bad, np.zeros(4))["label"] == "failed"


def test_logistic_chaos_lyapunov_ln2_and_classified_chaotic():
    step = logistic(4.0)
    lam = largest_lyapunov(step, np.array([0.2]), 4000, d0=1e-10)
    assert lam == pytest.approx(math.log(2), abs=0.03)
    pts = iterate(step, [0.2], 200)
    c = classify_orbit(pts, np.zeros(199, int), lyapunov=lam, lyap_tol=lyapunov_threshold(4000))
    assert c["label"] == "chaotic"


def test_lyapunov_of_linear_map_is_log_of_spectral_radius():
    A = np.array([[0.5, 0.3], [-0.2, 0.8]])
    lam = largest_lyapunov(lambda y, k: A @ y, np.array([1.0, 0.0]), 300)
    assert lam == pytest.approx(math.log(max(abs(np.linalg.eigvals(A)))), abs=5e-3)


def test_threshold_accounts_for_the_window():
    assert lyapunov_threshold(100) == pytest.approx(2 * math.log(100) / 100)
    assert lyapunov_threshold(10**6) == pytest.approx(2e-3)


def test_bisection_brackets_the_root_to_xtol():
    root = math.sqrt(2)
    g = locate_grazing(lambda p: p * p - 2, 1.0, 2.0, xtol=1e-9)
    lo, hi = g["bracket"]
    assert lo <= root <= hi and hi - lo <= 1e-9
    assert abs(g["value"] - root) <= 1e-9
    with pytest.raises(ParameterError, match="no sign change"):
        locate_grazing(lambda p: p + 5, 1.0, 2.0, xtol=1e-3)


def test_labels_and_flag_meanings_agree():
    from bifurc.labels.classify import FLAG_MEANINGS
    assert FLAG_MEANINGS.split() == list(CLASS_LABELS)


def test_exponent_interval_of_the_logistic_map_contains_ln2():
    """x -> 4x(1-x): the Lyapunov exponent is ln 2 exactly (its invariant density is known); the
    per-step log stretch is log|4 - 8x| along an orbit.  The batch-means interval over 2000 steps
    contains ln 2 and is narrow; over 20 steps it is wider."""
    from bifurc.labels.lyapunov import exponent_interval
    x, logs = 0.1234567, []
    for _ in range(2000):
        logs.append(math.log(abs(4 - 8 * x)))
        x = 4 * x * (1 - x)
    mean, lo, hi = exponent_interval(logs)
    assert lo < math.log(2) < hi and hi - lo < 0.15 and abs(mean - math.log(2)) < 0.05
    m20, lo20, hi20 = exponent_interval(logs[:20])
    assert hi20 - lo20 > hi - lo
    assert all(math.isnan(v) for v in exponent_interval([0.1, math.nan, 0.2])[:3])


def test_an_interval_that_straddles_the_threshold_is_not_converged_with_its_reason():
    pts = np.random.default_rng(3).uniform(size=(60, 2))       # no recurrence at all
    imp = np.zeros(59, dtype=int)
    thr = 0.09
    base = dict(max_period=4, lyap_tol=thr)
    assert classify_orbit(pts, imp, lyapunov=0.12, **base)["label"] == "chaotic"           # no interval: as before
    c = classify_orbit(pts, imp, lyapunov=0.12, lyapunov_interval=(0.05, 0.19), **base)
    assert c["label"] == "not-converged" and "contains the threshold 0.09" in c["reason"]
    assert classify_orbit(pts, imp, lyapunov=0.12, lyapunov_interval=(0.1, 0.14), **base)["label"] == "chaotic"
    c = classify_orbit(pts, imp, lyapunov=-0.05, lyapunov_interval=(-0.12, 0.0), **base)
    assert c["label"] == "not-converged" and "-0.09" in c["reason"]
    assert classify_orbit(pts, imp, lyapunov=0.0, lyapunov_interval=(-0.02, 0.03), **base)["label"] == "quasi-periodic"


def test_the_student_t_table_of_the_exponent_interval_equals_scipy():
    """The batch-means interval uses a table of t_{0.975, df} (no scipy.stats import in workers)."""
    from scipy.stats import t

    from bifurc.labels.lyapunov import T975, _student_t
    for df in range(1, 10):
        assert T975[df - 1] == pytest.approx(float(t.ppf(0.975, df)), rel=1e-14)
    assert _student_t(0.95, 4) == pytest.approx(float(t.ppf(0.95, 4)), rel=1e-12)     # off the table: scipy.special
    assert _student_t(0.975, 30) == pytest.approx(float(t.ppf(0.975, 30)), rel=1e-12)
