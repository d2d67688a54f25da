"""The evidence a label rests on, beyond the recurrence test: stationarity, an exponent interval
that holds across trajectories, and positive evidence of a torus.

- :func:`halves_differ`: a record is judged only where it is stationary; its first and second
  halves are compared (the exponent's and the impact rate's batch-means intervals, the presence
  of impacts).  Where they differ, the first half is a transient (or an intermittent burst).
- :func:`exponent_estimate`: the largest Lyapunov exponent from K tangent trajectories on the same
  attractor (perturbed copies of one state): their mean, and a 95 % interval that covers another
  trajectory's estimate over the same window (a prediction interval from the between-trajectory
  spread, never narrower than one trajectory's batch-means interval).
- :func:`zero_one_test`: Gottwald and Melbourne's 0-1 test for chaos (correlation method; G. A.
  Gottwald, I. Melbourne, SIAM J. Appl. Dyn. Syst. 8 (2009) 129-145): K near 0 for regular
  (periodic or quasi-periodic) motion, near 1 for chaos.
- :func:`rotation_number`: the mean turn per step of the samples about their centre in their
  principal plane (an invariant circle of the stroboscopic map), with the halves' difference.
"""
from __future__ import annotations

import math

import numpy as np

from .lyapunov import _student_t, exponent_interval

#: 0-1 test statistic below which motion counts as regular (Gottwald and Melbourne report K < 0.1
#: for regular and K > 0.9 for chaotic records of a few thousand samples; records here may be shorter)
TORUS_K = 0.25
#: fewest steps in each half for the halves to be compared
MIN_HALF = 50
#: samples the torus test needs
QP_SAMPLES = 400


def _disjoint(a, b) -> bool:
    return np.isfinite(a[1:]).all() and np.isfinite(b[1:]).all() and (a[2] < b[1] or b[2] < a[1])


def halves_differ(stretch, impacts) -> str:
    """Why the first and second halves of a record differ ("" when they agree or are too short):
    disjoint 95 % intervals of the exponent (``stretch``: log stretch per step, or None) or of the
    impact rate (``impacts``: contacts per step), or impacts in one half only."""
    imp = np.asarray(impacts, dtype=float)
    h = imp.size // 2
    if h < MIN_HALF:
        return ""
    a, b = imp[:h], imp[h:2 * h]
    if (a.sum() == 0) != (b.sum() == 0) and max(a.sum(), b.sum()) >= 3:
        return (f"impacts in one half of the record only ({int(a.sum())} then {int(b.sum())}): "
                f"an intermittent burst or a transient")
    ra, rb = exponent_interval(a), exponent_interval(b)
    if _disjoint(ra, rb):
        return f"the impact rate changes between the record's halves ({ra[0]:.3g} then {rb[0]:.3g} per step)"
    if stretch is not None:
        s = np.asarray(stretch, dtype=float)[:2 * h]
        if np.all(np.isfinite(s)):
            ea, eb = exponent_interval(s[:h]), exponent_interval(s[h:])
            if _disjoint(ea, eb):
                return (f"the exponent changes between the record's halves ({ea[0]:.3g} then {eb[0]:.3g} per step)")
    return ""


def exponent_estimate(stretches) -> tuple[float, float, float, float]:
    """(exponent, low, high, spread) [per step] from ``stretches`` (K, n): K tangent trajectories'
    log stretch per step over the same n steps.  The exponent is the mean of the K trajectories'
    means; ``spread`` their standard deviation (NaN for K = 1); the 95 % interval is the wider of
    the Student-t prediction interval for another trajectory's mean, mean +- t(K-1) spread
    sqrt(1 + 1/K), and the trajectories' batch-means intervals (:func:`exponent_interval`, their
    root mean square half-width).  NaN where a stretch is not finite.

    The batch means are not pooled with the spread: copies started near the value's own state share
    its slow intermittent phases, so on the thesis model at 9 Hz, 90 V a pooled interval covered 17
    of 20 independent trajectories' exponents over 800 periods, this one 19 (benchmarks/exponent_intervals.py)."""
    s = np.atleast_2d(np.asarray(stretches, dtype=float))
    if s.size == 0 or not np.all(np.isfinite(s)):
        return math.nan, math.nan, math.nan, math.nan
    each = [exponent_interval(row) for row in s]
    means = np.array([e[0] for e in each])
    halves = np.array([(e[2] - e[1]) / 2 for e in each])
    mean = float(np.mean(means))
    within = float(np.sqrt(np.mean(halves ** 2))) if np.all(np.isfinite(halves)) else math.nan
    if s.shape[0] == 1:
        return mean, mean - within, mean + within, math.nan
    k = s.shape[0]
    spread = float(np.std(means, ddof=1))
    between = _student_t(0.975, k - 1) * spread * math.sqrt(1 + 1 / k)
    half = max(between, within) if math.isfinite(within) else between
    return mean, mean - half, mean + half, spread


