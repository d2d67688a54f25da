"""How long trajectories stay on a non-periodic set: its mean lifetime from copies, and the verdict it gives.

A chaotic saddle is left after an exponentially distributed time (escape rate kappa, mean lifetime 1/kappa);
a chaotic attractor is never left.  :func:`estimate_lifetime` starts ``copies`` trajectories on a set's recorded
points, each point perturbed by ``perturb`` (relative), so that the copies decorrelate on the set instead of
being one trajectory shifted in time, runs them in legs of ``leg`` strobe periods and notes when each falls onto
a period (:func:`fall_index`).  With the copies censored at the time run, the mean lifetime's estimate is the
total time on the set over the falls, with the exact chi-square interval of a censored exponential sample
(:func:`lifetime_interval`).  After each leg the verdict (:meth:`Lifetime.verdict`) compares the interval with
the horizon: "attractor" where its lower end exceeds it, "saddle" where its upper end lies below it, otherwise
"long-lived" (a chaotic transient of the order of the horizon); the run stops once decided, once the falls
seen rule out "attractor" even if no other copy fell (:func:`_may_persist`), when every copy has fallen, or at
the horizon.  The interval's level is Bonferroni-corrected over the looks (0.95 overall).
Times are in strobe periods (the relay period, for the thesis scenes).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..labels.classify import candidate_periods, state_scale

#: copies run on a new non-periodic set (12 batches of 4 SIMD lanes), their relative perturbation, the
#: periods per leg between two looks at the interval, and the interval's overall level
COPIES, PERTURB, LEG, LEVEL = 48, 1e-7, 500, 0.95


@dataclass(frozen=True)
class Lifetime:
    """A set's mean lifetime [strobe periods]: estimate ``tau`` (inf: no copy fell), its interval [low, high],
    the copies that fell, the total periods the copies spent on the set, the copies run, the periods each ran, and
    (where asked for: ``estimate_lifetime(..., ends=True)``) each fallen copy's last leg as (its MapOrbit, the sample it
    started at): where the copies went, the saddle's exit distribution (:func:`.census.copy_exits`)."""

    tau: float
    low: float
    high: float
    falls: int
    exposure: float
    copies: int
    ran: int
    ends: tuple = ()


    def verdict(self, horizon: float) -> str:
        """'attractor' (lifetime surely above ``horizon`` periods), 'saddle' (surely below) or 'long-lived'."""
        if self.low > horizon:
            return "attractor"
        if self.high < horizon:
            return "saddle"
        return "long-lived"

    def text(self) -> str:
        return (f"mean lifetime {self.tau:.4g} [{self.low:.4g}, {self.high:.4g}] strobe periods ({self.falls} of "
                f"{self.copies} copies fell within {self.ran} periods)")


def lifetime_interval(exposure: float, falls: int, level: float = LEVEL) -> tuple[float, float, float]:
    """(estimate, low, high) of an exponential mean from ``falls`` observed falls and the total time
    ``exposure`` of all copies (the fallen ones to their fall, the others censored): estimate exposure / falls
    (inf for none), interval 2 T / chi2(1 - a/2; 2d + 2) to 2 T / chi2(a/2; 2d) (inf for none), a = 1 - level."""
    from scipy.stats import chi2
    a = 1.0 - level
    tau = exposure / falls if falls else math.inf
    low = 2.0 * exposure / chi2.ppf(1.0 - a / 2.0, 2 * falls + 2)
    high = 2.0 * exposure / chi2.ppf(a / 2.0, 2 * falls) if falls else math.inf
    return tau, float(low), float(high)


def periodic_tail(points, periods, rtol: float = 1e-6, atol: float = 1e-9) -> bool:
    """Whether ``points`` repeat with some period n of ``periods``: every point within rtol of each state's scale
    (plus atol) of the point n before.  A tolerance of the states, not of the grid."""
    P = np.asarray(points, dtype=float)
    tol = rtol * state_scale(P, atol) + atol
    return any(bool(np.all(np.abs(P[n:] - P[:-n]) <= tol)) for n in _last_repeats(P, periods, tol))


def _last_repeats(P: np.ndarray, periods, tol) -> list:
    """The periods n of ``periods`` (below len(P)) at which the last point repeats the one n before, within ``tol``:
    the only ones at which a tail can repeat (one numpy pass instead of one per period: on a chaotic set none)."""
    n = np.asarray([m for m in periods if 0 < m < len(P)], dtype=np.int64)
    if not n.size:
        return []
    return n[~np.any(np.abs(P[-1] - P[len(P) - 1 - n]) > tol, axis=1)].tolist()    # as the callers' tests read NaN


