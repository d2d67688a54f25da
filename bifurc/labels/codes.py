"""The codes stored in datasets: orbit classes and integration status, one vocabulary.

Both are :class:`enum.IntEnum`: a code compares equal to the integer stored in a netCDF
file, and :func:`flag_attrs` gives the CF ``flag_values`` / ``flag_meanings`` of a variable
holding them, so storage, reports and plots read one definition.
"""
from __future__ import annotations

from enum import IntEnum

import numpy as np

class _Coded(IntEnum):
    @property
    def label(self) -> str:
        """Human label, e.g. "periodic-no-impact"."""
        return self.name.lower().replace("_", "-")

    @classmethod
    def of(cls, label: str):
        """The member with this label ("not-converged" -> NOT_CONVERGED)."""
        try:
            return cls[label.upper().replace("-", "_")]
        except KeyError:
            raise ValueError(f"{cls.__name__} {label!r}; allowed: {', '.join(m.label for m in cls)}") from None


class ClassCode(_Coded):
    """Class of a stroboscopic orbit, as datasets store it in ``class_code``: ``ds.class_code == ClassCode.CHAOTIC``
    selects the chaotic values; ``ClassCode(3).label`` is "chaotic"."""

    PERIODIC = 0
    PERIODIC_NO_IMPACT = 1
    QUASI_PERIODIC = 2
    CHAOTIC = 3
    NOT_CONVERGED = 4
    ESCAPED = 5
    FAILED = 6

    @property
    def periodic(self) -> bool:
        """Periodic, with or without impacts."""
        return self in (ClassCode.PERIODIC, ClassCode.PERIODIC_NO_IMPACT)


class Status(_Coded):
    """How the integration of one parameter value ended, as datasets store it in ``status``."""

    OK = 0
    ESCAPED = 1
    FAILED = 2


class Outcome(_Coded):
    """Where a census start went when it reached no attractor (attractor ids are 0, 1, ...; outcomes are
    negative): escaped; not converged at the budget; failed; "neutral", motion that dissipates nothing over its
    record, on which a start keeps its own amplitude; "transient", still on a chaotic saddle or long-lived chaotic
    transient at the budget (it is in chaotic motion there and will leave it)."""

    ESCAPED = -1
    NOT_CONVERGED = -2
    FAILED = -3
    NEUTRAL = -4
    TRANSIENT = -5

    @property
    def key(self) -> str:
        """The entry's name in a census and its dataset, e.g. "not_converged"."""
        return self.name.lower()

    @property
    def class_code(self) -> ClassCode:
        """The class code an attractors dataset stores for the outcome's entry."""
        return {Outcome.ESCAPED: ClassCode.ESCAPED, Outcome.FAILED: ClassCode.FAILED}.get(self, ClassCode.NOT_CONVERGED)


#: outcome name -> id, in the outcomes' order (the entries after the attractors in an attractors dataset)
OUTCOMES = {o.key: int(o) for o in Outcome}


def flag_attrs(codes: type[_Coded]) -> dict:
    """CF ``flag_values`` (int8) and ``flag_meanings`` (labels with "_" for "-") of an enum."""
    return {"flag_values": np.array([int(m) for m in codes], np.int8),
            "flag_meanings": " ".join(m.name.lower() for m in codes)}
