"""Pseudo-arclength continuation of periodic orbits of a stroboscopic map in one parameter.

The unknowns are the orbit's nodes (multiple shooting, :mod:`bifurc.orbits.periodic`) and the
parameter p, scaled: u = (z_0 / s, ..., z_{n-1} / s, (p - p_0) / p_s), with s the orbit's
magnitude per state component and p_s the span asked for.  A branch point solves F(u) = 0,
F_j = (P_{k0+j}(z_j; p) - z_{j+1 mod n}) / s, and the arclength condition
t . (u - u_prev) = h, t the unit tangent (the null vector of DF = [dF/dz | dF/dp]).  Every
derivative is exact: variational equations with saltation (:meth:`maps.StroboscopicMap.linearize`).
The corrector is Newton's method on the bordered system [DF; t^T] (:func:`bordered_newton`, shared with
the two-parameter curves); predictor, step rule and turning-angle control are the one driver's
(:mod:`bifurc.orbits.driver`).

The branch's refusals, section moves and stops are in :mod:`bifurc.orbits.arclength`; test
functions, their location and the discontinuity-induced events in :mod:`bifurc.orbits.special_points`.
"""
from __future__ import annotations

import contextlib
import math
from dataclasses import dataclass, field

import numpy as np

from maps.hybrid import HybridState, IntegrationFailure
from maps.parameters import ParameterError

from .floquet import product_eigenvalues
from .newton import accept
from .periodic import Coordinates, Cycle, shooting_matrix

#: the corrector's options on a branch's shooting system and the driver's default (:func:`bordered_newton`)
NEWTON_OPTIONS = {"max_iter": 10, "stall_after": 3, "tiny_update": True}

#: event roles that make the map non-smooth when they appear or vanish (observations and
#: free-flight minima only record; they may come and go along a smooth branch)
SMOOTH_ROLES = ("observation", "flight_minimum", "deepest")


def transition_signature(signatures) -> tuple:
    """The roles of a period's events that change the state or the mode, node by node."""
    return tuple(tuple(r for r in sig if r not in SMOOTH_ROLES) for sig in signatures)


@dataclass
class BranchPoint(Cycle):
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
    corrected: bool = True      # False: the map at a predicted point, where the corrector failed

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
        self.co = Coordinates(smap.system)
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
        self.smap = self.smap.at({self.param: p})
        nodes = [self.consistent(s) for s in self.states(u, flags)]
        F, M, C, lins = self.shooting(nodes, (self.param,), np.array([self.p_scale]))
        return F, np.column_stack([M, C]), lins

    def consistent(self, node: HybridState) -> HybridState:
        """``node`` with the flags that follow from its state (:meth:`maps.hybrid.HybridSystem.mode_at`: the
        measured DC law's region, contact inside the stop) where its carried flags contradict them.  A corrector
        step can move a node across a region knot or deep into the stop; its previous point's flags, taken as a
        complete mode, then left the region's cubic evaluated far outside its region and no guard able to fire
        (thesis-1dof, measured law, 155 V: the cubic blew up and one heyoka step ran for minutes)."""
        fl = node.flags or {}
        rule = self.smap.system.mode_at(node.y, self.smap.params, fl, ())
        wrong = {k: v for k, v in rule.items() if k in fl and fl[k] != v}
        return HybridState(node.y, dict(fl, **wrong)) if wrong else node

    def shooting(self, nodes, names: tuple, p_scales):
        """(F, M, C, linearizations) at ``nodes`` under the map's current parameters: the scaled
        residuals, the scaled shooting matrix dF/dz and the columns dF/dp of the parameters
        ``names``, each scaled by its ``p_scales`` entry."""
        lins = [self.smap.linearize(s, self.k0 + j, params=tuple(names)) for j, s in enumerate(nodes)]
        co, s, n = self.co, self.scale, self.n
        F = np.concatenate([(co.reduce(lins[j].state.y) - co.reduce(nodes[(j + 1) % n].y)) / s for j in range(n)])
        M = shooting_matrix([co.R @ L.J @ co.E for L in lins], s)
        C = np.vstack([(co.R @ L.J_p) / s[:, None] * np.asarray(p_scales)[None, :] for L in lins])
        return F, M, C, lins

    def residual(self, u, flags):
        """:meth:`evaluate` with its integration failures raised as NoConvergence (the corrector's form)."""
        try:
            return self.evaluate(u, flags)
        except (IntegrationFailure, ZeroDivisionError, ParameterError) as exc:
            raise NoConvergence(f"the integration failed: {exc}") from None

    def correct(self, u_pred, normal, flags, *, max_move: float | None = None):
        """Newton on [F(u); normal . (u - u_pred)] = 0 from u_pred (:func:`bordered_newton`; a
        predictor step passes ``max_move``, its length).

        Returns (u, F, DF, lins, flags, iterations) or raises NoConvergence."""
        return bordered_newton(self.residual, u_pred, normal, flags, self.tol, max_move=max_move, **NEWTON_OPTIONS)

    def point(self, u, F, DF, lins, flags, iterations, reference, *, tangent=None) -> BranchPoint:
        co = self.co
        Js = [co.R @ L.J @ co.E for L in lins]
        advance = float(sum(L.state.y[co.a] for L in lins)) if co.a is not None else 0.0
        return BranchPoint(p=self.parameter(u), nodes=self.states(u, flags), multipliers=product_eigenvalues(Js, self.scale),
                           signatures=[L.signature for L in lins], jacobians=Js, u=u,
                           tangent=unit_tangent(DF, reference) if tangent is None else tangent / np.linalg.norm(tangent),
                           iterations=iterations,
                           residual=float(np.max(np.abs(F))), events=[list(L.events) for L in lins],
                           advance=advance, phase=self.smap.phase, k0=self.k0)


