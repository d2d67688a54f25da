"""Special points along a branch: smooth bifurcations located by test functions, and the events
that stop smooth continuation.

Test functions, each evaluated at every corrected point and located, where it changes sign, by
the Illinois variant of false position on the arclength (each evaluation a corrected point):

- fold: the parameter component of the unit tangent (the branch turns; a multiplier +1);
- period doubling: Re prod (mu_i + 1) (a real multiplier through -1);
- Neimark-Sacker: Re prod_{i<j} (mu_i mu_j - 1) with the pair complex at the zero (a neutral
  saddle, real mu_i mu_j = 1, is not a bifurcation and is not reported).

A change of the transition signature (an impact born or lost, a stick) stops the branch: where a
free-flight minimum is about to touch the stop, the grazing is located by the augmented system
(:func:`bifurc.orbits.grazing_orbit.locate_grazing`); an impact lost (its speed slowing to zero) is
extrapolated from the slowest impact's speed squared, linear in the parameter there, when that
falls inside the bracket; otherwise the last point before the change is reported, not located,
with the bracket up to the next point as its tolerance.
"""
from __future__ import annotations

import math

import numpy as np

from maps.impacts import impact_log

from ..storage.schema import SPECIAL_KINDS
from .continuation import SMOOTH_ROLES, BranchPoint, NoConvergence, SpecialPoint, flags_of, in_section
from .grazing_orbit import closest_flight_minimum, locate_grazing

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


#: the special points located by a test function or an augmented system (the others bound a
#: branch's end: the last point before an event, or an extrapolation); names of schema.SPECIAL_KINDS
LOCATED_KINDS = (*TESTS, "grazing")
assert set(LOCATED_KINDS) <= set(SPECIAL_KINDS), "special-point kinds outside the one vocabulary"

#: the words of a failed fold's note where a period-2m branch is born at a period doubling
BIRTH_NOTE = "born at a period doubling"


def _zero_of_square(p0: float, r0: float, p1: float, r1: float) -> float:
    """The parameter where r^2, linear in p through (p0, r0^2) and (p1, r1^2), vanishes (r ~
    sqrt(p - p*) near a branch point or a grazing)."""
    return p1 - r1 * r1 * (p1 - p0) / (r1 * r1 - r0 * r0)


def _complex_pair_on_circle(pt: BranchPoint, tol: float = 1e-6) -> bool:
    mu = pt.multipliers
    return bool(np.any((np.abs(mu.imag) > 1e-8) & (np.abs(np.abs(mu) - 1.0) < tol)))


def event_reason(prev, pt, why, problem) -> str:
    """The stop reason of a branch whose step after ``prev`` failed (``why``) or reached ``pt``
    with another transition signature (``why == "signature"``)."""
    at = f"{problem.param} = {prev.p:.10g}"
    if why != "signature":
        speed = _slowest_impact(problem, prev)
        near = f"; the slowest impact is at {speed:.3g} (gap rate): near a grazing" if _impact_slowing(problem, prev) \
            else ""
        return f"stopped after {at}: {why} at the smallest step{near}"
    what = {"section": None, "impact_born": "an impact is born (grazing)",
            "impact_lost": "an impact is lost (grazing from the impacting side)", "stick_onset": "sticking sets in",
            "signature_change": "the transition signature changes"}[_change(problem, prev, pt)]
    if what is None:
        return (f"stopped after {at}: an event crosses the strobe section (it happens at a sample time t_k), "
                f"which moves it between periods; the map in this section is not smooth there")
    return f"stopped after {at}: {what}; smooth continuation cannot pass it"


def _change(problem, prev, pt) -> str:
    """How the transition signature changes from ``prev`` to ``pt``: "section" (the same events
    moved across a sample time), "stick_onset", "impact_born", "impact_lost" or "signature_change"."""
    if _crosses_section(prev.transitions, pt.transitions) or event_at_section(problem, prev):
        return "section"
    if any("stick" in s for s in pt.transitions) and not any("stick" in s for s in prev.transitions):
        return "stick_onset"
    if pt.impacts_per_period != prev.impacts_per_period:
        return "impact_born" if pt.impacts_per_period > prev.impacts_per_period else "impact_lost"
    return "signature_change"


