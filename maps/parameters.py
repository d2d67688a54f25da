"""Named physical parameters with units and allowed ranges.

One table serves the model, the API, the command line and the datasets: a
parameter is addressed by its name everywhere (``k``, ``relay_hz``, ...).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

class ParameterError(ValueError):
    """A parameter name or value that the model cannot accept."""


@dataclass(frozen=True)
class Parameter:
    """A named scalar parameter.

    ``low``/``high`` bound the physically meaningful range; ``low_open`` /
    ``high_open`` make the bound strict (``m > 0`` rather than ``m >= 0``).
    """

    name: str
    unit: str
    long_name: str
    low: float = -math.inf
    high: float = math.inf
    low_open: bool = False
    high_open: bool = False

    def range_text(self) -> str:
        lo = "(" if self.low_open or math.isinf(self.low) else "["
        hi = ")" if self.high_open or math.isinf(self.high) else "]"
        return f"{lo}{self.low:g}, {self.high:g}{hi}"

    def validate(self, value) -> float:
        """Return ``value`` as a float or raise :class:`ParameterError` naming the parameter."""
        return validate_value(self.name, value, self.low, self.high, self.low_open,
                              self.high_open, self.unit, self.long_name)


def validate_value(name, value, low=-math.inf, high=math.inf, low_open=False,
                   high_open=False, unit="", long_name="") -> float:
    """Check one scalar against a range; the error names the parameter and the range."""
    if not isinstance(value, (str, bytes, bool)):
        try:
            x = float(value)
        except (TypeError, ValueError):
            x = None
        if x is not None and math.isfinite(x) and not (x <= low if low_open else x < low) \
                and not (x >= high if high_open else x > high):
            return x                # the common case: no message to build
    what = f"parameter {name!r}" + (f" ({long_name})" if long_name else "")
    if isinstance(value, (str, bytes, bool)) or x is None:
        raise ParameterError(f"{what} must be a number, got {value!r}")
    rng = Parameter(name, unit, long_name, low, high, low_open, high_open).range_text()
    units = f" {unit}" if unit and unit not in ("-", "1") else ""  # "1": dimensionless (CF)
    if not math.isfinite(x):
        raise ParameterError(f"{what} must be finite, got {x}; allowed range {rng}{units}")
    raise ParameterError(f"{what} = {x:g}{units} is outside its allowed range {rng}{units}")