def fall_index(points, periods, tail: int, rtol: float = 1e-6, atol: float = 1e-9) -> int | None:
    """The first index from which ``points`` repeat with some period n of ``periods`` to the end (as
    :func:`periodic_tail`), provided their last ``tail`` points do; None if they do not (still on the set)."""
    P = np.asarray(points, dtype=float)
    tol = rtol * state_scale(P[-tail:], atol) + atol
    best = None
    for n in _last_repeats(P, periods, tol):      # the last point too must repeat
        bad = np.flatnonzero(np.any(np.abs(P[n:] - P[:-n]) > tol, axis=1))
        if len(bad) and bad[-1] >= len(P) - n - tail:
            continue                      # the last ``tail`` points do not repeat after n
        j = int(bad[-1]) + 1 if len(bad) else 0
        best = j if best is None else min(best, j)
    return best


def _copies(record, k0: int, copies: int, perturb: float, rng, window: int | None = None) -> list:
    """``copies`` (state, sample) pairs on the record's points, spread over its first ``window`` periods (None: all
    of it), each multiplied by 1 + perturb * N(0, 1) per state (exact zeros, a bar on its stop, stay zero)."""
    from maps.hybrid import HybridState
    last = len(record.points) - 1 if window is None else min(int(window), len(record.points) - 1)
    idx = np.linspace(0, last, copies).astype(int)
    out = []
    for j in idx:
        st = record.state(int(j))
        y = np.asarray(st.y, dtype=float)
        out.append((HybridState(y * (1.0 + perturb * rng.standard_normal(y.shape)), st.flags), k0 + int(j)))
    return out


def estimate_lifetime(smap, record, k0: int, horizon: int, *, max_period: int = 16, batch_size: int = 4,
                      copies: int = COPIES, perturb: float = PERTURB, leg: int = LEG, seed: int = 0,
                      window: int | None = None, ends: bool = False) -> Lifetime:
    """The mean lifetime of the non-periodic set recorded in ``record`` (a MapOrbit from sample ``k0``) under
    ``smap``: copies started on the record's first ``window`` periods (None: all of it) run in legs of ``leg``
    periods up to ``horizon`` periods each, stopped once the verdict against ``horizon`` is decided, once
    "attractor" is ruled out, or when every copy has fallen (module docstring).  Reproducible: the perturbations
    come from ``seed``.  ``ends``: keep each fallen copy's last leg (:attr:`Lifetime.ends`)."""
    periods = candidate_periods(smap.forcing_period_steps, max_period)
    tail = 4 * max_period
    looks = max(1, math.ceil(horizon / leg))
    level = 1.0 - (1.0 - LEVEL) / looks
    starts = _copies(record, k0, copies, perturb, np.random.default_rng(seed), window)
    live = [(x, k, np.empty((0, 0))) for x, k in starts]
    done, fallen, got, last = 0, [], None, []
    while live and done < horizon:
        n = min(leg, horizon - done)
        runs = smap.orbits([{}] * len(live), [x for x, _, _ in live], n, k0=[k for _, k, _ in live],
                           batch_size=batch_size, events=False)
        kept = []
        for o, (_, k, before) in zip(runs, live):
            at = _fall_time(o, before, done, periods, tail)
            if at is None:
                kept.append((o.final, k + n, np.asarray(o.points, dtype=float)[-tail:]))
            else:
                fallen.append(at)
                if ends:
                    last.append((o, k))
        done, live = done + n, kept
        exposure = sum(fallen) + done * len(live)
        got = Lifetime(*lifetime_interval(exposure, len(fallen), level), len(fallen), exposure, copies, done,
                       tuple(last))
        if got.verdict(horizon) != "long-lived" or not _may_persist(got, len(live), horizon, level):
            break
    return got


def _may_persist(got: Lifetime, live: int, horizon: int, level: float) -> bool:
    """Whether the verdict may still become "attractor": the interval's lower end exceeds ``horizon`` if the
    ``live`` copies all stay on the set to the horizon (else the run stops: the census treats a saddle and a
    long-lived transient alike, so only the attractor verdict needs the rest of the run)."""
    best = got.exposure + live * (horizon - got.ran)
    return lifetime_interval(best, got.falls, level)[1] > horizon


def _fall_time(o, before, done: int, periods, tail: int) -> int | None:
    """When a copy's leg ``o`` (from time ``done``, after the previous leg's last points ``before``) shows it
    fell: the first time from which it repeats with a period, or the time it escaped or failed; None: still on
    the set."""
    pts = np.asarray(o.points, dtype=float)
    if o.status != "ok":
        return done + max(len(pts) - 1, 0)
    joined = np.vstack([before, pts[1:]]) if before.size else pts
    j = fall_index(joined, periods, tail)
    return None if j is None else max(done + len(pts) - 1 - (len(joined) - 1 - j), 0)
