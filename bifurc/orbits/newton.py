"""The one Newton acceptance rule of the orbit solver, the continuation corrector and the grazing solver.

The shooting residuals are integrated to a tolerance ``tol_int``; amplified by the orbit's multipliers they
have a noise floor that Newton cannot go below, often above the residual tolerance asked for near a
grazing or on a long unstable orbit.  A Newton iterate is accepted when

- its scaled residual is below ``tol``, or
- it is below ``NOISE_FACTOR`` tol and the iteration is at the floor: the Newton update asked for is below
  tol (the solution is as good as that update), or no step reduces the residual (it is noise).

Any other residual is a failure with its reason.  The accepted residual is stored with every point, so
a value accepted at the floor says so.
"""
from __future__ import annotations

import math

#: how far above tol a residual may be accepted at the integration's noise floor
NOISE_FACTOR = 100.0


def accept(norm: float, tol: float, *, update: float = math.inf, stalled: bool = False) -> bool:
    """True when the scaled residual ``norm`` is accepted under tolerance ``tol``, given the largest
    component of the Newton update asked for (scaled as the unknowns) and whether the iteration
    ``stalled`` (no step reduced the residual, or it no longer halves)."""
    if norm < tol:
        return True
    return norm < NOISE_FACTOR * tol and (update < tol or stalled)
