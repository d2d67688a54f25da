"""The work for one parameter value: orbit, classification, Lyapunov exponent, as a ValueResult.

:class:`ValueJob` is picklable, so it runs in any worker process (:mod:`bifurc.sweeps.executor`);
calling it with a value returns a :class:`ValueResult`, whose fields are named as the
sweep dataset's variables (:mod:`bifurc.storage.schema`).
"""
from __future__ import annotations

import math
import time as _time
from dataclasses import dataclass

import numpy as np

from maps.poincare import StroboscopicMap
from maps.problem import Problem
from maps.translation import reduce_points, translation_basis

from .classify import DECAY_RATE, candidate_periods, classify_orbit, lyapunov_threshold, state_scale
from ..codes import ClassCode, Status
from .lyapunov import exponent_interval, largest_lyapunov

__all__ = ["ValueJob", "ValueResult", "RECORD_FACTOR", "FORCING_PERIODS"]

_MAPS: dict = {}      # (problem key, tol) -> the process-wide map
#: default cap of the record extension, in multiples of ``record`` (3 x 100 periods holds three forcing
#: periods of every q up to the default max_period of 100)
RECORD_FACTOR = 3
#: whole forcing periods q the record must hold before the period search (two for the recurrence
#: test of period q, one more for its decay fit); a shorter record is extended up to ``max_record``
FORCING_PERIODS = 3


@dataclass
class ValueResult:
    """Everything computed at one parameter value (arrays padded to the job's record and impact sizes).

    Units: gaps [m], speeds [m/s], times [s], ``lyapunov`` [1/relay period], ``run_seconds`` [s].
    """

    value: float
    points: np.ndarray                      # (record + 1, states) stroboscopic samples, NaN after an escape
    point_flags: np.ndarray                 # (record + 1, flags) the mode at each sample, NaN after an escape
    record_used: int                        # relay periods recorded and classified (extended for a long q;
                                            # fewer after an escape); ``points`` keeps the first ``record``
    class_code: ClassCode
    period: int                             # period n of the orbit in relay periods (0: not periodic)
    candidate_period: int                   # period of the best recurrence candidate (0: none)
    impacts_per_period: int                 # impacts per period m (-1: not periodic)
    recurrence: float                       # scaled recurrence distance at the candidate period
    convergence_rate: float                 # fitted per-period decay of that distance
    lyapunov: float                         # NaN: not computed
    lyapunov_low: float                     # 95 % interval of the exponent (NaN: none)
    lyapunov_high: float
    class_reason: str                       # why a value is not-converged ("" otherwise)
    forcing_period: int                     # forcing period in relay periods (0: incommensurate)
    impacts_per_step: np.ndarray            # (record,) contacts per recorded period, -1: not reached
    min_clearance_per_step: np.ndarray            # (record,)
    min_impact_speed_per_step: np.ndarray   # (record,)
    min_clearance: float
    min_flight_clearance: float
    min_impact_speed: float
    impact_time: np.ndarray                    # (max_impacts,) NaN-padded
    impact_velocity: np.ndarray
    impact_phase: np.ndarray
    impact_penetration: np.ndarray
    impact_duration: np.ndarray
    n_impacts: int
    status: Status
    failure_time: float
    failure: str
    n_steps: int
    transient_used: int
    run_seconds: float                      # time spent on this value (a batch's share, plus its own extension)
    final_state: np.ndarray
    final_flags: dict
    held_time: float = math.nan             # [s] time the soil holds the rig over the stored samples (NaN: no soil)

    @property
    def label(self) -> str:
        """Class label, e.g. "periodic-no-impact"."""
        return ClassCode(self.class_code).label

    @property
    def end_state(self):
        """``(final_state, final_flags)``: the start of a value that follows this one."""
        return self.final_state, self.final_flags