def unit_tangent(DF, reference) -> np.ndarray:
    """The unit null vector of DF (k x k+1) oriented along ``reference`` (where the bordered system
    is singular, e.g. where a multiplier is exactly 1 along the whole branch: the right singular
    vector of DF's smallest singular value)."""
    A = np.vstack([DF, reference])
    rhs = np.zeros(A.shape[0])
    rhs[-1] = 1.0
    try:
        t = np.linalg.solve(A, rhs)
    except np.linalg.LinAlgError:
        t = np.zeros(A.shape[1])
    if not np.all(np.isfinite(t)) or not np.any(t):
        t = np.linalg.svd(DF)[2][-1]
    t = t / np.linalg.norm(t)
    return t if t @ reference >= 0 else -t


class NoConvergence(RuntimeError):
    """The corrector did not converge (the message says how it stopped)."""


def impact_count(lins) -> int:
    """Impacts in the steps of linearizations ``lins`` (their events' roles)."""
    return sum(L.signature.count("impact") for L in lins)


def bordered_newton(evaluate, u_pred, normal, flags, tol: float, *, max_iter: int, stall_after: int,
                    tiny_update: bool, keep_impacts: bool = False, max_move: float | None = None):
    """Newton on [G(u); normal . (u - u_pred)] = 0 from u_pred, the one corrector of branches
    (:class:`ContinuationProblem`) and two-parameter curves (:mod:`bifurc.orbits.curves`).

    ``evaluate(u, flags) -> (G, DG, linearizations)`` raises :class:`NoConvergence` when it
    cannot.  Converged by :func:`~bifurc.orbits.newton.accept`: max |G| < ``tol``, or at the noise
    floor when the iteration stalls (the residual no longer halves) or, with ``tiny_update``, when
    the Newton update falls below tol.  With
    ``keep_impacts`` a step that adds an impact (crossing a grazing, where the map is not
    differentiable) is halved, down to 1e-3 of itself.  ``max_move`` (a predictor step's length):
    a solution farther than that (and than 1e3 tol) from u_pred is refused, Newton having
    converged on another branch.  Returns (u, G, DG, linearizations, flags, iterations); raises
    NoConvergence."""
    u, last, allowed = np.array(u_pred, dtype=float), math.inf, None

    def done(u, G, DG, lins, flags, it):
        moved = float(np.linalg.norm(u - u_pred))
        if max_move is not None and moved > max(max_move, 1e3 * tol):
            raise NoConvergence(f"the corrector moved {moved:.3g} from a step of {max_move:.3g} (scaled): "
                                f"it converged on another branch")
        return u, G, DG, lins, flags, it

    G, DG, lins = evaluate(u, flags)
    for it in range(max_iter + 1):
        flags = [dict(lins[j - 1].state.flags) for j in range(len(lins))]
        if keep_impacts and allowed is None:
            allowed = impact_count(lins)
        norm = float(np.max(np.abs(G)))
        if not math.isfinite(norm):
            raise NoConvergence("non-finite residual")
        stalled = it >= 2 and norm > 0.5 * last
        if accept(norm, tol, stalled=stalled):
            return done(u, G, DG, lins, flags, it)
        if it == max_iter or (it >= stall_after and stalled):
            raise NoConvergence(f"the corrector stalled at scaled residual {norm:.3g} after {it} iterations")
        last = norm
        try:
            du = np.linalg.solve(np.vstack([DG, normal]), np.append(-G, -float(normal @ (u - u_pred))))
        except np.linalg.LinAlgError:
            raise NoConvergence("singular bordered Jacobian") from None
        if tiny_update and accept(norm, tol, update=float(np.max(np.abs(du)))):
            return done(u, G, DG, lins, flags, it)
        lam = 1.0
        while True:                        # the trial's evaluation is the next iteration's
            trial = evaluate(u + lam * du, flags)
            if allowed is None or lam <= 1e-3 or impact_count(trial[2]) <= allowed:
                break
            lam /= 2
        u = u + lam * du
        G, DG, lins = trial
    raise NoConvergence("no convergence")   # pragma: no cover - the loop returns or raises


def flags_of(pt) -> list:
    """The mode flags of each node of ``pt`` (anything with ``nodes``: a branch point, an orbit)."""
    return [dict(s.flags or {}) for s in pt.nodes]


@contextlib.contextmanager
def in_section(problem, pt):
    """Work in the strobe section of branch point ``pt`` (phase and k0), then restore the problem's."""
    phase, k0 = problem.smap.phase, problem.k0
    problem.smap, problem.k0 = problem.smap.at(phase=pt.phase), pt.k0
    try:
        yield
    finally:      # the section only: the parameters stay where the work left them
        problem.smap, problem.k0 = problem.smap.at(phase=phase), k0
