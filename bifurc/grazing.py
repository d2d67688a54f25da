"""Locating grazing parameter values by bisection on a signed clearance."""
from __future__ import annotations

import math

from maps.parameters import ParameterError

__all__ = ["locate_grazing", "GRAZING_GAP", "GRAZING_SPEED"]

#: an orbit grazes when its smallest clearance is below GRAZING_GAP [m] without contact,
#: or its slowest impact is below GRAZING_SPEED [m/s]
GRAZING_GAP = 1e-6
GRAZING_SPEED = 1e-3


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
