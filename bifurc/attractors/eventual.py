"""Where the starts still in a chaotic transient at the periods' budget go: apportioned by the exits of the starts
that left the same chaotic saddle.

A trajectory that has stayed on a chaotic saddle for a while is distributed by the saddle's conditionally invariant
measure, whatever its start, and leaves it after an exponentially distributed time to where that measure's
escaping part leads (Lai and Tel, *Transient Chaos*, 2011, ch. 2).  So the census' starts seen on a saddle that
then settled (on an attractor, or escaped, failed, neutral) sample where the saddle's trajectories go, and the
starts still on it at the budget (outcome "transient") go there in those proportions.  Saddles sharing a grid cell
are one.  Without an observed exit a saddle's transient starts stay "transient".

The eventual fraction of an outcome is (its starts + the transient starts x its share of the exits) / all starts.
Its interval combines two 95 % Wilson intervals, each at 97.5 % (Bonferroni): that of each exit share, and that of
the resulting count among the starts; where no start is apportioned it is the basin fraction and its interval.
"""
from __future__ import annotations

import math

import numpy as np

from ..labels.codes import OUTCOMES

#: the normal quantile of a two-sided 97.5 % interval: two of them make a 95 % one (Bonferroni)
Z_HALF = 2.241402727604947


def wilson(k, n, z: float = 1.959963984540054) -> tuple[float, float]:
    """Wilson score interval of a binomial proportion k/n (95 % by default)."""
    if n <= 0:
        return math.nan, math.nan
    p = k / n
    den = 1 + z * z / n
    centre = (p + z * z / (2 * n)) / den
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / den
    return max(0.0, centre - half), min(1.0, centre + half)


def saddle_groups(saddles: list) -> list:
    """The group of each saddle (an :class:`.identify.Attractor` with grid cells): saddles sharing a cell, directly
    or through others, are one group, numbered by its first saddle."""
    group = list(range(len(saddles)))

    def root(j):
        while group[j] != j:
            j = group[j]
        return j
    for j, a in enumerate(saddles):
        for i in range(j):
            if a.cells & saddles[i].cells:
                ri, rj = root(i), root(j)
                group[max(ri, rj)] = min(ri, rj)
    return [root(j) for j in range(len(saddles))]


def eventual_fractions(outcomes, via, saddles: list, keys) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(fraction, low, high) for each of ``keys`` (attractor ids and :data:`bifurc.labels.codes.OUTCOMES` ids) of
    the starts whose ``outcomes`` are given, with those still "transient" apportioned by the exits of their saddle:
    ``via`` is each start's index in ``saddles`` of the saddle it was last seen on (-1: none)."""
    out = np.asarray(outcomes)
    n = len(out)
    group = saddle_groups(saddles)
    g = np.array([group[v] if v >= 0 else -1 for v in via], dtype=int) if len(via) else np.full(n, -1)
    keys = list(keys)
    count = np.array([np.sum(out == k) for k in keys], dtype=float)
    low, high = count.copy(), count.copy()
    transient = out == OUTCOMES["transient"]
    settled = ~np.isin(out, [OUTCOMES["transient"], OUTCOMES["not_converged"]])
    moved = False
    t_col = keys.index(OUTCOMES["transient"]) if OUTCOMES["transient"] in keys else None
    for grp in sorted(set(g[transient]) - {-1}):
        t = int(np.sum(transient & (g == grp)))
        exits = out[settled & (g == grp)]
        if not len(exits):
            continue
        moved = True
        for c, k in enumerate(keys):
            e = int(np.sum(exits == k))
            lo, hi = wilson(e, len(exits), Z_HALF)
            count[c] += t * e / len(exits)
            low[c] += t * lo
            high[c] += t * hi
        if t_col is not None:
            count[t_col] -= t
            low[t_col] -= t
            high[t_col] -= t
    if not moved:
        bounds = np.array([wilson(int(k), n) for k in count])
    else:
        bounds = np.array([(wilson(lo, n, Z_HALF)[0], wilson(hi, n, Z_HALF)[1]) for lo, hi in zip(low, high)])
    return count / n, bounds[:, 0], bounds[:, 1]


def apportioned_fractions(outcomes, via, exits, keys) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(fraction, low, high) for each of ``keys`` where the starts stopped on a known chaotic saddle (outcome
    "transient", ``via`` the saddle's index) are apportioned by that saddle's measured exit distribution: ``exits[j]``
    lists where each of saddle j's fallen lifetime copies went (an id of ``keys``; empty: not measured, its starts
    stay "transient").  With N starts, d_k of them settled directly on k, n_j stopped on saddle j whose m_j copies
    sent e_jk to k (p_jk = e_jk / m_j), the fraction is f_k = (d_k + sum_j n_j p_jk) / N.  Its variance carries both
    sampling errors (delta method, starts and copies independent):

        var f_k = [d_k / N + sum_j (n_j / N) p_jk^2 - f_k^2] / N  +  sum_j (n_j / N)^2 q_jk (1 - q_jk) / m_j

    the first term the starts' multinomial error (each start's contribution is 1 on k, p_jk on saddle j, 0
    elsewhere), the second the exit shares' own, with the share q_jk = (e_jk + 1/2) / (m_j + 1) (Jeffreys' prior's
    posterior mean) so that a share of 0 copies still carries its error (in the Monte-Carlo of the test, of six
    cases with 6-48 copies and shares 0.03-0.5 the plug-in share e_jk / m_j covered 71-95 %, the Agresti-Coull share
    92-99 %, this one 94.5-98.4 %).  The 95 % interval is Wilson's at the effective number of
    starts f (1 - f) / var (Kish's design effect); at f = 0 or 1 that number is 1 / (1 / N + sum_j (n_j / N)^2 / m_j).
    Checked for coverage against a Monte-Carlo of a fake saddle with known exit probabilities
    (tests/test_apportion.py)."""
    out = np.asarray(outcomes)
    n = len(out)
    keys = list(keys)
    T = OUTCOMES["transient"]
    via = np.asarray(via, dtype=int) if len(via) else np.full(n, -1)
    stopped = np.zeros(n, bool)
    weights = []                                   # (n_j / N, m_j, counts e_jk per key)
    for j, e in enumerate(exits):
        sel = (out == T) & (via == j)
        if not len(e) or not sel.any():
            continue
        stopped |= sel
        e = np.asarray(e)
        weights.append((sel.sum() / n, len(e), np.array([np.sum(e == k) for k in keys], dtype=float)))
    direct = np.array([np.sum((out == k) & ~stopped) for k in keys], dtype=float) / n
    if not weights:
        bounds = np.array([wilson(round(d * n), n) for d in direct])
        return direct, bounds[:, 0], bounds[:, 1]
    frac, second, var_copy = direct.copy(), direct.copy(), np.zeros(len(keys))
    for w, m, e in weights:
        p, q = e / m, (e + 0.5) / (m + 1)
        frac += w * p
        second += w * p * p
        var_copy += w * w * q * (1 - q) / m
    var = np.maximum(second - frac ** 2, 0.0) / n + var_copy
    flat = 1.0 / (1.0 / n + sum(w * w / m for w, m, _ in weights))
    inner = (frac > 0) & (frac < 1) & (var > 0)
    n_eff = np.where(inner, frac * (1 - frac) / np.where(var > 0, var, 1.0), flat)
    bounds = np.array([wilson(f * ne, ne) for f, ne in zip(frac, n_eff)])
    return frac, bounds[:, 0], bounds[:, 1]
