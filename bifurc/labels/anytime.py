"""Anytime classification: a value's record is extended where its evidence does not decide.

After the transient and the first record, every value is judged (:func:`judge`) on its window, the
stationary part of its record; undecided values are extended together, on the map's batch engine
(:meth:`maps.StroboscopicMap.orbits`), until each is decided or has spent its budget:

1. periodic on the window, or on its second half (then the first half was a transient and is
   discarded): **periodic**, with its period and impacts;
2. a recurrence that still decays geometrically: a transient approaching a periodic orbit, extend;
3. the window's halves differ (:func:`~bifurc.labels.evidence.halves_differ`): the first half is
   a transient or an intermittent burst: discard it, extend;
4. the exponent from K tangent trajectories (the value's own and K - 1 perturbed copies of its
   state, decorrelated over :attr:`Value.decorrelate` periods; :func:`~bifurc.labels.evidence.exponent_estimate`):
   an interval above the threshold: **chaotic**; within +-threshold with positive evidence of a
   torus (the 0-1 test's K below ``TORUS_K`` and a rotation number whose halves agree):
   **quasi-periodic**; below -threshold (contracting without a period up to ``max_period``) or
   containing a threshold: extend.

Steps 2-4 are the one judge's (:func:`bifurc.labels.judge.decide`), the census' too; this module keeps
the window (a periodic second half, a dropped first half), the copies and the budget.

A value still undecided when its budget is spent is "not-converged" with its reason and the budget
its evidence suggests.  Each value's decisions depend on its own record only, so a sweep gives the
same dataset with any number of workers or batch lanes.  The budget counts relay (strobe) periods
of the value's own trajectory, transient included; its copies run alongside.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .vocabulary import BUDGET, MAX_PERIOD, TRAJECTORIES
from .evidence import TORUS_K
from .judge import decide

#: fewest periods a copy runs from its perturbed start before it is recorded (decorrelation)
DECORRELATE = 100
#: most periods a copy runs before it is recorded
MAX_DECORRELATE = 400
#: a value whose evidence asks for more than this many budgets is not extended further (it cannot decide)
HOPELESS = 4
#: relative size of the copies' perturbations (of each state's scale).  A copy is another start on the
#: same attractor, not an infinitesimal one: it must have forgotten its origin before it is recorded, or
#: the copies share the value's intermittent phase and their spread underestimates the between-trajectory
#: one (9 Hz, 90 V, matlab-listing, 800-period window: copies perturbed by 1e-6 and run 100 periods gave a
#: spread of 0.0086 per period against 0.019 for 20 trajectories from other starts; by 1e-2, 0.017)
PERTURBATION = 1e-3
#: how values are classified (stored with every sweep)
ANYTIME_METHOD = ("anytime: judged on a stationary window (halves compared, a non-stationary first half discarded); "
                  "periodic by recurrence; otherwise extended, doubling, up to the budget with the method's "
                  "tangent trajectories (lyapunov_trajectories): chaotic when every trajectory's exponent interval "
                  "is above the threshold, quasi-periodic when within it with a torus (0-1 test K below "
                  f"{TORUS_K}, a converged rotation number not near a fraction with a recurring period)")


@dataclass
class Value:
    """One parameter value's evidence while it is judged."""

    value: float
    params: dict
    q: int
    orbit: object                    # MapOrbit: the judged window of the value's own trajectory
    start: int                       # sample index of orbit.points[0] (the transient used)
    seconds: float = 0.0
    steps: int = 0                   # Taylor steps, discarded parts included
    periods: int = 0                 # strobe periods integrated, the copies' included
    copies: list = field(default_factory=list)   # MapOrbits of the perturbed copies (their recorded parts)
    copy_ends: list = field(default_factory=list)   # sample index of each copy's last point
    copy_stretch: list = field(default_factory=list)  # each copy's log stretch per recorded step
    stretch: np.ndarray | None = None  # the window's log stretch per step (None: no exponent)
    scale: np.ndarray | None = None    # the state scale of the exponent's norm (the first record's)
    cls: dict | None = None
    lyap: tuple = (math.nan, math.nan, math.nan)
    spread: float = math.nan
    trajectories: int = 1
    window: int = 0                  # periods the exponent and its interval are measured over (0: none)
    rotation: float = math.nan
    zero_one: float = math.nan
    budget_needed: int = 0
    action: tuple | None = None      # ("extend", periods, copies wanted) or None (decided, or out of budget)

    @property
    def decorrelate(self) -> int:
        """Periods a new copy runs before it is recorded: twice the time its perturbation takes to grow
        to the state's scale at the value's own exponent, within [DECORRELATE, MAX_DECORRELATE]."""
        rate = self.lyap[0]
        if not (math.isfinite(rate) and rate > 0):
            return DECORRELATE
        return int(min(MAX_DECORRELATE, max(DECORRELATE, math.ceil(2 * math.log(1 / PERTURBATION) / rate))))

    @property
    def end(self) -> int:
        """The sample index of the window's last point."""
        return self.start + self.orbit.n

    def discard(self, k: int) -> None:
        """Drop the window's first ``k`` steps (a transient); the copies keep what overlaps."""
        self.orbit = self.orbit.since(k)
        self.stretch = None if self.stretch is None else self.stretch[k:]
        self.start += k
        cuts = [max(0, c.n - self.orbit.n) for c in self.copies]
        self.copies = [c.since(cut) for c, cut in zip(self.copies, cuts)]
        self.copy_stretch = [st[cut:] for st, cut in zip(self.copy_stretch, cuts)]


