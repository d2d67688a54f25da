"""Tangent directions by a companion trajectory (Benettin et al., Meccanica 15 (1980) 9-20).

A companion starts ``d0`` away from a reference state (norm scaled by ``scale``) and after
each map step is moved back to distance ``d0`` from the reference; the log of each step's
stretch is the tangent growth along the companion's direction.  Engines integrate the
companion (:mod:`maps.engines`); the exponent and its spread are analysis
(:mod:`bifurc.lyapunov`).
"""
from __future__ import annotations

import math

import numpy as np

__all__ = ["companion_start", "renormalise"]


def companion_start(y0, d0: float = 1e-8, scale=None) -> np.ndarray:
    """The companion's start: ``d0`` from ``y0`` along a fixed random direction (norm scaled by ``scale``)."""
    y = np.asarray(y0, dtype=float)
    s = np.ones_like(y) if scale is None else np.asarray(scale, dtype=float)
    u = np.random.default_rng(12345).standard_normal(y.size)
    return y + d0 * (u / np.linalg.norm(u)) * s


def renormalise(reference, z, d0: float = 1e-8, scale=None, shift=None) -> tuple[np.ndarray, float]:
    """Move companion ``z`` back to distance ``d0`` from ``reference``; return it and
    log(distance / d0), the step's stretch (NaN: the distance is not finite or zero).

    ``shift = (e, a)`` (:func:`maps.translation.translation_basis`): the flow is invariant under
    the translation e, so the companion is first shifted along e to the reference's anchor ``a``
    (the same motion): the distance is measured in the reduced coordinates, without the neutral
    direction."""
    y = np.asarray(reference, dtype=float)
    dz = np.asarray(z, dtype=float) - y
    if shift is not None:
        e, a = shift
        dz = dz - dz[a] * e
    d = dz if scale is None else dz / np.asarray(scale, dtype=float)
    dist = math.sqrt(float(d @ d))
    if not math.isfinite(dist) or dist == 0.0:
        return np.asarray(z, dtype=float), math.nan
    return y + dz * (d0 / dist), math.log(dist / d0)