def detect(problem, a: BranchPoint, b: BranchPoint, kind: str) -> SpecialPoint | None:
    name, description, fn = TESTS[kind]
    fa, fb = fn(a), fn(b)
    if not (fa * fb < 0):
        return None
    pt, f, width = _locate(problem, a, b, fn, kind)
    if pt is None:
        note = f"{name} between {a.p:.10g} and {b.p:.10g}; location failed"
        value, width = 0.5 * (a.p + b.p), abs(b.p - a.p)
        ra, rb = half_period_mismatch(a), half_period_mismatch(b)
        if kind == "fold" and max(ra, rb) < BIRTH_MISMATCH:
            m = len(a.nodes) // 2
            note += (f"; the orbit nearly repeats after {m} of its {2 * m} periods at both points (mismatch "
                     f"{ra:.2g} and {rb:.2g} of the state): where it is {BIRTH_NOTE} of a "
                     f"period-{m} orbit (a branch point, singular for Newton); that orbit's period doubling "
                     f"locates it")
            if ra != rb:     # p - p_birth ~ mismatch^2 near the birth: extrapolated to mismatch 0
                birth = _zero_of_square(b.p, rb, a.p, ra)
                if not min(a.p, b.p) <= birth <= max(a.p, b.p):      # a fold lies beyond both points
                    value, width = birth, min(abs(birth - a.p), abs(birth - b.p))
                    note += (f"; the mismatch extrapolates to 0 at {birth:.10g} (p - p_birth ~ mismatch^2), "
                             f"+- the distance to the nearer point")
        return SpecialPoint(kind, value, width, description, math.nan, None, note=note)
    if kind == "neimark_sacker" and not _complex_pair_on_circle(pt):
        return None                    # a neutral saddle: real mu_i mu_j = 1
    return SpecialPoint(kind, pt.p, width, description, f, pt)


#: half-period mismatch below which a failed fold is read as a period-doubling birth (see detect)
BIRTH_MISMATCH = 0.3


def half_period_mismatch(pt: BranchPoint) -> float:
    """max_j,i |y_j,i - y_j+m,i| / max_j |y_j,i| over the nodes y_j of an orbit of even period 2m
    (0: the orbit repeats after m periods, a period-m orbit taken twice); NaN for an odd period."""
    return nodes_mismatch(np.array([np.asarray(s.y, dtype=float) for s in pt.nodes]))


#: smallest state scale in :func:`nodes_mismatch`, relative to the orbit's largest state magnitude
SCALE_FLOOR = 1e-9


