"""Grazing: the thresholds that flag a grazing orbit, and locating grazing parameter values.

A located graze is a parameter value between two grid neighbours whose impacts per period
differ, found by bisection (:func:`locate_grazing`) on the signed clearance of the branch
with fewer impacts (:class:`BranchFollower`).  :func:`grazing_brackets` picks the neighbour
pairs of a sweep where that is meaningful (cheap), :func:`locate_bracket` bisects one (a task
with a small picklable payload, run on a sweep's workers); :func:`locate_grazing_values` does
both here.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from maps.parameters import ParameterError

from ..labels.codes import ClassCode, Status
from ..storage.schema import GRAZING_GAP

#: a located sign change counts as a graze when the bisection shrank the clearance at its end
#: with fewer impacts to this fraction of its value at the grid neighbour
GRAZE_SHRINK = 0.1
#: classes between which a bracket can hold a graze (a periodic orbit on at least one side)
_BRACKETABLE = (ClassCode.PERIODIC, ClassCode.PERIODIC_NO_IMPACT, ClassCode.NOT_CONVERGED)


def locate_grazing(signed_clearance, a: float, b: float, *, xtol: float) -> dict:
    """Bisection for the parameter where ``signed_clearance(p)`` changes sign on [a, b].

    ``signed_clearance(p)`` is the attractor's minimum clearance to the stop at p
    (> 0: no contact) or minus its maximum penetration (< 0: impacting); it crosses
    zero where the orbit grazes.  Returns {"value", "bracket", "xtol", "evaluations"}:
    the grazing value lies in ``bracket`` whose width is <= xtol.
    """
    if not (math.isfinite(xtol) and xtol > 0):
        raise ParameterError(f"xtol = {xtol}: must be finite and > 0")
    fa, fb = signed_clearance(a), signed_clearance(b)
    evals = 2
    if not (math.isfinite(fa) and math.isfinite(fb)) or (fa > 0) == (fb > 0):
        raise ParameterError(f"no sign change of the clearance on [{a:g}, {b:g}] "
                             f"(f(a) = {fa:.3g}, f(b) = {fb:.3g}): no grazing bracketed")
    lo, hi, flo = a, b, fa
    while abs(hi - lo) > xtol:
        mid = 0.5 * (lo + hi)
        fm = signed_clearance(mid)
        evals += 1
        if not math.isfinite(fm):
            raise ParameterError(f"clearance not finite at {mid:g}")
        if (fm > 0) == (flo > 0):
            lo, flo = mid, fm
        else:
            hi = mid
    return {"value": 0.5 * (lo + hi), "bracket": (min(lo, hi), max(lo, hi)), "xtol": xtol, "evaluations": evals}


def _impact_rate(r) -> float:
    """Contacts per recorded period."""
    return r.n_impacts / max(1, r.record_used)


@dataclass(frozen=True)
class GrazingBracket:
    """Grid neighbours ``a < b`` of ``branch`` whose impacts per period differ, and where the
    bisection starts: the neighbour with fewer impacts (``clear_value``, its end state
    ``clear_start = (state, flags)`` and contact count ``clear_impacts``)."""

    branch: str
    a: float
    b: float
    impacts_below: int      # contacts in the record at a
    impacts_above: int      # contacts in the record at b
    clear_value: float
    clear_start: tuple
    clear_impacts: int
    xtol: float             # bisection bracket width to reach [parameter units]


def grazing_brackets(results, values, xtol) -> list:
    """The :class:`GrazingBracket` of every neighbour pair whose number of impacts per period differs.

    ``results``: {branch: [ValueResult or None per value]}; ``xtol`` None: a thousandth of the grid
    spacing.  From no impact to impacts, one neighbour must be periodic and the other periodic or
    not-converged (near a grazing bifurcation convergence is slow), or the non-impacting one periodic
    and the other of any class (a grazing into chaos: the periodic orbit's clearance still vanishes
    in the bracket, and the bisection follows it); from m > 0 to m' impacts per
    period both must be periodic.  Between chaotic or quasi-periodic neighbours the sign of the
    clearance brackets nothing meaningful.  Nothing is integrated.
    """
    found = []
    if xtol is None and values.size > 1:  # default: a thousandth of the grid spacing
        xtol = float(np.min(np.abs(np.diff(values)))) * 1e-3
    for b, res in results.items():
        for i in range(values.size - 1):
            ra, rb = res[i], res[i + 1]
            if ra is None or rb is None or ra.status != Status.OK or rb.status != Status.OK:
                continue
            birth = min(ra.n_impacts, rb.n_impacts) == 0 and \
                (ra if ra.n_impacts == 0 else rb).class_code == ClassCode.PERIODIC_NO_IMPACT
            if not birth and (ra.class_code not in _BRACKETABLE or rb.class_code not in _BRACKETABLE):
                continue
            if ra.class_code == rb.class_code == ClassCode.NOT_CONVERGED:
                continue  # no periodic orbit on either side: no branch whose clearance vanishes
            if _impact_rate(ra) == _impact_rate(rb):
                continue
            if ra.n_impacts and rb.n_impacts and not (ra.class_code == rb.class_code == ClassCode.PERIODIC):
                continue  # m -> m' > 0 impacts: only between periodic orbits (a transient's count drifts)
            value, clear = (values[i], ra) if _impact_rate(ra) < _impact_rate(rb) else (values[i + 1], rb)
            found.append(GrazingBracket(b, values[i], values[i + 1], ra.n_impacts, rb.n_impacts, value,
                                        clear.end_state, clear.n_impacts, xtol))
    return found


def bracket_cost(job, bracket: GrazingBracket) -> float:
    """Relay periods :func:`locate_bracket` integrates, roughly: a value and its ramp per bisection step."""
    steps = 2 + max(0.0, math.log2(abs(bracket.b - bracket.a) / bracket.xtol)) if bracket.xtol > 0 else 2
    return steps * (2 * job.transient + job.record)


def locate_bracket(job, bracket: GrazingBracket):
    """Bisect one :class:`GrazingBracket` along the branch with fewer impacts (see
    :class:`BranchFollower`); ``job``: the sweep's ValueJob.  Returns the :func:`locate_grazing`
    result with the neighbours' data, or None where the bracket holds no sign change (an attractor
    that changes under re-computation brackets nothing)."""
    follower = BranchFollower(job, bracket.clear_value, bracket.clear_start, bracket.clear_impacts)
    try:
        g = locate_grazing(follower, bracket.a, bracket.b, xtol=bracket.xtol)
    except ParameterError:
        return None
    g["impacts_below"], g["impacts_above"] = bracket.impacts_below, bracket.impacts_above
    g["clearance"], g["impact_speed"] = follower.clearance[-1], follower.speed[-1]
    # a graze: the clearance of the branch with fewer impacts vanishes as the bracket shrinks;
    # if it stays finite the branch ends otherwise (a jump, e.g. a saddle-node).  The impact
    # speed past a graze need not be small: the orbit may jump to a distant impacting attractor.
    # A grid value on the graze itself starts with a clearance already at the grazing gap:
    # that is a graze too, not a jump (nothing is left to shrink).
    g["confirmed"] = (follower.clearance[-1] <= GRAZE_SHRINK * follower.clearance[0]
                      or follower.clearance[0] < GRAZING_GAP)
    g["clearance_start"] = follower.clearance[0]
    return g


def locate_grazing_values(results, values, job, xtol):
    """Grazing values between neighbours whose number of impacts per period differs, here, one
    bracket after the other (:func:`grazing_brackets`, :func:`locate_bracket`).

    ``results``: {branch: [ValueResult or None per value]}; ``job``: the sweep's ValueJob.
    Returns [(branch, locate_grazing result + neighbour data), ...].
    """
    located = [(br.branch, locate_bracket(job, br)) for br in grazing_brackets(results, values, xtol)]
    return [(b, g) for b, g in located if g is not None]


class BranchFollower:
    """Signed clearance along the branch with fewer impacts, for bisection.

    On that branch (``m`` contacts in the record, possibly 0) it is the smallest
    clearance: the whole orbit's for m = 0, the lowest free-flight minimum for m > 0;
    both reach 0 at the graze.  Past it (more contacts) it is minus the slowest impact
    speed, which also reaches 0 at the graze.
    An orbit with more impacts may coexist just before grazing, and a parameter jump excites a
    transient about as large as the change of the forced response, which can touch the
    stop and land on it.  So each evaluation ramps the parameter from the last clear
    value in ``substeps`` steps (transient split between them) and, when the result is
    clear, becomes the new starting point: the branch is followed up to its graze.
    """

    def __init__(self, job, value, start, impacts, substeps=8):
        """From ``value`` whose orbit ended at ``start = (state, flags)`` with ``impacts`` contacts in its record."""
        self.job, self.substeps = replace(job, lyapunov=False), substeps
        self.value, self.start, self.impacts = value, start, impacts
        self.clearance, self.speed = [], []  # every positive and negative value returned, in order

    def __call__(self, p):
        f = self._evaluate(p)
        if math.isfinite(f):
            (self.clearance if f > 0 else self.speed).append(abs(f))
        return f

    def _evaluate(self, p):
        if p == self.value:
            r = self.job(p, self.start)
        else:
            start, short = self.start, replace(self.job, transient=max(1, self.job.transient // self.substeps),
                                               record=3, max_record=3)  # a ramp: never extended
            for j in range(1, self.substeps):
                r = short(self.value + (p - self.value) * j / self.substeps, start)
                if r.status != Status.OK:
                    return math.nan
                start = r.end_state
            r = self.job(p, start)
        if r.status != Status.OK:
            return math.nan
        if r.n_impacts > self.impacts:
            return -r.min_impact_speed
        self.value, self.start = p, r.end_state
        return r.min_clearance if self.impacts == 0 else r.min_flight_clearance
