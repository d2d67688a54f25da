"""Past a grazing or a stick onset: the orbit on the other side of the event that stopped a smooth
piece of a branch, with its new transition signature, to restart continuation from.

The event's orbit (the located grazing orbit, else the branch's last point) is the first guess of
Newton (:func:`~bifurc.orbits.periodic.find_periodic_orbit`) at p_e + dp on the far side, for dp a
growing ladder of fractions of the span; at a grazing the guess adds Nordmark's predicted jump
(:mod:`bifurc.orbits.nordmark`) and the ladder starts where the predicted impact speed is resolved.
An orbit whose transition signature differs from the stopped piece's is the restart; none: the
orbit does not persist there, and the reason says what was tried.  Past a stick onset an orbit in flight is
preferred to the bar at rest on the stop all period (no impact), which the chattering orbit meets at the section:
on thesis-1dof at 110.79918 V Newton 7.5e-6 V past the onset landed on the bar at rest, 7.5e-4 V past on the
4-impact orbit the branch continues as (the census meets that one).  The bar at rest is the restart only where
no orbit in flight is found along the ladder in that direction.
"""
from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np

from maps.engines.scalar import HybridRun
from maps.hybrid import HybridState, IntegrationFailure
from maps.parameters import ParameterError

from ..storage.schema import SPECIAL_KINDS
from .continuation import NoConvergence, transition_signature
from .grazing_orbit import gap_derivatives, locate_grazing
from .nordmark import impact_speed, predict
from .periodic import OrbitNotFound, find_periodic_orbit

#: the events a branch is continued through
PASSABLE = ("grazing", "impact_lost", "stick_onset", "signature_change")
assert set(PASSABLE) <= set(SPECIAL_KINDS), "special-point kinds outside the one vocabulary"

#: the far side's distances from the event, in units of the span
LADDER = (1e-5, 1e-4, 1e-3, 1e-2)


def restart(problem, sp, last, lo: float, hi: float):
    """(start, p, direction, prediction note) of the piece past the event ``sp`` that stopped after branch
    point ``last``, or (None, reason, 0, note).  ``start`` has ``nodes`` at p, in the problem's section, and their ``scale``;
    ``direction`` the sign of the parameter's change along the new piece (at a grazing whose small
    impacting orbit lies on the non-impacting side, Nordmark's K < 0, the branch turns back there)."""
    impacting_side = bool(sp.data.get("from_impacting_side"))
    if impacting_side:
        _graze_virtual(problem, sp, last)
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
        if pred is not None:       # the small impacting orbit's side; from it, the non-impacting orbit's
            direction = -pred.direction if impacting_side else pred.side
    old = transition_signature(last.signatures)
    tried = []
    for way in ((direction,) if pred is not None else (direction, -direction)):
        rest = None
        for frac in LADDER:
            p = p_e + way * frac * problem.p_scale
            if not lo <= p <= hi:
                tried.append(f"{p:.10g} outside [{lo:.6g}, {hi:.6g}]")
                break
            nodes = _guess(problem, ref, p - ref.p, None if impacting_side else pred)
            problem.smap = problem.smap.at({problem.param: p})
            try:
                orbit = find_periodic_orbit(problem.smap, nodes, problem.n, k0=problem.k0, tol=problem.tol)
            except (OrbitNotFound, IntegrationFailure, ParameterError) as exc:
                tried.append(f"{p:.10g} ({exc})")
                continue
            if transition_signature(orbit.signatures) != old:
                if sp.kind == "stick_onset" and orbit.impacts_per_period == 0 < last.impacts_per_period:
                    rest = rest or (orbit, p)           # the restart only if no orbit in flight is found this way
                    tried.append(f"{p:.10g} (the bar at rest on the stop all period)")
                    continue
                if impacting_side and sp.kind != "grazing":
                    _graze_from(problem, sp, orbit, p, way)
                return SimpleNamespace(nodes=orbit.nodes, scale=orbit.scale), p, way, note
            tried.append(f"{p:.10g} (converged to the same signature)")
        if rest is not None:
            return SimpleNamespace(nodes=rest[0].nodes, scale=rest[0].scale), rest[1], way, note
    return None, ("no periodic orbit of period {} with another transition signature past the event: Newton "
                  "from the event's orbit at {} = {}".format(problem.n, problem.param, "; ".join(tried))), 0.0, note


