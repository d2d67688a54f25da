"""Distinct attractors: the state-space grid, what one attractor is, and matching two of them.

A periodic attractor is its orbit polished by Newton (:func:`bifurc.orbits.periodic.find_periodic_orbit`:
exact multipliers), whatever the phase at which a trajectory met it; a chaotic or quasi-periodic set
is the grid cells its recorded points visit, and two such sets are one where they share a cell.
Distances are measured in grid cells (each state divided by its cell width).
"""
from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, field

import numpy as np

from maps.hybrid import HybridState, IntegrationFailure

from ..labels.codes import ClassCode
from ..orbits.periodic import OrbitNotFound, find_periodic_orbit
from ..labels.classify import candidate_periods, classify_orbit, mechanical_period, state_scale
from ..labels.evidence import locked_lag
from ..labels.judge import decide
from ..labels.lyapunov import exponent_interval
from ..labels.vocabulary import MAX_PERIOD

@dataclass(frozen=True)
class Grid:
    """A state-space grid: cell j of state i spans low_i + [j, j+1) width_i (unbounded: any j)."""

    low: np.ndarray
    width: np.ndarray

    @classmethod
    def over(cls, box: dict, system, cells: int, base: np.ndarray) -> "Grid":
        """``cells`` per box side; the states outside the box are not discretised (width inf: one cell), so
        attractors are told apart and matched by the box's states (for the thesis scenes, the bar's)."""
        low = np.asarray(base, dtype=float).copy()
        width = np.full(low.shape, np.inf)
        for k, (lo, hi) in box.items():
            j = system.state_names.index(k)
            if hi > lo:              # a state held fixed (lo = hi) is not discretised
                low[j], width[j] = lo, (hi - lo) / cells
        return cls(low, width)

    def keys(self, points) -> list:
        """The cell of each row of ``points`` as a hashable tuple (NaN rows: None)."""
        p = np.atleast_2d(np.asarray(points, dtype=float))
        ok = np.all(np.isfinite(p), axis=1)
        idx = np.floor((np.where(ok[:, None], p, 0.0) - self.low) / self.width).astype(np.int64)
        return [tuple(r) if g else None for r, g in zip(idx.tolist(), ok)]

    def around(self, points) -> set:
        """The cells of ``points`` and their neighbours (one cell either way along each gridded state)."""
        free = np.flatnonzero(np.isfinite(self.width))
        steps = np.zeros((3 ** len(free), len(self.width)), dtype=np.int64)
        steps[:, free] = list(itertools.product((-1, 0, 1), repeat=len(free)))
        return {tuple(r) for c in self.keys(points) if c is not None for r in (np.asarray(c) + steps).tolist()}

    def scaled(self, points) -> np.ndarray:
        return np.asarray(points, dtype=float) / self.width

    def gridded(self, points) -> np.ndarray:
        """``points`` in cell widths, the gridded states only (those of finite width)."""
        return self.scaled(points)[:, np.isfinite(self.width)]


@dataclass
class Attractor:
    """One attractor at one parameter value: class, periods, impacts, exponent, its points and cells."""

    code: int
    period: int = 0
    period_mechanical: int = 0
    impacts: int = -1
    impacts_mechanical: int = -1
    lyapunov: float = math.nan
    lyapunov_interval: tuple = (math.nan, math.nan)
    max_multiplier: float = math.nan
    points: np.ndarray = None            # (m, d): the polished nodes (periodic) or recorded points
    flags: list = field(default_factory=list)   # flags of each point
    k0: int = 0                          # strobe sample of points[0]
    cells: set = field(default_factory=set)
    min_flight_clearance: float = math.nan
    residual: float = math.nan
    how: str = ""                        # how it was identified
    lifetime: float = math.nan           # non-periodic: mean lifetime on the set [strobe periods] (inf: none fell)
    lifetime_interval: tuple = (math.nan, math.nan)   # its interval (bifurc.attractors.lifetime)
    area_rate: float = math.nan          # non-periodic: sum of the two leading exponents [per period] (area_rate)
    area_rate_interval: tuple = (math.nan, math.nan)  # its 95 % interval
    multiplier_abs: tuple = ()           # periodic, polished: every Floquet multiplier's modulus, largest first
    multiplier_arg: tuple = ()           # and its argument [rad] (the orbit solver's periodic Schur product)
    lifetime_verdict: str = ""           # non-periodic: "attractor", "long-lived" or "saddle" (lifetime.verdict)

    @property
    def periodic(self) -> bool:
        return ClassCode(self.code).periodic

    def label(self) -> str:
        from ..labels.classify import describe
        return describe(self.code, self.period, self.impacts)