def zero_one_test(phi, n_c: int = 100, seed: int = 0) -> float:
    """Gottwald and Melbourne's 0-1 test (correlation method) on the observable ``phi`` (N,):
    the median over ``n_c`` frequencies c in (pi/5, 4 pi/5) of the correlation between n and the
    mean square displacement of the translation variables (p_c, q_c), less its oscillatory part,
    for n up to N/10.  Near 0: regular; near 1: chaotic.  NaN for fewer than 100 samples or a
    constant observable."""
    x = np.asarray(phi, dtype=float)
    N = x.size
    if N < 100 or not np.all(np.isfinite(x)) or np.ptp(x) == 0:
        return math.nan
    x = (x - x.mean()) / x.std()
    ncut = N // 10
    j = np.arange(1, N + 1)
    n = np.arange(1, ncut + 1)
    cs = np.random.default_rng(seed).uniform(math.pi / 5, 4 * math.pi / 5, n_c)
    size = 1 << int(math.ceil(math.log2(2 * N)))
    ks = []
    for c in cs:
        z = np.cumsum(x * np.exp(1j * j * c))                   # p_c + i q_c
        f = np.fft.fft(z, size)
        lagged = np.fft.ifft(f * np.conj(f))[1:ncut + 1].real   # sum_j Re z_{j+n} conj(z_j)
        sq = np.concatenate([[0.0], np.cumsum(np.abs(z) ** 2)])
        head, tail = sq[N - n], sq[N] - sq[n]                   # sum |z_j|^2 over j < N-n, over j >= n
        M = (head + tail - 2 * lagged) / (N - n)
        D = M - np.mean(x) ** 2 * (1 - np.cos(n * c)) / (1 - math.cos(c))
        if np.std(D) > 0:
            ks.append(np.corrcoef(n, D)[0, 1])
    return float(np.median(ks)) if ks else math.nan


def rotation_number(points) -> tuple[float, float]:
    """(rotation number in [0, 1/2], |difference between the halves' numbers|) of samples ``points``
    (N, d) turning about their centre in their principal plane (the first two principal components
    of the samples, each component scaled by its range): the mean wrapped angle increment per step
    over 2 pi, taken mod 1 and folded to [0, 1/2] (a projection does not keep the orientation: rho
    and 1 - rho are the same circle turned over).  Meaningful for an invariant circle that winds
    once about its centre."""
    p = np.asarray(points, dtype=float)
    if p.shape[0] < 8 or not np.all(np.isfinite(p)):
        return math.nan, math.nan
    turn = np.angle(np.exp(1j * np.diff(_angles(p)))) / (2 * math.pi)
    h = turn.size // 2
    rho = float(np.mean(turn)) % 1.0
    return min(rho, 1.0 - rho), abs(float(np.mean(turn[:h]) - np.mean(turn[h:])))


def _angles(p) -> np.ndarray:
    """Each sample's angle [rad] about the samples' centre in their principal plane (the first two principal
    components of the samples, each state scaled by its range)."""
    span = np.ptp(p, axis=0)
    p = (p - p.mean(axis=0)) / np.where(span > 0, span, 1.0)
    _, _, vt = np.linalg.svd(p, full_matrices=False)
    xy = p @ vt[:2].T if vt.shape[0] >= 2 else np.c_[p[:, 0], np.zeros(p.shape[0])]
    return np.arctan2(xy[:, 1], xy[:, 0])


