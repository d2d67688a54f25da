"""Shift invariance: systems whose flow commutes with a translation of the state.

The 2-DOF scenes declare one (``HybridSystem.translation``: bar, rig and, under the drift soil,
the slider shifted together give the same motion).  Along that direction every map has the
multiplier 1 and a zero Lyapunov exponent, and a rig that progresses never returns to a sampled
state, so analysis works in the reduced coordinates: every state less the anchor's (the last
component of the translation, the rig's or the slider's position) times the translation, the
anchor itself then 0.  An orbit that repeats in them while the anchor advances is periodic with
a progression per period (:func:`advance_per_step`).
"""
from __future__ import annotations

import numpy as np

__all__ = ["translation_basis", "reduce_points", "reduce_jacobian", "advance_per_step"]


def translation_basis(system) -> tuple[np.ndarray, int] | None:
    """``(e, a)``: the translation as a state-space vector with ``e[a] = 1`` at its anchor ``a``
    (the last state it moves); None for a system without a translation."""
    tr = system.translation
    if not tr:
        return None
    e = np.array([float(tr.get(n, 0.0)) for n in system.state_names])
    a = max(i for i, n in enumerate(system.state_names) if tr.get(n, 0.0))
    return e / e[a], a


def reduce_points(system, points) -> np.ndarray:
    """States ``points`` (..., d) shifted along the translation until the anchor is 0 (a copy;
    the points themselves without a translation)."""
    p = np.array(points, dtype=float)
    basis = translation_basis(system)
    if basis is None:
        return p
    e, a = basis
    return p - p[..., a:a + 1] * e


def reduce_jacobian(system, J) -> np.ndarray:
    """A map Jacobian (d x d) in the reduced coordinates ((d-1) x (d-1): the anchor fixed at 0,
    the translation's multiplier 1 removed); unchanged without a translation."""
    J = np.asarray(J, dtype=float)
    basis = translation_basis(system)
    if basis is None:
        return J
    e, a = basis
    d = J.shape[0]
    keep = [i for i in range(d) if i != a]
    R = (np.eye(d) - np.outer(e, np.eye(d)[a]))[keep]       # d reduce / dy
    return R @ J @ np.eye(d)[:, keep]


def advance_per_step(system, points) -> np.ndarray:
    """The anchor's change over each step of ``points`` (N, d) [its unit] (empty without a translation)."""
    basis = translation_basis(system)
    if basis is None:
        return np.zeros(0)
    return np.diff(np.asarray(points, dtype=float)[:, basis[1]])
