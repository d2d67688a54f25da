"""One judge: the label of a record on its evidence, for the diagram, the regime map and the census.

:func:`decide` takes what a record shows (its recurrence class, the impacts per step of its window, the log stretch
per step of however many tangent trajectories it has, its torus samples) and whether the caller can still lengthen
it, and returns a :class:`Verdict`: the label, its reason, and what more evidence is needed.  The diagram's anytime
judge (:func:`bifurc.labels.anytime.judge`, which keeps its window management: discarding a transient, asking for
copies, the budget) and the census (:func:`bifurc.attractors.identify.identify`, which keeps Newton polishing and
grid matching) both call it, so a record gets one label whichever analysis met it (tests/test_one_judge.py).

The rules, in order (``thr`` = :func:`~bifurc.labels.classify.lyapunov_threshold` of the common window m):

1. periodic by recurrence (or escaped, failed): that class;
2. a recurrence still decaying geometrically (rate below ``DECAY_RATE``): a transient, a longer record;
3. the window's halves differ (:func:`~bifurc.labels.evidence.halves_differ`): not stationary, its first half is
   dropped and the record lengthened;
4. fewer tangent trajectories than wanted: more trajectories;
5. a window shorter than ``MIN_WINDOW`` while the record can be lengthened: a longer record (for a chaotic label,
   unless the caller tests the set's lifetime itself: the census);
6. **chaotic** when every trajectory's batch-means interval lies above ``thr``, or every exponent and the 95 %
   interval of their common mean (:func:`mean_interval`) do;
7. every interval within +-thr: contracting (common mean's interval below 0), else **quasi-periodic** only with
   positive torus evidence (:func:`~bifurc.labels.evidence.torus_evidence`, at least ``QP_SAMPLES`` samples);
8. otherwise (contracting without a period, an interval containing a threshold): a longer record.

Where the diagram's and the census' rules differed before this function (issue 45 section 2), the stricter one was
kept, each for a measured reason:

- a decaying recurrence (2) and halves that differ (3) ask for more evidence even where the exponent is positive:
  the census called such a record chaotic (a chaotic record's recurrence distance can trend down over a short
  window by chance, but so does a transient's on its way to an orbit; the diagram's rule lets the longer record
  decide);
- a chaotic label needs a window of ``MIN_WINDOW`` periods while the record can grow (the diagram's rule: on the
  main job's grid 10 of 74 labels given on 200-400 periods changed on a 4x longer record), unless the caller tests
  the set's persistence itself: the census calls a set chaotic from 48 periods (bound 0.16), and a new chaotic set
  is an attractor only if its mean lifetime's interval lies above ``persist`` (4000) periods, a stricter test of a
  chaotic transient than the window floor.  Applied to the census too, the floor cost more than twice its CPU
  seconds at 120 V (63 s and still running against 29.6 s, 100 box starts: every wandering start is recorded 48 +
  96 + 192 + 384 + 768 periods before the first can be called; benchmarks/reports/one-judge.md);
- a torus needs every exponent interval within +-thr: the census also accepted an exponent within the threshold
  whose interval reached above it (its torus evidence deciding), which does not exclude chaos: a weakly chaotic
  set's interval reaches above the threshold too, and the longer record decides (thesis-1dof, `listing` law,
  80 V: then "not_converged" at the census' budget, as the diagram has it);
- a torus needs a window of ``MIN_WINDOW`` periods while the record can grow (the diagram's floor) where the census
  had its own of 768 (QP_RECORD; thesis-1dof, `matlab-listing`, `measured`, 10 Hz, 179.5 V: a set read
  quasi-periodic over 48 periods is chaotic over 384, benchmarks/reports/attractors-recovery/undecided-*).  On the
  census' records, 48 periods doubled, the first at or above 400 is 768, so its torus labels stay where they were;
  the census' 768 on the diagram moved the main job's quasi-periodic value at 9.8 Hz from a 588-period window to
  1176 (label unchanged), against its bit-identity (benchmarks/reports/one-judge.md).

The census judges one trajectory per record (``trajectories`` = 1): its starts are independent trajectories, and a
new non-periodic set must also persist (its lifetime test) before it is listed as an attractor.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .classify import DECAY_RATE, lyapunov_threshold
from .codes import ClassCode
from .evidence import QP_SAMPLES, exponent_estimate, halves_differ, torus_evidence
from .lyapunov import _student_t, exponent_interval

#: the shortest window on which a record is called chaotic or quasi-periodic while it can still be lengthened
#: [strobe periods].  Chaotic transients of the thesis model last hundreds to thousands of periods: on the main
#: job's grid 10 of 74 labels given on 200-400 periods changed on a 4x longer record from the same attractor, and
#: 7 of about 60 with this minimum at 800 (18 values then undecided at the budget)
MIN_WINDOW = 400

PERIODIC = ("periodic", "periodic-no-impact")


@dataclass
class Verdict:
    """What :func:`decide` made of a record.

    ``cls``: the class dict on this evidence (``label``, ``code``, ``period``, ``impacts_per_period``, ``reason``,
    the recurrence numbers).  ``wants``: "" (decided, or nothing more can decide it), "longer" (a longer record),
    "stationary" (its first half dropped, then a longer record) or "trajectories" (more tangent trajectories).
    ``rule``: which rule of :func:`decide` gave it ("class", "decay", "stationary", "no-exponent",
    "trajectories", "exponent").  ``need``: the window [periods] the evidence asks for (0: not stated).
    ``lyap`` (mean, low, high) with its
    ``window`` and, once the trajectories are compared, ``spread`` and ``trajectories``; ``zero_one`` and
    ``rotation`` once a torus was tested (None: not reached)."""

    cls: dict
    rule: str
    wants: str = ""
    need: int = 0
    lyap: tuple | None = None
    window: int = 0
    spread: float | None = None
    trajectories: int = 0
    zero_one: float | None = None
    rotation: float | None = None

    @property
    def label(self) -> str:
        return self.cls["label"]

    @property
    def reason(self) -> str:
        return self.cls.get("reason", "")


def decide(cls: dict, impacts, rows, samples, *, can_extend: bool, max_period: int, trajectories: int = 1,
           lifetime_tested: bool = False) -> Verdict:
    """The label of a record (module docstring).  ``cls``: its recurrence class
    (:func:`~bifurc.labels.classify.classify_orbit` without an exponent); ``impacts``: impacts per step of its
    window; ``rows``: the log stretch per step of each tangent trajectory, the record's own first (its whole window),
    the others over their recorded parts (all are compared over their common last m steps); empty or None: no
    exponent; ``samples()``: the torus test's samples (N, d), each state scaled (called only when a torus is
    tested); ``can_extend``: whether the record can still be lengthened; ``trajectories``: how many tangent
    trajectories the exponent must come from; ``lifetime_tested``: the caller tests a new chaotic set's persistence
    itself (the census: its mean lifetime must lie above ``persist`` periods, else it is a saddle the start runs on
    from), so the chaotic window floor, a proxy for that test, is not applied."""
    if cls["label"] in PERIODIC + ("escaped", "failed"):
        return Verdict(cls, "class")
    own = rows[0] if rows else None
    lyap, window = (exponent_estimate(own[None, :])[:3], len(own)) if own is not None else (None, 0)
    if math.isfinite(cls["convergence_rate"]) and cls["convergence_rate"] < DECAY_RATE:
        return Verdict(cls, "decay", "longer" if can_extend else "", lyap=lyap, window=window)
    why = halves_differ(own, impacts)
    if why:
        if can_extend:
            return Verdict(dict(cls, reason=why), "stationary", "stationary", lyap=lyap, window=window)
        return Verdict(undecided(cls, f"not stationary at the budget: {why}"), "stationary", lyap=lyap,
                       window=window)
    if own is None:
        return Verdict(undecided(cls, cls.get("reason") or "no period found and no exponent (lyapunov=False)"),
                       "no-exponent")
    if len(rows) < trajectories:     # the interval must hold across trajectories: copies first
        return Verdict(undecided(cls, "the exponent needs other trajectories" if can_extend else
                                 "the exponent needs other trajectories on the same attractor (out of budget before "
                                 "they could run)"), "trajectories", "trajectories" if can_extend else "", lyap=lyap,
                       window=window)
    return _exponent(cls, rows, samples, can_extend, max_period, lifetime_tested)


def _exponent(cls, rows, samples, can_extend: bool, max_period: int, lifetime_tested: bool = False) -> Verdict:
    """Rules 5-8 of :func:`decide`: chaotic, quasi-periodic, or a longer record."""
    m = min(len(r) for r in rows)
    rows = [np.asarray(r)[-m:] for r in rows]
    mean, lo, hi, spread = exponent_estimate(np.vstack(rows))
    out = Verdict(cls, "exponent", lyap=(mean, lo, hi), window=m, spread=spread, trajectories=len(rows))
    thr = lyapunov_threshold(m)
    each = [exponent_interval(r) for r in rows]       # each trajectory's own batch-means interval
    common = mean_interval(each)                       # the 95 % interval of their common mean
    lo_all, hi_all = min(e[1] for e in each), max(e[2] for e in each)
    short = m < MIN_WINDOW and can_extend              # too short to call: extend first
    above = all(e[1] > thr for e in each) or (all(e[0] > thr for e in each) and common[0] > thr)
    if (not short or lifetime_tested) and above:
        # every trajectory separates (whatever their spread), or every one's exponent is above the threshold
        # and so is the 95 % interval of their common mean: chaos
        out.cls = labelled(cls, "chaotic")
        if lo <= thr:   # the stored interval (another trajectory's) reaches the threshold: say what decided
            out.cls["reason"] = (f"chaotic on the evidence of {len(rows)} trajectories over {m} periods: "
                                 + ("each one's exponent interval lies above the threshold"
                                    if all(e[1] > thr for e in each)
                                    else f"each exponent and their common mean's 95 % interval [{common[0]:.3g}, "
                                         f"{common[1]:.3g}] lie above the threshold")
                                 + f" {thr:.3g}; another trajectory's exponent may lie in [{lo:.3g}, {hi:.3g}]")
        return out
    if short:
        why, need = f"the window ({m} periods) is shorter than {MIN_WINDOW}", MIN_WINDOW
    elif -thr <= lo_all and hi_all <= thr and common[1] < 0:
        why = (f"contracting: the exponents' common mean lies below 0 (interval [{common[0]:.3g}, "
               f"{common[1]:.3g}]), a periodic orbit still converging rather than a torus")
        need = 2 * m
    elif -thr <= lo_all and hi_all <= thr:         # a torus has exponent 0: evidence of one is needed
        torus, why_not, out.zero_one, out.rotation = torus_evidence(samples(), max_period)
        if torus:
            out.cls = labelled(cls, "quasi-periodic")
            return out
        why = f"the exponent's interval [{lo:.3g}, {hi:.3g}] lies within +-{thr:.3g} but {why_not}"
        need = max(QP_SAMPLES, 2 * m)
    elif hi_all < -thr:
        why = f"contracting (exponent {mean:.3g}, interval [{lo:.3g}, {hi:.3g}]) yet no period up to the maximum"
        need = 2 * m
    else:
        open_ = [e for e in each if e[1] <= thr and not (e[2] < -thr or (-thr <= e[1] and e[2] <= thr))]
        worst = max(open_ or each, key=lambda e: e[2] - e[1])
        near = min(abs(worst[0] - thr), abs(worst[0] + thr))
        why = (f"{len(open_) or len(each)} of {len(each)} trajectories' exponent intervals contain a threshold "
               f"+-{thr:.3g} (widest [{worst[1]:.3g}, {worst[2]:.3g}])")
        need = int(min(1e7, m * ((worst[2] - worst[1]) / 2 / max(near, 1e-12)) ** 2)) if near > 0 else 10 ** 7
    out.cls, out.need, out.wants = undecided(cls, why), need, "longer" if can_extend else ""
    return out


def mean_interval(each) -> tuple[float, float]:
    """95 % interval of the common mean of K trajectories' exponents, from their means' spread and
    their batch-means half-widths (each: (mean, low, high)), the wider."""
    means = np.array([e[0] for e in each])
    k = means.size
    half_between = _student_t(0.975, k - 1) * float(np.std(means, ddof=1)) / math.sqrt(k) if k > 1 else 0.0
    half_within = float(np.sqrt(np.mean([((e[2] - e[1]) / 2) ** 2 for e in each]))) / math.sqrt(k)
    half = max(half_between, half_within)
    return float(means.mean()) - half, float(means.mean()) + half


def undecided(cls, why: str) -> dict:
    """``cls`` as "not-converged" for the reason ``why``."""
    return dict(cls, code=ClassCode.NOT_CONVERGED, label="not-converged", impacts_per_period=-1, reason=why)


def labelled(cls, label: str) -> dict:
    """``cls`` relabelled as a non-periodic class decided by the exponent."""
    return dict(cls, code=ClassCode.of(label), label=label, period=0, impacts_per_period=-1, reason="")
