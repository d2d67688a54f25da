"""Periodic orbits of a stroboscopic map, stable or unstable, with their Floquet multipliers.

A period-n orbit of P (n strobe periods: relay periods for the relay scenes) solves
P_{k0+n-1} o ... o P_{k0}(y) = y.  Single shooting over n periods multiplies the one-period
Jacobians (spectral radius ~5 per relay period on thesis-1dof), so the solver shoots from
every strobe sample: unknowns y_0 ... y_{n-1}, residuals r_j = P_{k0+j}(y_j) - y_{j+1 mod n},
a block-cyclic Jacobian with the exact one-period Jacobians J_j (variational equations with
saltation, :meth:`maps.StroboscopicMap.linearize`) on its diagonal and -I beside it.  Newton
with a backtracking line search on the scaled residual.  Each node carries its mode (flags),
taken from the previous iterate's step that ends there.

A system invariant under a translation (``system.translation``: the 2-DOF scenes, whose bar and
rig shifted together move the same) has a multiplier 1 along it and a singular Newton system in
the full state: its orbits are solved in the reduced coordinates (the anchor state, the last of
the translation, fixed at 0 at every node; the rig for the 2-DOF scenes), and the shift each
period needs is a result of the orbit: ``advance`` [the anchor's unit] per period.

The forcing of a relay scene repeats after q relay periods (``forcing_period_steps``): n must
be a multiple of q.  The multipliers are the eigenvalues of J_{n-1} ... J_0 (the monodromy
matrix at node 0), computed from the n Jacobians without forming their product
(:mod:`bifurc.orbits.floquet`: the small ones keep their relative accuracy).  The solver never returns an unconverged orbit: it says why it stopped
(singular Jacobian, a transition signature that kept changing, residual stalled, iteration cap,
the integration failing).
"""
from __future__ import annotations

import math
import time as _time
from dataclasses import dataclass, field

import numpy as np

from maps.translation import reduction_matrices, translation_basis

from maps.hybrid import HybridState, IntegrationFailure
from maps.impacts import impact_log
from maps.parameters import ParameterError, validate_value

from .floquet import product_eigenvalues
from .newton import accept

class OrbitNotFound(RuntimeError):
    """Newton did not converge to a periodic orbit; ``reason`` says why."""

    def __init__(self, reason: str, iterations: int = 0, residual: float = math.nan):
        super().__init__(reason)
        self.reason, self.iterations, self.residual = reason, iterations, residual


class Cycle:
    """What a periodic orbit's record says from its Floquet ``multipliers`` and its nodes' event ``signatures``,
    one rule for :class:`PeriodicOrbit` and :class:`bifurc.orbits.continuation.BranchPoint` (review D8)."""

    @property
    def stable(self) -> bool:
        """Every Floquet multiplier inside the unit circle."""
        return bool(np.max(np.abs(self.multipliers)) < 1.0)

    @property
    def impacts_per_period(self) -> int:
        """Impacts in one period of the orbit (every node's step)."""
        return sum(sig.count("impact") for sig in self.signatures)


@dataclass
class PeriodicOrbit(Cycle):
    """A converged periodic orbit of a stroboscopic map.

    ``nodes[j]`` is the hybrid state at sample k0 + j (j < n); ``jacobians[j]`` the exact
    one-period Jacobian there; ``signatures[j]`` the roles of the events of that period, in
    order.  ``multipliers`` are the Floquet multipliers (eigenvalues of the monodromy matrix, from
    the cyclic matrix of the Jacobians: :func:`~bifurc.orbits.floquet.product_eigenvalues`),
    ``stable`` is max |multiplier| < 1 (:class:`Cycle`).  ``residual`` is the largest scaled residual
    |P(y_j) - y_{j+1}| / scale at the solution; ``conditioning`` compares the multiple-shooting
    matrix with single shooting's (monodromy - I)."""

    nodes: list
    k0: int
    period: int
    jacobians: list
    signatures: list
    multipliers: np.ndarray
    residual: float
    iterations: int
    scale: np.ndarray
    conditioning: dict = field(default_factory=dict)
    seconds: float = 0.0
    advance: float = 0.0              # [anchor unit] shift along the translation per period (0: none)
    reduced: tuple = ()               # names of the reduced coordinates when a translation was removed

    @property
    def monodromy(self) -> np.ndarray:
        return monodromy(self.jacobians)