def is_flow(smap) -> bool:
    """True when ``smap`` samples an autonomous flow (``HybridSystem.autonomous``; a system without the attribute is
    not one)."""
    return bool(getattr(smap.system, "autonomous", False))


def distance(a: Attractor, b: Attractor, grid: Grid, q: int = 1) -> float:
    """State-space distance [grid cells] between two attractors: for two periodic orbits of one period, the
    largest node distance at the best phase (shifts keeping the forcing's phase, a multiple of q); otherwise
    the symmetric mean nearest-point distance of their point sets."""
    A, B = grid.scaled(a.points), grid.scaled(b.points)
    if a.periodic and b.periodic:
        if a.period != b.period:
            return math.inf
        n = a.period
        best = math.inf
        for s in range(n):
            if q > 1 and (a.k0 - b.k0 - s) % q:
                continue
            best = min(best, float(np.max(np.abs(A[:n] - np.roll(B[:n], -s, axis=0)))))
        return best
    d = np.max(np.abs(A[:, None, :] - B[None, :, :]), axis=2)
    return 0.5 * float(d.min(axis=1).mean() + d.min(axis=0).mean())


def same_attractor(a: Attractor, b: Attractor, grid: Grid, q: int = 1) -> bool:
    """One attractor: periodic orbits whose polished nodes agree at some phase (:func:`same_orbit`: a tolerance
    of the states, so that two orbits within a cell stay two on a coarse grid); other sets sharing a grid cell."""
    if a.periodic and b.periodic:
        return same_orbit(a, b, q)
    if a.periodic != b.periodic:
        return False
    return bool(a.cells & b.cells)


def same_orbit(a: Attractor, b: Attractor, q: int = 1, rtol: float = 1e-6, atol: float = 1e-9) -> bool:
    """Whether two polished periodic orbits of one period are one: every node within rtol of each state's scale
    (plus atol) at some phase (shifts keeping the forcing's phase, a multiple of q).  Newton polishes to 1e-10."""
    if a.period != b.period:
        return False
    n = a.period
    A, B = np.asarray(a.points[:n], dtype=float), np.asarray(b.points[:n], dtype=float)
    tol = rtol * state_scale(np.vstack([A, B]), atol) + atol
    return any(not (q > 1 and (a.k0 - b.k0 - s) % q) and bool(np.all(np.abs(A - np.roll(B, -s, axis=0)) <= tol))
               for s in range(n))


def converging(points, a: Attractor, grid: Grid) -> bool:
    """Whether a trajectory's ``points`` (strobe points, oldest first, at least three periods of ``a``) approach
    the periodic attractor ``a``: the largest distance [cells] of a period's points to the orbit's nearest node
    halves from the first period to the middle one and again to the last, at least at half the rate of the orbit's
    multipliers (:func:`approaching`), or the last is below 1e-6 cells (there already).  A grid-free test that a
    start landing in the orbit's cells is captured, not passing by or settling on another orbit close to it
    (thesis-1dof at 94 V: a 1:6 orbit lies within a cell of 100 per side of the state at rest)."""
    d = _node_distances(points, a, grid)
    n = a.period
    if d is None:
        return False
    m = (len(d) - n) // 2
    start, mid, end = float(d[:n].max()), float(d[m:m + n].max()), float(d[-n:].max())
    return end <= 1e-6 or (end <= 0.5 * mid and mid <= 0.5 * start and _at_its_rate(d, a))


def approaching(points, a: Attractor, grid: Grid) -> bool:
    """Whether ``points`` approach the polished periodic orbit ``a`` at least at half the rate of its largest
    |multiplier| mu: the largest distance [cells] of their last period to its nodes is at most mu^(m/2) times that
    of their first, m the orbit's periods between the two, or below 1e-6 cells (True where mu is unknown: an orbit
    Newton did not polish).  On thesis-1dof at 136 V starts wandering over the stop for 2000 periods halved their
    distance to the state at rest (mu 0.10) twice within a chunk by chance: 10 of 200 outcomes differed between
    grids of 100 and 200 cells per side for it."""
    d = _node_distances(points, a, grid, 2)
    return d is not None and _at_its_rate(d, a)


