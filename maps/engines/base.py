"""The engine interface: integrate orbit jobs of a hybrid system, return their samples.

In the spirit of scipy's ``OdeSolver``: a small base class and one implementation per way
of integrating (:mod:`maps.engines.scalar`: one trajectory at a time; :mod:`maps.engines.batch`:
heyoka's batch mode, several parameter sets per SIMD pass).  Both take every transition rule
from :mod:`maps.transitions`, so they produce the same event sequence and states (to
round-off; ``tests/test_engines.py`` runs both on the same problems).

A job samples the state at t_k = ``offset`` + k ``period`` [s] (k / ``rate`` when the rate is
given, so that samples fall exactly on relay switch instants): it starts at sample ``k0``,
integrates ``transient`` periods, then records the states at the next ``record + 1`` sample
times and, with ``log``, every guard crossing in between.  A job with a ``reference`` (the
``record + 1`` states of another orbit at the same sample times) is a *companion*: after each
recorded period it is moved back to distance ``d0`` (norm scaled by ``scale``) from the
reference (in the reduced coordinates of a shift-invariant system: ``shift``), and the log of each
period's stretch is returned (the tangent direction of Benettin's method; the exponent itself is
analysis, :mod:`bifurc.labels.lyapunov`).  A job with a ``tangent`` start direction, on an engine that
carries tangent vectors, also returns the tangent vector integrated with the flow over each
recorded period (:mod:`maps.tangent`).  A job with a ``timed`` mode (flag, value) also returns the
time spent in that mode from the first recorded sample to each recorded sample (e.g. the time the
soil holds the rig, :func:`maps.progression.held_mode`).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

@dataclass
class OrbitJob:
    """One trajectory to integrate (see the module docstring)."""

    params: dict                      # validated parameter values
    y0: np.ndarray                    # continuous state at sample k0
    flags: dict | None = None         # flags at the start (None: the system's rule)
    period: float = 1.0               # [s] sampling period T
    offset: float = 0.0               # [s] t_k = offset + k T
    rate: float | None = None         # [Hz] 1/T exactly when known (a relay frequency): t_k = offset + k / rate,
                                      # computed as the relay's own switch instants are
    k0: int = 0
    transient: int = 0
    record: int = 1
    log: bool = False
    reference: list | None = None     # companion: the reference orbit's record + 1 states
    d0: float = 1e-8
    scale: np.ndarray | None = None
    tangent: np.ndarray | None = None  # start direction of a tangent vector over the record (engines that carry one)
    shift: tuple | None = None        # companion: (translation, anchor) removed before each renormalisation
    timed: tuple | None = None        # (flag, value): the mode whose time within the record is measured

    def sample_time(self, k: int) -> float:
        return self.offset + (k / self.rate if self.rate is not None else k * self.period)


@dataclass
class OrbitResult:
    """What a job produced: the recorded samples (the first at the end of the transient),
    their flags, each recorded period's guard crossings ``(name, t, y_minus)``, the status
    (ok, escaped, failed) and counters; companions: ``stretch`` (log growth per period)."""

    times: list = field(default_factory=list)
    points: list = field(default_factory=list)
    flags: list = field(default_factory=list)
    period_events: list = field(default_factory=list)
    tail_events: list = field(default_factory=list)
    status: str = "ok"
    failure: str = ""
    failure_time: float = math.nan
    final_time: float = 0.0
    final_state: np.ndarray | None = None
    final_flags: dict = field(default_factory=dict)
    n_steps: int = 0
    n_events: int = 0
    n_switches: int = 0
    seconds: float = 0.0
    stretch: list = field(default_factory=list)
    tangent: list = field(default_factory=list)   # the tangent vector at the end of each recorded period
    mode_time: list = field(default_factory=list)  # [s] time in the job's ``timed`` mode from the first recorded
                                                   # sample to each recorded sample (empty: no mode timed)
    point_flags: np.ndarray | None = None   # the flags at each sample as an array (columns: the system's
                                            # flag_names), where the engine has them so (else read from ``flags``)


class Engine:
    """Integrates :class:`OrbitJob` s of one system at one tolerance.

    Subclasses implement :meth:`run`.  ``max_events_per_period`` caps the events in any one
    sampling (or relay) period: more end the job with status "failed" (chattering or a
    runaway).  ``observations=False`` lets an engine skip stops at guards that only observe
    (no logged crossings are then complete: use it for transients)."""

    name = "base"

    def __init__(self, system, tol: float, *, max_events_per_period: int = 10_000,
                 observations: bool = True):
        self.system, self.tol = system, float(tol)
        self.max_events_per_period = max_events_per_period
        self.observations = observations

    def run(self, jobs: list[OrbitJob]) -> list[OrbitResult]:  # pragma: no cover - interface
        raise NotImplementedError