@dataclass(frozen=True)
class ValueJob:
    """The work for one parameter value (picklable, so it runs in any worker process).

    Calling it with a value returns a :class:`ValueResult`: the recorded orbit, its
    impacts, clearance, classification and run time.
    """

    problem: Problem  # what is integrated (scene, options, values, start): maps.problem
    param: str
    transient: int = 300
    record: int = 100
    tol: float = 1e-10
    max_period: int = 100   # cap of the period search [relay periods]; candidates are multiples of q
    rtol: float = 1e-6
    atol: float = 1e-9
    lyapunov: bool = True
    lyapunov_steps: int | None = None   # steps of the exponent (None: the whole recorded window)
    max_impacts: int = 400
    max_transient: int | None = None  # extend a still-converging transient up to this [relay periods]
    batch_size: int = 4               # SIMD lanes of run_many (heyoka batch mode); 1: scalar path
    max_record: int | None = None   # cap of the record extension [relay periods] (None: RECORD_FACTOR x record)
    lyapunov_method: str = "tangent"  # "tangent": a tangent vector with the batch engine's record; "companion"

    @property
    def params(self) -> dict:
        """The problem's parameter values (the swept one is set per value: :meth:`at`)."""
        return self.problem.values

    @property
    def x0(self) -> dict:
        """The start state {name: value} [SI]."""
        return self.problem.x0

    @property
    def scene(self):
        """The problem's scene."""
        return self.problem.scene

    def warm(self) -> StroboscopicMap:
        """The process-wide map for this problem's model and tolerance (compiled once)."""
        key = (self.problem.key, self.tol)
        if key not in _MAPS:
            _MAPS[key] = StroboscopicMap(self.problem, tol=self.tol)
        return _MAPS[key]

    @property
    def record_cap(self) -> int:
        """The longest record of a value [relay periods]: ``max_record``, else RECORD_FACTOR x ``record``."""
        return self.max_record if self.max_record is not None else RECORD_FACTOR * self.record

    def record_for(self, q: int) -> int:
        """Relay periods to record at a value whose forcing repeats every ``q`` periods: ``record``,
        extended to FORCING_PERIODS x q (never beyond :attr:`record_cap`) when the period search
        has candidates (0 < q <= max_period) and the record holds fewer than FORCING_PERIODS of them."""
        if 0 < q <= self.max_period and self.record < FORCING_PERIODS * q:
            return max(self.record, min(FORCING_PERIODS * q, self.record_cap))
        return self.record

    def x0_state(self):
        return self.problem.state_vector()

    def at(self, value) -> dict:
        """The parameter values of the grid point ``value`` (here ``param = value``)."""
        return dict(self.params, **{self.param: float(value)})

    def __call__(self, value, start=None) -> ValueResult:
        """Orbit and class at ``param = value``; ``start = (state, flags)`` overrides x0."""
        smap = self.warm()
        smap.set_params(**self.at(value))
        y0, flags = (self.x0_state(), self.problem.flags0) if start is None else start
        clock = _time.perf_counter()
        o = smap.orbit(y0, self.record_for(smap.forcing_period_steps), transient=self.transient, flags=flags,
                       tangent=self._tangent)
        return self._complete(value, smap, o, clock)

    @property
    def exponent_steps(self) -> int:
        """Map steps the Lyapunov exponent is estimated over at an unextended record (the
        recorded window by default; a value's own window: :meth:`_exponent_steps`)."""
        return self._exponent_steps(self.record)

    def _exponent_steps(self, record: int) -> int:
        return record if self.lyapunov_steps is None else self.lyapunov_steps

    def _lyapunov_needed(self, o, cls) -> bool:
        return self.lyapunov and o.status == "ok" and not ClassCode(cls["code"]).periodic

    def _lyapunov_scale(self, o):
        return state_scale(self._reduced(o), self.atol)

    def _reduced(self, o):
        """The orbit's samples in the reduced coordinates of a shift-invariant system (maps.translation):
        a rig that advances by the same amount every period repeats there."""
        return reduce_points(self.warm().system, o.points)

    @property
    def _tangent(self) -> bool:
        """Integrate a tangent vector with the record (the exponent's method)."""
        return self.lyapunov and self.lyapunov_method == "tangent"

    def _tangent_exponent(self, o, steps: int):
        """(exponent, low, high) over the first ``steps`` of the tangent vector integrated with ``o``
        (None: none was, or the record is shorter)."""
        st = o.tangent_stretch(self._lyapunov_scale(o))
        return None if st is None or steps > st.size else exponent_interval(st[:steps])

    def _classify(self, o, q: int, **kw):
        """Classify orbit ``o`` of a map whose forcing repeats every ``q`` samples (0: never)."""
        return classify_orbit(self._reduced(o), o.impacts_per_step, max_period=self.max_period, rtol=self.rtol,
                              periods=candidate_periods(q, self.max_period),
                              atol=self.atol, status=o.status, **kw)

    def _complete(self, value, smap, o, clock, lyap=None, seconds=None, cls=None) -> ValueResult:
        """Classification (integrating on while still converging, up to ``max_transient``), the
        Lyapunov exponent where not periodic (``lyap``: already computed along ``o``), packing.
        ``cls``: ``o``'s classification without an exponent, if already made.  The value's run
        time is the time since ``clock``, plus ``seconds`` already spent on it (a batch's share)."""
        used, steps = self.transient, o.n_steps
        q = smap.forcing_period_steps        # smap holds this value's parameters
        record = self.record_for(q)
        cls = self._classify(o, q) if cls is None else cls
        limit = self.max_transient if self.max_transient is not None else self.transient
        while self._extends(o, cls, used):  # still converging: integrate on
            extra = max(1, min(used, limit - used))  # doubling, up to the limit
            o = smap.orbit(o.final_state, record, transient=extra, flags=o.final_flags,
                           t0=smap.sample_time(used + record) - smap.sample_time(0), tangent=self._tangent)
            used, steps, lyap = used + record + extra, steps + o.n_steps, None
            cls = self._classify(o, q)
        steps_l = self._exponent_steps(record)
        if self._lyapunov_needed(o, cls):
            if lyap is None:
                scale = self._lyapunov_scale(o)
                lyap = self._tangent_exponent(o, steps_l)
                if lyap is None and steps_l <= record:    # the companion along the recorded window
                    lyap = exponent_interval(smap.stretch([o.points[:steps_l + 1]], [{}], k0=[used],
                                                          scales=[scale], method="scalar")[0])
                elif lyap is None:                        # two trajectories after it (no interval)
                    lyap = (largest_lyapunov(smap.step, o.final_state, steps_l, scale=scale,
                                             k0=used + record, shift=translation_basis(smap.system)),
                            math.nan, math.nan)
            cls = self._classify(o, q, lyapunov=lyap[0], lyap_tol=lyapunov_threshold(steps_l),
                                 lyapunov_interval=lyap[1:])
        else:
            lyap = (math.nan, math.nan, math.nan)
        return self._pack(value, smap, o, cls, lyap, used, steps, _time.perf_counter() - clock + (seconds or 0.0))

    def _pack(self, value, smap, o, cls, lyap, used, steps, seconds) -> ValueResult:
        cap = self.max_impacts
        pad = lambda a: np.concatenate([a[:cap], np.full(max(0, cap - a.size), np.nan)])  # noqa: E731
        keep = min(o.points.shape[0], self.record + 1)       # an extended record: its first ``record`` steps
        points = np.full((self.record + 1, o.points.shape[1]), np.nan)
        points[:keep] = o.points[:keep]
        point_flags = np.full((self.record + 1, len(o.flag_names)), np.nan)
        if o.point_flags is not None:
            point_flags[:keep] = o.point_flags[:keep]
        gaps = o.min_clearance_per_step
        speeds = o.min_impact_speed_per_step
        per_step = lambda a, fill: np.pad(a[:self.record], (0, max(0, self.record - a.size)),  # noqa: E731
                                          constant_values=fill)
        periodic = ClassCode(cls["code"]).periodic
        return ValueResult(
            value=float(value), points=points, point_flags=point_flags, record_used=o.n, class_code=ClassCode(cls["code"]),
            period=cls["period"] if periodic else 0, candidate_period=cls["period"],
            impacts_per_period=cls["impacts_per_period"], recurrence=cls["recurrence"],
            convergence_rate=cls["convergence_rate"], lyapunov=lyap[0], lyapunov_low=lyap[1], lyapunov_high=lyap[2],
            class_reason=cls.get("reason", ""), forcing_period=smap.forcing_period_steps,
            impacts_per_step=per_step(o.impacts_per_step, -1), min_clearance_per_step=per_step(gaps, np.nan),
            min_impact_speed_per_step=per_step(speeds, np.nan),
            min_clearance=float(np.min(gaps)) if gaps.size else math.nan,
            min_flight_clearance=float(np.min(o.min_flight_clearance_per_step)) if gaps.size else math.nan,
            min_impact_speed=float(np.min(speeds)) if speeds.size else math.nan,  # NaN: no step recorded
            impact_time=pad(o.impact_time), impact_velocity=pad(o.impact_velocity), impact_phase=pad(o.impact_phase),
            impact_penetration=pad(o.impact_penetration), impact_duration=pad(o.impact_duration),
            n_impacts=o.impact_time.size, status=Status.of(o.status), failure_time=o.failure_time,
            failure=o.failure, n_steps=steps, transient_used=used, run_seconds=seconds,
            final_state=o.final_state, final_flags=o.final_flags,
            held_time=float(o.mode_time[keep - 1]) if o.mode_time is not None and len(o.mode_time) >= keep else math.nan)

    # ----- many values at once: the map's ensemble method ----------------------------
    def run_many(self, values) -> list:
        """The same results as ``[self(v) for v in values]`` (up to round-off), with the orbits of
        every value integrated together by the map (:meth:`maps.StroboscopicMap.orbits`: heyoka's
        batch mode where the engine supports the system).  The Lyapunov exponent comes from the
        tangent vector integrated with each recorded window (``lyapunov_method="tangent"``),
        else from companions (``StroboscopicMap.stretch``).  Values that are still converging
        and may integrate on (``max_transient``) continue one by one."""
        smap = self.warm()
        if self.batch_size == 1:
            return [self(v) for v in values]
        clock = _time.perf_counter()
        over = [self.at(v) for v in values]
        qs = [smap.forcing_period_for(p) for p in over]
        records = [self.record_for(q) for q in qs]
        orbits = smap.orbits(over, self.x0_state(), records, transient=self.transient,
                             batch_size=self.batch_size, tangent=self._tangent)
        classes = [self._classify(o, q) for o, q in zip(orbits, qs)]
        lyap = [None] * len(values)
        want = [i for i, (o, cls) in enumerate(zip(orbits, classes))
                if self._lyapunov_needed(o, cls) and self._exponent_steps(records[i]) <= records[i]
                and not self._extends(o, cls)]
        for i in want:                                    # the tangent vector integrated with the record
            lyap[i] = self._tangent_exponent(orbits[i], self._exponent_steps(records[i]))
        want = [i for i in want if lyap[i] is None]       # else the companions (the cross-check)
        if want:
            stretch = smap.stretch([orbits[i].points[:self._exponent_steps(records[i]) + 1] for i in want],
                                   [over[i] for i in want], k0=[self.transient] * len(want),
                                   scales=[self._lyapunov_scale(orbits[i]) for i in want],
                                   batch_size=self.batch_size)
            for i, st in zip(want, stretch):
                lyap[i] = exponent_interval(st)
        share = (_time.perf_counter() - clock) / max(1, len(values))
        out = []
        for v, p, o, lam, cls in zip(values, over, orbits, lyap, classes):
            smap.set_params(**p)
            out.append(self._complete(v, smap, o, _time.perf_counter(), lyap=lam, seconds=share, cls=cls))
        return out

    def _extends(self, o, cls, used=None) -> bool:
        """Still converging and allowed to integrate on (``max_transient``) after ``used`` periods."""
        used = self.transient if used is None else used
        limit = self.max_transient if self.max_transient is not None else self.transient
        return (o.status == "ok" and cls["label"] == "not-converged" and used < limit
                and cls["convergence_rate"] < DECAY_RATE)
