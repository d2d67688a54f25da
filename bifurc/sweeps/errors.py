"""Numerical error estimate of a sweep: re-runs at tol/100 and the one-step map error.

Returns the keywords of :func:`bifurc.sweeps.dataset.add_error_estimate`.  NaN means nothing of
that kind was measured.  :class:`ErrorEstimate` chooses the sampled values (cheap) and hands out
the integrations as tasks with small picklable payloads (a sweep runs them on its workers);
:func:`error_estimate` runs them here.
"""
from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from maps.hybrid import HybridState

from ..labels.classify import state_scale
from ..labels.codes import Status
from ..run.executor import result_of, submit_all, timed

#: tighter tolerance of the re-runs: tol / TIGHTER
TIGHTER = 100


def _spread(pool, k):
    """Up to ``k`` members of ``pool``, evenly spaced."""
    if not pool or k <= 0:
        return []
    return [pool[j] for j in np.unique(np.linspace(0, len(pool) - 1, k).round().astype(int))]


#: a periodic value re-run at tol/100 whose window differs by more than this (scaled, at any phase)
#: reached another attractor from the same start: its label is not robust to the tolerance
ROBUST = 1e-3


def error_estimate(results, values, job, branch, sample, step_points=32) -> dict:
    """Re-run ``sample`` values of ``results[branch]`` at tol/100 and compare, here (see :class:`ErrorEstimate`)."""
    est = ErrorEstimate(results, values, job, branch, sample, step_points)
    return est.result(submit_all(est.tasks))


class ErrorEstimate:
    """The error estimate of ``sample`` values of ``results[branch]`` (ValueResults or None per value).

    - ``step_err``: one relay period from the same recorded state at tol and at tol/100, at up
      to ``step_points`` states of each sampled value: the error of each map step, meaningful
      for every class (chaotic ones included).
    - ``point_err``, ``time_err`` [s]: whole re-runs from the same start, largest difference of the
      recorded points (scaled) and contact times, over periodic values only: there it is the global
      error.  Elsewhere the difference grows with the dynamics' sensitivity whatever the
      tolerance; it is reported apart (``sensitive_err``).  Periodic values are sampled first.
      A followed value is re-run from the same start (the previous value's final state).
    NaN: nothing of that kind was sampled (``time_err``: no periodic impacting value re-run with
    the same contact count).

    ``tasks``: the integrations as [(cost [relay periods], fn, args)], each returning
    ``(output, seconds)`` (:func:`bifurc.run.executor.timed`); :meth:`result` takes their Futures (in
    the order of ``tasks``) and assembles the keywords of :func:`bifurc.sweeps.dataset.add_error_estimate`.
    """

    def __init__(self, results, values, job, branch, sample, step_points=32):
        res = self.res = results[branch]
        self.values, self.job, self.branch = values, job, branch
        ok = [i for i in range(values.size) if res[i] is not None and res[i].status == Status.OK]
        self.good = [i for i in ok if res[i].class_code.periodic]
        idx = _spread(self.good, min(sample, len(self.good)))
        self.idx = sorted(idx + _spread([i for i in ok if i not in self.good], sample - len(idx)))
        self.tight = tight = replace(job, tol=job.tol / TIGHTER, lyapunov=False)
        # costs [relay periods] only order the tasks: a period at tol/TIGHTER counted as two at tol
        length = lambda i: 2.0 * (res[i].transient_used + res[i].record_used)  # noqa: E731
        # the same window at tol/TIGHTER: from the same start, to the same sample index, recorded as long
        window = lambda i: (res[i].transient_used, min(res[i].record_used, job.record))  # noqa: E731
        if branch == "independent":      # one batch pass for the whole sample, job.batch_size values at once
            passes = math.ceil(len(self.idx) / max(1, job.batch_size))
            reruns = [(passes * max(map(length, self.idx)), timed,
                       (rerun, tight, values[self.idx], [window(i) for i in self.idx], None))] if self.idx else []
        else:
            reruns = [(length(i), timed, (rerun, tight, values[[i]], [window(i)], [self._start(i)]))
                      for i in self.idx]
        steps = [(3.0 * min(step_points, res[i].record_used), timed,
                  (map_step_error, res[i].points[:res[i].record_used + 1], res[i].transient_used, values[i], job,
                   tight, step_points)) for i in self.idx]
        self.tasks = reruns + steps

    def _start(self, i):
        """The start of followed value ``i``: the previous value's final state (None: x0)."""
        prev = self.res[i - 1] if i > 0 else None
        return prev.end_state if prev is not None and prev.status == Status.OK else None

    def result(self, futures) -> dict:
        """The keywords of :func:`bifurc.sweeps.dataset.add_error_estimate` from the tasks' Futures;
        ``seconds``: the tasks' run times summed."""
        outputs = [result_of(f) for f in futures]
        seconds = sum(s for _, s in outputs)
        n = len(outputs) - len(self.idx)            # the re-runs' tasks, then one map step task per value
        reruns = outputs[0][0] if self.branch == "independent" and n else [out[0] for out, _ in outputs[:n]]
        res, good, job = self.res, self.good, self.job
        point_err = sensitive_err = step_err = time_err = math.nan
        counts_differ, not_robust = 0, []
        for i, b, (step, _) in zip(self.idx, reruns, outputs[n:]):
            a = res[i]
            step_err = np.fmax(step_err, step)
            if b.status != "ok":
                counts_differ += 1
                continue
            m = min(a.points.shape[0], b.points.shape[0])
            scale = state_scale(a.points[:m], job.atol)
            err = float(np.nanmax(np.abs(a.points[:m] - b.points[:m]) / scale))
            if i in good and err > ROBUST:      # the same orbit at another phase, or another attractor?
                err = min([err] + [float(np.nanmax(np.abs(a.points[j:m] - b.points[:m - j]) / scale))
                                   for j in range(1, min(int(a.period), m - 1))])
                if err > ROBUST:
                    not_robust.append(float(self.values[i]))
            if i in good and err <= ROBUST:
                point_err = np.fmax(point_err, err)
            else:
                sensitive_err = np.fmax(sensitive_err, err)
            ta = a.impact_time[np.isfinite(a.impact_time) & (a.impact_time <= b.times[-1])]
            if ta.size == b.impact_time.size:
                if ta.size and i in good:
                    time_err = np.fmax(time_err, float(np.max(np.abs(ta - b.impact_time))))
            else:
                counts_differ += 1
        return dict(sample_values=self.values[self.idx], point_err=float(point_err), time_err=float(time_err),
                    counts_differ=counts_differ, seconds=seconds, tight_tol=self.tight.tol,
                    sensitive_err=float(sensitive_err),
                    n_sensitive=len([i for i in self.idx if i not in good]) + len(not_robust),
                    step_err=float(step_err), not_robust=not_robust)