def nodes_mismatch(Y) -> float:
    """:func:`half_period_mismatch` of an orbit's nodes given as an array (period x states): each state's
    mismatch relative to its largest magnitude on the orbit, at least :data:`SCALE_FLOOR` of the largest state's (a
    state decayed to rounding noise, 1e-48 on a kicked map's y' = -y, would otherwise read a mismatch of 1)."""
    n = len(Y)
    if n < 2 or n % 2:
        return math.nan
    scale = np.max(np.abs(Y), axis=0)
    scale = np.maximum(scale, SCALE_FLOOR * np.max(scale)) if np.max(scale) > 0 else np.ones_like(scale)
    return float(np.max(np.abs(Y[:n // 2] - Y[n // 2:]) / scale))


def _locate(problem, a: BranchPoint, b: BranchPoint, fn, kind, *, max_iter: int = 40):
    """Illinois false position on the arclength from a toward b (one section) for a zero of ``fn``."""
    with in_section(problem, a):
        return _false_position(problem, a, b, fn, kind, max_iter)


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
            u, F, DF, lins, flags, its = problem.correct(a.u + s * a.tangent, a.tangent, flags_of(a))
        except NoConvergence:
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
    return before != after and sorted(r for s in before for r in s) == sorted(r for s in after for r in s)


def event_at_section(problem, pt, within: float = 1e-5) -> bool:
    """A state-changing event of ``pt`` within ``within`` strobe periods of a sample time."""
    smap, T = problem.smap, problem.smap.period
    for j, evs in enumerate(pt.events):
        t0, t1 = smap.sample_time(problem.k0 + j), smap.sample_time(problem.k0 + j + 1)
        for ev in evs:
            if smap.system.role_of(ev.name) not in SMOOTH_ROLES and min(ev.t - t0, t1 - ev.t) < within * T:
                return True
    return False


def _slowest_impact(problem, pt) -> float:
    if problem.smap.system.gap is None:
        return math.inf
    log = impact_log(problem.smap.system, problem.smap.params,
                     ((ev.name, ev.t, ev.y_minus) for evs in pt.events for ev in evs))
    return float(np.min(np.abs(log["velocity"]))) if log["velocity"].size else math.inf


def _impact_slowing(problem, pt) -> bool:
    """The slowest impact of ``pt`` is below 1e-3 of the largest gap rate at its nodes (the orbit's
    own speed toward or away from the stop): an impact slowing to 0, a grazing from the impacting side."""
    gap = problem.smap.system.gap
    if gap is None:
        return False
    scale = max([abs(gap(s.y, problem.smap.params)[1]) for s in pt.nodes] + [1e-300])
    return _slowest_impact(problem, pt) < 1e-3 * scale


def discontinuity(problem, prev: BranchPoint, pt: BranchPoint | None, earlier: BranchPoint | None = None
                  ) -> SpecialPoint | None:
    """Locate the event that stopped the branch after ``prev``: a grazing where a free-flight
    minimum touches the stop (augmented system); an impact lost, where the slowest impact's speed
    squared, linear in the parameter near a grazing from the impacting side, extrapolates to zero
    from ``earlier`` and ``prev`` inside the bracket; else the bracket [prev, pt]."""
    if pt is None and _impact_slowing(problem, prev):
        # an impact slowing to 0: a grazing from the impacting side, located past it (bifurc.orbits.passage)
        speed = _slowest_impact(problem, prev)
        return SpecialPoint("impact_lost", prev.p, math.nan, "slowest impact speed squared", speed * speed, prev,
                            note=f"the slowest impact slows to {speed:.3g} (gap rate) where the corrector stalls: "
                                 f"a grazing from the impacting side", data={"from_impacting_side": True})
    born = pt is not None and pt.impacts_per_period > prev.impacts_per_period
    if closest_flight_minimum(problem, prev) is not None and (born or pt is None):
        with in_section(problem, prev):
            p, tol, gap, at, note, data = locate_grazing(problem, prev)
        return SpecialPoint("grazing", p, tol, "gap h(t_g) and its rate dh/dt(t_g) at the closest free-flight minimum",
                            gap, at, note=note, data=data)
    change = None if pt is None else _change(problem, prev, pt)
    if change in (None, "section"):
        return None
    kind = "signature_change" if change == "impact_born" else change
    nxt = (f"the next corrected point, at {pt.p:.10g}," if pt.corrected else
           f"the map at the predicted point {pt.p:.10g}, where the corrector failed,")
    note = f"the last point before the change ({_sig(prev)}; {nxt} has {_sig(pt)})"
    if kind == "impact_lost" and earlier is not None:
        s1, s0 = _slowest_impact(problem, prev), _slowest_impact(problem, earlier)
        if math.isfinite(s0) and s1 < s0:
            p_lost = _zero_of_square(earlier.p, s0, prev.p, s1)
            if min(prev.p, pt.p) <= p_lost <= max(prev.p, pt.p):
                return SpecialPoint(kind, p_lost, abs(p_lost - prev.p), "slowest impact speed squared",
                                    s1 * s1, prev,
                                    note=note + f": the slowest impact's speed squared ({s0:.3g}, then {s1:.3g} "
                                                f"[gap rate]) extrapolates to zero at {p_lost:.10g}, inside the "
                                                f"bracket; +- the distance to the last point")
    return SpecialPoint(kind, prev.p, abs(pt.p - prev.p), "transition signature", math.nan, prev,
                        note=note + f": not located; the change lies between {prev.p:.10g} and {pt.p:.10g}")


def _sig(pt) -> str:
    return ";".join(",".join(s) for s in pt.transitions)
