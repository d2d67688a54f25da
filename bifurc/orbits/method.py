"""How periodic orbits are found and followed: :class:`Shooting` (Newton on the stroboscopic map) and :class:`PALC`
(pseudo-arclength continuation of the orbit found by shooting)."""
from __future__ import annotations

from dataclasses import dataclass

from ..run.settings import Settings, setting


def _period():
    return setting(None, "the orbit's period in strobe periods (relay periods for relay scenes), a multiple of the "
                   "forcing period q (default: q)", unit="strobe periods", low=1, high=1e6, whole=True, optional=True,
                   kind=int)


def _k0():
    return setting(None, "strobe sample index of the first guess (default: after the transient)", low=0, high=1e12,
                   whole=True, optional=True, kind=int)


def _transient():
    return setting(300, "strobe periods integrated from the start state to the first guess", unit="strobe periods",
                   low=0, high=1e7, whole=True)


def _tol():
    return setting(1e-12, "heyoka tolerance", low=0.0, high=1e-2, low_open=True)


def _newton_tol():
    return setting(None, "largest scaled shooting residual accepted (default 10 tol: the integration's own noise "
                   "bounds how far the residual can fall)", low=0.0, high=1.0, low_open=True, optional=True, kind=float)


def _error(what):
    return setting(True, f"solve again at tol/100 and store {what}", flag="--no-error")


@dataclass(frozen=True)
class Shooting(Settings):
    """A periodic orbit by Newton's method on the stroboscopic map (multiple shooting with one node per strobe
    period), its Floquet multipliers from the periodic Schur product of the nodes' Jacobians."""

    period: int | None = _period()
    k0: int | None = _k0()
    transient: int = _transient()
    tol: float = _tol()
    newton_tol: float | None = _newton_tol()
    max_iter: int = setting(40, "Newton iterations at most", low=1, high=10_000, whole=True)
    error: bool = _error("the multipliers' change (multiplier_error)")


@dataclass(frozen=True)
class PALC(Settings):
    """Pseudo-arclength continuation of the orbit found by :class:`Shooting`'s settings, through folds, stable and
    unstable parts alike; folds, period doublings, Neimark-Sacker points and grazings located on the way."""

    step: float = setting(0.02, "first arclength step, in the scaled unknowns (states by the orbit's magnitude, the "
                          "parameter by the span's length)", low=0.0, high=1.0, low_open=True)
    max_step: float = setting(0.1, "largest arclength step", low=0.0, high=10.0, low_open=True)
    max_points: int = setting(200, "branch points per branch at most", low=2, high=100_000, whole=True)
    branch_switch: bool = setting(False, "follow the doubled branch from each located period doubling")
    period: int | None = _period()
    k0: int | None = _k0()
    transient: int = _transient()
    tol: float = _tol()
    newton_tol: float | None = _newton_tol()
    error: bool = _error("each special point's multipliers' change, and locate it again: its stated tolerance is a "
                         "measured bound")

    def _check(self) -> None:
        if self.max_step < self.step:
            from maps.parameters import ParameterError
            raise ParameterError(f"max_step = {self.max_step:g} is below step = {self.step:g}")
