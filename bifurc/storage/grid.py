"""Looking a stored dataset up: by grid value (refused outside the grid, a warning when the grid
value used is half a grid step or more from the one asked for) and by kind (one line naming the
kind a function needs)."""
from __future__ import annotations

import warnings

import numpy as np

from maps.parameters import ParameterError

#: round-off allowed at the grid's ends and in "half a step", relative to the grid step
SLACK = 1e-6


class OffGridWarning(UserWarning):
    """A lookup by value used a grid value half a grid step or more away from the one asked for."""


def nearest_index(grid, value, name: str, units: str = "") -> int:
    """Index of the grid value nearest to ``value`` (``name [units]`` in messages).

    Refuses (ParameterError) a value outside the grid's range; warns (:class:`OffGridWarning`) when the
    nearest grid value is half the grid step (the median spacing) or more away: a hole in an uneven
    grid, or a tie on an even one (8.5 Hz on a 0.2 Hz grid), where the value used is not the one asked for."""
    grid = np.asarray(grid, dtype=float).ravel()
    value = float(value)
    step = float(np.median(np.diff(np.unique(grid)))) if np.unique(grid).size > 1 else 0.0
    lo, hi, u = float(np.nanmin(grid)), float(np.nanmax(grid)), f" {units}" if units else ""
    if not lo - SLACK * step <= value <= hi + SLACK * step:
        raise ParameterError(f"{name} = {value:g}{u} is outside the grid ({grid.size} values from {lo:g} to "
                             f"{hi:g}{u}); choose a value in that range")
    i = int(np.nanargmin(np.abs(grid - value)))
    gap = abs(grid[i] - value)
    if step > 0 and gap >= 0.5 * step * (1 - SLACK):
        warnings.warn(f"{name} = {value:g}{u} is not on the grid (step {step:g}{u}); using the nearest "
                      f"grid value {grid[i]:g}{u}", OffGridWarning, stacklevel=3)
    return i


