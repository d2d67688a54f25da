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

def translation_basis(system) -> tuple[np.ndarray, int] | None:
    """``(e, a)``: the translation as a state-space vector with ``e[a] = 1`` at its anchor ``a``
    (the last state it moves); None for a system without a translation."""
    tr = system.translation
    if not tr:
        return None
    e = np.array([float(tr.get(n, 0.0)) for n in system.state_names])
    a = max(i for i, n in enumerate(system.state_names) if tr.get(n, 0.0))
    return e / e[a], a


def shift_off(u, shift) -> np.ndarray:
    """The one reduction: states or tangent vectors ``u`` (..., d) less their anchor component
    times the translation, u - u[a] e, with ``shift = (e, a)`` (:func:`translation_basis`); the
    anchor's component is then 0.  ``u`` itself (as an array) when ``shift`` is None."""
    u = np.asarray(u, dtype=float)
    if shift is None:
        return u
    e, a = shift
    return u - u[..., a:a + 1] * e


def reduction_matrices(shift, d: int) -> tuple[np.ndarray, np.ndarray, list]:
    """``(R, E, keep)`` of :func:`shift_off` as matrices: R ((d-1) x d) maps a state to its reduced
    coordinates (the anchor left out), E (d x (d-1)) embeds them back with the anchor at 0, ``keep``
    lists the kept components.  The identity (and every component) when ``shift`` is None."""
    if shift is None:
        return np.eye(d), np.eye(d), list(range(d))
    e, a = shift
    keep = [i for i in range(d) if i != a]
    return (np.eye(d) - np.outer(e, np.eye(d)[a]))[keep], np.eye(d)[:, keep], keep


def reduce_points(system, points) -> np.ndarray:
    """States ``points`` (..., d) shifted along the translation until the anchor is 0 (a copy;
    the points themselves without a translation)."""
    return shift_off(np.array(points, dtype=float), translation_basis(system))


def reduce_jacobian(system, J) -> np.ndarray:
    """A map Jacobian (d x d) in the reduced coordinates ((d-1) x (d-1): the anchor fixed at 0,
    the translation's multiplier 1 removed); unchanged without a translation."""
    J = np.asarray(J, dtype=float)
    basis = translation_basis(system)
    if basis is None:
        return J
    R, E, _ = reduction_matrices(basis, J.shape[0])
    return R @ J @ E


def advance_per_step(system, points) -> np.ndarray:
    """The anchor's change over each step of ``points`` (N, d) [its unit] (empty without a translation)."""
    basis = translation_basis(system)
    if basis is None:
        return np.zeros(0)
    return np.diff(np.asarray(points, dtype=float)[:, basis[1]])
