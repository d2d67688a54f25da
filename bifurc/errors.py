"""Numerical error estimate of a sweep: re-runs at tol/100 and the one-step map error.

Returns the keywords of :func:`bifurc.storage.add_error_estimate`.  NaN means nothing of
that kind was measured.
"""
from __future__ import annotations

import math
import time as _time
from dataclasses import replace

import numpy as np

from .classify import state_scale
from .codes import Status

__all__ = ["error_estimate", "map_step_error"]

#: tighter tolerance of the re-runs: tol / TIGHTER
TIGHTER = 100


def _spread(pool, k):
    """Up to ``k`` members of ``pool``, evenly spaced."""
    if not pool or k <= 0:
        return []
    return [pool[j] for j in np.unique(np.linspace(0, len(pool) - 1, k).round().astype(int))]


def error_estimate(results, values, job, branch, sample, step_points=32) -> dict:
    """Re-run ``sample`` values of ``results[branch]`` at tol/100 and compare.

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
    """
    res = results[branch]
    ok = [i for i in range(values.size) if res[i] is not None and res[i].status == Status.OK]
    good = [i for i in ok if res[i].class_code.periodic]
    idx = _spread(good, min(sample, len(good)))
    idx = sorted(idx + _spread([i for i in ok if i not in good], sample - len(idx)))
    tight = replace(job, tol=job.tol / TIGHTER, lyapunov=False)
    point_err = sensitive_err = step_err = time_err = math.nan
    counts_differ = 0
    clock = _time.perf_counter()
    if branch == "independent":      # one batch pass for the whole sample
        reruns = dict(zip(idx, tight.run_many([values[i] for i in idx]))) if idx else {}
    for i in idx:
        a = res[i]
        step_err = np.fmax(step_err, map_step_error(a, values[i], job, tight, step_points))
        if branch == "independent":
            b = reruns[i]
        else:
            prev = res[i - 1] if i > 0 else None
            b = tight(values[i], prev.end_state if prev is not None and prev.status == Status.OK else None)
        if b.status != Status.OK:
            counts_differ += 1
            continue
        err = float(np.nanmax(np.abs(a.points - b.points) / state_scale(a.points, job.atol)))
        if i in good:
            point_err = np.fmax(point_err, err)
        else:
            sensitive_err = np.fmax(sensitive_err, err)
        if a.n_impacts == b.n_impacts:
            if a.n_impacts and i in good:
                time_err = np.fmax(time_err, float(np.nanmax(np.abs(a.impact_t - b.impact_t))))
        else:
            counts_differ += 1
    return dict(sample_values=values[idx], point_err=float(point_err), time_err=float(time_err),
                counts_differ=counts_differ, seconds=_time.perf_counter() - clock, tight_tol=job.tol / TIGHTER,
                sensitive_err=float(sensitive_err), n_sensitive=len([i for i in idx if i not in good]),
                step_err=float(step_err))


def map_step_error(r, value, job, tight, n_points) -> float:
    """Largest scaled difference of one relay period at ``job.tol`` and at ``tight.tol`` from the
    same recorded states of result ``r`` (flags from the state, as StroboscopicMap.step)."""
    pts = r.points[:r.record_used + 1]
    ks = np.unique(np.linspace(0, pts.shape[0] - 2, min(n_points, pts.shape[0] - 1)).round().astype(int))
    scale = state_scale(pts, job.atol)
    params = job.at(value)
    worst = math.nan
    maps_ = job.warm(), tight.warm()
    for smap in maps_:
        smap.set_params(**params)
    for k in ks:
        try:
            a, b = (smap.step(pts[k], r.transient_used + int(k)) for smap in maps_)
        except Exception:  # noqa: BLE001 - a failed step leaves this point out
            continue
        worst = np.fmax(worst, float(np.max(np.abs(a - b) / scale)))
    return float(worst)