def judge(v: Value, *, classify, stretch, budget: int, record: int, lyapunov: bool, observable,
          max_period: int = MAX_PERIOD, trajectories: int = TRAJECTORIES) -> None:
    """Set ``v.cls`` (the class on its current evidence) and ``v.action`` (the next extension, or
    None).  ``classify(orbit)``: the recurrence classification of a window; ``stretch(orbit)``: the
    log stretch per step of the window or of a copy; ``observable(orbit)``: the torus test's
    samples (N, d); ``trajectories``: how many tangent trajectories the exponent comes from.  The
    label itself is the one judge's (:func:`bifurc.labels.judge.decide`); this keeps the window: a
    periodic second half, a non-stationary first half dropped, copies, the budget."""
    o = v.orbit
    v.action = None
    cls = classify(o)
    if o.status != "ok" or cls["label"] in ("periodic", "periodic-no-impact", "escaped", "failed"):
        v.cls = cls
        return
    half = o.n // 2
    if half >= max(3, record // 2):
        cut = min(half, max(0, o.n - record))     # the later part, at least a record long (the stored samples)
        late = classify(o.since(cut)) if cut else cls
        if cut and late["label"] in ("periodic", "periodic-no-impact"):
            v.discard(cut)
            v.cls = late
            return
    left = budget - v.end
    more = min(max(record, o.n), left)
    st = stretch(o) if lyapunov else None
    rows = [st] + [stretch(c) for c in v.copies] if st is not None else []
    verdict = decide(cls, o.impacts_per_step, rows, lambda: observable(o), can_extend=more > 0,
                     max_period=max_period, trajectories=trajectories)
    v.cls = verdict.cls
    if verdict.lyap is not None:
        v.lyap, v.window = verdict.lyap, verdict.window
    if verdict.spread is not None:
        v.spread, v.trajectories = verdict.spread, verdict.trajectories
    if verdict.zero_one is not None:
        v.zero_one, v.rotation = verdict.zero_one, verdict.rotation
    if verdict.rule == "decay":
        v.action = ("extend", more, 1) if more > 0 else None
        v.budget_needed = 2 * v.end if more <= 0 else 0
    elif verdict.rule == "stationary":
        if verdict.wants:
            v.discard(half)
            v.action = ("extend", min(max(record, o.n), budget - v.end), 1)
        else:
            v.budget_needed = 2 * v.end
    elif verdict.rule == "trajectories":
        v.action = ("extend", more, trajectories) if more > 0 else None
        v.budget_needed = 0 if more > 0 else v.end + 2 * v.decorrelate
    elif verdict.rule == "exponent" and verdict.label == "not-converged":
        wanted = int(v.start + max(verdict.need, 2 * o.n))
        if more > 0 and (wanted <= HOPELESS * budget or v.end < budget // 2):
            v.action = ("extend", more, trajectories)
        else:             # out of budget, or the evidence says the budget cannot decide it: stop here
            v.budget_needed = wanted
