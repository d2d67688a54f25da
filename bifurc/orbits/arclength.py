"""Pseudo-arclength continuation of a branch on the one driver (:mod:`bifurc.orbits.driver`: predictor,
corrector, step rule, turning-angle control): here the branch's parts, the shooting system's corrector
(:class:`bifurc.orbits.continuation.ContinuationProblem`), the test functions, the strobe section moved away
from events, the stops (interval left, point cap, non-smooth events) and the restarts past them.
"""
from __future__ import annotations

import math
import time as _time

import numpy as np

from maps.hybrid import IntegrationFailure
from maps.parameters import ParameterError

from .continuation import SMOOTH_ROLES, Branch, ContinuationProblem, NoConvergence, flags_of
from .driver import Steps, Track, follow
from .passage import PASSABLE, restart
from .special_points import TESTS, detect, discontinuity, event_at_section, event_reason

def continue_branch(problem: ContinuationProblem, orbit, p_start: float, p_end: float, *, max_points: int = 200,
                    bounds=None, locate: bool = True, max_passages: int = 20, **options) -> Branch:
    """Follow ``orbit`` (at p_start) toward p_end as :func:`continue_piece` does, and past each grazing,
    impact lost or stick onset that stops a piece (at most ``max_passages``): continuation restarts on
    the other side with the new transition signature (:func:`bifurc.orbits.passage.restart`) and the
    pieces are joined into one branch, the located event between them (its note holds Nordmark's
    prediction at a grazing); each piece scales its unknowns by its own orbit's magnitude.  Where no orbit
    persists on the other side, the branch ends there, or turns back onto the orbit with the other signature on
    the same side (a non-smooth fold), and its ``stop_reason`` says so."""
    clock = _time.perf_counter()
    lo, hi = sorted(bounds) if bounds is not None else (min(p_start, p_end), max(p_start, p_end))
    branch = continue_piece(problem, orbit, p_start, p_end, max_points=max_points, bounds=(lo, hi), locate=locate,
                            **options)
    options.pop("tangent", None)
    for _ in range(max_passages if locate else 0):
        sp = branch.special[-1] if branch.special else None
        if (sp is None or sp.kind not in PASSABLE or sp.index != len(branch.points) - 1
                or (sp.kind == "grazing" and sp.point is None)         # a grazing not located: no orbit to start from
                or not branch.stop_reason.startswith("stopped after") or len(branch.points) >= max_points):
            break
        start, p, direction, note = restart(problem, sp, branch.points[-1], lo, hi)
        if note:
            sp.note = f"{sp.note}; {note}" if sp.note else note
        if start is None:
            branch.stop_reason += f"; the branch ends there: {p}"
            break
        came = branch.points[-1].tangent[-1]
        problem = ContinuationProblem(problem.smap, problem.param, problem.n, problem.k0, scale=start.scale,
                                      p_scale=problem.p_scale, p_ref=problem.p_ref, tol=problem.tol)
        piece = continue_piece(problem, start, p, p_end, max_points=max_points - len(branch.points),
                               bounds=(lo, hi), locate=locate, direction=direction, **options)
        _join(branch, piece, problem.param, p, direction, sp.p if came * direction < 0 else None)
    branch.seconds = _time.perf_counter() - clock
    return branch


def _join(branch, piece, param: str, p: float, direction: float, turned_at: float | None = None) -> None:
    """Append the piece restarted at ``param`` = ``p`` past the event that stopped ``branch`` (``turned_at``: the
    event's value where the new piece goes back, no orbit persisting beyond it)."""
    offset = len(branch.points)
    for sp in piece.special:
        sp.index += offset
    first = piece.points[0] if piece.points else None
    n = first.impacts_per_period if first is not None else 0
    what = f"{n} impact{'' if n == 1 else 's'} per period" if first is not None else ""
    way = "increasing" if direction > 0 else "decreasing"
    turn = ("" if turned_at is None else f"; no orbit persists past {param} = {turned_at:.10g}: the branch turns "
            f"back there (a non-smooth fold)")
    branch.stop_reason += (f"{turn}; continued from {param} = {p:.10g} toward {way} {param} ({what}): "
                           f"{piece.stop_reason}")
    branch.points += piece.points
    branch.special += piece.special
    branch.newton_iterations += piece.newton_iterations


