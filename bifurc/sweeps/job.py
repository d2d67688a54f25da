"""The work for one parameter value: orbit, classification, Lyapunov exponent, as a ValueResult.

:class:`ValueJob` is picklable, so it runs in any worker process (:mod:`bifurc.run.executor`);
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

from maps.hybrid import HybridState

from ..labels.anytime import BUDGET, TRAJECTORIES, Value
from ..labels.classify import candidate_periods, classify_orbit, mechanical_period, state_scale
from ..labels.codes import ClassCode, Status
from .method import record_cap, record_length

_MAPS: dict = {}      # (problem key, tol) -> the process-wide map


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
    period_mechanical: int = 0              # period of the mechanical states alone (0: not periodic)
    impacts_per_period_mechanical: int = -1  # impacts per mechanical period (-1: not periodic)
    period_difference: str = ""             # why the mechanical period differs from the full one ("": it does not)
    lyapunov_spread: float = math.nan       # standard deviation of the exponent between trajectories
    lyapunov_window: int = -1               # relay periods each trajectory's exponent is measured over (-1: none)
    lyapunov_trajectories: int = 0          # tangent trajectories the exponent comes from (0: none)
    rotation_number: float = math.nan       # a torus' rotation number per strobe period, in [0, 1/2] (NaN: none)
    zero_one_k: float = math.nan            # the 0-1 test's K on the window (NaN: not tested)
    budget_needed: int = 0                  # relay periods the evidence suggests (0: decided)
    periods_integrated: int = 0             # relay periods integrated for the value, its copies' included

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
    budget: int = BUDGET              # relay periods per value, transient included (anytime classification)
    trajectories: int = TRAJECTORIES  # tangent trajectories of the exponent (the value's own and its copies)
    deadline: float | None = None     # wall-clock time (time.time(), s) after which no value is extended

    #: the default workers keep at least this many values each (a worker's start and compilation cost ~1-2 s)
    points_per_worker = 16

    @property
    def planned_periods(self) -> int:
        """Periods a value runs before it is first judged (the progress bar's planned work per value)."""
        return self.transient + self.record

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
        return record_cap(self.record, self.max_record)

    def record_for(self, q: int) -> int:
        """Relay periods to record at a value whose forcing repeats every ``q`` periods (:func:`.method.record_length`)."""
        return record_length(self.record, q, self.max_period, self.record_cap)

    def x0_state(self):
        return self.problem.state_vector()

    def at(self, value) -> dict:
        """The parameter values of the grid point ``value`` (here ``param = value``)."""
        return dict(self.params, **{self.param: float(value)})

    def __call__(self, value, start=None) -> ValueResult:
        """Orbit and class at ``param = value``; ``start = (state, flags)`` overrides x0."""
        smap = self.warm().at(self.at(value))
        y0, flags = (self.x0_state(), self.problem.flags0) if start is None else start
        clock = _time.perf_counter()
        q = smap.forcing_period_steps
        o = smap.orbit(y0, self.record_for(q), transient=self.transient, flags=flags, tangent=self._tangent)
        v = self._value(smap, value, dict(smap.params), q, o, _time.perf_counter() - clock)
        self._anytime(smap, [v], "scalar")
        return self._pack(smap, v)

    @property
    def exponent_steps(self) -> int:
        """Map steps the Lyapunov exponent is estimated over at an unextended record (the
        recorded window by default; a value's own window: :meth:`_exponent_steps`)."""
        return self._exponent_steps(self.record)

    def _exponent_steps(self, record: int) -> int:
        return record if self.lyapunov_steps is None else self.lyapunov_steps

    @property
    def spent(self) -> int:
        """A value's budget [relay periods of its own trajectory, transient included]: ``budget``,
        at least ``max_transient`` + the record (the former extension's limit)."""
        extra = self.max_transient + self.record if self.max_transient is not None else 0
        return max(self.budget, extra, self.transient + self.record)

    def _scale(self, o):
        return state_scale(self._reduced(o), self.atol)

    def _reduced(self, o):
        """The orbit's samples in the reduced coordinates of a shift-invariant system (maps.translation):
        a rig that advances by the same amount every period repeats there."""
        return reduce_points(self.warm().system, o.points)

    @property
    def _tangent(self) -> bool:
        """Integrate a tangent vector with the record (the exponent's method)."""
        return self.lyapunov and self.lyapunov_method == "tangent"

    def _classify(self, o, q: int, **kw):
        """Classify orbit ``o`` of a map whose forcing repeats every ``q`` samples (0: never)."""
        return classify_orbit(self._reduced(o), o.impacts_per_step, max_period=self.max_period, rtol=self.rtol,
                              periods=candidate_periods(q, self.max_period),
                              atol=self.atol, status=o.status, **kw)

    def _stretch(self, smap, o, params, k0: int, scale) -> np.ndarray | None:
        """The log stretch per step along ``o`` (starting at sample ``k0``): its tangent vector's, or
        a companion's (``lyapunov_method="companion"``); None without exponents."""
        if not self.lyapunov or o.n == 0:
            return None
        if o.tangent_start is not None:
            return o.tangent_stretch(scale)
        return smap.stretch([o.points], [params], k0=[k0], scales=[scale], method="scalar")[0]

    def _value(self, smap, value, params, q, o, seconds) -> Value:
        v = Value(float(value), params, q, o, self.transient, seconds=seconds, steps=o.n_steps,
                  periods=self.transient + o.n)
        v.scale = self._scale(o)
        v.stretch = self._stretch(smap, o, params, self.transient, v.scale)
        return v

    def _judge(self, v: Value) -> None:
        from ..labels.anytime import judge
        mech = self.warm().system.mechanical_index

        def stretch_of(o):      # the stretch of the window or of a copy, kept in step with it
            return v.stretch[-o.n:] if o is v.orbit else v.copy_stretch[[id(c) for c in v.copies].index(id(o))][-o.n:]

        judge(v, classify=lambda o: self._classify(o, v.q), stretch=stretch_of, budget=self.spent,
              record=self.record_for(v.q), lyapunov=self.lyapunov,
              observable=lambda o: self._reduced(o)[:, mech] / v.scale[mech], max_period=self.max_period,
              trajectories=self.trajectories)

    def _anytime(self, smap, vs: list, method: str) -> None:
        """Judge every value; extend the undecided ones together until each is decided or out of budget."""
        for v in vs:
            self._judge(v)
        while True:
            todo = [v for v in vs if v.action is not None]
            if not todo:
                return
            if self.deadline is not None and _time.time() >= self.deadline:
                for v in todo:
                    _cut(v)
                return
            clock = _time.perf_counter()
            self._extend(smap, todo, method)
            share = (_time.perf_counter() - clock) / len(todo)
            for v in todo:
                v.seconds += share
                self._judge(v)

    def _extend(self, smap, todo: list, method: str) -> None:
        """One round: each value's own trajectory and its copies on by the periods it asked for; new
        copies start from its state perturbed, decorrelate, then record as much."""
        from maps.tangent import start_direction
        from ..labels.anytime import PERTURBATION
        d = len(smap.system.states)
        start = start_direction(d, translation_basis(smap.system))
        kw = dict(method=method, batch_size=self.batch_size, tangent=self._tangent)
        runs, jobs = [], []            # (value, which copy or None for its own trajectory, new?)
        for v in todo:
            n = v.action[1]
            jobs.append((v.params, v.orbit.final, n, v.end, v.orbit.tangent_direction))
            runs.append((v, None))
            for c, end in zip(v.copies, v.copy_ends):
                jobs.append((v.params, c.final, n, end, c.tangent_direction))
                runs.append((v, c))
        ext = self._orbits(smap, jobs, 0, start, kw)
        fresh, born = [], []
        for v in todo:
            for j in range(len(v.copies) + 1, v.action[2]):
                u = np.random.default_rng(j).standard_normal(d)
                y = v.orbit.final.y + PERTURBATION * v.scale * u / np.linalg.norm(u)
                fresh.append((v.params, HybridState(y, dict(v.orbit.final_flags)), v.action[1], v.end, start))
                born.append(v)
        new = self._copies(smap, fresh, born, start, kw)
        for (v, c), o in zip(runs, ext):
            v.steps += o.n_steps
            v.periods += o.n
            if c is None:
                extra = self._stretch(smap, o, v.params, v.end, v.scale) if o.status == "ok" else None
                v.orbit = v.orbit.then(o)
                v.stretch = None if extra is None or v.stretch is None else np.concatenate([v.stretch, extra])
                continue
            i = [id(x) for x in v.copies].index(id(c))
            extra = self._stretch(smap, o, v.params, v.copy_ends[i], v.scale) if o.status == "ok" else None
            if extra is None or v.copy_stretch[i] is None:     # a copy that left the domain: not the attractor
                del v.copies[i], v.copy_ends[i], v.copy_stretch[i]
                continue
            v.copies[i], v.copy_ends[i] = c.then(o), v.copy_ends[i] + o.n
            v.copy_stretch[i] = np.concatenate([v.copy_stretch[i], extra])
        for v, o, job in zip(born, new, fresh):
            v.steps += o.n_steps
            v.periods += v.decorrelate + o.n
            extra = self._stretch(smap, o, v.params, job[3] + v.decorrelate, v.scale) if o.status == "ok" else None
            if extra is not None:
                v.copies.append(o)
                v.copy_ends.append(job[3] + v.decorrelate + o.n)
                v.copy_stretch.append(extra)

    def _copies(self, smap, fresh: list, born: list, start, kw) -> list:
        """The new copies' orbits, each decorrelated over its value's periods before it is recorded
        (runs grouped by that length, results in the order of ``fresh``)."""
        out = [None] * len(fresh)
        for n in sorted({v.decorrelate for v in born}):
            idx = [i for i, v in enumerate(born) if v.decorrelate == n]
            for i, o in zip(idx, self._orbits(smap, [fresh[i] for i in idx], n, start, kw)):
                out[i] = o
        return out

    def _orbits(self, smap, jobs, transient: int, start, kw) -> list:
        """Orbits of ``jobs`` (params, hybrid start, steps, sample index, tangent direction or None)."""
        return smap.orbits([p for p, *_ in jobs], [s for _, s, *_ in jobs], [n for _, _, n, *_ in jobs],
                           k0=[k for *_, k, _ in jobs], transient=transient,
                           tangent_start=[t if t is not None else start for *_, t in jobs] if kw["tangent"] else None,
                           **kw)

    def _pack(self, smap, v: Value) -> ValueResult:
        """The ValueResult of a judged value: its window's first ``record`` samples and per-step rows,
        its window's impacts (the first ``max_impacts``), its class and evidence."""
        o, cls, lyap, used, steps, seconds, value = v.orbit, v.cls, v.lyap, v.start, v.steps, v.seconds, v.value
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
        mech = mechanical_period(self._reduced(o), o.impacts_per_step, cls["period"] if periodic else 0,
                                 smap.system.mechanical_index, rtol=self.rtol, atol=self.atol,
                                 impacts=cls["impacts_per_period"]) if o.status == "ok" else (0, -1, "")
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
            held_time=float(o.mode_time[keep - 1]) if o.mode_time is not None and len(o.mode_time) >= keep else math.nan,
            period_mechanical=mech[0], impacts_per_period_mechanical=mech[1], period_difference=mech[2],
            lyapunov_spread=v.spread, lyapunov_trajectories=v.trajectories if np.isfinite(lyap[0]) else 0,
            lyapunov_window=v.window if np.isfinite(lyap[0]) else -1,
            rotation_number=v.rotation, zero_one_k=v.zero_one, periods_integrated=v.periods,
            budget_needed=v.budget_needed if not periodic and
            ClassCode(cls["code"]) == ClassCode.NOT_CONVERGED else 0)

    # ----- many values at once: the map's ensemble method ----------------------------
    def run_many(self, values) -> list:
        """The same results as ``[self(v) for v in values]`` (up to round-off), with the orbits of
        every value integrated together by the map (:meth:`maps.StroboscopicMap.orbits`: heyoka's
        batch mode where the engine supports the system), the extensions of undecided values too."""
        smap = self.warm()
        if self.batch_size == 1:
            return [self(v) for v in values]
        clock = _time.perf_counter()
        over = [self.at(v) for v in values]
        qs = [smap.forcing_period_for(p) for p in over]
        orbits = smap.orbits(over, self.x0_state(), [self.record_for(q) for q in qs], transient=self.transient,
                             flags=self.problem.flags0, batch_size=self.batch_size, tangent=self._tangent)
        share = (_time.perf_counter() - clock) / max(1, len(values))
        vs = []
        for v, p, q, o in zip(values, over, qs, orbits):
            here = smap.at(p)
            vs.append(self._value(here, v, here.params, q, o, share))
        self._anytime(smap.at(over[-1]), vs, "auto")      # its jobs carry each value's parameters
        return [self._pack(smap.at(v.params), v) for v in vs]


def _cut(v) -> None:
    """A value the sweep's time budget stops before its evidence decides: not-converged, with why."""
    from ..labels.judge import undecided
    why = (v.cls or {}).get("reason") or "undecided"
    v.cls = undecided(v.cls or {}, f"cut by the sweep's time budget (--time-budget) at {v.end} relay periods: {why}")
    v.budget_needed = max(v.budget_needed, v.end + v.action[1])
    v.action = None
