"""Pseudo-arclength continuation of periodic orbits of a stroboscopic map in one parameter.

The unknowns are the orbit's nodes (multiple shooting, :mod:`bifurc.periodic`) and the
parameter p, scaled: u = (z_0 / s, ..., z_{n-1} / s, (p - p_0) / p_s), with s the orbit's
magnitude per state component and p_s the span asked for.  A branch point solves F(u) = 0,
F_j = (P_{k0+j}(z_j; p) - z_{j+1 mod n}) / s, and the arclength condition
t . (u - u_prev) = h, t the unit tangent (the null vector of DF = [dF/dz | dF/dp]).  Every
derivative is exact: variational equations with saltation (:meth:`maps.StroboscopicMap.linearize`).
The corrector is Newton's method on the bordered system [DF; t^T]; the step h grows after easy
corrections and halves after a failure, a tangent turning by more than ``max_turn`` radians
or a change of the transition signature.

Smooth bifurcations are zeros of test functions along the branch, located by the Illinois
variant of false position on the arclength, each evaluation a corrected branch point:

- fold: the parameter component of the tangent (the branch turns; a multiplier +1);
- period doubling: Re prod (mu_i + 1) (a real multiplier through -1);
- Neimark-Sacker: Re prod_{i<j} (mu_i mu_j - 1) with the pair complex at the zero (a neutral
  saddle, real mu_i mu_j = 1, is not a bifurcation and is not reported).

Discontinuity-induced events stop the smooth continuation (the map is not differentiable
there): a change of the transition signature (an impact born or lost, a stick, a slip).  The
step is halved toward the event until it is shorter than ``min_step``; a grazing is then located
by solving the augmented system orbit + grazing point (:func:`bifurc.grazing_orbit.locate_grazing`).
"""
from __future__ import annotations

import contextlib
import math
import time as _time
from dataclasses import dataclass, field

import numpy as np

from maps.hybrid import HybridState, IntegrationFailure
from maps.parameters import ParameterError

from .grazing_orbit import closest_flight_minimum, locate_grazing
from .periodic import PeriodicOrbit, _Coordinates, _shooting_matrix

__all__ = ["BranchPoint", "SpecialPoint", "Branch", "ContinuationProblem", "continue_branch",
           "SMOOTH_ROLES"]

#: event roles that make the map non-smooth when they appear or vanish (observations and
#: free-flight minima only record; they may come and go along a smooth branch)
SMOOTH_ROLES = ("observation", "flight_minimum", "deepest")


def transition_signature(signatures) -> tuple:
    """The roles of a period's events that change the state or the mode, node by node."""
    return tuple(tuple(r for r in sig if r not in SMOOTH_ROLES) for sig in signatures)


@dataclass
class BranchPoint:
    """One corrected point of a branch (scaled unknowns ``u``, unit tangent ``tangent``)."""

    p: float
    nodes: list                 # HybridState per node (full state; anchor 0 under a translation)
    multipliers: np.ndarray
    signatures: list            # per node, the roles of the step's events in order
    jacobians: list             # reduced one-period Jacobians
    u: np.ndarray
    tangent: np.ndarray
    iterations: int
    residual: float
    events: list                # per node, the step's EventRecords
    advance: float = 0.0
    phase: float = 0.0          # the strobe section: node j at t = (k0 + j + phase) T
    k0: int = 0

    @property
    def stable(self) -> bool:
        return bool(np.max(np.abs(self.multipliers)) < 1.0)

    @property
    def impacts(self) -> int:
        return sum(s.count("impact") for s in self.signatures)

    @property
    def transitions(self) -> tuple:
        return transition_signature(self.signatures)


@dataclass
class SpecialPoint:
    """A located bifurcation or event: ``kind``, the parameter value ``p`` and its ``tolerance``
    (width of the final bracket, or the last Newton update), the test function and its value."""

    kind: str
    p: float
    tolerance: float
    test_function: str
    test_value: float
    point: BranchPoint | None
    note: str = ""
    index: int = -1             # the branch point after which it lies
    multiplier_error: float = math.nan
    data: dict = field(default_factory=dict)   # what a two-parameter continuation needs (grazing: t_g, node)


