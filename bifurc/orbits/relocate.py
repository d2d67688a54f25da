"""A located point's stated tolerance as a measured bound: the point is located again from the branch
points around it with the integration and the Newton tolerance at 1/100 of the branch's, and its
tolerance (:func:`bifurc.orbits.branch.continue_orbit`) combines the difference of the two locations with
the re-location's final bracket (test functions) or the Newton update still asked for (the augmented
grazing system).  The codimension-two points of a two-parameter curve are measured alike
(:func:`measure_codim2`)."""
from __future__ import annotations

import math

import numpy as np

from maps.poincare import StroboscopicMap

from .continuation import ContinuationProblem, NoConvergence, SpecialPoint, flags_of
from .curves import CODIM2, CurveProblem, codim2_tests, correct_curve, zero_on_curve
from .grazing_orbit import FAILURES, locate_grazing
from .passage import _graze_virtual
from .periodic import _scale
from .special_points import TESTS, _false_position

#: the relative resolution of a located value computed through integrations in double precision (a grazing
#: located at tol 1e-12 and 1e-14 is 3e-14 relative off its closed form both times: tests/test_grazing_passage.py)
RESOLUTION = 1e-13


def relocate(system, values, param, sp, br, problem, tol: float, newton_tol: float):
    """(value, its bracket or Newton update) of special point ``sp`` of branch ``br`` located again on
    the integration at ``tol`` / 100 from the branch points around it, or (NaN, NaN)."""
    if sp.point is None or not 0 <= sp.index < len(br.points) - (0 if sp.kind == "grazing" else 1):
        return math.nan, math.nan
    a = br.points[sp.index]
    tight = StroboscopicMap(system, dict(values, **{param: a.p}), tol=tol / 100, phase=a.phase)
    cp = ContinuationProblem(tight, param, br.period, a.k0, scale=_scale([n.y for n in a.nodes], 1e-9),
                             p_scale=problem.p_scale, p_ref=problem.p_ref, tol=newton_tol / 100)
    try:
        if sp.kind == "grazing" and sp.data.get("from_impacting_side"):
            return _from_impacting_side(cp, a)
        a2 = _recorrect(cp, a)
        if sp.kind == "grazing":
            p, width, *_ = locate_grazing(cp, a2)
            return p, width
        b = br.points[sp.index + 1]
        if b.phase != a.phase or b.k0 != a.k0:
            return math.nan, math.nan
        b2 = _recorrect(cp, b)
        fn = TESTS[sp.kind][2]
        if not fn(a2) * fn(b2) < 0:
            return math.nan, math.nan
        pt, _, width = _false_position(cp, a2, b2, fn, sp.kind, 40)
        return (math.nan, math.nan) if pt is None else (pt.p, width)
    except (NoConvergence, *FAILURES):
        return math.nan, math.nan


def _from_impacting_side(cp, a):
    """A grazing approached from the impacting side located again (:func:`bifurc.orbits.passage._graze_virtual`)
    from the branch's last point ``a`` as it is (its corrector stalled there), on ``cp``."""
    F, DF, lins = cp.evaluate(cp.pack(a.nodes, a.p), flags_of(a))
    pt = cp.point(cp.pack(a.nodes, a.p), F, DF, lins, flags_of(a), 0, a.tangent)
    again = SpecialPoint("impact_lost", a.p, math.nan, "", math.nan, pt, data={"from_impacting_side": True})
    _graze_virtual(cp, again, pt)
    return (again.p, again.tolerance) if again.kind == "grazing" else (math.nan, math.nan)


def _recorrect(cp, pt):
    """Branch point ``pt`` corrected again on ``cp`` (its tighter integration) at the same arclength."""
    u = cp.pack(pt.nodes, pt.p)
    t = np.asarray(pt.tangent, float)
    u_scale = np.append(np.tile(cp.scale, cp.n), cp.p_scale)
    old_scale = _unit_scale(pt, cp)
    t = t * old_scale / u_scale
    t /= np.linalg.norm(t)
    u, F, DF, lins, flags, its = cp.correct(u, t, flags_of(pt))
    return cp.point(u, F, DF, lins, flags, its, t)


def _unit_scale(pt, cp):
    """The scales of ``pt``'s unknowns u (nodes and parameter), read back from u and its nodes."""
    y = np.concatenate([cp.co.reduce(s.y) for s in pt.nodes])
    with np.errstate(divide="ignore", invalid="ignore"):
        s = np.where(pt.u[:-1] != 0, y / pt.u[:-1], np.tile(cp.scale, cp.n))
    return np.append(np.abs(s), cp.p_scale)


def measure_codim2(cp, curve, system, tol: float, newton_tol: float) -> None:
    """Each codimension-two point of ``curve`` (continued on ``cp``) stated with a measured tolerance: in each
    parameter the larger of its own bracket and |p - p2| + the re-location's bracket (at least RESOLUTION
    times the larger of |p2| and the parameter's span: the resolution of a value computed through
    integrations), p2 located again from the same curve points with the integration and Newton at
    tol/100 (:func:`relocate_codim2`).  Where that fails, the stated tolerance (bracket, at least the
    corrector's acceptance) is kept and the point is listed in ``curve.unmeasured`` (its stored line says
    so)."""
    for i, (kind, p1, p2, stated) in enumerate(curve.special):
        again = relocate_codim2(cp, curve, i, system, tol, newton_tol)
        if again is None:
            curve.unmeasured.add(i)
            continue
        p_again, width2 = again
        own = np.maximum(width2, RESOLUTION * np.maximum(np.abs(p_again), cp.p_scales))
        bound = np.maximum(curve.brackets[i][4], np.abs(np.array([p1, p2]) - p_again) + own)
        curve.special[i] = (kind, p1, p2, float(np.max(bound)))


def relocate_codim2(cp, curve, i: int, system, tol: float, newton_tol: float):
    """(p, bracket widths) of codimension-two point ``i`` of ``curve`` located again between the same two
    curve points on the curve problem ``cp`` rebuilt on an integration at ``tol`` / 100 with Newton at
    ``newton_tol`` / 100, or None."""
    kind = curve.special[i][0]
    w_a, t_a, flags, s_b, _ = curve.brackets[i]
    base = cp.base
    tight_map = StroboscopicMap(system, dict(base.smap.params), tol=tol / 100, phase=base.smap.phase)
    tight_base = ContinuationProblem(tight_map, base.param, base.n, base.k0, scale=base.scale,
                                     p_scale=base.p_scale, p_ref=base.p_ref, tol=newton_tol / 100)
    tight = CurveProblem(tight_base, cp.kind, cp.param2, float(cp.p_refs[1]), float(cp.p_scales[1]), node=cp.node)
    j = CODIM2[cp.kind].index(kind)

    def test(w, f):
        return codim2_tests(tight, w, f)[j]
    try:
        if tight.kind != "grazing":
            tight.refresh_bordering(w_a, flags)
        ends = [correct_curve(tight, w_a + s * t_a, t_a, flags, tight_base.tol)[0] for s in (0.0, s_b)]
    except NoConvergence:
        return None
    K_a, K_b = test(ends[0], flags), test(ends[1], flags)
    if not K_a * K_b < 0:
        return None
    return zero_on_curve(tight, test, w_a, t_a, flags, K_a, K_b, s_b)
