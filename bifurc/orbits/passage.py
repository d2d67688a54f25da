"""Past a grazing or a stick onset: the orbit on the other side of the event that stopped a smooth
piece of a branch, with its new transition signature, to restart continuation from.

The event's orbit (the located grazing orbit, else the branch's last point) is the first guess of
Newton (:func:`~bifurc.orbits.periodic.find_periodic_orbit`) at p_e + dp on the far side, for dp a
growing ladder of fractions of the span; at a grazing the guess adds Nordmark's predicted jump
(:mod:`bifurc.orbits.nordmark`) and the ladder starts where the predicted impact speed is resolved.
An orbit whose transition signature differs from the stopped piece's is the restart; none: the
orbit does not persist there, and the reason says what was tried.
"""
from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np

from maps.hybrid import HybridState, IntegrationFailure
from maps.parameters import ParameterError

from .continuation import transition_signature
from .nordmark import impact_speed, predict
from .periodic import OrbitNotFound, find_periodic_orbit

__all__ = ["PASSABLE", "restart"]

#: the events a branch is continued through
PASSABLE = ("grazing", "impact_lost", "stick_onset", "signature_change")

#: the far side's distances from the event, in units of the span
LADDER = (1e-5, 1e-4, 1e-3, 1e-2)


def restart(problem, sp, last, lo: float, hi: float):
    """(start, p, direction, prediction note) of the piece past the event ``sp`` that stopped after branch
    point ``last``, or (None, reason, 0, note).  ``start`` has ``nodes`` at p, in the problem's section, and their ``scale``;
    ``direction`` the sign of the parameter's change along the new piece (at a grazing whose small
    impacting orbit lies on the non-impacting side, Nordmark's K < 0, the branch turns back there)."""
    ref = sp.point if sp.point is not None else last
    p_e = sp.p if math.isfinite(sp.p) else last.p
    direction = math.copysign(1.0, last.tangent[-1]) if last.tangent[-1] != 0 else 1.0
    pred, note = None, ""
    if sp.kind == "grazing" and sp.point is not None:
        try:
            pred = predict(problem, sp)
        except (IntegrationFailure, ParameterError, np.linalg.LinAlgError, ZeroDivisionError):
            pred = None
        note = pred.describe() if pred is not None else ""
        if pred is not None:
            direction = pred.side
    old = transition_signature(last.signatures)
    tried = []
    for frac in LADDER:
        p = p_e + direction * frac * problem.p_scale
        if not lo <= p <= hi:
            tried.append(f"{p:.10g} outside [{lo:.6g}, {hi:.6g}]")
            break
        nodes = _guess(problem, ref, p - ref.p, pred)
        problem.smap.set_params(**{problem.param: p})
        try:
            orbit = find_periodic_orbit(problem.smap, nodes, problem.n, k0=problem.k0, tol=problem.tol)
        except (OrbitNotFound, IntegrationFailure, ParameterError) as exc:
            tried.append(f"{p:.10g} ({exc})")
            continue
        if transition_signature(orbit.signatures) != old:
            return SimpleNamespace(nodes=orbit.nodes, scale=orbit.scale), p, direction, note
        tried.append(f"{p:.10g} (converged to the same signature)")
    return None, ("no periodic orbit of period {} with another transition signature past the event: Newton "
                  "from the event's orbit at {} = {}".format(problem.n, problem.param, "; ".join(tried))), 0.0, note


def _guess(problem, ref, dp: float, pred) -> list:
    """The event orbit's nodes moved along its tangent by dp, plus Nordmark's jump at a grazing."""
    t = ref.tangent
    shift = (t[:-1] * np.tile(problem.scale, problem.n) / (t[-1] * problem.p_scale) * dp
             if abs(t[-1]) > 1e-12 else np.zeros(problem.n * problem.d)).reshape(problem.n, problem.d)
    nodes = [HybridState(problem.co.embed(problem.co.reduce(s.y) + shift[j]), s.flags) for j, s in enumerate(ref.nodes)]
    if pred is not None and math.isfinite(impact_speed(pred, dp)):
        j = pred.node
        try:
            dy = np.linalg.solve(pred.Phi, pred.state_jump(impact_speed(pred, dp)))
        except np.linalg.LinAlgError:
            return nodes
        nodes[j] = HybridState(nodes[j].y + dy, nodes[j].flags)
    return nodes