def _at_its_rate(d, a: Attractor) -> bool:
    """:func:`approaching` from the points' distances ``d`` [cells] to the nodes of ``a``."""
    n, mu = a.period, a.max_multiplier
    first, last = float(d[:n].max()), float(d[-n:].max())
    if last <= 1e-6 or not mu < 1.0:
        return True
    return last <= first * mu ** (0.5 * (len(d) - n) / n)


def _node_distances(points, a: Attractor, grid: Grid, periods: int = 3):
    """Each point's distance [cells] to the nearest node of the periodic orbit ``a`` (None: under ``periods``
    periods of it)."""
    n = a.period
    P, N = grid.scaled(points), grid.scaled(a.points[:n])
    if len(P) < periods * n:
        return None
    return np.max(np.abs(P[:, None, :] - N[None, :, :]), axis=2).min(axis=1)


def identify(smap, orbit, k0: int, grid: Grid, *, max_period: int = MAX_PERIOD, tol: float = 1e-10,
             rtol: float = 1e-6, atol: float = 1e-9, tried: dict | None = None, last: bool = False) -> Attractor | None:
    """The attractor a recorded orbit (a :class:`maps.poincare.MapOrbit` starting at sample ``k0``, with a
    tangent vector) lies on, or None when the record decides nothing yet (a transient).  Its label is the one
    judge's (:func:`bifurc.labels.judge.decide`, as a diagram's value; ``last``: no longer record will follow; a new
    chaotic set's lifetime is the census' own test, :func:`bifurc.attractors.census._persists`); the census adds
    Newton: every record the judge does not call chaotic is tried for a periodic orbit first (a torus' exponent
    about 0 is also a slow approach's)."""
    pts, imp = orbit.points, orbit.impacts_per_step
    q = smap.forcing_period_steps
    stretch = orbit.tangent_stretch(np.maximum(np.nanmax(np.abs(pts), axis=0), atol))
    finite = stretch[np.isfinite(stretch)] if stretch is not None else np.zeros(0)
    lam, lo, hi = exponent_interval(finite) if finite.size else (math.nan, math.nan, math.nan)
    cls = classify_orbit(pts, imp, max_period=max_period, rtol=rtol, atol=atol,
                         periods=candidate_periods(q, max_period))
    verdict = decide(cls, imp, [finite] if finite.size else [], lambda: grid.gridded(pts), can_extend=not last,
                     max_period=max_period, lifetime_tested=True)
    label, how = verdict.label, f"recurrence on the grid; judged {verdict.label} over {len(imp)} periods"
    # an autonomous flow's record judged quasi-periodic is a limit cycle, an invariant circle of the sampled map, no
    # periodic orbit of it but at a period of a whole number of samples: Newton is tried at period 1 only (a slow
    # focus); the modified Lorenz-84 flow at a = 5.2 and 5.6 (1000 starts): 9 polishes at lags up to 100 samples,
    # 41.7 of 56 s, none converged
    circle = label == "quasi-periodic" and is_flow(smap)
    if label != "chaotic":
        for n in itertools.chain(newton_periods(pts, grid, candidate_periods(q, max_period)),
                                 _lag_beyond(pts, grid, q, max_period, label, lam)):
            if circle and n > 1:
                continue
            found = polish_once(smap, orbit, k0, n, grid, tol, rtol, atol, tried)
            if found is not None:
                return found
    if label == "quasi-periodic":
        how += f"; torus evidence: 0-1 test K = {verdict.zero_one:.2f}, rotation number {verdict.rotation:.4f}"
    if label in ("periodic", "periodic-no-impact") and stretch is not None:
        whole = _whole_periods(stretch, int(cls["period"]))
        if whole[2] < 0.0:
            return _unpolished(smap, orbit, k0, cls, grid, whole, rtol, atol)
    if label in ("chaotic", "quasi-periodic"):
        return Attractor(int(ClassCode.of(label)), lyapunov=lam, lyapunov_interval=(lo, hi), points=pts.copy(),
                         flags=[orbit.state(j).flags for j in range(len(pts))], k0=k0,
                         cells={c for c in grid.keys(pts) if c is not None},
                         min_flight_clearance=float(np.min(orbit.min_flight_clearance_per_step)), how=how)
    return None