def near_period(samples, rho: float, max_period: int) -> str:
    """Why samples (N, d) with rotation number ``rho`` look like a periodic orbit still converging
    rather than a torus ("": they do not): rho within 1e-3 of a fraction a/b with b <= max_period
    and the samples' lag-b distance decaying (a fitted rate below 0.999 per sample).  A small lag-b distance
    alone is no evidence of convergence: about a period-b orbit that is not stable the samples may lie on b small
    circles, an island chain (thesis-1dof, `matlab-listing`, `listing` law, 10 Hz, 95 V: rotation
    number 0.1667, lag-6 distance 0.73 % of the extent, its fitted rate within 1.5e-4 of 1 per period in each
    768-period window after the first 1536; the period-6 orbit at its centre is unstable, multipliers of modulus
    1.0008: benchmarks/reports/attractors-recovery/torus-windows-*).  An orbit approached more slowly than 1e-3
    per sample (exponent within 1e-3 of 0) passes for a torus here: the census tries Newton first."""
    from fractions import Fraction
    if not math.isfinite(rho):
        return ""
    f = Fraction(rho).limit_denominator(max(1, int(max_period)))
    b = f.denominator
    if abs(rho - f.numerator / b) > 1e-3 or samples.shape[0] <= 4 * b:
        return ""
    d = np.max(np.abs(samples[b:] - samples[:-b]), axis=1)
    k = np.arange(d.size)
    ok = d > 0
    if ok.sum() > 10:
        rate = math.exp(np.polyfit(k[ok], np.log(d[ok]), 1)[0])
        if rate < 0.999:
            return (f"the rotation number {rho:.5f} is near {f.numerator}/{b} and the lag-{b} distance decays "
                    f"({rate:.4f} per period): a period-{b} orbit still converging, not a torus")
    return ""


#: recurrence [fraction of the samples' extent] at a lag up to N/4 that shows samples locked (periodic, or on a
#: circle within LOCK_TOL of a resonance: in a dissipative map, a periodic orbit approached slowly) rather than shown to
#: be on a torus.  On a circle the lag-L chord is about pi ||L rho|| of the extent, so a torus of random rotation
#: number rho passes for locked with probability at most N LOCK_TOL / (2 pi): 2.4 % over 1536 samples; one at the
#: golden mean recurs at best to 4e-3 of its extent within 384 samples.  Thesis-1dof (`matlab-listing`, `measured`,
#: 10 Hz) at 136 V, a set whose 1536-period record has exponent -0.0026 (-0.0086-0.0034) and rotation number 1/3
#: about its centre recurs at lag 24 to 2e-5 of its extent (an 8000-period record: exponent -0.0031, -0.0044 to
#: -0.0018: a stable orbit of period above the census' 16); at 203 V one recurs at lag 4 to 1e-6
LOCK_TOL = 1e-4


