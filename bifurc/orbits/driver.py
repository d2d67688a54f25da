"""The one pseudo-arclength driver of branches (:mod:`bifurc.orbits.arclength`) and two-parameter curves
(:mod:`bifurc.orbits.curves`): predictor along the unit tangent, corrector with the pseudo-arclength
condition, step-size rule, turning-angle control and a hook for test functions and events.

The corrector is Newton on the bordered system [G(u); t_prev . (u - u_pred)] = 0 (the pseudo-arclength
condition; :func:`bifurc.orbits.continuation.bordered_newton`), a solution farther than the step from the
prediction refused.  What is continued is a :class:`Track`: it gives the residual G and its Jacobian
(``evaluate``), its Newton options and tolerance, builds a point from a solution, may refuse a corrected point
(a branch: its transition signature changed), records a point, evaluates its test functions between two
points, says when the track leaves its box, and names the stop when the corrector fails at the smallest step.
Points are anything with the scaled unknowns ``u``, the unit tangent ``tangent``, the mode flags per node
(``Track.flags``) and the corrector's ``iterations``.

The step rule (:func:`step_after`): the arclength step h (scaled unknowns) grows x1.5 after an easy
correction (<= 3 iterations), is kept after <= 5, else shrinks x0.7, at most ``max_step``; a refused or failed
correction halves it, down to ``min_step``, where the track stops.  A tangent turning by more than
``max_turn`` radians in one step is refused like a failed correction (the step jumped to another branch
or across a fold it did not resolve).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .continuation import NEWTON_OPTIONS, NoConvergence, bordered_newton

@dataclass(frozen=True)
class Steps:
    """The arclength steps of a track, in its scaled unknowns: first, largest and smallest step, and the
    largest turn of the unit tangent in one step [rad]."""

    step: float = 0.02
    max_step: float = 0.1
    min_step: float = 1e-7
    max_turn: float = 0.3


class Track:
    """The problem-specific parts of a continuation: ``size``, ``evaluate``, ``flags``, ``point`` and ``record``
    are required; the hooks after them default to nothing."""

    #: Newton's tolerance on the largest scaled residual, and the options of
    #: :func:`bifurc.orbits.continuation.bordered_newton` (max_iter, stall_after, tiny_update, keep_impacts)
    tol: float = 1e-10
    newton: dict = NEWTON_OPTIONS

    def size(self) -> int:
        """Points recorded so far (the driver stops at ``max_points``)."""
        raise NotImplementedError

    def evaluate(self, u: np.ndarray, flags: list):
        """(G, DG, linearizations) at the unknowns ``u``; raises NoConvergence where it cannot."""
        raise NotImplementedError

    def flags(self, pt) -> list:
        """The mode flags per node of point ``pt``, to start the corrector from."""
        raise NotImplementedError

    def point(self, prev, u, G, DG, lins, flags, iterations: int):
        """The point at the corrector's solution ``u`` after ``prev`` (its unit tangent oriented along prev's)."""
        raise NotImplementedError

    def record(self, prev, pt) -> None:
        """Keep the accepted point ``pt``."""
        raise NotImplementedError

    def refuse(self, prev, pt) -> str | None:
        """Why the corrected point ``pt`` is not taken (the step is then halved), or None."""
        return None

    def detect(self, prev, pt) -> None:
        """The test-function and event hook: locate what changed between ``prev`` and ``pt``."""
        return None

    def settle(self, pt):
        """The point to step on from after ``pt`` was recorded (a branch may move its strobe section)."""
        return pt

    def outside(self, pt) -> str | None:
        """The stop reason when ``pt`` lies outside the track's box, else None."""
        return None

    def fail(self, prev, pt, why: str, u_pred: np.ndarray) -> str:
        """The stop reason after the correction from ``prev`` failed (``why``) at the smallest step; ``pt``:
        the refused point, or None where the corrector did not converge."""
        return f"{why} at the smallest step"


def turn_angle(t_a: np.ndarray, t_b: np.ndarray) -> float:
    """The angle [rad] between two unit tangents."""
    return math.acos(max(-1.0, min(1.0, float(t_a @ t_b))))


def step_after(h: float, iterations: int, max_step: float) -> float:
    """The arclength step after a point the corrector took ``iterations`` to converge: x1.5 after an easy
    one (<= 3), kept (<= 5), else x0.7, at most ``max_step``."""
    return min(max_step, h * (1.5 if iterations <= 3 else 1.0 if iterations <= 5 else 0.7))


def follow(track: Track, start, steps: Steps, max_points: int) -> str:
    """Continue ``track`` from its recorded point ``start`` until it leaves its box, has ``max_points``
    points, or a correction fails at ``steps.min_step``; returns the stop reason.  Each step: predict
    u_pred = u + h t, correct on the hyperplane t . (u - u_pred) = 0, refuse (the track's reason, or a turn of
    the tangent above ``steps.max_turn``) and halve h, or record, detect, settle, check the box and size the
    next step (:func:`step_after`)."""
    prev, h = start, float(steps.step)
    while track.size() < max_points:
        u_pred = prev.u + h * prev.tangent
        try:
            u, G, DG, lins, flags, its = bordered_newton(track.evaluate, u_pred, prev.tangent, track.flags(prev),
                                                         track.tol, max_move=h, **track.newton)
            pt = track.point(prev, u, G, DG, lins, flags, its)
        except NoConvergence as exc:
            pt, why = None, str(exc)
        else:
            why = track.refuse(prev, pt)
            turn = turn_angle(pt.tangent, prev.tangent)
            if why is None and turn > steps.max_turn:
                why = f"the tangent turned {turn:.2f} rad"
        if why is not None:
            if h / 2 >= steps.min_step:
                h /= 2
                continue
            return track.fail(prev, pt, why, u_pred)
        track.record(prev, pt)
        track.detect(prev, pt)
        iterations = pt.iterations         # the step rule reads the corrector's effort, not a section move's
        pt = track.settle(pt)
        out = track.outside(pt)
        if out is not None:
            return out
        prev, h = pt, step_after(h, iterations, steps.max_step)
    return f"reached max_points = {max_points}"