def _graze_virtual(problem, sp, last) -> None:
    """Locate the grazing that the impact slowing to 0 of branch point ``last`` approaches: its orbit less
    that impact (the state just before it with the gap rate set to 0, integrated to the next sample and
    stepped round the period) starts the augmented system (:func:`_graze`)."""
    smap = problem.smap = problem.smap.at({problem.param: last.p})
    system = smap.system
    hits = [(abs(system.gap(ev.y_minus, smap.params, ev.t)[1]), j, ev) for j, evs in enumerate(last.events)
            for ev in evs if system.role_of(ev.name) == "impact"]
    if not hits:
        return
    _, j, ev = min(hits, key=lambda h: h[0])
    try:
        pars = np.asarray(system.par_vector(smap.params, last.nodes[j].flags or {}), float)
        _, r, _, _, gr, _, _ = gap_derivatives(system, ())(ev.t, np.asarray(ev.y_minus, float), pars)
        y = np.asarray(ev.y_minus, float) - r * gr / float(gr @ gr)
        run = HybridRun(system, smap.params, HybridState(y, dict(last.nodes[(j + 1) % problem.n].flags or {})),
                        t0=ev.t, tol=smap.tol)
        run.advance(smap.sample_time(problem.k0 + j + 1))
        nodes = [None] * problem.n
        i = (j + 1) % problem.n
        nodes[i] = HybridState(np.array(run.y, float), dict(run.flags))
        for _ in range(problem.n - 1):
            nodes[(i + 1) % problem.n] = smap.step(nodes[i], problem.k0 + i)
            i = (i + 1) % problem.n
    except (IntegrationFailure, ParameterError, ZeroDivisionError):
        return
    _graze(problem, sp, nodes, last.p, -math.copysign(1.0, last.tangent[-1]), "its orbit less that impact")


def _graze_from(problem, sp, orbit, p: float, way: float) -> None:
    _graze(problem, sp, orbit.nodes, p, -way, f"the orbit without that impact found at {p:.10g}")


def _graze(problem, sp, nodes, p: float, back: float, what: str) -> None:
    """Turn ``sp``, an impact slowing to 0 where the corrector stalled, into the grazing located by the
    augmented system (:func:`~bifurc.orbits.grazing_orbit.locate_grazing`) started from ``nodes`` at ``p``
    (an orbit without that impact; ``back``: the parameter's direction toward the event)."""
    e_p = np.zeros(problem.n * problem.d + 1)
    e_p[-1] = back
    flags = [dict(s.flags or {}) for s in nodes]
    try:
        u = problem.pack(nodes, p)
        F, DF, lins = problem.evaluate(u, flags)
        start = problem.point(u, F, DF, lins, flags, 0, e_p)
        value, tol, gap, at, why, data = locate_grazing(problem, start)
    except (NoConvergence, IntegrationFailure, ParameterError, ZeroDivisionError) as exc:
        at, tol, why = None, math.nan, str(exc)
    if at is None or not math.isfinite(tol):
        sp.note += f"; the grazing was not located from {what}: {why}"
        return
    sp.kind, sp.p, sp.tolerance, sp.point, sp.data = "grazing", value, tol, at, dict(data, from_impacting_side=True)
    sp.test_function, sp.test_value = "gap h(t_g) and its rate dh/dt(t_g) at the closest free-flight minimum", gap
    sp.note += f", located by the augmented system from {what}; {why}"


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
