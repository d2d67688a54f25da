"""A grazing periodic orbit: the orbit and its grazing point solved together.

The gap h(t, y) > 0 clear is the impact guard's surface (signed so), its rate along the flow
r = dh/dt = grad h . f + dh/dt and its acceleration a = dr/dt.  A grazing orbit of period n in
parameter p satisfies the shooting equations F(z, p) = 0 and, at a time t_g inside the period of
node j, h(y(t_g)) = 0 and r(y(t_g)) = 0 (the orbit touches the stop with zero normal velocity).
Unknowns (z, p, t_g), equations (F, h, r): Newton with exact derivatives,

    dh/dz_j = grad h . Phi(t_g),   dh/dp = grad h . Phi_p(t_g) + dh/dp,   dh/dt_g = r,
    dr/dz_j = grad r . Phi(t_g),   dr/dp = grad r . Phi_p(t_g) + dr/dp,   dr/dt_g = a,

Phi, Phi_p the sensitivities from node j's sample time to t_g (variational equations with
saltation, :meth:`maps.StroboscopicMap.linearize` with ``until``).  The start is the branch point
before the event and its free-flight minimum closest to the stop; iterates that would add an
impact are damped back (the map is not differentiable across the grazing).
"""
from __future__ import annotations

import math

import heyoka as hy
import numpy as np

from maps.hybrid import IntegrationFailure, call_cfunc
from maps.impacts import impact_log
from maps.parameters import ParameterError

from .continuation import flags_of, impact_count
from .newton import accept

#: what makes an evaluation of the map fail
FAILURES = (IntegrationFailure, ZeroDivisionError, ParameterError)


def gap_derivatives(system, params: tuple):
    """f(t, y, pars) -> (h, r, a, grad h, grad r, dh/dp, dr/dp) of the impact guard's gap (the last
    two: vectors over ``params``)."""
    cache = system.__dict__.setdefault("_graze_cfuncs", {})
    params = tuple(params)
    if params not in cache:
        g = system.impact_guard
        h = g.expr * (-1.0 if g.direction == 1 else 1.0)
        r = system.lie_derivative(h)
        a = system.lie_derivative(r)
        s = system.sym
        exprs = [h, r, a] + [hy.diff(h, v) for v in s.state_vars] + [hy.diff(r, v) for v in s.state_vars] \
            + [hy.diff(h, s[p]) for p in params] + [hy.diff(r, s[p]) for p in params]
        cache[params] = hy.cfunc(exprs, vars=s.state_vars, compact_mode=True)
    f, d, m = cache[params], len(system.states), len(params)

    def evaluate(t, y, pars):
        out = call_cfunc(f, y, pars, t)
        return (out[0], out[1], out[2], out[3:3 + d], out[3 + d:3 + 2 * d], out[3 + 2 * d:3 + 2 * d + m],
                out[3 + 2 * d + m:])
    return evaluate


def grazing_rows(problem, nodes, j, t_g, names, p_scales, gscale):
    """(G, rows, h, a): the scaled gap and gap rate at t_g in node j's period and their derivatives
    with respect to the scaled node j (d columns), the parameters ``names`` and t_g / T; the gap h
    and its acceleration a (> 0 where the gap has a minimum: the orbit touches the stop from the
    free side)."""
    smap, system = problem.smap, problem.smap.system
    t0, t1 = smap.sample_time(problem.k0 + j), smap.sample_time(problem.k0 + j + 1)
    if not t0 <= t_g <= t1:
        raise IntegrationFailure(f"the grazing time left the period of node {j}")
    L = smap.linearize(nodes[j], problem.k0 + j, params=tuple(names), until=t_g)
    h, r, a, gh, gr, hp, rp = gap_derivatives(system, names)(
        t_g, L.state.y, np.asarray(system.par_vector(smap.params, L.state.flags), float))
    T = smap.period
    Y = L.J @ problem.co.E * problem.scale                   # d y(t_g) / d (scaled node j)
    rows = np.zeros((2, problem.d + len(names) + 1))
    rows[:, :problem.d] = np.vstack([gh @ Y, gr @ Y])
    rows[:, problem.d:-1] = np.vstack([gh @ L.J_p + hp, gr @ L.J_p + rp]) * np.asarray(p_scales)[None, :]
    rows[:, -1] = np.array([r, a]) * T
    rows /= gscale
    rows[1] *= T
    return np.array([h / gscale, r * T / gscale]), rows, float(h), float(a)


def closest_flight_minimum(problem, pt):
    """(node j, time [s], gap [state unit]) of the free-flight minimum of ``pt`` nearest the stop."""
    system = problem.smap.system
    if system.impact_guard is None or system.gap is None:
        return None
    node_of = [j for j, events in enumerate(pt.events) for _ in events]
    log = impact_log(system, problem.smap.params, ((ev.name, ev.t, ev.y_minus) for evs in pt.events for ev in evs))
    if not log["flight_gap"].size:
        return None
    i = int(np.argmin(log["flight_gap"]))          # the first of equal minima, as a scan would keep
    return node_of[log["flight_event"][i]], float(log["flight_time"][i]), float(log["flight_gap"][i])