def monodromy(jacobians) -> np.ndarray:
    """J_{n-1} ... J_0: the product of the one-period Jacobians of an orbit, in order."""
    M = np.eye(jacobians[0].shape[0])
    for J in jacobians:
        M = J @ M
    return M


def _scale(states, atol, amplitude=0.0):
    """Per state component: the largest |y| over ``states``, at least ``atol``; where that is below
    1e-3 of the orbit's ``amplitude`` between samples, the amplitude (a component zero at every
    sample, e.g. a velocity sampled at its turning point, scaled by atol made the Newton matrix
    singular)."""
    at_nodes = np.max(np.abs(np.asarray(states)), axis=0)
    return np.maximum(np.where(at_nodes < 1e-3 * amplitude, amplitude, at_nodes), atol)


def _amplitude(smap, node, k: int, co) -> np.ndarray:
    """max |y| per (reduced) component at a quarter, half and three quarters of the period from ``node``
    at sample k (zeros where the integration fails: the node magnitudes then scale alone)."""
    t0, t1 = smap.sample_time(k), smap.sample_time(k + 1)
    try:
        ys = [co.reduce(smap.linearize(node, k, until=t0 + f * (t1 - t0)).state.y) for f in (0.25, 0.5, 0.75)]
    except (IntegrationFailure, ZeroDivisionError, ParameterError):
        return np.zeros(co.E.shape[1])
    return np.max(np.abs(np.array(ys)), axis=0)


class Coordinates:
    """The solver's unknowns: the full state, or with a translation removed the state less its
    anchor component (the anchor fixed at 0; reduce(y) shifts y back along the translation)."""

    def __init__(self, system):
        basis = translation_basis(system)
        self.a, self.e = (None, None) if basis is None else (basis[1], basis[0])
        self.R, self.E, keep = reduction_matrices(basis, len(system.states))   # d reduce / dy; z -> y (anchor 0)
        self.names = tuple(system.state_names[i] for i in keep)

    def reduce(self, y):
        return self.R @ np.asarray(y, dtype=float)

    def embed(self, z):
        return self.E @ z


