"""Two-parameter curves of folds, period doublings and grazings, by pseudo-arclength continuation of
their defining systems.

Unknowns w = (z, p1, p2[, t_g]) in the scaled coordinates of the branch (nodes by the orbit's
magnitude, each parameter by its span, t_g by the strobe period); equations:

- fold: the shooting residuals F(z; p1, p2) = 0 and sigma = 0, where sigma is the last component
  of the solution of the bordered system [[A, b], [c^T, 0]] (v, sigma) = (0, 1) with A = dF/dz
  (singular exactly when a multiplier is +1) and b, c the left and right singular vectors of A's
  smallest singular value, refreshed after every accepted point (a minimally augmented system, as
  in BifurcationKit.jl);
- period doubling: the same with A the shooting matrix whose wrap-around block is +I instead of -I
  (singular exactly when a multiplier is -1);
- Neimark-Sacker: the same with A complex, its wrap-around block -exp(i theta) I (singular exactly
  when exp(i theta) is a multiplier), sigma complex (Re and Im = 0) and theta an unknown;
- grazing: F = 0 and, at t_g in the period of one node, the gap h = 0 and its rate dh/dt = 0
  (:func:`bifurc.orbits.grazing_orbit.grazing_rows`, exact derivatives).

The rows of F and of the grazing conditions are exact (variational equations with saltation);
sigma's gradient is a forward difference of sigma itself (each sigma from exact Jacobians): second
derivatives of the map are not integrated.  It only steers Newton; a converged point satisfies
sigma = 0 to the tolerance.

Codimension-two points found along a curve (``Curve.special``, stored as ``curve_codim2``), each where a
test function changes sign between two curve points, located by false position on the arclength:
a grazing-fold on a grazing curve (Nordmark's feedback K = 0), a cusp on a fold curve (the fold's
second-order coefficient b^T D^2F(v, v) = 0, a central difference of exact Jacobians along the null
vector v) and a fold-flip on a fold curve (det of the shooting matrix with wrap-around +I = 0: a
multiplier -1 beside the +1) or on a period-doubling curve (det of the shooting matrix = 0: a +1 beside
the -1).  Each is stated with its bracket (at least the corrector's acceptance), or, with error estimates, a
measured bound (:func:`bifurc.orbits.relocate.measure_codim2`: located again at tol/100).

A curve is stepped by the one pseudo-arclength driver of branches and curves (:mod:`bifurc.orbits.driver`).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from maps.hybrid import IntegrationFailure
from maps.parameters import ParameterError

from ..storage.schema import CURVE_KINDS, SPECIAL_KINDS
from .continuation import NoConvergence, bordered_newton, impact_count, unit_tangent
from .driver import Steps, Track, follow
from .grazing_orbit import grazing_rows
from .nordmark import normal_form

#: the codimension-two points looked for on each kind of curve
CODIM2 = {"grazing": ("grazing_fold",), "fold": ("cusp", "fold_flip"), "period_doubling": ("fold_flip",)}
assert set(CODIM2) <= set(CURVE_KINDS) <= set(SPECIAL_KINDS), "curve kinds outside the one vocabulary"
assert {k for kinds in CODIM2.values() for k in kinds} <= set(SPECIAL_KINDS), "codim-2 kinds outside the vocabulary"


@dataclass
class Curve:
    """Points (p1, p2) of a codimension-one curve and why it stopped."""

    kind: str
    params: tuple
    p1: list = field(default_factory=list)
    p2: list = field(default_factory=list)
    residual: list = field(default_factory=list)
    stop_reason: str = ""
    start: int = -1            # index of the special point of the branch it starts from
    special: list = field(default_factory=list)   # codimension-two points on it: (kind, p1, p2, tolerance)
    brackets: list = field(default_factory=list)  # per special point: (w_a, t_a, flags, s_b, bracket widths)
    unmeasured: set = field(default_factory=set)  # indices of special points whose re-location failed


class CurveProblem:
    """The defining system of ``kind`` for the branch problem ``base`` in (base.param, param2)."""

    def __init__(self, base, kind: str, param2: str, p2_ref: float, p2_scale: float, *, node: int = 0):
        if kind not in CURVE_KINDS:
            raise ParameterError(f"curve kind {kind!r}; allowed: {', '.join(CURVE_KINDS)}")
        self.base, self.kind, self.param2 = base, kind, param2
        self.names = (base.param, param2)
        self.p_refs = np.array([base.p_ref, p2_ref])
        self.p_scales = np.array([base.p_scale, p2_scale])
        self.node = int(node)
        self.N = base.n * base.d
        self.b = self.c = None

    def values(self, w) -> np.ndarray:
        return self.p_refs + w[self.N:self.N + 2] * self.p_scales

    def pack(self, nodes, p1, p2, extra=None) -> np.ndarray:
        """The unknowns at ``nodes``, (p1, p2) and ``extra``: t_g [s] for a grazing, the multiplier's
        angle theta [rad] for a Neimark-Sacker point."""
        u = self.base.pack(nodes, p1)[:-1]
        w = np.concatenate([u, (np.array([p1, p2]) - self.p_refs) / self.p_scales])
        if self.kind == "grazing":
            return np.append(w, extra / self.base.smap.period)
        return np.append(w, extra) if self.kind == "neimark_sacker" else w

    def _matrix(self, M, w=None):
        A = M.copy()
        d = self.base.d
        if self.kind == "period_doubling":       # the wrap-around block: +I (a multiplier -1)
            A[self.N - d:, :d] += 2 * np.eye(d)
        elif self.kind == "neimark_sacker":      # -exp(i theta) I (a multiplier exp(i theta))
            A = A.astype(complex)
            A[self.N - d:, :d] += (1.0 - np.exp(1j * w[-1])) * np.eye(d)
        return A

    def _shoot(self, w, flags):
        p = self.values(w)
        if not np.all(np.isfinite(p)):
            raise NoConvergence("non-finite parameters")
        try:
            self.base.smap = self.base.smap.at(dict(zip(self.names, p)))
            nodes = self.base.states(w, flags)
            F, M, C, lins = self.base.shooting(nodes, self.names, self.p_scales)
        except (IntegrationFailure, ZeroDivisionError, ParameterError) as exc:
            raise NoConvergence(str(exc)) from None
        return nodes, F, M, C, lins

    def refresh_bordering(self, w, flags):
        """b, c: the left and right singular vectors of A's smallest singular value at w."""
        _, _, M, _, _ = self._shoot(w, flags)
        U, _, Vt = np.linalg.svd(self._matrix(M, w))
        self.b, self.c = U[:, -1], Vt[-1]

    def _sigma(self, M, w=None):
        """The test function: real, or complex (Neimark-Sacker)."""
        A = self._matrix(M, w)
        K = np.block([[A, self.b[:, None]], [self.c[None, :], np.zeros((1, 1))]])
        rhs = np.zeros(K.shape[0], dtype=K.dtype)
        rhs[-1] = 1.0
        try:
            out = np.linalg.solve(K, rhs)[-1]
        except np.linalg.LinAlgError:
            raise NoConvergence("singular bordered matrix of the test function") from None
        return complex(out) if self.kind == "neimark_sacker" else float(np.real(out))

    def evaluate(self, w, flags):
        """(G, DG, linearizations): the defining system and its Jacobian (len(w) - 1 rows)."""
        nodes, F, M, C, lins = self._shoot(w, flags)
        top = np.column_stack([M, C])
        if self.kind == "grazing":
            j, d = self.node, self.base.d
            t_g = w[-1] * self.base.smap.period
            try:
                G2, rows, _, _ = grazing_rows(self.base, nodes, j, t_g, self.names, self.p_scales,
                                           float(np.max(self.base.scale)))
            except (IntegrationFailure, ZeroDivisionError, ParameterError) as exc:
                raise NoConvergence(str(exc)) from None
            B = np.zeros((2, w.size))
            B[:, j * d:(j + 1) * d] = rows[:, :d]
            B[:, self.N:] = rows[:, d:]
            for i, name in enumerate(self.names):     # t_g = (t_g / T) T(p): it moves with a period-setting parameter
                B[:, self.N + i] += rows[:, -1] * w[-1] * self.base.smap.period_derivative(name) \
                    * self.p_scales[i] / self.base.smap.period
            return np.concatenate([F, G2]), np.vstack([np.column_stack([top, np.zeros(top.shape[0])]), B]), lins
        sigma = self._sigma(M, w)
        grad = np.zeros(w.size, dtype=complex)
        eps = 1e-7
        for i in range(w.size):           # sigma's gradient: forward differences of sigma (steers Newton only)
            dw = np.zeros(w.size)
            dw[i] = eps
            M_i = M if i == w.size - 1 and self.kind == "neimark_sacker" else self._shoot(w + dw, flags)[2]
            grad[i] = (self._sigma(M_i, w + dw) - sigma) / eps
        if self.kind == "neimark_sacker":
            top = np.column_stack([top, np.zeros(top.shape[0])])
            return (np.concatenate([F, [sigma.real, sigma.imag]]),
                    np.vstack([top, grad.real, grad.imag]), lins)
        return np.append(F, sigma.real), np.vstack([top, grad.real]), lins


