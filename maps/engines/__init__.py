"""Engines that integrate orbit jobs of a hybrid system (see :mod:`maps.engines.base`).

``ENGINES`` names them; :func:`engine_for` returns the process-wide engine for a system
structure, tolerance and method (compiled once).
"""
from __future__ import annotations

from .base import Engine, OrbitJob, OrbitResult  # noqa: F401 - maps.OrbitJob etc. are read from here
from .batch import BatchEngine, unsupported
from .scalar import HybridRun, ScalarEngine

ENGINES = {"scalar": ScalarEngine, "batch": BatchEngine}
_CACHE: dict = {}


def engine_for(system, tol: float, method: str = "batch", *, batch_size: int = 4, observations: bool = True,
               max_events_per_period: int = 10_000, tangent: bool = False) -> Engine:
    """The process-wide engine of ``method`` ("scalar" or "batch") for this system structure and tolerance."""
    if method not in ENGINES:
        from ..parameters import ParameterError
        raise ParameterError(f"engine method {method!r}; allowed: {', '.join(ENGINES)}")
    key = (system.structure, float(tol), method, int(batch_size) if method == "batch" else 1,
           bool(observations), int(max_events_per_period), bool(tangent))
    eng = _CACHE.get(key)
    if eng is None:
        kw = dict(observations=observations, max_events_per_period=max_events_per_period)
        if method == "batch":
            kw["batch_size"] = batch_size
            kw["tangent"] = tangent
        elif tangent:
            from ..parameters import ParameterError
            raise ParameterError("tangent vectors run on the batch engine")
        eng = _CACHE[key] = ENGINES[method](system, tol, **kw)
    return eng