@dataclass
class Branch:
    """The points of one branch in arclength order, its special points, and why it stopped."""

    param: str
    period: int
    k0: int
    points: list = field(default_factory=list)
    special: list = field(default_factory=list)
    stop_reason: str = ""
    seconds: float = 0.0
    newton_iterations: int = 0
    label: str = "main"


class ContinuationProblem:
    """The scaled shooting system of a period-``period`` orbit of ``smap`` in parameter ``param``."""

    def __init__(self, smap, param: str, period: int, k0: int, *, scale, p_scale: float, p_ref: float,
                 tol: float = 1e-10):
        self.smap, self.param, self.n, self.k0 = smap, param, int(period), int(k0)
        self.co = _Coordinates(smap.system)
        self.d = self.co.E.shape[1]
        self.scale, self.p_scale, self.p_ref, self.tol = np.asarray(scale, float), float(p_scale), float(p_ref), tol

    # ----- scaled unknowns ---------------------------------------------------------------------
    def pack(self, nodes, p) -> np.ndarray:
        z = np.concatenate([self.co.reduce(s.y) / self.scale for s in nodes])
        return np.append(z, (p - self.p_ref) / self.p_scale)

    def parameter(self, u) -> float:
        return self.p_ref + float(u[-1]) * self.p_scale

    def states(self, u, flags) -> list:
        """The nodes (full states) of the scaled unknowns u (the nodes first, then parameters)."""
        z = u[:self.n * self.d].reshape(self.n, self.d) * self.scale
        return [HybridState(self.co.embed(z[j]), flags[j]) for j in range(self.n)]

    # ----- the system and its derivatives --------------------------------------------------------
    def evaluate(self, u, flags):
        """(F, DF, linearizations) at u; raises IntegrationFailure when a step fails."""
        p = self.parameter(u)
        if not math.isfinite(p):
            raise IntegrationFailure("non-finite parameter")
        self.smap.set_params(**{self.param: p})
        F, M, C, lins = self.shooting(self.states(u, flags), (self.param,), np.array([self.p_scale]))
        return F, np.column_stack([M, C]), lins

    def shooting(self, nodes, names: tuple, p_scales):
        """(F, M, C, linearizations) at ``nodes`` under the map's current parameters: the scaled
        residuals, the scaled shooting matrix dF/dz and the columns dF/dp of the parameters
        ``names``, each scaled by its ``p_scales`` entry."""
        lins = [self.smap.linearize(s, self.k0 + j, params=tuple(names)) for j, s in enumerate(nodes)]
        co, s, n = self.co, self.scale, self.n
        F = np.concatenate([(co.reduce(lins[j].state.y) - co.reduce(nodes[(j + 1) % n].y)) / s for j in range(n)])
        M = _shooting_matrix([co.R @ L.J @ co.E for L in lins], s)
        C = np.vstack([(co.R @ L.J_p) / s[:, None] * np.asarray(p_scales)[None, :] for L in lins])
        return F, M, C, lins

    def tangent(self, DF, reference) -> np.ndarray:
        """The unit null vector of DF oriented along ``reference``."""
        A = np.vstack([DF, reference])
        rhs = np.zeros(A.shape[0])
        rhs[-1] = 1.0
        t = np.linalg.solve(A, rhs)
        t /= np.linalg.norm(t)
        return t if t @ reference >= 0 else -t

    def correct(self, u_pred, normal, flags, *, max_iter: int = 10):
        """Newton on [F(u); normal . (u - u_pred)] = 0 from u_pred: converged when the scaled
        residual is below ``tol``, or below 100 tol when the iteration stalls or its update falls
        below tol (the integration's noise floor, amplified by large multipliers near a grazing).

        Returns (u, F, DF, lins, flags, iterations) or raises _NoConvergence."""
        u = u_pred.copy()
        flags = list(flags)
        last = math.inf
        for it in range(max_iter + 1):
            try:
                F, DF, lins = self.evaluate(u, flags)
            except (IntegrationFailure, ZeroDivisionError, ParameterError) as exc:
                raise _NoConvergence(f"the integration failed: {exc}") from None
            flags = [dict(lins[j - 1].state.flags) for j in range(self.n)]
            norm = float(np.max(np.abs(F)))
            if not math.isfinite(norm):
                raise _NoConvergence("non-finite residual")
            stalled = it >= 2 and norm > 0.5 * last
            if norm < self.tol or (stalled and norm < 100 * self.tol):
                return u, F, DF, lins, flags, it     # converged, or at the integration's noise floor
            if it == max_iter or (it >= 3 and stalled):
                raise _NoConvergence(f"the corrector stalled at scaled residual {norm:.3g} after {it} iterations")
            last = norm
            A = np.vstack([DF, normal])
            rhs = np.append(-F, -float(normal @ (u - u_pred)))
            try:
                du = np.linalg.solve(A, rhs)
            except np.linalg.LinAlgError:
                raise _NoConvergence("singular bordered Jacobian") from None
            if norm < 100 * self.tol and float(np.max(np.abs(du))) < self.tol:
                return u, F, DF, lins, flags, it      # at the integration's noise floor (large multipliers)
            u = u + du
        raise _NoConvergence("no convergence")   # pragma: no cover - loop returns or raises

    def point(self, u, F, DF, lins, flags, iterations, reference, *, tangent=None) -> BranchPoint:
        co = self.co
        Js = [co.R @ L.J @ co.E for L in lins]
        M = np.eye(self.d)
        for J in Js:
            M = J @ M
        advance = float(sum(L.state.y[co.a] for L in lins)) if co.a is not None else 0.0
        return BranchPoint(p=self.parameter(u), nodes=self.states(u, flags), multipliers=np.linalg.eigvals(M),
                           signatures=[L.signature for L in lins], jacobians=Js, u=u,
                           tangent=self.tangent(DF, reference) if tangent is None else tangent / np.linalg.norm(tangent),
                           iterations=iterations,
                           residual=float(np.max(np.abs(F))), events=[list(L.events) for L in lins],
                           advance=advance, phase=self.smap.phase, k0=self.k0)