def correct_curve(problem, w_pred, normal, flags, tol, max_move=None):
    """Newton on [G(w); normal . (w - w_pred)] = 0 (:func:`bifurc.orbits.continuation.bordered_newton`); on
    a grazing curve an iterate that adds an impact is damped back toward the last one; a step
    passes its length ``max_move`` (a solution farther away is on another curve: refused).
    Returns (w, G, DG, flags, max |G|, iterations)."""
    w, G, DG, _, flags, its = bordered_newton(problem.evaluate, w_pred, normal, flags, tol, max_move=max_move,
                                              **newton_options(problem))
    return w, G, DG, flags, float(np.max(np.abs(G))), its


def newton_options(problem) -> dict:
    """The corrector's options on a curve's defining system (:func:`bifurc.orbits.continuation.bordered_newton`):
    on a grazing curve an iterate that adds an impact is damped back."""
    return {"max_iter": 12, "stall_after": 4, "tiny_update": False, "keep_impacts": problem.kind == "grazing"}


def follow_curve(problem: CurveProblem, w0, flags, p2_end: float, bounds1, *, step: float = 0.02,
                 max_step: float = 0.1, min_step: float = 1e-6, max_points: int = 100,
                 max_turn: float = 0.3) -> Curve:
    """Continue the defining system from w0 (a located special point, parameter 2 at its start)
    toward ``p2_end``, staying inside ``bounds1`` for parameter 1, with the one driver
    (:func:`bifurc.orbits.driver.follow`; ``max_turn`` [rad] as there)."""
    tol = problem.base.tol
    curve = Curve(problem.kind, problem.names)
    p2_start = float(problem.values(w0)[1])
    try:
        if problem.kind != "grazing":
            problem.refresh_bordering(w0, flags)
        e = np.zeros(w0.size)
        e[problem.N + 1] = 1.0                       # fix p2 for the start
        w, G, DG, flags, norm, _ = correct_curve(problem, w0, e, flags, tol)
    except NoConvergence as exc:
        curve.stop_reason = f"the start does not converge: {exc}"
        return curve
    first = CurvePoint(w, unit_tangent(DG, e * math.copysign(1.0, p2_end - p2_start)), flags, 0, norm)
    track = _CurveTrack(problem, curve, sorted(bounds1), sorted((p2_start, p2_end)))
    track.record(None, first)
    track.tests = codim2_tests(problem, w, flags) if problem.kind in CODIM2 else ()
    curve.stop_reason = follow(track, first, Steps(step, max_step, min_step, max_turn), max_points)
    return curve


