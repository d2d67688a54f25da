"""Classification of stroboscopic orbits: period-n with m impacts, or why not.

Rules (every label rests on numbers stored beside it; when the numbers do not
decide, the label is "not-converged", never a guess):

1. ``status`` "escaped"/"failed" pass through.
2. Each state component j is scaled by s_j = max(|p_j|) over the record (floor
   ``atol``).  For n = 1..max_period the recurrence is
   d_n = max_k max_j |p_{k+n,j} - p_{k,j}| / (rtol s_j + atol) over the whole record.
   The smallest n with d_n <= 1 whose impact count per n steps is the same for
   every window of n steps is the period; m = that count.  m = 0 is
   "periodic-no-impact".  If a shorter candidate m < n is still decaying
   geometrically (rule 3), n is only a near-recurrence of a transient:
   "not-converged".
3. Otherwise, for the best candidate n* (smallest d_n), the distances
   e_k = max_j |p_{k+n*,j} - p_{k,j}| / s_j are fitted by log e_k = a + k log rho.
   rho < 0.98 per step (a clear geometric decay): "not-converged" (a transient
   still approaching a period-n* orbit; rho is stored as ``convergence_rate``),
   unless the Lyapunov exponent is positive (lambda > lyap_tol): trajectories that
   separate exponentially are not converging, and a chaotic record's recurrence
   distance can trend down over a short window by chance.
4. Else the largest Lyapunov exponent of the map lambda [per step] decides:
   lambda > +lyap_tol: "chaotic"; |lambda| <= lyap_tol: "quasi-periodic";
   lambda < -lyap_tol (contracting, yet not periodic within max_period) or NaN:
   "not-converged".  With an interval for lambda (``lyapunov_interval``), a threshold
   (+lyap_tol or -lyap_tol) inside it decides nothing: "not-converged", with that threshold as
   ``threshold_in_interval`` (other evidence may decide: :func:`bifurc.attractors.identify.identify`).  Every
   "not-converged" result says why (``reason``).  A finite window of n steps biases lambda upward on a
   sheared torus (separation growing like n, so lambda ~ ln(n)/n), hence
   ``lyap_tol`` defaults to ``lyapunov_threshold(n) = max(2e-3, 2 ln(n)/n)``.
The thesis' notation n:m is period-n with m impacts per period.
"""
from __future__ import annotations

import math

import numpy as np

from .codes import ClassCode

#: class labels in code order (ClassCode(c).label)
CLASS_LABELS = tuple(c.label for c in ClassCode)
FLAG_MEANINGS = " ".join(CLASS_LABELS)
#: per-step decay below which a non-periodic record counts as a converging transient
DECAY_RATE = 0.98
#: |largest Lyapunov exponent| [per step] within which the orbit counts as quasi-periodic
LYAP_TOL = 2e-3


def lyapunov_threshold(n_steps: int) -> float:
    """|lambda| [per step] below which an n-step Benettin estimate is not evidence of chaos."""
    return max(LYAP_TOL, 2.0 * math.log(max(n_steps, 2)) / max(n_steps, 2))


def code_of(label: str) -> ClassCode:
    return ClassCode.of(label)


def state_scale(points, atol: float) -> np.ndarray:
    """Each state component's largest magnitude over ``points`` (N, d), NaN padding ignored, >= ``atol``:
    the scale s_j of the recurrence test, the Lyapunov norm and the error estimates."""
    return np.maximum(np.nanmax(np.abs(points), axis=0), atol)


def describe(code: int, period: int = 0, impacts: int = -1, progression: float | None = None) -> str:
    """Human text: 'period-2, 3 impacts (2:3)', 'quasi-periodic', ...; ``progression`` [m per
    relay period] of a shift-invariant system's periodic orbit (classified in reduced coordinates,
    :mod:`maps.translation`) adds its advance over one period of the orbit."""
    label = CLASS_LABELS[int(code)]
    adv = ""
    if progression is not None and math.isfinite(progression) and progression != 0.0:
        adv = f", progression {1e3 * progression * period:.4g} mm per period"
    if label == "periodic":
        return f"period-{period}, {impacts} impact{'s' if impacts != 1 else ''} ({period}:{impacts}){adv}"
    if label == "periodic-no-impact":
        return f"period-{period}, no impact{adv}"
    return label


