"""The one pseudo-arclength driver (bifurc.orbits.driver) on a curve known in closed form: the unit circle
G(u) = u0^2 + u1^2 - 1 = 0, followed from (1, 0) once round.  The points must lie on the circle, in order, and no
accepted step may turn the tangent by more than max_turn (on a unit circle the tangent turns by the arc between
two points: the step grows until the turning-angle control holds it)."""
import math
from dataclasses import dataclass

import numpy as np

from bifurc.orbits.continuation import unit_tangent
from bifurc.orbits.driver import Steps, Track, follow


@dataclass
class Point:
    u: np.ndarray
    tangent: np.ndarray
    iterations: int


class Circle(Track):
    tol = 1e-12

    def __init__(self):
        self.points = []

    def size(self):
        return len(self.points)

    def evaluate(self, u, flags):
        return np.array([u @ u - 1.0]), 2.0 * u[None, :], []

    def flags(self, pt):
        return []

    def point(self, prev, u, G, DG, lins, flags, iterations):
        return Point(u, unit_tangent(DG, prev.tangent), iterations)

    def record(self, prev, pt):
        self.points.append(pt)

    def outside(self, pt):
        U = np.array([p.u for p in self.points])
        return "around" if np.unwrap(np.arctan2(U[:, 1], U[:, 0]))[-1] > 2 * math.pi else None


def _run(max_turn, max_step=2.0):
    track = Circle()
    start = Point(np.array([1.0, 0.0]), np.array([0.0, 1.0]), 0)
    track.record(None, start)
    why = follow(track, start, Steps(step=0.1, max_step=max_step, min_step=1e-6, max_turn=max_turn), 200)
    return track.points, why


def test_points_lie_on_the_circle_and_go_round_it():
    points, why = _run(max_turn=0.3)
    assert why == "around"
    U = np.array([p.u for p in points])
    np.testing.assert_allclose(np.hypot(U[:, 0], U[:, 1]), 1.0, rtol=0, atol=1e-12)
    angles = np.unwrap(np.arctan2(U[:, 1], U[:, 0]))
    assert np.all(np.diff(angles) > 0) and angles[-1] > 2 * math.pi      # counter-clockwise, once round


def test_no_accepted_step_turns_more_than_max_turn():
    for max_turn in (0.3, 0.1):
        points, _ = _run(max_turn)
        turns = [math.acos(np.clip(a.tangent @ b.tangent, -1, 1)) for a, b in zip(points, points[1:])]
        assert max(turns) <= max_turn and max(turns) > 0.5 * max_turn, (max_turn, max(turns))
    points, _ = _run(max_turn=math.pi, max_step=1.0)        # without the control the steps grow to max_step
    turns = [math.acos(np.clip(a.tangent @ b.tangent, -1, 1)) for a, b in zip(points, points[1:])]
    assert max(turns) > 0.5                                  # measured 0.53