def _lag_beyond(pts, grid: Grid, q: int, max_period: int, label: str, lam: float):
    """Yields L where an undecided record with a negative exponent recurs at a lag L beyond ``max_period`` (a
    multiple of the forcing's ``q`` samples) to LOCK_TOL of its extent (:func:`bifurc.labels.evidence.locked_lag`, on
    the gridded states, lags up to a quarter of the record): a stable orbit of period L for Newton to polish.
    Thesis-1dof (`matlab-listing`, `listing`, 10 Hz, 160 V): 16 % of the switch-on starts were not_converged,
    "contracting (exponent -0.033) yet no period up to 16", on a stable period-18 orbit with 10 impacts (largest
    |multiplier| 0.52) that their records repeat to 4e-11 of their extent."""
    if label == "not-converged" and lam < 0.0:
        lag = locked_lag(grid.gridded(pts))[0]
        if lag > max_period and lag % q == 0:
            yield lag


def _whole_periods(stretch, n: int) -> tuple[float, float, float]:
    """(exponent, low, high) [per strobe period] of a period-n record from its tangent stretch summed over whole
    periods (the stretch within a period varies with the phase; over whole periods it repeats): NaN bounds with
    fewer than 4 whole periods."""
    s = np.asarray(stretch, dtype=float)
    m = len(s) // n * n
    if not m or not np.all(np.isfinite(s[len(s) - m:])):
        return math.nan, math.nan, math.nan
    return exponent_interval(s[len(s) - m:].reshape(-1, n).sum(axis=1) / n)


def _unpolished(smap, orbit, k0, cls: dict, grid: Grid, exponent: tuple, rtol: float, atol: float) -> Attractor:
    """A record that repeats with period n to ``rtol`` of each state's scale over all its points
    (:func:`bifurc.labels.classify.classify_orbit`), whose tangent exponent's interval over whole periods
    (:func:`_whole_periods`) lies below 0, where Newton did not converge: a periodic attractor all the same, its
    nodes the record's last n points (as close as the record repeats), its exponent the record's tangent estimate,
    its multipliers unknown (NaN).  (A record of a neutral centre, every orbit around it periodic, has an exponent
    about 0 and is not an attractor.)  On thesis-1dof (`measured`, 10 Hz) at 94 V, 17 of 200 box starts sit on a
    chattering period-6 orbit with 50 impacts that repeats to 1e-10 from 500 periods on and that Newton does not
    polish; they were "not_converged"."""
    pts, imp, n = orbit.points, orbit.impacts_per_step, int(cls["period"])
    j = len(pts) - 1 - n
    pm, mm, _ = mechanical_period(pts, imp, n, smap.system.mechanical_index, rtol=rtol, atol=atol,
                                  impacts=int(cls["impacts_per_period"]))
    lam, lo, hi = exponent
    return Attractor(int(cls["code"]), n, pm, int(cls["impacts_per_period"]), mm, lyapunov=lam,
                     lyapunov_interval=(lo, hi), points=pts[j:j + n].copy(),
                     flags=[orbit.state(i).flags for i in range(j, j + n)], k0=k0 + j,
                     cells={c for c in grid.keys(pts[j:]) if c is not None}, min_flight_clearance=_min_flight(orbit),
                     residual=math.nan,
                     how=f"recurrence on the grid; the record repeats with period {n} to {cls['recurrence']:.2g} x "
                         f"{rtol:g} of each state's scale over {len(imp)} periods; Newton did not converge: not "
                         f"polished, multipliers unknown, exponent from the record's tangent vector")


def no_contraction(low, high):
    """Whether area-rate intervals [low, high] contain 0 to AREA_ATOL (numbers or arrays): no area contraction shown."""
    return (low - AREA_ATOL <= 0.0) & (high + AREA_ATOL >= 0.0)


#: |area rate| [per strobe period] taken as 0: the integration's round-off (one period of an undamped linear
#: oscillator at tol 1e-10: rate 4.8e-12)
AREA_ATOL = 1e-6

#: periods of a record left out of :func:`area_rate` while the tangent plane aligns with the leading directions
AREA_SKIP = 8


