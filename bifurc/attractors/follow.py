"""Global continuation: matching the attractors of neighbouring parameter values, and what their
appearances and disappearances are linked to.

Each value is seeded with the neighbouring values' periodic attractors (one start on each, not counted in the
basin fractions; a sweep up the values, then one back down) besides the fresh starts; an attractor is matched to the
nearest one of the previous value within ``threshold`` grid cells (:func:`.identify.distance`), like with like
only (a periodic orbit to an orbit of its period, by their polished nodes; a chaotic set to a set, never to an
orbit), greedily by distance, as Attractors.jl's matching by state-space distance; two orbits whose impact counts
differ or that lie more than a cell apart only if Newton from the earlier one at the new value lands on the later
one (:func:`continues`).  An
attractor left unmatched appeared or disappeared: its periodic orbit is continued across the step by
:func:`bifurc.orbits.branch.continue_orbit`, and a fold, period doubling, Neimark-Sacker point, grazing or stick
onset located within the step is the link (a period-2m branch folding at, or turning into, a period-m orbit
traversed twice is the birth at that orbit's period doubling: :func:`half_gaps`, :func:`collapse`); otherwise the
change is flagged "global" with its evidence.
"""
from __future__ import annotations

import math

import numpy as np

from maps.hybrid import HybridState

from ..orbits.special_points import BIRTH_MISMATCH, BIRTH_NOTE, nodes_mismatch
from ..storage.schema import SPECIAL_KINDS
from ..labels.codes import ClassCode
from .identify import Attractor, distance, same_orbit

def alike(a, b) -> bool:
    """Only like continues like: two periodic orbits of one period (with or without impacts: a grazing changes
    the impacts, not the orbit), or two sets that are not periodic (chaotic, quasi-periodic)."""
    if a.periodic != b.periodic:
        return False
    return not a.periodic or a.period == b.period


def match(prev: list, cur: list, grid, q: int = 1, threshold: float = 20.0, smap=None) -> dict:
    """{index in ``cur``: (index in ``prev``, distance [cells])} for the matched pairs: like with like only
    (:func:`alike`), periodic orbits by their polished nodes' distance at the best phase.  With ``smap`` (the map at
    ``cur``'s value) two periodic orbits whose impact counts differ or that lie more than :data:`CONFIRM` cells
    apart are paired only if the earlier one, corrected by Newton at this value, is the later one
    (:func:`continues`): an impact gained at a grazing keeps the orbit, while an orbit lost beside another of its
    period must not be read as turning into it."""
    pairs = sorted((distance(a, b, grid, q), i, j) for j, a in enumerate(prev) for i, b in enumerate(cur)
                   if alike(a, b))
    out, used = {}, set()
    for d, i, j in pairs:
        if d <= threshold and i not in out and j not in used and (
                smap is None or not prev[j].periodic or (prev[j].impacts == cur[i].impacts and d <= CONFIRM)
                or continues(smap, prev[j], cur[i], q)):
            out[i] = (j, d)
            used.add(j)
    return out


#: grid cells beyond which a periodic pair is confirmed by Newton (:func:`continues`): an orbit continued over a
#: 0.5 V step of thesis-1dof moves 0.03-0.5 cells; at 211-211.5 V a 2:4 orbit lost at its period doubling lay 13.1
#: cells from another 2:4 orbit
CONFIRM = 1.0


def continues(smap, a, b, q: int = 1) -> bool:
    """Whether the periodic orbit ``a`` (polished at the previous value), corrected by Newton on ``smap`` (this
    value), is the orbit ``b`` (:func:`.identify.same_orbit`); True where Newton does not converge from ``a``'s
    nodes (a grazing between the values changes its transitions: the distance decides then)."""
    from ..orbits.periodic import OrbitNotFound, find_periodic_orbit
    nodes = [HybridState(np.asarray(a.points[k], dtype=float), dict(a.flags[k]) if a.flags and a.flags[k] else None)
             for k in range(a.period)]
    try:
        po = find_periodic_orbit(smap, nodes, a.period, k0=a.k0, tol=1e-10)
    except OrbitNotFound:
        return True
    got = Attractor(int(ClassCode.PERIODIC), a.period, k0=po.k0, points=np.array([n.y for n in po.nodes], dtype=float))
    return same_orbit(got, b, q)


#: special points of a branch that can create or destroy an attractor
LOCAL = ("fold", "period_doubling", "neimark_sacker", "grazing", "impact_lost", "stick_onset")
assert set(LOCAL) <= set(SPECIAL_KINDS), "special-point kinds outside the one vocabulary"