def _result(label, period=0, impacts=-1, recurrence=math.nan, rate=math.nan, rtol=0.0, atol=0.0, reason=""):
    return {"code": code_of(label), "label": label, "period": int(period), "impacts_per_period": int(impacts),
            "reason": reason,
            "recurrence": float(recurrence), "convergence_rate": float(rate), "rtol": float(rtol),
            "atol": float(atol)}


def classify_orbit(points, impacts_per_step, *, max_period: int = 16, rtol: float = 1e-6, atol: float = 1e-9,
                   scale=None, status: str = "ok", lyapunov: float = math.nan,
                   lyap_tol: float = LYAP_TOL, lyapunov_interval: tuple | None = None,
                   periods=None) -> dict:
    """Classify recorded stroboscopic states ``points`` (N, d) with ``impacts_per_step`` (N-1,).

    ``periods``: the candidate periods (default 1 ... max_period); a periodically forced map
    can only have periods that are multiples of its forcing period q (see
    :func:`candidate_periods`).  Every candidate needs two whole periods in the record.

    Returns a dict: code, label, period, impacts_per_period, recurrence (scaled
    distance at the detected or best candidate period), convergence_rate (per step),
    rtol, atol.  See the module docstring for the rules.
    """
    if status in ("escaped", "failed"):
        return _result(status, rtol=rtol, atol=atol)
    if status != "ok":
        raise ValueError(f"status {status!r}; allowed: ok, escaped, failed")
    p = np.asarray(points, dtype=float)
    imp = np.asarray(impacts_per_step, dtype=np.int64)
    if p.ndim != 2 or p.shape[0] < 3:
        raise ValueError(f"points must be (N >= 3, d), got shape {p.shape}")
    if imp.shape != (p.shape[0] - 1,):
        raise ValueError(f"impacts_per_step must have N - 1 = {p.shape[0] - 1} entries, got {imp.shape}")
    if not np.all(np.isfinite(p)):
        return _result("failed", rtol=rtol, atol=atol)
    s = state_scale(p, atol) if scale is None else np.asarray(scale, float)
    N = p.shape[0]
    max_n = min(int(max_period), (N - 1) // 2)
    candidates = list(range(1, max_n + 1)) if periods is None else \
        sorted({int(n) for n in periods if 1 <= int(n) <= max_n})
    best_n, best_d = 0, math.inf
    for n in candidates:
        diff = np.abs(p[n:] - p[:-n])
        d = float(np.max(diff / (rtol * s + atol)))
        if d < best_d:
            best_n, best_d = n, d
        if d <= 1.0:
            windows = np.convolve(imp, np.ones(n, dtype=np.int64), mode="valid")
            if windows.size and np.all(windows == windows[0]):
                for m_ in (c for c in candidates if c < n):  # a shorter candidate still converging
                    rate_m = _decay_rate(p, m_, s, atol)
                    if math.isfinite(rate_m) and rate_m < DECAY_RATE:
                        d_m = float(np.max(np.abs(p[m_:] - p[:-m_]) / (rtol * s + atol)))
                        return _result("not-converged", m_, -1, d_m, rate_m, rtol, atol,
                                       f"a recurrence at {n}, but the shorter candidate {m_} still decays "
                                       f"(rate {rate_m:.3g}): a transient near a period-{m_} orbit")
                m = int(windows[0])
                label = "periodic" if m > 0 else "periodic-no-impact"
                return _result(label, n, m, d, _decay_rate(p, n, s, atol), rtol, atol)
    rate = _decay_rate(p, best_n, s, atol) if best_n else math.nan
    if math.isfinite(rate) and rate < DECAY_RATE and not lyapunov > lyap_tol:
        return _result("not-converged", best_n, -1, best_d, rate, rtol, atol,
                       f"the recurrence at {best_n} still decays (rate {rate:.3g} per step): a transient")
    if math.isfinite(lyapunov):
        lo, hi = lyapunov_interval if lyapunov_interval is not None else (math.nan, math.nan)
        for thr, what in ((lyap_tol, "chaotic from quasi-periodic"), (-lyap_tol, "quasi-periodic from contracting")):
            if lo <= thr <= hi:
                return dict(_result("not-converged", best_n, -1, best_d, rate, rtol, atol,
                                    f"the exponent's interval [{lo:.3g}, {hi:.3g}] contains the threshold {thr:.3g} "
                                    f"that separates {what}"), threshold_in_interval=thr)
        if lyapunov > lyap_tol:
            return _result("chaotic", 0, -1, best_d, rate, rtol, atol)
        if abs(lyapunov) <= lyap_tol:
            return _result("quasi-periodic", 0, -1, best_d, rate, rtol, atol)
        return _result("not-converged", best_n, -1, best_d, rate, rtol, atol,
                       f"contracting (exponent {lyapunov:.3g}) yet no period up to {max_period}")
    why = "no period found" if candidates else "no candidate period fits the record (see candidate_periods)"
    return _result("not-converged", best_n, -1, best_d, rate, rtol, atol, f"{why} and no exponent")


def mechanical_period(points, impacts_per_step, period: int, mechanical, *, rtol: float = 1e-6,
                      atol: float = 1e-9, impacts: int = -1) -> tuple[int, int, str]:
    """(period, impacts per period, why it differs) of the mechanical states alone (the columns
    ``mechanical`` of ``points`` (N, d)) on an orbit of full-state ``period`` n with ``impacts``
    per period: the smallest divisor p of n at which the mechanical states recur (the recurrence
    test of :func:`classify_orbit`) and every window of p steps holds the same impacts.  ``why``
    names what repeats only every n: the other (electrical) states' sign flip, or their own period.
    (0, -1, "") when the orbit is not periodic."""
    if period <= 0:
        return 0, -1, ""
    p = np.asarray(points, dtype=float)
    mech = list(mechanical)
    other = [j for j in range(p.shape[1]) if j not in mech]
    s = state_scale(p, atol)
    imp = np.asarray(impacts_per_step, dtype=np.int64)
    for d in (k for k in range(1, period) if period % k == 0):
        if p.shape[0] <= 2 * d:
            break
        diff = np.abs(p[d:, mech] - p[:-d, mech]) / (rtol * s[mech] + atol)
        windows = np.convolve(imp, np.ones(d, dtype=np.int64), mode="valid")
        if float(np.max(diff)) <= 1.0 and windows.size and np.all(windows == windows[0]):
            flip = other and float(np.max(np.abs(p[d:, other] + p[:-d, other]) / (rtol * s[other] + atol))) <= 1.0
            why = (f"the other states change sign every {d} strobe periods (the relay-switched forcing's "
                   f"half-period symmetry): they repeat every {period}" if flip else
                   f"the other states repeat only every {period} strobe periods")
            return d, int(windows[0]), why
    return period, int(impacts), ""


def candidate_periods(q: int, max_period: int) -> list[int]:
    """The periods a map forced with period q [strobe periods] can have, up to ``max_period``: the
    multiples of q (every period when q = 1; none when the forcing never repeats, q = 0)."""
    if q <= 0:
        return []
    return [q * j for j in range(1, int(max_period) // q + 1)]


def _decay_rate(p, n, s, atol):
    """Geometric decay rate per step of the period-n recurrence distance (log-linear fit)."""
    e = np.max(np.abs(p[n:] - p[:-n]) / s, axis=1)
    e = np.maximum(e, 1e-300)
    if e.size < 3:
        return math.nan
    k = np.arange(e.size)
    slope = np.polyfit(k, np.log(e), 1)[0]
    return float(math.exp(slope))