class _NoConvergence(RuntimeError):
    pass


# ----- test functions -------------------------------------------------------------------------------
def _fold(pt: BranchPoint) -> float:
    return float(pt.tangent[-1])


def _period_doubling(pt: BranchPoint) -> float:
    return float(np.real(np.prod(pt.multipliers + 1.0)))


def _neimark_sacker(pt: BranchPoint) -> float:
    mu = pt.multipliers
    out = 1.0 + 0j
    for i in range(mu.size):
        for j in range(i + 1, mu.size):
            out *= mu[i] * mu[j] - 1.0
    return float(np.real(out))


TESTS = {"fold": ("fold", "dp/ds: the parameter component of the unit tangent", _fold),
         "period_doubling": ("period-doubling", "Re prod(mu_i + 1)", _period_doubling),
         "neimark_sacker": ("Neimark-Sacker", "Re prod_{i<j}(mu_i mu_j - 1)", _neimark_sacker)}


def _complex_pair_on_circle(pt: BranchPoint, tol: float = 1e-6) -> bool:
    mu = pt.multipliers
    return bool(np.any((np.abs(mu.imag) > 1e-8) & (np.abs(np.abs(mu) - 1.0) < tol)))


# ----- the continuation loop -----------------------------------------------------------------------
def continue_branch(problem: ContinuationProblem, orbit: PeriodicOrbit, p_start: float, p_end: float, *,
                    step: float = 0.02, max_step: float = 0.1, min_step: float = 1e-7, max_points: int = 200,
                    max_turn: float = 0.3, tangent=None, label: str = "main", progress=None,
                    locate: bool = True, bounds=None, section_margin: float = 0.02,
                    max_resections: int = 50) -> Branch:
    """Follow ``orbit`` (at p_start) toward p_end until it leaves [p_start, p_end] (or the interval
    of the two), ``max_points`` points are taken, or a non-smooth event or a corrector failure at
    ``min_step`` stops it (``Branch.stop_reason`` says which).  When a state-changing event comes
    within ``section_margin`` strobe periods of a sample time, the section moves (the map's phase)
    to the middle of the widest event-free interval of the period, at most ``max_resections`` times:
    an event crossing the section would move between periods and break the map's smoothness.  ``tangent``: a start direction
    (scaled unknowns; branch switching), else the null vector pointing toward p_end; ``bounds``:
    the interval to stay in, if not [p_start, p_end]."""
    clock = _time.perf_counter()
    lo, hi = sorted(bounds) if bounds is not None else (min(p_start, p_end), max(p_start, p_end))
    branch = Branch(problem.param, problem.n, problem.k0, label=label)
    flags = [dict(s.flags or {}) for s in orbit.nodes]
    u0 = problem.pack(orbit.nodes, p_start)
    direction = math.copysign(1.0, p_end - p_start) if p_end != p_start else 1.0
    e_p = np.zeros(u0.size)
    e_p[-1] = direction
    reference = e_p if tangent is None else np.asarray(tangent, float)
    try:
        u, F, DF, lins, flags, its = problem.correct(u0, e_p, flags)    # the start, at p_start
    except _NoConvergence as exc:
        branch.stop_reason = f"the start orbit does not converge at {problem.param} = {p_start:.10g}: {exc}"
        return branch
    branch.points.append(problem.point(u, F, DF, lins, flags, its, reference, tangent=tangent))
    h = float(step)
    resections = 0
    while len(branch.points) < max_points:
        prev = branch.points[-1]
        u_pred = prev.u + h * prev.tangent
        try:
            u, F, DF, lins, flags_new, its = problem.correct(u_pred, prev.tangent, _flags_of(prev))
            pt = problem.point(u, F, DF, lins, flags_new, its, prev.tangent)
            turn = math.acos(max(-1.0, min(1.0, float(pt.tangent @ prev.tangent))))
            why = None
            if pt.transitions != prev.transitions:
                why = "signature"
            elif turn > max_turn:
                why = f"the tangent turned {turn:.2f} rad"
        except _NoConvergence as exc:
            why, pt = str(exc), None
        branch.newton_iterations += 0 if pt is None else pt.iterations
        if why is not None:
            if h / 2 >= min_step:
                h /= 2
                continue
            branch.stop_reason = _event_reason(prev, pt, why, problem)
            if locate and pt is not None and why == "signature" or locate and pt is None:
                sp = _discontinuity(problem, prev, pt)
                if sp is not None:
                    sp.index = len(branch.points) - 1
                    branch.special.append(sp)
            break
        branch.points.append(pt)
        if progress is not None:
            progress(pt)
        if locate:
            for kind in TESTS:
                sp = _detect(problem, prev, pt, kind)
                if sp is not None:
                    sp.index = len(branch.points) - 2
                    branch.special.append(sp)
        if resections < max_resections and _event_at_section(problem, pt, within=section_margin):
            moved = _resection(problem, pt)
            if moved is not None:            # the same orbit, sampled where no event happens
                resections += 1
                branch.points.append(moved)
                pt = moved
        if not lo - 1e-12 * max(1.0, abs(lo)) <= pt.p <= hi + 1e-12 * max(1.0, abs(hi)):
            branch.stop_reason = f"left the interval [{lo:.6g}, {hi:.6g}] at {problem.param} = {pt.p:.10g}"
            break
        h = min(max_step, h * (1.5 if its <= 3 else 1.0 if its <= 5 else 0.7))
    else:
        branch.stop_reason = f"reached max_points = {max_points}"
    branch.seconds = _time.perf_counter() - clock
    return branch