def locate_grazing(problem, prev, *, max_iter: int = 30, radius: float = 0.1):
    """Solve the augmented system from branch point ``prev``: (parameter value, its tolerance (NaN:
    not located), the gap at t_g, the grazing BranchPoint or None, a note, {"t_g", "node"}).
    Iterates stay within ``radius`` (scaled units, as the arclength step) of ``prev``: farther, it is
    another grazing, and this one is reported as not located.  Converged when the residual is below
    the problem's tol, or at the integration's noise floor (:func:`~bifurc.orbits.newton.accept`, the
    one rule of every Newton here), the tolerance then the update left."""
    near = closest_flight_minimum(problem, prev)
    if near is None:
        return math.nan, math.nan, math.nan, None, "no free-flight minimum to graze", {}
    j, t_g, _ = near
    gscale = float(np.max(problem.scale))
    u, flags = prev.u.copy(), flags_of(prev)
    impacts, last_step, norm, last_update = prev.impacts_per_period, math.inf, math.inf, math.inf

    def failed(exc):
        return problem.parameter(u), math.nan, math.nan, None, f"the augmented Newton failed: {exc}", {}
    try:
        F, DF, lins = problem.evaluate(u, flags)
    except FAILURES as exc:
        return failed(exc)
    for it in range(max_iter + 1):
        try:
            flags = [dict(lins[i - 1].state.flags) for i in range(problem.n)]
            j, t_g = _node_of(problem, j, t_g)
            G, rows, h, acc = grazing_rows(problem, problem.states(u, flags), j, t_g, (problem.param,),
                                           [problem.p_scale], gscale)
        except FAILURES as exc:
            return failed(exc)
        norm = max(float(np.max(np.abs(F))), float(np.max(np.abs(G))))

        def converged(last):
            if not acc > 0:
                return (problem.parameter(u), math.nan, math.nan, None,
                        f"the augmented Newton converged to a tangency from the wrong side (gap acceleration "
                        f"{acc:.3g} <= 0 at t_g): not the grazing of this branch", {})
            pt = problem.point(u, F, DF, lins, flags, it, prev.tangent)
            return (pt.p, abs(last) * problem.p_scale, h, pt, f"t_g = {t_g:.12g} s in the period of node {j}",
                    {"t_g": t_g, "node": j})
        B = np.zeros((2, u.size + 1))
        B[:, j * problem.d:(j + 1) * problem.d] = rows[:, :problem.d]
        B[:, -2:] = rows[:, problem.d:]
        A = np.vstack([np.column_stack([DF, np.zeros(DF.shape[0])]), B])
        try:
            step = np.linalg.solve(A, -np.concatenate([F, G]))
        except np.linalg.LinAlgError:
            break
        if norm < problem.tol and impact_count(lins) == impacts:
            return converged(step[-2])      # the update still asked for: the error left (Newton converges quadratically)
        if it == max_iter:
            break
        update = float(np.max(np.abs(step[:-1])))
        stalled = it >= 2 and update > 0.9 * last_update     # at the residual's noise floor: the update stopped shrinking
        last_update = update
        if accept(norm, problem.tol, update=update, stalled=stalled) \
                and impact_count(lins) == impacts:
            # the integration's noise floor (as find_periodic_orbit's): residual and update are both
            # round-off; the value is as good as the update Newton still asks for
            return converged(step[-2])
        if float(np.max(np.abs(u - prev.u))) > radius:
            return (problem.parameter(u), math.nan, math.nan, None, "the augmented Newton left the neighbourhood "
                    "of the branch's last point (it heads for another grazing): not located", {})
        lam = 1.0
        while True:     # an iterate that adds or loses an impact is damped back; its evaluation is the next one's
            u_try = u + lam * step[:-1]
            try:
                trial, error = problem.evaluate(u_try, flags), None
            except FAILURES as exc:
                trial, error = None, exc
            if lam <= 1e-3 or (trial is not None and impact_count(trial[2]) == impacts):
                break
            lam /= 2
        u, t_g, last_step = u_try, t_g + lam * step[-1] * problem.smap.period, lam * step[-2]
        if trial is None:
            return failed(error)
        F, DF, lins = trial
    return problem.parameter(u), math.nan, math.nan, None, f"the augmented Newton did not converge (residual {norm:.3g})", {}


def _node_of(problem, j, t_g):
    """(node, t_g) with t_g inside that node's period: a grazing time that Newton moved past a sample
    time belongs to the neighbouring node (the orbit is periodic: past the last node, the first, a
    whole orbit period earlier)."""
    smap, n, k0 = problem.smap, problem.n, problem.k0
    orbit_period = smap.sample_time(k0 + n) - smap.sample_time(k0)
    for _ in range(2 * n):
        if t_g > smap.sample_time(k0 + j + 1):
            j, t_g = (j + 1, t_g) if j + 1 < n else (0, t_g - orbit_period)
        elif t_g < smap.sample_time(k0 + j):
            j, t_g = (j - 1, t_g) if j > 0 else (n - 1, t_g + orbit_period)
        else:
            break
    return j, t_g