def find_periodic_orbit(smap, start, period: int, *, k0: int = 0, tol: float = 1e-10, max_iter: int = 40,
                        atol: float = 1e-9) -> PeriodicOrbit:
    """Newton by multiple shooting for a period-``period`` orbit of ``smap`` through samples
    k0 ... k0 + period - 1, from ``start`` (a :class:`~maps.hybrid.HybridState` or a bare state
    at sample k0: the first guess of the nodes is the map's own iteration from it; or the list of
    the ``period`` nodes).

    Converged when the largest residual, scaled per state component by the orbit's magnitude
    (at the nodes and between them, at least ``atol``), passes :func:`~bifurc.orbits.newton.accept` (below ``tol``, or at the
    integration's noise floor).  Raises :class:`OrbitNotFound` with the reason
    otherwise, and :class:`~maps.parameters.ParameterError` for a period that is not a multiple
    of the forcing period q (or q = 0: the forcing never repeats).
    """
    n = int(validate_value("period", period, 1, 100_000))
    q = smap.forcing_period_steps
    if q == 0:
        raise ParameterError("the forcing never repeats within 1000 strobe periods at these parameters (q = 0): "
                             "no periodic orbit exists; choose a relay frequency with f_mains/relay_hz rational")
    if n % q:
        raise ParameterError(f"period = {n} strobe periods is not a multiple of the forcing period q = {q}: "
                             f"periodic orbits here have periods {q}, {2 * q}, {3 * q}, ...")
    clock = _time.perf_counter()
    co = Coordinates(smap.system)
    nodes = _first_nodes(smap, start, n, k0, co)
    d = co.E.shape[1]
    amplitude = _amplitude(smap, nodes[0], k0, co)
    scale = _scale([co.reduce(s.y) for s in nodes], atol, amplitude)
    signatures_seen = []
    for it in range(max_iter + 1):
        if it:      # the orbit's magnitude, not the first guess's (a guess at rest scaled v by atol)
            scale = _scale([co.reduce(s.y) for s in nodes], atol, amplitude)
        try:
            lins = [smap.linearize(s, k0 + j) for j, s in enumerate(nodes)]
        except (IntegrationFailure, ZeroDivisionError) as exc:
            raise OrbitNotFound(f"iteration {it}: {exc}", it) from None
        res = np.concatenate([(co.reduce(lins[j].state.y) - co.reduce(nodes[(j + 1) % n].y)) / scale
                              for j in range(n)])
        norm = float(np.max(np.abs(res)))
        sig = [L.signature for L in lins]
        signatures_seen.append(sig)
        # the mode of each node: the flags its incoming step ends in
        nodes = [HybridState(nodes[j].y, dict(lins[j - 1].state.flags)) for j in range(n)]
        if norm < tol:
            return _solution(smap, nodes, lins, k0, n, norm, it, scale, clock, co)
        if it == max_iter:
            break
        M = shooting_matrix([co.R @ L.J @ co.E for L in lins], scale)
        cond = np.linalg.cond(M)
        if not np.isfinite(cond) or cond > 1e14:
            raise OrbitNotFound(f"singular Jacobian at iteration {it} (condition number {cond:.3g}): a fold, "
                                f"a grazing or a stick makes the orbit degenerate", it, norm)
        step = np.linalg.solve(M, -res).reshape(n, d) * scale
        if accept(norm, tol, update=float(np.max(np.abs(step / scale)))):
            # the integration's noise floor (amplified by large multipliers): the update is below tol
            return _solution(smap, nodes, lins, k0, n, norm, it, scale, clock, co)
        trial = _line_search(smap, nodes, step, k0, co, scale, norm)
        if trial is not None:
            nodes = trial
        else:
            if accept(norm, tol, stalled=True):   # at the noise floor: no step reduces a residual that is noise
                return _solution(smap, nodes, lins, k0, n, norm, it, scale, clock, co)
            changing = len({tuple(s) for s in signatures_seen[-3:]}) > 1
            why = ("the transition signature keeps changing (an impact born or lost between iterates)"
                   if changing else "the residual stalled: no step along the Newton direction reduces it")
            raise OrbitNotFound(f"{why}; scaled residual {norm:.3g} after {it} iterations", it, norm)
    changing = len({tuple(s) for s in signatures_seen[-3:]}) > 1
    raise OrbitNotFound(f"no convergence in {max_iter} iterations (scaled residual {norm:.3g}"
                        f"{'; the transition signature keeps changing' if changing else ''})", max_iter, norm)


def _first_nodes(smap, start, n: int, k0: int, co) -> list:
    """The first guess's n nodes: ``start`` and its n - 1 images (or ``start`` itself when it is a
    list of n HybridStates: an unstable orbit's iterates drift away), with the anchor at 0."""
    if isinstance(start, (list, tuple)) and len(start) == n and all(isinstance(s, HybridState) for s in start):
        return [HybridState(co.embed(co.reduce(s.y)), s.flags) for s in start]
    y0 = start.y if isinstance(start, HybridState) else np.asarray(smap.system.state_vector(start), dtype=float)
    if not np.all(np.isfinite(y0)):
        raise ParameterError(f"the start state has a non-finite component: {y0}")
    nodes = [start if isinstance(start, HybridState) else HybridState(y0, None)]
    try:
        for j in range(n - 1):
            nodes.append(smap.step(nodes[-1], k0 + j))
    except IntegrationFailure as exc:
        raise OrbitNotFound(f"the first guess fails to integrate: {exc}") from None
    return [HybridState(co.embed(co.reduce(s.y)), s.flags) for s in nodes]     # anchor at 0