@dataclass
class CurvePoint:
    """One corrected point of a curve: scaled unknowns ``u``, unit tangent, mode flags per node, the
    corrector's iterations and the defining system's largest residual."""

    u: np.ndarray
    tangent: np.ndarray
    flags: list
    iterations: int
    residual: float


class _CurveTrack(Track):
    """A two-parameter curve for the driver: the defining system's corrector, the bordering refreshed at each
    point, the codimension-two test functions (``CODIM2``) and the parameter box."""

    def __init__(self, problem, curve, box1, box2):
        self.problem, self.curve, self.box1, self.box2, self.tests = problem, curve, box1, box2, ()

    def size(self) -> int:
        return len(self.curve.p1)

    @property
    def tol(self) -> float:
        return self.problem.base.tol

    @property
    def newton(self) -> dict:
        return newton_options(self.problem)

    def evaluate(self, u, flags):
        return self.problem.evaluate(u, flags)

    def flags(self, pt) -> list:
        return pt.flags

    def point(self, prev, u, G, DG, lins, flags, iterations):
        return CurvePoint(u, unit_tangent(DG, prev.tangent), flags, iterations, float(np.max(np.abs(G))))

    def record(self, prev, pt) -> None:
        p1, p2 = self.problem.values(pt.u)
        self.curve.p1.append(float(p1))
        self.curve.p2.append(float(p2))
        self.curve.residual.append(pt.residual)
        if prev is not None and self.problem.kind != "grazing":
            try:
                self.problem.refresh_bordering(pt.u, pt.flags)
            except NoConvergence:
                pass

    def detect(self, prev, pt) -> None:
        problem = self.problem
        if problem.kind not in CODIM2:
            return
        before, self.tests = self.tests, codim2_tests(problem, pt.u, pt.flags)
        for i, kind in enumerate(CODIM2[problem.kind]):
            if before[i] * self.tests[i] < 0:
                _locate_zero(problem, self.curve, kind, lambda w_, f_, i=i: codim2_tests(problem, w_, f_)[i],
                             prev.u, prev.tangent, prev.flags, before[i], self.tests[i],
                             float(prev.tangent @ (pt.u - prev.u)))

    def outside(self, pt):
        p1, p2 = self.problem.values(pt.u)
        (lo1, hi1), (lo2, hi2) = self.box1, self.box2
        if not (lo2 - 1e-12 <= p2 <= hi2 + 1e-12 and lo1 - 1e-12 <= p1 <= hi1 + 1e-12):
            return f"left the parameter box at ({p1:.10g}, {p2:.10g})"
        return None

    def fail(self, prev, pt, why, u_pred):
        return f"stopped after ({self.curve.p1[-1]:.10g}, {self.curve.p2[-1]:.10g}): {why} at the smallest step"