def area_rate(smap, orbit, k0: int, skip: int = AREA_SKIP, steps: int | None = None) -> tuple[float, float, float]:
    """(rate, low, high): the sum of the two leading Lyapunov exponents [per strobe period] on a recorded set, the
    mean log growth of a tangent plane carried by the exact one-period Jacobians at the record's states (QR, each
    state in units of its largest size on the record), after ``skip`` periods that align the plane, with the 95 %
    batch-means interval of :func:`bifurc.labels.lyapunov.exponent_interval`.  Below 0: the set contracts areas (an attractor of a
    dissipative map has a negative sum); an interval about 0: no contraction shown, as on the invariant tori of an
    area-preserving map (thesis-1dof under the `listing` law at 90 V, 10 Hz: with no impact the bar's multipliers'
    product is 1, the circuit's states contract alone; with impacts 0.96 per period).  ``steps``: the record's first
    ``steps`` periods only (None: all).  NaN where a step fails."""
    P = np.asarray(orbit.points, dtype=float)
    scale = np.maximum(np.nanmax(np.abs(P), axis=0), 1e-9)     # each state in units of its size on the set
    s, Q = [], None
    try:
        for j in range(len(P) - 1 if steps is None else min(len(P) - 1, steps)):
            J = smap.linearize(orbit.state(j), k0 + j).J / scale[:, None] * scale[None, :]
            Q = np.eye(J.shape[0])[:, :2] if Q is None else Q
            Q, R = np.linalg.qr(J @ Q)
            with np.errstate(divide="ignore"):         # a map constant along a direction: -inf, contraction to 0
                s.append(float(np.sum(np.log(np.abs(np.diag(R))))))
    except (IntegrationFailure, ValueError, ZeroDivisionError, np.linalg.LinAlgError):
        return math.nan, math.nan, math.nan
    return exponent_interval(np.asarray(s[skip:]))


def from_chunk(smap, orbit, k0: int, grid: Grid, found: list, *, max_period: int = MAX_PERIOD, tol: float = 1e-10,
               rtol: float = 1e-6, atol: float = 1e-9, tried: dict | None = None, newton: str = "near"):
    """A recurring start's attractor from its last chunk (a bare :class:`maps.poincare.MapOrbit` from sample
    ``k0``): the index in ``found`` of a periodic attractor within two cells of its last n points at some
    phase that they approach (:func:`converging`), else its period-n orbit polished by Newton (a new
    :class:`Attractor`), else None (record it); n the periods of :func:`newton_periods`.
    ``newton="contracting"``: Newton only at a near period n where the chunk contracts
    (:func:`contracting`; a start on a known chaotic saddle, whose near returns are chance)."""
    pts, q = orbit.points, smap.forcing_period_steps
    near = newton_periods(pts, grid, candidate_periods(q, max_period))
    for n in near:
        tail = Attractor(int(ClassCode.PERIODIC), n, points=pts[len(pts) - n:], k0=k0 + len(pts) - n)
        for j, b in enumerate(found):
            close = b.periodic and b.period == n and distance(tail, b, grid, q) <= 2.0
            if close and converging(pts, b, grid):
                return j
    for n in near:
        if newton == "contracting" and not contracting(pts, grid, n):
            continue
        got = polish_once(smap, orbit, k0, n, grid, tol, rtol, atol, tried)
        if got is not None:
            return got
    return None


def contracting(pts, grid: Grid, n: int, factor: float = 0.5, close: float = 0.05) -> bool:
    """Whether a record's points approach a period-n orbit: the largest distance [cells] of its last n points
    to the points n before is at most ``factor`` times that of its first n points, or smaller than theirs and
    below ``close`` cells (a slow approach, multiplier near 1, gets there within a few chunks), or below 1e-6
    cells (there already, to round-off).  On thesis-1dof at 122, 129, 192 and 199 V every chunk from which
    Newton found a stable orbit shrank so, to 0.2515 or less; at 122 and 129 V five in six from which it failed, a
    chaotic saddle's chance near returns, did not (at 199 V most did) (benchmarks/reports/census-diagnostics)."""
    P = grid.scaled(pts)
    if len(P) < 2 * n + 1:
        return False
    d = np.max(np.abs(P[n:] - P[:-n]), axis=1)
    first, last = float(np.max(d[:n])), float(np.max(d[-n:]))
    return last <= 1e-6 or last <= factor * first or (last < first and last <= close)