def _line_search(smap, nodes, step, k0: int, co, scale, norm: float):
    """Nodes moved by lam * ``step`` for the first lam = 1, 1/2, ..., 1/64 whose scaled residual
    falls below (1 - 1e-4 lam) ``norm`` (Armijo), or None."""
    n, lam = len(nodes), 1.0
    while lam >= 1.0 / 64:
        trial = [HybridState(co.embed(co.reduce(nodes[j].y) + lam * step[j]), nodes[j].flags) for j in range(n)]
        try:
            ends = [smap.step(s, k0 + j) for j, s in enumerate(trial)]
            tn = max(float(np.max(np.abs((co.reduce(ends[j].y) - co.reduce(trial[(j + 1) % n].y)) / scale)))
                     for j in range(n))
        except IntegrationFailure:
            tn = math.inf
        if tn < (1 - 1e-4 * lam) * norm:
            return trial
        lam /= 2
    return None


def shooting_matrix(Js, scale) -> np.ndarray:
    """The multiple-shooting Newton matrix in scaled coordinates: the one-period Jacobians J_j on the
    block diagonal, -I on the cyclic block beside each (residual r_j = P(y_j) - y_{j+1 mod n})."""
    n, d = len(Js), Js[0].shape[0]
    M = np.zeros((n * d, n * d))
    for j, J in enumerate(Js):
        M[j * d:(j + 1) * d, j * d:(j + 1) * d] = J / scale[:, None] * scale[None, :]
        k = (j + 1) % n
        M[j * d:(j + 1) * d, k * d:(k + 1) * d] -= np.eye(d)
    return M


def _chattering(smap, lins) -> str:
    """Why the converged nodes are no orbit: a period whose impacts slow geometrically to below 1e-8 of
    its fastest (20 or more: an accumulation of impacts the integration stops resolving, the mass then
    passing the stop unseen), else ''."""
    system = smap.system
    if system.gap is None:
        return ""
    for j, L in enumerate(lins):
        speeds = np.abs(impact_log(system, smap.params, ((ev.name, ev.t, ev.y_minus) for ev in L.events))["velocity"])
        if speeds.size >= 20 and speeds.min() < 1e-8 * speeds.max():
            return (f"period {j} of the converged nodes has {speeds.size} impacts slowing to {speeds.min():.3g} "
                    f"(from {speeds.max():.3g}): an accumulation of impacts (chattering) the integration does not "
                    f"resolve; the mass sticks there (declare a stick mode, e.g. stick_speed > 0)")
    return ""


def _solution(smap, nodes, lins, k0, n, norm, it, scale, clock, co) -> PeriodicOrbit:
    why = _chattering(smap, lins)
    if why:
        raise OrbitNotFound(why, it, norm)
    Js = [co.R @ L.J @ co.E for L in lins]             # the reduced map's Jacobians
    orbit = PeriodicOrbit(nodes=nodes, k0=k0, period=n, jacobians=Js, signatures=[L.signature for L in lins],
                          multipliers=np.array([]), residual=norm, iterations=it, scale=scale,
                          seconds=_time.perf_counter() - clock)
    if co.a is not None:
        orbit.advance = float(sum(L.state.y[co.a] for L in lins))     # every node starts with the anchor at 0
        orbit.reduced = co.names
    M = orbit.monodromy
    orbit.multipliers = product_eigenvalues(Js, scale)
    d = M.shape[0]
    partial, growth = np.eye(d), 1.0
    for J in Js:              # how far single shooting's intermediate products stretch a perturbation
        partial = (J / scale[:, None] * scale[None, :]) @ partial
        growth = max(growth, float(np.linalg.norm(partial, 2)))
    orbit.conditioning = {"multiple_shooting": float(np.linalg.cond(shooting_matrix(Js, scale))),
                          "single_shooting": float(np.linalg.cond(M / scale[:, None] * scale[None, :] - np.eye(d))),
                          "single_shooting_growth": growth}
    return orbit