def _feedback(problem, w, flags, shift: float = 1e-9) -> float:
    """Nordmark's feedback K at the grazing-curve point w (:func:`bifurc.orbits.nordmark.normal_form`); NaN
    where it cannot be evaluated.  The Jacobians are those of the flow missing the stop: p1 moved by
    ``shift`` (scaled) to the side with fewer impacts (at the exact grazing, rounding may count the touch
    as an impact of speed ~0, whose saltation is not the smooth flow's)."""
    co, best = problem.base.co, None
    for sign in (1.0, -1.0):
        w2 = np.array(w, dtype=float)
        w2[problem.N] += sign * shift
        try:
            nodes, _, _, _, lins = problem._shoot(w2, flags)
        except NoConvergence:
            continue
        if best is None or impact_count(lins) < best[0]:
            best = (impact_count(lins), nodes, lins, w2)
    if best is None:
        return math.nan
    _, nodes, lins, w2 = best
    problem.base.smap = problem.base.smap.at(dict(zip(problem.names, problem.values(w2))))
    try:
        Js = [co.R @ L.J @ co.E for L in lins]
        return normal_form(problem.base, nodes, Js, problem.node, float(w[-1]) * problem.base.smap.period)[-1]
    except (IntegrationFailure, ZeroDivisionError, ParameterError, np.linalg.LinAlgError):
        return math.nan


def codim2_tests(problem, w, flags) -> tuple:
    """The test functions of the codimension-two points ``CODIM2[problem.kind]`` at the curve point w:
    Nordmark's K on a grazing curve (:func:`_feedback`); (cusp, fold-flip) on a fold curve
    (:func:`_fold_tests`); on a period-doubling curve det of the shooting matrix (zero where a multiplier
    +1 joins the -1).  NaN where the shots fail."""
    if problem.kind == "grazing":
        return (_feedback(problem, w, flags),)
    if problem.kind == "fold":
        return _fold_tests(problem, w, flags)
    try:
        M = problem._shoot(w, flags)[2]
    except NoConvergence:
        return (math.nan,)
    return (float(np.linalg.det(M)),)