def _flags_of(pt: BranchPoint) -> list:
    return [dict(s.flags or {}) for s in pt.nodes]


def _event_reason(prev, pt, why, problem) -> str:
    at = f"{problem.param} = {prev.p:.10g}"
    if why != "signature":
        speed = _slowest_impact(problem, prev)
        near = f"; the slowest impact is at {speed:.3g} (gap rate): near a grazing" if speed < 1e-3 else ""
        return f"stopped after {at}: {why} at the smallest step{near}"
    before, after = prev.transitions, pt.transitions
    nb, na = sum(s.count("impact") for s in before), sum(s.count("impact") for s in after)
    if _crosses_section(before, after) or _event_at_section(problem, prev):
        return (f"stopped after {at}: an event crosses the strobe section (it happens at a sample time t_k), "
                f"which moves it between periods; the map in this section is not smooth there")
    if na > nb:
        what = "an impact is born (grazing)"
    elif na < nb:
        what = "an impact is lost (grazing from the impacting side)"
    elif any("stick" in s for s in after) and not any("stick" in s for s in before):
        what = "sticking sets in"
    else:
        what = "the transition signature changes"
    return f"stopped after {at}: {what}; smooth continuation cannot pass it"


def _detect(problem, a: BranchPoint, b: BranchPoint, kind: str) -> SpecialPoint | None:
    name, description, fn = TESTS[kind]
    fa, fb = fn(a), fn(b)
    if not (fa * fb < 0):
        return None
    pt, f, width = _locate(problem, a, b, fn, kind)
    if pt is None:
        return SpecialPoint(kind, 0.5 * (a.p + b.p), abs(b.p - a.p), description, math.nan, None,
                            note=f"{name} between {a.p:.10g} and {b.p:.10g}; location failed")
    if kind == "neimark_sacker" and not _complex_pair_on_circle(pt):
        return None                    # a neutral saddle: real mu_i mu_j = 1
    return SpecialPoint(kind, pt.p, width, description, f, pt)


