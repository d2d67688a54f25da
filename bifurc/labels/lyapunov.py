"""Largest Lyapunov exponent of a map by the two-trajectory (Benettin) method.

G. Benettin, L. Galgani, A. Giorgilli, J.-M. Strelcyn, Meccanica 15 (1980) 9-20.
"""
from __future__ import annotations

import math

import numpy as np

from maps.tangent import companion_start, renormalise

from .vocabulary import METHODS  # noqa: F401 - read here by the sweep's dataset; defined light for the CLI

#: how the exponent's interval is estimated (stored with every sweep)
INTERVAL_METHOD = ("95 % Student-t interval of the mean of 10 consecutive batch means of the per-step log "
                   "stretch (fewer batches below 50 steps, at least 2)")


#: two-sided 95 % Student-t quantiles t_{0.975, df} for df = 1 ... 9 (the batch means of
#: :func:`exponent_interval`): a table, so that a sweep's worker does not import scipy.stats
#: (1.3 s per process); tests/test_classify.py checks it against scipy.stats.t.ppf
T975 = (12.706204736174694, 4.302652729749462, 3.1824463052837078, 2.7764451051977934, 2.5705818356363146,
        2.4469118511449786, 2.364624251592784, 2.306004135204166, 2.262157162798205)


def _student_t(q: float, df: int) -> float:
    """The ``q`` quantile of Student's t with ``df`` degrees of freedom."""
    if q == 0.975 and 1 <= df <= len(T975):
        return T975[df - 1]
    from scipy.special import stdtrit
    return float(stdtrit(df, q))


def batch_means(stretch, batches: int = 10) -> np.ndarray:
    """The means of ``batches`` consecutive batches of ``stretch`` (fewer below 50 steps, at least 2;
    empty with fewer than 4 steps): nearly independent when a batch is longer than the correlation."""
    s = np.asarray(stretch, dtype=float)
    b = min(batches, s.size // 5) if s.size >= 50 else max(2, min(batches, s.size // 2))
    if s.size < 4 or b < 2:
        return np.zeros(0)
    return np.array([np.mean(part) for part in np.array_split(s, b)])


def exponent_interval(stretch, batches: int = 10, level: float = 0.95) -> tuple[float, float, float]:
    """(exponent, low, high) [per step] from the log stretch of each step: the mean, and a ``level``
    Student-t interval from the spread of ``batches`` consecutive batch means (:func:`batch_means`).
    NaN where a step failed; (mean, NaN, NaN) with fewer than 4 steps."""
    s = np.asarray(stretch, dtype=float)
    if s.size == 0 or not np.all(np.isfinite(s)):
        return math.nan, math.nan, math.nan
    mean = float(np.mean(s))
    means = batch_means(s, batches)
    if means.size < 2:
        return mean, math.nan, math.nan
    b = means.size
    half = float(_student_t(0.5 + level / 2, b - 1) * np.std(means, ddof=1) / math.sqrt(b))
    return mean, mean - half, mean + half


def largest_lyapunov(step, y0, n: int, *, d0: float = 1e-8, scale=None, k0: int = 0, shift=None) -> float:
    """Largest Lyapunov exponent [per map step] of ``step(y, k) -> y_next``.

    A companion trajectory starts ``d0`` away (in the norm scaled by ``scale``) and
    is renormalised to ``d0`` after every step; the exponent is the mean log growth.
    ``k0`` is the index of the first step (for non-autonomous maps).  ``shift``: a
    translation the map commutes with (:func:`maps.translation.translation_basis`), removed
    from the separation.  NaN if a step fails or the separation collapses to zero.
    """
    y = [np.asarray(y0, dtype=float).copy()]

    def reference(k):           # the reference trajectory, computed alongside its companion
        y[0] = step(y[0], k)
        return y[0]
    return _benettin(step, reference, y[0], int(n), d0, scale, k0, shift)


def lyapunov_along(step, points, *, d0: float = 1e-8, scale=None, k0: int = 0) -> float:
    """Largest Lyapunov exponent [per map step] along a recorded orbit ``points[0..n]`` of ``step``.

    Benettin's method with the reference trajectory already known: only the companion is
    integrated.  It starts ``d0`` from ``points[0]`` (:func:`companion_start`) and after each
    step is moved back to distance ``d0`` from ``points[k+1]``.  ``k0`` is the index of
    ``points[0]`` (for non-autonomous maps).  NaN if a step fails or the separation collapses.
    """
    y = np.asarray(points, dtype=float)
    return _benettin(step, lambda k: y[k - k0 + 1], y[0], y.shape[0] - 1, d0, scale, k0, None)


def _benettin(step, reference, y0, n: int, d0: float, scale, k0: int, shift) -> float:
    """The one Benettin loop: the companion of ``y0`` stepped ``n`` times and renormalised to ``d0``
    from ``reference(k)`` (the reference's state after step ``k``) each time; the mean log stretch."""
    s = np.ones_like(y0) if scale is None else np.asarray(scale, dtype=float)
    z = companion_start(y0, d0, s, shift)
    total = 0.0
    for k in range(k0, k0 + n):
        try:
            y1, z1 = reference(k), step(z, k)
        except Exception:  # a failed step leaves the exponent undetermined
            return math.nan
        z, stretch = renormalise(y1, z1, d0, s, shift)
        if not math.isfinite(stretch):
            return math.nan
        total += stretch
    return total / n