def polish_once(smap, orbit, k0, n, grid, tol, rtol, atol, tried: dict | None):
    """:func:`_polish`, unless Newton already failed at period n from the cell of this record's last point for a
    record that repeated about as closely (``tried``: the census' {(n, cell): (mismatch [cells] of the failed
    record's last n points against the n before, failures)}, so that Newton runs about once per distinct
    attractor; a record repeating RETRY_CLOSER times more closely is tried again, up to RETRIES failures: a start
    at rest in the cell where a chattering transient's Newton failed)."""
    key = (n, grid.keys(orbit.points[-1:])[0])
    P = grid.scaled(orbit.points[-2 * n:]) if 2 * n < len(orbit.points) else None
    mismatch = float(np.max(np.abs(P[n:] - P[:n]))) if P is not None else math.inf
    before = tried.get(key) if tried is not None else None
    if before is not None and (before[1] >= RETRIES or not mismatch * RETRY_CLOSER < before[0]):
        return None
    unstable: list = []
    a = _polish(smap, orbit, k0, n, grid, tol, rtol, atol, unstable)
    if a is None and tried is not None:
        tried[key] = (min(mismatch, before[0]), before[1] + 1) if before else (mismatch, 1)
        # an unstable orbit found is noted in the cells about its nodes too (where no failure is noted yet): a record
        # nearing it at another phase would find it again, unless it repeats RETRY_CLOSER times more closely (a
        # stable orbit beside it; thesis-1dof, 200 box starts: at 192 V, 101 Newton runs found a few unstable
        # period-3, 6 and 9 orbits, 35 with this note, the outcomes unchanged: newton-calls-*.txt)
        for c in grid.around(unstable[0]) if unstable else ():
            tried.setdefault((n, c), (mismatch, 1))
    return a


#: how many times more closely a record must repeat for Newton to be tried again where it failed, and how often
RETRY_CLOSER, RETRIES = 10.0, 3


def _min_flight(orbit) -> float:
    m = orbit.min_flight_clearance_per_step
    return float(np.min(m)) if len(m) else math.nan


def near_periods(pts, grid: Grid, periods) -> list:
    """The candidate periods n (ascending) at which the record's last n points recur within two grid cells."""
    return [n for n, _ in _mismatches(pts, grid, periods)]


def _mismatches(pts, grid: Grid, periods) -> list:
    """(n, mismatch) for the candidate periods n (ascending) at which the record's last n points recur within two
    grid cells, the mismatch being their largest distance [cells] to the n points before."""
    P = grid.scaled(pts)
    N = len(P)
    out = [(n, float(np.max(np.abs(P[N - n:] - P[N - 2 * n:N - n])))) for n in periods if 2 * n < N]
    return [(n, m) for n, m in out if m <= 2.0]


def newton_periods(pts, grid: Grid, periods) -> list:
    """The periods at which Newton is tried from a record: its two shortest near periods (:func:`near_periods`; a
    stable period-2 orbit close to its period doubling also nearly repeats after one period, where Newton finds the
    unstable period-1 orbit), and the shortest longer near period at which it repeats CLOSER times more closely than
    at both (the shortest: on an orbit reached to round-off every multiple of its period repeats about as closely,
    and Newton over a multiple is a larger system that may fail where the period's does).  Thesis-1dof
    (`matlab-listing`, `measured`, 10 Hz) at 211.5 V: starts approaching a stable 4:8 orbit (largest |multiplier|
    0.976, born at the 2:4 orbit's doubling) repeat after 2 periods to 3e-4 cells, where Newton finds the unstable
    2:4 orbit, and after 4 far more closely; tried at 1 and 2 only, 125 of 1000 starts were "not_converged"."""
    near = _mismatches(pts, grid, periods)
    out = [n for n, _ in near[:2]]
    if len(near) > 2:
        bar = min(m for _, m in near[:2]) / CLOSER
        out += [n for n, m in near[2:] if m < bar][:1]
    return out


#: how many times more closely a record must repeat at a longer near period for Newton to be tried there too
CLOSER = 10.0