def _locate(problem, a: BranchPoint, b: BranchPoint, fn, kind, *, max_iter: int = 40):
    """Illinois false position on the arclength from a toward b (one section) for a zero of ``fn``."""
    with in_section(problem, a):
        return _false_position(problem, a, b, fn, kind, max_iter)


@contextlib.contextmanager
def in_section(problem, pt):
    """Work in the strobe section of branch point ``pt`` (phase and k0), then restore the problem's."""
    section = (problem.smap.phase, problem.k0)
    problem.smap.phase, problem.k0 = pt.phase, pt.k0
    try:
        yield
    finally:
        problem.smap.phase, problem.k0 = section


def _false_position(problem, a, b, fn, kind, max_iter):
    s_lo, s_hi = 0.0, float(a.tangent @ (b.u - a.u))
    f_lo, f_hi = fn(a), fn(b)
    p_lo, p_hi = a.p, b.p
    side, best = 0, None
    for _ in range(max_iter):
        s = (s_lo * f_hi - s_hi * f_lo) / (f_hi - f_lo)
        if not s_lo < s < s_hi:
            s = 0.5 * (s_lo + s_hi)
        try:
            u, F, DF, lins, flags, its = problem.correct(a.u + s * a.tangent, a.tangent, _flags_of(a))
        except _NoConvergence:
            return None, math.nan, math.nan
        pt = problem.point(u, F, DF, lins, flags, its, a.tangent)
        f = fn(pt)
        best = pt
        if f == 0.0:
            return pt, f, 0.0
        if (f < 0) == (f_lo < 0):
            s_lo, f_lo, p_lo = s, f, pt.p
            if side == -1:
                f_hi /= 2
            side = -1
        else:
            s_hi, f_hi, p_hi = s, f, pt.p
            if side == 1:
                f_lo /= 2
            side = 1
        width = abs(p_hi - p_lo)
        if s_hi - s_lo < 1e-12 or (kind != "fold" and width < 1e-12 * max(1.0, abs(pt.p))) \
                or (kind == "fold" and s_hi - s_lo < 1e-8):
            break
    return best, fn(best), abs(p_hi - p_lo)


