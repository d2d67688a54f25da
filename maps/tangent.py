"""Tangent growth along an orbit, one direction at a time (Benettin et al., Meccanica 15 (1980) 9-20).

Two ways, both integrated by the engines (:mod:`maps.engines`); the exponent and its spread
are analysis (:mod:`bifurc.labels.lyapunov`):

- a *tangent vector* u integrated with the flow (u' = (df/dy) u, the saltation rule applied to
  u at every state event, :meth:`maps.variational.Derivatives.transition`) and renormalised to
  length :data:`TANGENT_SIZE` after each map step (logged as a unit vector);
  :func:`tangent_stretch` gives each step's log stretch;
- a *companion* trajectory that starts ``d0`` away from a reference state (norm scaled by
  ``scale``) and after each map step is moved back to distance ``d0`` from the reference (a
  finite-difference stand-in for the tangent vector, kept as a cross-check).
"""
from __future__ import annotations

import math

import numpy as np

from .translation import shift_off

#: the length a tangent vector is integrated at (it is logged and renormalised as a unit vector).
#: heyoka controls the error of all state components together, so a unit vector whose fast
#: components vary faster than the state set the step size (16 % more steps than the state alone);
#: at this size the state sets it.  A power of two: scaling back and forth is exact.
TANGENT_SIZE = 2.0 ** -10


def start_direction(d: int, shift=None) -> np.ndarray:
    """The fixed random unit direction (d,) that tangent vectors and companions start along
    (with ``shift = (e, a)``: without its component along the translation e, see :func:`reduce`)."""
    u = reduce(np.random.default_rng(12345).standard_normal(d), shift)
    return u / np.linalg.norm(u)


def reduce(u, shift=None) -> np.ndarray:
    """Tangent vectors ``u`` (..., d) less their component along a translation ``shift = (e, a)``
    (:func:`maps.translation.shift_off`, the one reduction).  The flow commutes with the
    translation, so J e = e: a tangent vector reduced after every map step evolves by the reduced
    map's Jacobian, without the neutral multiplier 1.  Unchanged without a shift."""
    return shift_off(u, shift)


def companion_start(y0, d0: float = 1e-8, scale=None, shift=None) -> np.ndarray:
    """The companion's start: ``d0`` from ``y0`` along :func:`start_direction` (norm scaled by ``scale``); with a
    translation ``shift = (e, a)``, moved back to ``d0`` from ``y0`` in the reduced coordinates (:func:`renormalise`),
    as every later step is.  The one start of a Benettin companion: :func:`bifurc.labels.lyapunov.largest_lyapunov`'s
    and the engines' companion lanes (:meth:`maps.poincare.StroboscopicMap.stretch`)."""
    y = np.asarray(y0, dtype=float)
    s = np.ones_like(y) if scale is None else np.asarray(scale, dtype=float)
    z = y + d0 * start_direction(y.size) * s
    return z if shift is None else renormalise(y, z, d0, scale, shift)[0]


def tangent_sample(u, log: list, start=None, shift=None) -> bool:
    """At a recorded sample, the tangent vector ``u`` (an engine's live view, changed in place)
    starts at ``start`` (a unit vector), or is appended to ``log`` (as grown from a unit vector),
    reduced by ``shift`` (:func:`reduce`) and scaled back to length :data:`TANGENT_SIZE`.  False
    (and u zeroed): it is no longer finite or vanished, nothing more to log."""
    if start is not None:
        u[:] = start
        u *= TANGENT_SIZE
        return True
    log.append(np.array(u, dtype=float) / TANGENT_SIZE)
    if shift is not None:
        u[:] = reduce(u, shift)
    norm = math.sqrt(float(np.dot(u, u)))
    if math.isfinite(norm) and norm > 0.0:
        u *= TANGENT_SIZE / norm
        return True
    u[:] = 0.0
    return False


def tangent_stretch(start, ends, scale=None, shift=None) -> np.ndarray:
    """Log stretch of each map step of a tangent vector in the norm scaled by ``scale``.

    ``ends[k]`` (m, d) is the vector at the end of step k, which started from ``start`` (k = 0)
    or from ``ends[k-1]`` renormalised to unit Euclidean length: the stretch is
    log(|ends[k] / scale| / |ends[k-1] / scale| * |ends[k-1]|).  The direction, hence the
    stretch, does not depend on the norm the vector was renormalised in.  With ``shift`` the
    vectors are measured reduced (:func:`reduce`), as :func:`tangent_sample` renormalised them."""
    u = reduce(ends, shift)
    s = np.ones(u.shape[1]) if scale is None else np.asarray(scale, dtype=float)
    before = np.vstack([np.asarray(start, dtype=float)[None, :], u[:-1] / np.linalg.norm(u[:-1], axis=1)[:, None]])
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.log(np.linalg.norm(u / s, axis=1) / np.linalg.norm(before / s, axis=1))


def renormalise(reference, z, d0: float = 1e-8, scale=None, shift=None) -> tuple[np.ndarray, float]:
    """Move companion ``z`` back to distance ``d0`` from ``reference``; return it and
    log(distance / d0), the step's stretch (NaN: the distance is not finite or zero).

    ``shift = (e, a)`` (:func:`maps.translation.translation_basis`): the flow is invariant under
    the translation e, so the companion is first shifted along e to the reference's anchor ``a``
    (the same motion): the distance is measured in the reduced coordinates, without the neutral
    direction."""
    y = np.asarray(reference, dtype=float)
    dz = shift_off(np.asarray(z, dtype=float) - y, shift)
    d = dz if scale is None else dz / np.asarray(scale, dtype=float)
    dist = math.sqrt(float(d @ d))
    if not math.isfinite(dist) or dist == 0.0:
        return np.asarray(z, dtype=float), math.nan
    return y + dz * (d0 / dist), math.log(dist / d0)
