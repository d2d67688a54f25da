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
    """(fraction, low, high) for each of ``keys`` (attractor ids and :data:`.census.OUTCOMES` ids) of the starts
    whose ``outcomes`` are given, with those still "transient" apportioned by the exits of their saddle: ``via``
    is each start's index in ``saddles`` of the saddle it was last seen on (-1: none)."""
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