def _fold_tests(problem, w, flags, eps: float = 1e-5) -> tuple:
    """(cusp, fold-flip) test functions at the fold-curve point w: the fold's second-order coefficient
    b^T (A(z + eps v) - A(z - eps v)) v / (2 eps), with v, b the right and left singular vectors of the
    shooting matrix A's smallest singular value (b oriented along the previous point's b), and det(A with
    wrap-around block +I) (zero where a multiplier is -1); NaN where the shots fail."""
    try:
        _, _, M, _, _ = problem._shoot(w, flags)
        U, _, Vt = np.linalg.svd(M)
        b, v = U[:, -1], Vt[-1]
        prev = getattr(problem, "_cusp_b", None)
        if prev is not None and b @ prev < 0:
            b = -b
        problem._cusp_b = b
        dv = np.zeros(w.size)
        dv[:problem.N] = eps * v
        M_plus, M_minus = problem._shoot(w + dv, flags)[2], problem._shoot(w - dv, flags)[2]
        A_pd = M.copy()
        A_pd[problem.N - problem.base.d:, :problem.base.d] += 2 * np.eye(problem.base.d)
        problem.base.smap = problem.base.smap.at(dict(zip(problem.names, problem.values(w))))
    except NoConvergence:
        return math.nan, math.nan
    return float(b @ (M_plus - M_minus) @ v / (2 * eps)), float(np.linalg.det(A_pd))


def _locate_zero(problem, curve, kind, test, w_a, t_a, flags, K_a, K_b, s_b) -> None:
    """Locate where the test function ``test(w, flags)`` changes sign between the curve points w_a and
    w_a + s_b t_a (:func:`zero_on_curve`) and record it as ``kind`` in ``curve.special`` with its
    tolerance: the bracket's width in the parameters, at least the corrector's acceptance (newton_tol times
    each parameter's span), and its bracket in ``curve.brackets`` (for a measured tolerance:
    :func:`bifurc.orbits.relocate.measure_codim2`).  Kinds: ``CODIM2``; a grazing-fold is where the
    impacting orbits' fold meets the grazing."""
    found = zero_on_curve(problem, test, w_a, t_a, flags, K_a, K_b, s_b)
    if found is None:
        return
    p, width = found
    floor = problem.base.tol * problem.p_scales       # the corrector's acceptance, in parameter units
    curve.special.append((kind, float(p[0]), float(p[1]), float(np.max(np.maximum(width, floor)))))
    curve.brackets.append((np.array(w_a, dtype=float), np.array(t_a, dtype=float), [dict(f) for f in flags],
                           float(s_b), width))


def zero_on_curve(problem, test, w_a, t_a, flags, K_a, K_b, s_b, max_iter: int = 40):
    """(p, width): the parameters (p1, p2) where ``test(w, flags)`` changes sign between the curve points
    w_a and w_a + s_b t_a (Illinois false position on the arclength, each evaluation a corrected curve
    point) and the final bracket's width in each; None where the location fails or the sign change is
    through a pole of the test function, not a zero."""
    s_lo, s_hi, f_lo, f_hi, side, w = 0.0, s_b, K_a, K_b, 0, w_a
    K, p_lo, p_hi = K_a, problem.values(w_a), problem.values(w_a + s_b * t_a)
    for _ in range(max_iter):
        s = (s_lo * f_hi - s_hi * f_lo) / (f_hi - f_lo)
        if not s_lo < s < s_hi:
            s = 0.5 * (s_lo + s_hi)
        w, s = _correct_near(problem, w_a, t_a, flags, s, s_lo, s_hi)
        if w is None:
            return None
        K = test(w, flags)
        if not math.isfinite(K):
            return None
        if (K < 0) == (f_lo < 0):
            s_lo, f_lo, p_lo = s, K, problem.values(w)
            f_hi = f_hi / 2 if side == -1 else f_hi
            side = -1
        else:
            s_hi, f_hi, p_hi = s, K, problem.values(w)
            f_lo = f_lo / 2 if side == 1 else f_lo
            side = 1
        if K == 0.0 or s_hi - s_lo < 1e-12:
            break
    if abs(K) > 1e-6 * min(abs(K_a), abs(K_b)):
        return None                              # a pole of the test function, not a zero
    return problem.values(w), np.abs(np.asarray(p_hi) - p_lo)


def _correct_near(problem, w_a, t_a, flags, s: float, s_lo: float, s_hi: float):
    """(the grazing-curve point on the hyperplane at arclength s from w_a along t_a, s), or, where Newton
    stalls there (a touch counted as an impact), at s moved 2 %, 4 %, 6 % of the way to the bracket's
    middle; (None, s)."""
    mid = 0.5 * (s_lo + s_hi)
    for k in range(4):
        s_k = s + 0.02 * k * (mid - s)
        try:
            w, *_ = correct_curve(problem, w_a + s_k * t_a, t_a, flags, problem.base.tol)
            return w, s_k
        except NoConvergence:
            continue
    return None, s