def rerun(job, values, windows, starts=None) -> list:
    """The orbits of ``values`` under ``job`` (a tighter tolerance's) over the given windows
    [(transient, record)]: from x0 (or ``starts[i]``, a (state, flags) pair), the transient, then
    the record: the same sample indexes as the run they check, without its judgement."""
    smap = job.warm()
    over = [job.at(v) for v in values]
    x0 = [job.x0_state() if s is None else HybridState(s[0], s[1]) for s in (starts or [None] * len(over))]
    flags = [job.problem.flags0 if s is None else None for s in (starts or [None] * len(over))]
    return smap.orbits(over, x0, [r for _, r in windows], transient=[t for t, _ in windows], flags=flags,
                       batch_size=job.batch_size)


def map_step_error(pts, k0, value, job, tight, n_points) -> float:
    """Largest scaled difference of one relay period at ``job.tol`` and at ``tight.tol`` from up to
    ``n_points`` of the recorded states ``pts`` (map steps ``k0``, ``k0 + 1``, ... of the value
    ``value``; flags from the state, as StroboscopicMap.step)."""
    ks = np.unique(np.linspace(0, pts.shape[0] - 2, min(n_points, pts.shape[0] - 1)).round().astype(int))
    scale = state_scale(pts, job.atol)
    params = job.at(value)
    worst = math.nan
    maps_ = job.warm().at(params), tight.warm().at(params)
    for k in ks:
        try:
            a, b = (smap.step(pts[k], k0 + int(k)) for smap in maps_)
        except Exception:  # noqa: BLE001 - a failed step leaves this point out
            continue
        worst = np.fmax(worst, float(np.max(np.abs(a - b) / scale)))
    return float(worst)