def _polish(smap, orbit, k0, n, grid, tol, rtol, atol, unstable: list | None = None) -> Attractor | None:
    """The period-n orbit through the record's last point polished by Newton, if it converges, is stable and
    lies within two cells of the record (else None: not this trajectory's attractor; the nodes of an unstable one
    found are appended to ``unstable``)."""
    j = len(orbit.points) - 1 - n     # the last whole period of the record
    if j < 0:                         # a chunk shorter than the period (an orbit found beyond the search)
        return None
    try:
        po = find_periodic_orbit(smap, orbit.state(j), n, k0=k0 + j, tol=tol, atol=atol, max_iter=NEWTON_ITER)
        nodes = np.array([s.y for s in po.nodes])
        d = _least_period(nodes, smap.forcing_period_steps, rtol, atol)
        if d < n:                     # a period-d orbit traversed n / d times: polished again as what it is
            n, j = d, len(orbit.points) - 1 - d
            po = find_periodic_orbit(smap, po.nodes[0], d, k0=po.k0, tol=tol, atol=atol, max_iter=NEWTON_ITER)
            nodes = np.array([s.y for s in po.nodes])
    except (OrbitNotFound, IntegrationFailure, ZeroDivisionError, ValueError):
        return None
    if not po.stable:
        if unstable is not None:
            unstable.append(nodes)
        return None
    if np.max(np.abs(grid.scaled(nodes) - grid.scaled(orbit.points[j:j + n]))) > 2.0:
        return None
    mu = float(np.max(np.abs(po.multipliers)))
    if not approaching(orbit.points, Attractor(int(ClassCode.PERIODIC), n, max_multiplier=mu, points=nodes), grid):
        return None          # a stable orbit beside the record, not the one it settles on
    mech = smap.system.mechanical_index
    m = po.impacts_per_period
    # the mechanical period from the polished nodes repeated three times (exact recurrence)
    rep = np.vstack([nodes] * 3 + [nodes[:1]])
    imp = np.array([sig.count("impact") for sig in po.signatures] * 3)
    pm, mm, _ = mechanical_period(rep, imp, n, mech, rtol=rtol, atol=atol, impacts=m)
    code = ClassCode.PERIODIC if m > 0 else ClassCode.PERIODIC_NO_IMPACT
    return Attractor(int(code), n, pm, m, mm, lyapunov=math.log(mu) / n if mu > 0 else -math.inf,
                     max_multiplier=mu, points=nodes, flags=[dict(s.flags or {}) for s in po.nodes],
                     **multiplier_fields(po.multipliers),
                     k0=po.k0, cells={c for c in grid.keys(np.vstack([nodes, orbit.points[j:]])) if c is not None},
                     min_flight_clearance=_min_flight(orbit),
                     residual=float(po.residual),
                     how=f"recurrence on the grid, then Newton (residual {po.residual:.2g}, "
                         f"{po.iterations} iterations)")


def multiplier_fields(mu) -> dict:
    """The Attractor fields of the Floquet multipliers ``mu``: moduli and arguments [rad], largest modulus first."""
    mu = np.asarray(mu, dtype=complex)
    mu = mu[np.argsort(-np.abs(mu), kind="stable")]
    return {"multiplier_abs": tuple(float(x) for x in np.abs(mu)),
            "multiplier_arg": tuple(float(x) for x in np.angle(mu))}


def _least_period(nodes, q: int, rtol: float, atol: float) -> int:
    """The least d dividing the node count n (a multiple of the forcing's ``q`` samples) after which the nodes
    repeat, each state within ``rtol`` of its scale (plus ``atol``) as :func:`same_orbit` compares orbits (n itself
    if none): thesis-1dof at 164 V, Newton at period 2 from a start settling on the 1:1 orbit converged to that orbit
    traversed twice, and the census listed a 2:2 attractor beside it."""
    n = len(nodes)
    tol = rtol * state_scale(nodes, atol) + atol
    return next(d for d in range(1, n + 1) if n % d == 0 and d % q == 0
                and np.all(np.abs(nodes[d:] - nodes[:-d]) <= tol))


#: Newton iterations allowed when polishing a recurring start's orbit: it starts within two cells of the orbit,
#: so more mean it is not there (a far guess cost minutes of chattering steps on thesis-1dof at 171 V)
NEWTON_ITER = 10


def representative(a: Attractor) -> HybridState:
    """A state on the attractor (its first point, with its flags) to seed the next parameter value from."""
    return HybridState(np.asarray(a.points[0], dtype=float).copy(), dict(a.flags[0]) if a.flags else None)
