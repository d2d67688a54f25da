"""A census' basin fractions with their intervals, computed from where each fresh start went, before any dataset.

For each point and each entry (the attractor ids, then the :data:`bifurc.labels.codes.OUTCOMES`), the basin
fraction is the share of the fresh starts that reached it, with its 95 % Wilson interval; the eventual fraction
apportions the starts still in a chaotic transient at the budget by where those that left the same saddle went
(:mod:`.eventual`)."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..labels.codes import OUTCOMES
from .eventual import apportioned_fractions, eventual_fractions, wilson


@dataclass(frozen=True)
class Fractions:
    """Basin and eventual fractions (points, entries) of a census; ``keys`` names each entry's id (attractor ids
    0, 1, ..., then the outcomes' negative ids)."""

    keys: tuple
    count: np.ndarray
    fraction: np.ndarray
    low: np.ndarray
    high: np.ndarray
    eventual: np.ndarray
    eventual_low: np.ndarray
    eventual_high: np.ndarray


def census_fractions(outcomes, n_ids: int, transients=None, exits=None) -> Fractions:
    """The :class:`Fractions` of a census whose fresh starts reached ``outcomes[i]`` (ids) at point ``i``, with
    ``n_ids`` attractors; ``transients[i]`` (each start's saddle index, the saddles) apportions its transient
    starts (None: no apportioning information, the eventual fractions are the basin fractions).  ``exits[i]`` (the
    census' ``apportion``: per saddle, where its fallen lifetime copies went) apportions the starts stopped on a saddle
    in the basin fractions themselves, with intervals carrying both sampling errors
    (:func:`.eventual.apportioned_fractions`), and the eventual fractions are those."""
    keys = tuple(range(n_ids)) + tuple(OUTCOMES.values())
    shape = (len(outcomes), len(keys))
    count = np.zeros(shape, np.int64)
    fraction, low, high, ev, ev_lo, ev_hi = (np.full(shape, np.nan) for _ in range(6))
    for i, out in enumerate(outcomes):
        out = np.asarray(out)
        n = len(out)
        count[i] = [int(np.sum(out == k)) for k in keys]
        via, saddles = transients[i] if transients else ([], [])
        if exits is not None and any(len(e) for e in exits[i]):
            fraction[i], low[i], high[i] = apportioned_fractions(out, via, exits[i], keys)
            ev[i], ev_lo[i], ev_hi[i] = fraction[i], low[i], high[i]      # the stopped starts have no exits of their own
        else:
            fraction[i] = count[i] / n if n else np.nan
            low[i], high[i] = np.array([wilson(int(k), n) for k in count[i]]).T
            ev[i], ev_lo[i], ev_hi[i] = eventual_fractions(out, via, saddles, keys)
    return Fractions(keys, count, fraction, low, high, ev, ev_lo, ev_hi)