def continue_piece(problem: ContinuationProblem, orbit, p_start: float, p_end: float, *,
                   step: float = 0.02, max_step: float = 0.1, min_step: float = 1e-7, max_points: int = 200,
                   max_turn: float = 0.3, tangent=None, label: str = "main", progress=None,
                   locate: bool = True, bounds=None, section_margin: float = 0.02,
                   max_resections: int = 50, direction: float | None = None) -> Branch:
    """Follow ``orbit`` (at p_start) toward p_end with the one driver (:func:`bifurc.orbits.driver.follow`)
    until it leaves [p_start, p_end] (or the interval of the two), ``max_points`` points are taken, or a
    non-smooth event or a corrector failure at ``min_step`` stops it (``Branch.stop_reason`` says which).
    When a state-changing event comes within ``section_margin`` strobe periods of a sample time, the section
    moves (the map's phase) to the middle of the widest event-free interval of the period, at most
    ``max_resections`` times: an event crossing the section would move between periods and break the map's
    smoothness.  ``tangent``: a start direction (scaled unknowns; branch switching), else the null
    vector pointing toward p_end; ``bounds``: the interval to stay in, if not [p_start, p_end]."""
    clock = _time.perf_counter()
    lo, hi = sorted(bounds) if bounds is not None else (min(p_start, p_end), max(p_start, p_end))
    branch = Branch(problem.param, problem.n, problem.k0, label=label)
    flags = flags_of(orbit)
    u0 = problem.pack(orbit.nodes, p_start)
    if direction is None:       # a restarted piece goes on in the parameter's direction at the event
        direction = math.copysign(1.0, p_end - p_start) if p_end != p_start else 1.0
    e_p = np.zeros(u0.size)
    e_p[-1] = direction
    reference = e_p if tangent is None else np.asarray(tangent, float)
    try:    # the start, corrected at p_start; a switched branch's start is the located bifurcation itself,
        # taken as it is (the doubled system is singular there: two null directions), its first step
        # corrected in the plane normal to the given tangent, the parameter free
        if tangent is None:
            u, F, DF, lins, flags, its = problem.correct(u0, e_p, flags)
        else:
            u, its = u0, 0
            F, DF, lins = _evaluate(problem, u0, flags)
    except NoConvergence as exc:
        branch.stop_reason = f"the start orbit does not converge at {problem.param} = {p_start:.10g}: {exc}"
        return branch
    branch.points.append(problem.point(u, F, DF, lins, flags, its, reference, tangent=tangent))
    track = _BranchTrack(problem, branch, (lo, hi), progress, locate, section_margin, max_resections)
    branch.stop_reason = follow(track, branch.points[0], Steps(step, max_step, min_step, max_turn), max_points)
    branch.seconds = _time.perf_counter() - clock
    return branch


class _BranchTrack(Track):
    """A branch piece for the driver: the shooting system's corrector, the transition signature's refusal,
    the test functions (:data:`bifurc.orbits.special_points.TESTS`), section moves and the stops."""

    def __init__(self, problem, branch, box, progress, locate, section_margin, max_resections):
        self.problem, self.branch, self.box, self.progress, self.locate = problem, branch, box, progress, locate
        self.section_margin, self.resections_left = section_margin, max_resections

    def size(self) -> int:
        return len(self.branch.points)

    @property
    def tol(self) -> float:
        return self.problem.tol

    def evaluate(self, u, flags):
        return self.problem.residual(u, flags)

    def flags(self, pt) -> list:
        return flags_of(pt)

    def point(self, prev, u, G, DG, lins, flags, iterations):
        self.branch.newton_iterations += iterations
        return self.problem.point(u, G, DG, lins, flags, iterations, prev.tangent)

    def refuse(self, prev, pt):
        return "signature" if pt.transitions != prev.transitions else None

    def record(self, prev, pt) -> None:
        self.branch.points.append(pt)
        if self.progress is not None:
            self.progress(pt)

    def detect(self, prev, pt) -> None:
        if not self.locate:
            return
        for kind in TESTS:
            sp = detect(self.problem, prev, pt, kind)
            if sp is not None:
                sp.index = len(self.branch.points) - 2
                self.branch.special.append(sp)

    def settle(self, pt):
        if self.resections_left > 0 and event_at_section(self.problem, pt, within=self.section_margin):
            moved = _resection(self.problem, pt)
            if moved is not None:            # the same orbit, sampled where no event happens
                self.resections_left -= 1
                self.branch.points.append(moved)
                return moved
        return pt

    def outside(self, pt):
        lo, hi = self.box
        if not lo - 1e-12 * max(1.0, abs(lo)) <= pt.p <= hi + 1e-12 * max(1.0, abs(hi)):
            return f"left the interval [{lo:.6g}, {hi:.6g}] at {self.problem.param} = {pt.p:.10g}"
        return None

    def fail(self, prev, pt, why, u_pred):
        _stop(self.branch, self.problem, prev, pt, why, u_pred, self.locate)
        return self.branch.stop_reason