def locked_lag(samples) -> tuple[int, float]:
    """(the least lag L <= N/4 at which the second half of samples (N, d) recurs to LOCK_TOL of its extent, that
    recurrence as a fraction of the extent), or (0, NaN) where none does."""
    p = np.asarray(samples, dtype=float)
    q = p[p.shape[0] // 2:]
    extent = float(np.max(np.ptp(q, axis=0))) if q.size else 0.0
    if extent <= 0 or not np.all(np.isfinite(q)):
        return 0, math.nan
    for lag in range(1, p.shape[0] // 4 + 1):
        d = float(np.max(np.abs(q[lag:] - q[:-lag])))
        if d <= LOCK_TOL * extent:
            return lag, d / extent
    return 0, math.nan


def torus_evidence(samples, max_period: int = 100) -> tuple[bool, str, float, float]:
    """(a torus?, why not, 0-1 test K, rotation number) of stroboscopic samples (N, d), each state
    scaled: positive evidence of quasi-periodic motion needs at least ``QP_SAMPLES`` samples, the 0-1
    test's K below ``TORUS_K`` (regular motion), samples turning at least once about their centre (thesis-1dof,
    `matlab-listing`, `measured`, 10 Hz, 179.5 V: a small chaotic set, exponent 0.03-0.05, turns 0.46 times in 768
    samples and passes every other test), a rotation number whose halves agree to 1e-2, halves of one
    extent where each covers the circle (:func:`extent_drift`), and no recurrence at the period a nearby
    fraction suggests nor at any lag up to N/4 (:func:`near_period`, :func:`locked_lag`)."""
    p = np.asarray(samples, dtype=float)
    if p.shape[0] < QP_SAMPLES:
        return False, f"a torus test needs {QP_SAMPLES} samples, the window has {p.shape[0]}", math.nan, math.nan
    drift = extent_drift(p)
    if drift > EXTENT_DRIFT:             # NaN (halves covering other arcs of the circle): not compared
        return (False, f"the samples' extent changes by {drift:.2g} between the window's halves: a spiral onto an "
                       f"orbit or a transient, not a torus", math.nan, math.nan)
    k01 = zero_one_test(p @ np.linspace(1.0, 0.5, p.shape[1]))
    rho, drift = rotation_number(p)
    lag, how_close = locked_lag(p)
    if lag:
        return (False, f"the samples recur at lag {lag} to {how_close:.2g} of their extent: periodic or locked with "
                       f"period {lag}, not shown to be a torus", k01, rho)
    near = near_period(p, rho, max_period)
    if near:
        return False, near, k01, rho
    turns = rho * (p.shape[0] - 1)
    if turns < 1.0:      # an arc: neither a closed curve nor the halves' extents (extent_drift) are shown
        return (False, f"the samples turn {turns:.2g} times about their centre (rotation number {rho:.2g}): no closed "
                       f"curve shown", k01, rho)
    if not (k01 < TORUS_K and drift < 1e-2):
        return False, f"no torus (0-1 test K = {k01:.2f}, rotation number drift {drift:.2g})", k01, rho
    return True, "", k01, rho


#: relative change of the samples' extent between a window's halves above which they are no torus: an invariant
#: circle's halves of 200 or more samples each cover it (extents within a few 1e-4); a spiral onto a fixed point with
#: multipliers of modulus 0.997 at a golden-mean rotation, which passes the 0-1 and rotation tests over 1536 samples,
#: shrinks by 0.997^768 = 0.1 from one half to the other
EXTENT_DRIFT = 0.05
#: widest gap [turns] in a half's angles for the halves' extents to be compared: near a resonance a/b the samples
#: sweep b arcs slowly, and each half covers other parts of the circle (thesis-1dof, `matlab-listing`, 90 V, 10 Hz:
#: rotation number 0.16670, within 4e-5 of 1/6, whose halves of 2750 samples cover 58 % of the circle each and
#: differ in extent by 7 %)
COVER_GAP = 0.02


def extent_drift(samples) -> float:
    """The largest relative change, over the states, of the samples' (N, d) range between the first and second
    halves, |range_2 - range_1| / max(range_1, range_2) (0 for states constant in both), where each half covers
    its circle: NaN where a half's angles about the samples' centre in their principal plane leave a gap wider
    than COVER_GAP turns (or the samples are not finite)."""
    p = np.asarray(samples, dtype=float)
    h = p.shape[0] // 2
    if h < 8 or not np.all(np.isfinite(p)):
        return math.nan
    turns = _angles(p) / (2 * math.pi) % 1.0
    for half in (turns[:h], turns[h:2 * h]):
        t = np.sort(half)
        if max(float(np.max(np.diff(t))), float(t[0] + 1.0 - t[-1])) > COVER_GAP:
            return math.nan
    a, b = np.ptp(p[:h], axis=0), np.ptp(p[h:2 * h], axis=0)
    big = np.maximum(a, b)
    ok = big > 0
    return float(np.max(np.abs(a - b)[ok] / big[ok])) if ok.any() else 0.0
