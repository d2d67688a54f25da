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

A value still undecided when its budget is spent is "not-converged" with its reason and the budget
its evidence suggests.  Each value's decisions depend on its own record only, so a sweep gives the
same dataset with any number of workers or batch lanes.  The budget counts relay (strobe) periods
of the value's own trajectory, transient included; its copies run alongside.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .codes import ClassCode
from .vocabulary import BUDGET, TRAJECTORIES
from .classify import DECAY_RATE, lyapunov_threshold
from .evidence import QP_SAMPLES, TORUS_K, exponent_estimate, halves_differ, torus_evidence
from .lyapunov import _student_t, exponent_interval

#: fewest periods a copy runs from its perturbed start before it is recorded (decorrelation)
DECORRELATE = 100
#: most periods a copy runs before it is recorded
MAX_DECORRELATE = 400
#: the shortest window on which a value is called chaotic or quasi-periodic [strobe periods] (the torus
#: test's samples).  Chaotic transients of the thesis model last hundreds to thousands of periods: on
#: the main job's grid 10 of 74 labels given on 200-400 periods changed on a 4x longer record from the
#: same attractor, and 7 of about 60 with this minimum at 800 (18 values then undecided at the budget)
MIN_WINDOW = 400
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
          max_period: int = 100, trajectories: int = TRAJECTORIES) -> None:
    """Set ``v.cls`` (the class on its current evidence) and ``v.action`` (the next extension, or
    None).  ``classify(orbit)``: the recurrence classification of a window; ``stretch(orbit)``: the
    log stretch per step of the window or of a copy; ``observable(orbit)``: the torus test's
    samples (N, d); ``trajectories``: how many tangent trajectories the exponent comes from."""
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
    if st is not None:       # the value's own exponent, until copies give one that holds across trajectories
        v.lyap, v.window = exponent_estimate(st[None, :])[:3], len(st)
    if math.isfinite(cls["convergence_rate"]) and cls["convergence_rate"] < DECAY_RATE:
        v.cls = cls
        v.action = ("extend", more, 1) if more > 0 else None
        v.budget_needed = 2 * v.end if more <= 0 else 0
        return
    why = halves_differ(st, o.impacts_per_step)
    if why:
        if more > 0:
            v.discard(half)
            v.cls, v.action = dict(cls, reason=why), ("extend", min(max(record, o.n), budget - v.end), 1)
            return
        v.cls = _undecided(cls, f"not stationary at the budget: {why}")
        v.budget_needed = 2 * v.end
        return
    if not lyapunov:
        v.cls = _undecided(cls, cls.get("reason") or "no period found and no exponent (lyapunov=False)")
        return
    _judge_exponent(v, cls, st, stretch, more, observable, max_period, budget, trajectories)


