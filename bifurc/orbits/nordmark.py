"""Nordmark's discontinuity-map prediction at a grazing periodic orbit, from the exact Jacobians.

At the grazing time t_g of a located grazing orbit (gap h = 0, gap rate 0, gap acceleration a > 0), a
nearby state y whose free flight would reach the gap minimum h_min(y) ~ grad h . (y - y_g) < 0 is
corrected by the impact (Nordmark's zero-time discontinuity map): to leading order its state at t_g
jumps by b sqrt(-2 a h_min), b = -(R_y - I) grad r / |grad r|^2 (R the impact reset, r the gap rate):
the square-root term.  With M the monodromy matrix in the section t = t_g and sigma = d h_min / dp
along the non-impacting branch, the impacting orbit of the same period at p_g + dp has the impact
speed s solving

    s^2 + 2 a K s + 2 a sigma dp = 0,      K = grad h . (I - M)^{-1} M b,

(s ~ |sigma dp| / K, linear in dp, for K > 0; no small impacting orbit beyond the grazing for
K < 0) and the state jump (I - M)^{-1} M b s at t_g.  Iterating the normal form
xi -> M (xi + b sqrt(2 a max(0, -(sigma dp + grad h . xi)))) classifies what follows the grazing:
persistence (a stable orbit of the same period), period-adding (a stable orbit of another period)
or chaos (no period up to ``max_period``).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import heyoka as hy
import numpy as np

from maps.hybrid import call_cfunc

from .grazing_orbit import gap_derivatives
from .periodic import monodromy

@dataclass
class GrazingPrediction:
    """The normal form of a grazing: gap acceleration ``a``, the jump direction ``b`` (state units per
    unit impact speed), ``sigma`` = d h_min / dp, the feedback ``K``, the monodromy ``M`` at t_g, the
    gap gradient ``n``, the state ``y_g`` at t_g, the side ``direction`` (+1 or -1) of p where the
    non-impacting orbit would penetrate, ``side`` where the small impacting orbit exists (``direction``
    for K > 0; the same side as the non-impacting orbit for K < 0: the branch turns at the grazing), and the ``outcome`` ("persistence", "period-adding" or "chaos") with its period."""

    a: float
    b: np.ndarray
    sigma: float
    K: float
    M: np.ndarray
    n: np.ndarray
    y_g: np.ndarray
    direction: float
    outcome: str = ""
    outcome_period: int = 0
    node: int = 0                       # the node whose period holds t_g
    Phi: np.ndarray | None = None       # d y(t_g) / d (node): carries the jump back to the node

    @property
    def side(self) -> float:
        return self.direction if self.K >= 0 else -self.direction

    @property
    def root_coefficient(self) -> float:
        """|b| sqrt(2 a): the square-root coefficient of the discontinuity map (state jump per
        sqrt(penetration depth))."""
        return float(np.linalg.norm(self.b) * math.sqrt(2 * self.a))

    def state_jump(self, s: float) -> np.ndarray:
        """The impacting orbit's state at t_g less the non-impacting orbit's, at impact speed s."""
        return np.linalg.solve(np.eye(self.M.shape[0]) - self.M, self.M @ self.b) * s

    def describe(self) -> str:
        small = (f"s ~ {abs(self.sigma / self.K):.6g} |dp| for small dp" if self.K != 0 else
                 f"s = {math.sqrt(2 * self.a * abs(self.sigma)):.6g} sqrt(|dp|)")
        law = (f"impact speed s^2 + 2 a K s + 2 a sigma dp = 0 (a = {self.a:.6g}, K = {self.K:.6g}, "
               f"sigma = {self.sigma:.6g}: {small}"
               f"{'' if self.K >= 0 else '; no small impacting orbit beyond the grazing: it lies on the non-impacting side, the branch turns there'})")
        return (f"Nordmark: square-root coefficient {self.root_coefficient:.6g}; {law}; normal form predicts "
                f"{self.outcome}{f' (period {self.outcome_period})' if self.outcome_period else ''}")


def impact_speed(pred: GrazingPrediction, dp: float) -> float:
    """The predicted impact speed of the small impacting orbit at p_g + dp: the root of
    s^2 + 2 a K s + 2 a sigma dp = 0 that vanishes with dp (NaN where it is not positive: no small
    impacting orbit on that side)."""
    disc = (pred.a * pred.K) ** 2 - 2 * pred.a * pred.sigma * dp
    if disc < 0:
        return math.nan
    s = -pred.a * pred.K + math.copysign(math.sqrt(disc), pred.K)
    return s if s > 0 else math.nan


def _reset_jacobian(system, t, y, pars) -> np.ndarray:
    cache = system.__dict__.setdefault("_nordmark_reset", {})
    g = system.impact_guard
    if g.name not in cache:
        exprs = system.reset_expressions(g)
        jac = [hy.diff(e, v) for e in exprs for v in system.sym.state_vars]
        cache[g.name] = hy.cfunc(jac, vars=system.sym.state_vars, compact_mode=True)
    d = len(system.states)
    return call_cfunc(cache[g.name], y, pars, t).reshape(d, d)


def predict(problem, sp, *, dp_probe: float = 1e-6, max_period: int = 64) -> GrazingPrediction | None:
    """The prediction at the located grazing ``sp`` (a SpecialPoint with its point, t_g and node) of
    a branch of ``problem`` (in the section it was located in); None for a translation-reduced
    system or a grazing without its orbit."""
    pt = sp.point
    if pt is None or problem.co.a is not None or "t_g" not in sp.data:
        return None
    param = problem.param
    j, t_g = sp.data["node"], sp.data["t_g"]
    problem.smap = problem.smap.at({param: pt.p})
    L, a, gh, hp, M, b, K = normal_form(problem, pt.nodes, pt.jacobians, j, t_g, (param,))
    t = pt.tangent
    dz = t[j * problem.d:(j + 1) * problem.d] * problem.scale / (t[-1] * problem.p_scale)
    sigma = float(gh @ (L.J @ dz + L.J_p[:, 0]) + hp[0])
    pred = GrazingPrediction(float(a), b, sigma, K, M, np.asarray(gh, float), np.asarray(L.state.y, float),
                             -math.copysign(1.0, sigma), node=j, Phi=np.asarray(L.J, float))
    pred.outcome, pred.outcome_period = _classify(pred, dp_probe * problem.p_scale * pred.direction, max_period)
    return pred


def normal_form(problem, nodes, jacobians, j: int, t_g: float, params: tuple = ()):
    """(linearization to t_g, gap acceleration a, grad h, dh/d params, monodromy M at t_g, jump direction b,
    feedback K) of the grazing orbit ``nodes`` (reduced one-period ``jacobians``) touching at t_g in the
    period of node j, under the map's current parameters.  K = 0: a grazing-fold (the impacting orbits'
    fold reaches the grazing)."""
    smap, system = problem.smap, problem.smap.system
    L = smap.linearize(nodes[j], problem.k0 + j, params=tuple(params), until=t_g)
    pars = np.asarray(system.par_vector(smap.params, L.state.flags), float)
    h, r, a, gh, gr, hp, rp = gap_derivatives(system, tuple(params))(t_g, L.state.y, pars)
    rotated = list(jacobians[j:]) + list(jacobians[:j])
    M = L.J @ monodromy(rotated) @ np.linalg.inv(L.J)
    R_y = _reset_jacobian(system, t_g, L.state.y, pars)
    b = -(R_y - np.eye(len(gr))) @ gr / float(gr @ gr)
    K = float(gh @ np.linalg.solve(np.eye(M.shape[0]) - M, M @ b))
    return L, float(a), np.asarray(gh, float), hp, M, b, K


def _classify(pred, dp: float, max_period: int, iterates: int = 4000):
    """Iterate the normal form at p_g + dp from the non-impacting orbit (xi = 0) and read the period of
    its attractor: ("persistence", 1), ("period-adding", m > 1) or ("chaos", 0)."""
    xi = np.zeros(pred.M.shape[0])
    xs = []
    for _ in range(iterates):
        pen = -(pred.sigma * dp + float(pred.n @ xi))
        xi = pred.M @ (xi + pred.b * math.sqrt(2 * pred.a * max(0.0, pen)))
        xs.append(xi.copy())
        if not np.all(np.isfinite(xi)) or np.max(np.abs(xi)) > 1e6 * abs(dp) + 1e-300:
            return "chaos", 0
    tail = np.array(xs[-2 * max_period:])
    size = float(np.max(np.abs(tail))) or 1.0
    for m in range(1, max_period + 1):
        if np.max(np.abs(tail[m:] - tail[:-m])) < 1e-9 * size:
            return ("persistence" if m == 1 else "period-adding"), m
    return "chaos", 0