def _crosses_section(before, after) -> bool:
    """The same events in the orbit, distributed differently over its strobe periods."""
    flat = lambda sig: sorted(r for s in sig for r in s)     # noqa: E731
    return before != after and flat(before) == flat(after)


def _event_at_section(problem, pt, within: float = 1e-5) -> bool:
    """A state-changing event of ``pt`` within ``within`` strobe periods of a sample time."""
    smap, T = problem.smap, problem.smap.period
    for j, evs in enumerate(pt.events):
        t0, t1 = smap.sample_time(problem.k0 + j), smap.sample_time(problem.k0 + j + 1)
        for ev in evs:
            if smap.system.role_of(ev.name) not in SMOOTH_ROLES and min(ev.t - t0, t1 - ev.t) < within * T:
                return True
    return False


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
        smap.set_params(**{problem.param: pt.p})
        nodes = []
        for j, node in enumerate(pt.nodes):
            t = smap.sample_time(problem.k0 + j) + shift * T
            L = smap.linearize(node, problem.k0 + j, until=min(t, smap.sample_time(problem.k0 + j + 1)))
            nodes.append(L.state)
        phase = smap.phase + shift
        smap.phase, problem.k0 = (phase - 1.0, problem.k0 + 1) if phase >= 1.0 else (phase, problem.k0)
        e_p = np.zeros(pt.u.size)
        e_p[-1] = 1.0
        u, F, DF, lins, flags, its = problem.correct(problem.pack(nodes, pt.p), e_p,
                                                     [dict(s.flags or {}) for s in nodes])
        reference = pt.tangent[-1] * e_p if abs(pt.tangent[-1]) > 1e-3 else e_p
        return problem.point(u, F, DF, lins, flags, its, reference)
    except (_NoConvergence, IntegrationFailure, ParameterError):
        smap.phase, problem.k0 = old
        return None


def _slowest_impact(problem, pt) -> float:
    gap = problem.smap.system.gap
    speeds = [abs(gap(ev.y_minus, problem.smap.params)[1]) for evs in pt.events for ev in evs
              if problem.smap.system.role_of(ev.name) == "impact"] if gap is not None else []
    return min(speeds) if speeds else math.inf


def _discontinuity(problem, prev: BranchPoint, pt: BranchPoint | None) -> SpecialPoint | None:
    """Locate the event that stopped the branch after ``prev``: a grazing where a free-flight
    minimum touches the stop (augmented system), else the bracket [prev, pt]."""
    born = pt is not None and pt.impacts > prev.impacts
    if closest_flight_minimum(problem, prev) is not None and (born or pt is None):
        with in_section(problem, prev):
            p, tol, gap, at, note, data = locate_grazing(problem, prev)
        return SpecialPoint("grazing", p, tol, "gap h(t_g) and its rate dh/dt(t_g) at the closest free-flight minimum",
                            gap, at, note=note, data=data)
    if pt is None or _crosses_section(prev.transitions, pt.transitions) or _event_at_section(problem, prev):
        return None
    kind = "signature_change"
    if any("stick" in s for s in pt.transitions) and not any("stick" in s for s in prev.transitions):
        kind = "stick_onset"
    elif pt.impacts < prev.impacts:
        kind = "impact_lost"
    return SpecialPoint(kind, prev.p, math.nan, "transition signature", math.nan, prev,
                        note=f"the last point before the change ({_sig(prev)}; the next corrected point, at "
                             f"{pt.p:.10g}, has {_sig(pt)}): not located")


def _sig(pt) -> str:
    return ";".join(",".join(s) for s in pt.transitions)