def _stop(branch, problem, prev, pt, why: str, u_pred, locate: bool) -> None:
    """End ``branch`` at the smallest step: name the reason, probe the map where the corrector
    failed (does its signature change there?) and locate the discontinuity."""
    if pt is None:
        probe = _probe(problem, u_pred, prev)
        if probe is not None and probe.transitions != prev.transitions:
            why, pt = "signature", probe
    branch.stop_reason = event_reason(prev, pt, why, problem)
    if locate and (pt is None or why == "signature") and "outside its allowed range" not in why:
        sp = discontinuity(problem, prev, pt, branch.points[-2] if len(branch.points) > 1 else None)
        if sp is not None:
            sp.index = len(branch.points) - 1
            branch.special.append(sp)


def _evaluate(problem, u, flags):
    """problem.evaluate, its failures as NoConvergence."""
    try:
        return problem.evaluate(u, flags)
    except (IntegrationFailure, ZeroDivisionError, ParameterError) as exc:
        raise NoConvergence(f"the integration failed: {exc}") from None


def _probe(problem, u, prev):
    """The map at the predicted point ``u`` past ``prev`` (not corrected: the corrector failed
    there), as a BranchPoint with ``corrected=False``, or None where it cannot be evaluated."""
    try:
        F, DF, lins = problem.evaluate(u, flags_of(prev))
    except (IntegrationFailure, ZeroDivisionError, ParameterError):
        return None
    pt = problem.point(u, F, DF, lins, flags_of(prev), 0, prev.tangent)
    pt.corrected = False
    return pt


def _resection(problem, pt):
    """The branch point ``pt`` sampled in a new section: the phase moves to the middle of the widest
    interval of the period free of state-changing events; the nodes are integrated there and
    corrected at the same parameter.  None when that fails."""
    smap, T = problem.smap, problem.smap.period
    phases = [0.0]
    for j, evs in enumerate(pt.events):
        t0 = smap.sample_time(problem.k0 + j)
        phases += [((ev.t - t0) / T) % 1.0 for ev in evs if smap.system.role_of(ev.name) not in SMOOTH_ROLES]
    ph = np.sort(np.array(phases))
    gaps = np.diff(np.append(ph, ph[0] + 1.0))
    i = int(np.argmax(gaps))
    shift = (ph[i] + 0.5 * gaps[i]) % 1.0
    if shift == 0.0:
        return None
    old = (smap.phase, problem.k0)
    try:
        smap = problem.smap = smap.at({problem.param: pt.p})
        nodes = []
        for j, node in enumerate(pt.nodes):
            t = smap.sample_time(problem.k0 + j) + shift * T
            L = smap.linearize(node, problem.k0 + j, until=min(t, smap.sample_time(problem.k0 + j + 1)))
            nodes.append(L.state)
        phase = smap.phase + shift
        phase, problem.k0 = (phase - 1.0, problem.k0 + 1) if phase >= 1.0 else (phase, problem.k0)
        problem.smap = smap.at(phase=phase)
        e_p = np.zeros(pt.u.size)
        e_p[-1] = 1.0
        u, F, DF, lins, flags, its = problem.correct(problem.pack(nodes, pt.p), e_p, [dict(s.flags) for s in nodes])
        reference = pt.tangent[-1] * e_p if abs(pt.tangent[-1]) > 1e-3 else e_p
        return problem.point(u, F, DF, lins, flags, its, reference)
    except (NoConvergence, IntegrationFailure, ParameterError):
        problem.smap, problem.k0 = problem.smap.at(phase=old[0]), old[1]
        return None