def _judge_exponent(v: Value, cls, own, stretch, more: int, observable, max_period: int = 100,
                    budget: int = BUDGET, trajectories: int = TRAJECTORIES) -> None:
    """The exponent's part of :func:`judge`: chaotic, quasi-periodic, or extend."""
    o = v.orbit
    if len(v.copies) + 1 < trajectories:     # the interval must hold across trajectories: copies first
        v.cls = _undecided(cls, "the exponent needs other trajectories on the same attractor (out of budget "
                                "before they could run)" if more <= 0 else "the exponent needs other trajectories")
        v.action = ("extend", more, trajectories) if more > 0 else None
        v.budget_needed = 0 if more > 0 else v.end + 2 * v.decorrelate
        return
    m = min([c.n for c in v.copies] + [o.n])
    rows = [own[-m:]] + [stretch(c)[-m:] for c in v.copies]
    mean, lo, hi, spread = exponent_estimate(np.vstack(rows))
    v.lyap, v.spread, v.trajectories, v.window = (mean, lo, hi), spread, len(rows), m
    thr = lyapunov_threshold(m)
    each = [exponent_interval(r) for r in rows]       # each trajectory's own batch-means interval
    common = mean_interval(each)                       # the 95 % interval of their common mean
    lo_all, hi_all = min(e[1] for e in each), max(e[2] for e in each)
    short = m < MIN_WINDOW and more > 0                # too short to call: extend first
    if not short and (all(e[1] > thr for e in each) or (all(e[0] > thr for e in each) and common[0] > thr)):
        # every trajectory separates (whatever their spread), or every one's exponent is above the threshold
        # and so is the 95 % interval of their common mean: chaos
        v.cls = _labelled(cls, "chaotic")
        if lo <= thr:   # the stored interval (another trajectory's) reaches the threshold: say what decided
            v.cls["reason"] = (f"chaotic on the evidence of {len(rows)} trajectories over {m} periods: "
                               + ("each one's exponent interval lies above the threshold" if all(e[1] > thr for e in each)
                                  else f"each exponent and their common mean's 95 % interval [{common[0]:.3g}, "
                                       f"{common[1]:.3g}] lie above the threshold")
                               + f" {thr:.3g}; another trajectory's exponent may lie in [{lo:.3g}, {hi:.3g}]")
        return
    if short:
        why, need = f"the window ({m} periods) is shorter than {MIN_WINDOW}", MIN_WINDOW
    elif -thr <= lo_all and hi_all <= thr and common[1] < 0:
        why = (f"contracting: the exponents' common mean lies below 0 (interval [{common[0]:.3g}, "
               f"{common[1]:.3g}]), a periodic orbit still converging rather than a torus")
        need = 2 * o.n
    elif -thr <= lo_all and hi_all <= thr:         # a torus has exponent 0: evidence of one is needed
        torus, why_not, v.zero_one, v.rotation = torus_evidence(observable(o), max_period)
        if torus:
            v.cls = _labelled(cls, "quasi-periodic")
            return
        why = f"the exponent's interval [{lo:.3g}, {hi:.3g}] lies within +-{thr:.3g} but {why_not}"
        need = max(QP_SAMPLES, 2 * o.n)
    elif hi_all < -thr:
        why = f"contracting (exponent {mean:.3g}, interval [{lo:.3g}, {hi:.3g}]) yet no period up to the maximum"
        need = 2 * o.n
    else:
        undecided = [e for e in each if e[1] <= thr and not (e[2] < -thr or (-thr <= e[1] and e[2] <= thr))]
        worst = max(undecided or each, key=lambda e: e[2] - e[1])
        near = min(abs(worst[0] - thr), abs(worst[0] + thr))
        why = (f"{len(undecided) or len(each)} of {len(each)} trajectories' exponent intervals contain a threshold "
               f"+-{thr:.3g} (widest [{worst[1]:.3g}, {worst[2]:.3g}])")
        need = int(min(1e7, m * ((worst[2] - worst[1]) / 2 / max(near, 1e-12)) ** 2)) if near > 0 else 10 ** 7
    v.cls = _undecided(cls, why)
    wanted = int(v.start + max(need, 2 * o.n))
    if more > 0 and (wanted <= HOPELESS * budget or v.end < budget // 2):
        v.action = ("extend", more, trajectories)
    else:                 # out of budget, or the evidence says the budget cannot decide it: stop here
        v.budget_needed = wanted


def mean_interval(each) -> tuple[float, float]:
    """95 % interval of the common mean of K trajectories' exponents, from their means' spread and
    their batch-means half-widths (each: (mean, low, high)), the wider."""
    means = np.array([e[0] for e in each])
    k = means.size
    half_between = _student_t(0.975, k - 1) * float(np.std(means, ddof=1)) / math.sqrt(k) if k > 1 else 0.0
    half_within = float(np.sqrt(np.mean([((e[2] - e[1]) / 2) ** 2 for e in each]))) / math.sqrt(k)
    half = max(half_between, half_within)
    return float(means.mean()) - half, float(means.mean()) + half


def _undecided(cls, why: str) -> dict:
    return dict(cls, code=ClassCode.NOT_CONVERGED, label="not-converged", impacts_per_period=-1, reason=why)


def _labelled(cls, label: str) -> dict:
    """``cls`` relabelled as a non-periodic class decided by the exponent."""
    return dict(cls, code=ClassCode.of(label), label=label, period=0, impacts_per_period=-1, reason="")