def link_event(pb, param: str, a, here: float, there: float, tol: float = 1e-10) -> tuple[str, str]:
    """(kind, evidence) of an attractor ``a`` found at ``here`` and absent at ``there``: the local event
    located on its branch between the two values, or "global" with what the branch did."""
    if not a.periodic:
        return "global", (f"a {a.label()} set absent at {there:g}: not a periodic orbit, so no branch to continue "
                          f"(exponent {a.lyapunov:.3g} per period)")
    from ..orbits.branch import continue_orbit
    start = HybridState(np.asarray(a.points[0], dtype=float), dict(a.flags[0]) if a.flags else None)
    far = there + 0.5 * (there - here)      # a little beyond, so that an event at the step's end is located
    try:
        br = continue_orbit(pb, param, (here, far), params={param: here}, period=a.period, start=start,
                            k0=a.k0, tol=tol, error=False, max_points=60, step=0.05)
    except Exception as exc:     # noqa: BLE001 - the evidence is the failure itself
        return "global", f"its branch could not be continued from {here:g} ({type(exc).__name__}: {exc})"
    lo, hi = min(here, there), max(here, there)
    gaps = half_gaps(br, pb.system.state_names, a.period)
    for kind, v, at in _ending_first(br, lo, hi)[:1]:
        if kind == "fold" and gaps is not None and gaps[int(at)] < BIRTH_MISMATCH:
            return "period_doubling", (f"period_doubling: the period-{a.period} branch continued from {here:g} "
                                       f"folds at {param} = {v:.10g} where it nearly repeats after {a.period // 2} "
                                       f"periods (half-period mismatch {gaps[int(at)]:.2g} of the state): "
                                       f"{BIRTH_NOTE} of a period-{a.period // 2} orbit")
        return kind, f"{kind} located at {param} = {v:.10g} on the branch continued from {here:g}"
    halved = collapse(gaps, br[param].values)
    if halved is not None and lo - 1e-12 <= min(halved) and max(halved) <= hi + 1e-12:
        return "period_doubling", (f"period_doubling bracketed in {param} = {halved[0]:.10g} to {halved[1]:.10g}: the "
                                   f"period-{a.period} branch continued from {here:g} becomes a period-{a.period // 2} "
                                   f"orbit traversed twice there (born or lost at that orbit's period doubling)")
    mu = a.max_multiplier
    reason = br.attrs.get("branch_stop_reasons", "")
    return "global", (f"no fold, period doubling, torus, grazing or stick onset on its branch between {here:g} and "
                      f"{there:g} (largest |multiplier| {mu:.3g} at {here:g}; branch: {reason}): a crisis or a "
                      f"basin-boundary collision")


def local_events(br) -> list:
    """(branch point, kind, value) of each event of a kind in :data:`LOCAL` located on the branch dataset ``br``
    (:func:`bifurc.continue_orbit`'s output), in the branch's order."""
    if "special_kind" not in br:
        return []
    return sorted((int(at), SPECIAL_KINDS[int(k)], float(v)) for k, v, at in
                  zip(br.special_kind.values, br.special_value.values, br.special_point.values)
                  if k >= 0 and SPECIAL_KINDS[int(k)] in LOCAL and np.isfinite(v))


def _ending_first(br, lo: float, hi: float) -> list:
    """The located events of kinds :data:`LOCAL` on the branch dataset ``br`` within [lo, hi] as (kind, value,
    point), in the branch's order, the first one past which the branch is no longer stable put first: an orbit
    continued across a step can pass a stick onset or a grazing and stay stable, and end at a fold further on
    (the thesis-orbits branch of thesis-1dof's 3-impact orbit: a stick onset at 110.799 V, where it gains an
    impact, then the fold at 110.946 V where it ends)."""
    stable = np.asarray(br.stable.values, dtype=bool)
    got = [e for e in local_events(br) if lo - 1e-12 <= e[2] <= hi + 1e-12]
    ends = [e for e in got if e[0] + 1 >= len(stable) or not stable[e[0] + 1]]
    return [(kind, v, at) for at, kind, v in ends[:1] + [e for e in got if e not in ends[:1]]]


def half_gaps(br, names, period: int):
    """Per point of the branch dataset ``br``, the half-period mismatch of its orbit
    (:func:`bifurc.orbits.special_points.nodes_mismatch`: 0 for a period-m orbit traversed twice, m = period / 2);
    None for an odd period or a branch storing fewer nodes."""
    if period % 2 or "node" not in br.dims or br.sizes["node"] < period:
        return None
    X = np.stack([np.asarray(br[n].values, dtype=float)[:, :period] for n in names], axis=-1)   # point, node, state
    return np.array([nodes_mismatch(Y) for Y in X])


#: half-period mismatch (:func:`half_gaps`) below which a period-2m orbit is a period-m orbit traversed twice (Newton
#: converges to 1e-10)
HALVED = 1e-6


def collapse(gaps, values) -> tuple[float, float] | None:
    """The parameter interval between two consecutive branch points (``values``) over which a period-2m branch
    turns into a period-m orbit traversed twice (its :func:`half_gaps` ``gaps`` fall below :data:`HALVED`): the
    branch passed through the period doubling that bore it onto the doubled parent (pseudo-arclength continuation
    can cross that branch point with neither a fold nor a period-doubling test firing), or None."""
    if gaps is None:
        return None
    for i in range(1, len(gaps)):
        if gaps[i - 1] > HALVED >= gaps[i]:
            return float(values[i - 1]), float(values[i])
    return None


def nan_if_none(x) -> float:
    return math.nan if x is None else float(x)
