"""The census at one parameter value: every start followed on the batch engine until it lands on a
known attractor or recurs on the state-space grid, then the new attractor identified.

The recurrence test follows the design of Attractors.jl's ``AttractorsViaRecurrences`` (Datseris and
Wagemakers 2022), written anew for hybrid maps: each start is iterated in chunks of ``chunk`` strobe
periods (one batch call for all active starts); each strobe point falls in a grid cell; a start whose
``land`` consecutive points lie in the cells of one known attractor is counted for it (early stop);
one whose ``recur`` consecutive points fall in cells it visited before has found an attractor: it is
recorded ``locate`` more periods with a tangent vector, classified (:mod:`bifurc.sweeps.classify`),
polished by Newton where periodic and matched against the attractors already found (:mod:`.identify`).
A start that escapes or fails is that outcome; one still undecided after ``max_periods`` is
"not_converged".
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from maps.hybrid import HybridState

from .identify import Attractor, Grid, from_chunk, identify, same_attractor

__all__ = ["Settings", "Track", "census_at", "OUTCOMES"]

#: outcome ids of a start that reached no attractor (attractor ids are 0, 1, ...)
OUTCOMES = {"escaped": -1, "not_converged": -2, "failed": -3}


@dataclass(frozen=True)
class Settings:
    """Census settings: periods per chunk, consecutive points to land or recur, periods recorded to
    identify, the budget per start [strobe periods], the period search, Newton's tolerance, SIMD lanes and
    the records (``locate`` periods each) after which a start still undecided is "not_converged"."""

    chunk: int = 20
    land: int = 6
    recur: int = 20
    locate: int = 48
    max_periods: int = 2000
    max_period: int = 16
    newton_tol: float = 1e-10
    batch_size: int = 4
    max_tries: int = 6


@dataclass
class Track:
    """One start being followed: its hybrid state at sample ``k``, the cells it visited, its counters."""

    state: object
    k: int = 0
    visits: set = field(default_factory=set)
    recur: int = 0
    land_id: int = -1
    land: int = 0
    tries: int = 0
    outcome: int | None = None
    periods: int = 0
    last: object = None


def _step_cells(t: Track, keys: list, owner: dict, s: Settings) -> str:
    """Walk the new points' cells: 'land' (outcome set), 'recur' (an attractor found) or ''."""
    for key in keys:
        aid = owner.get(key)
        if aid is not None:
            t.land = t.land + 1 if aid == t.land_id else 1
            t.land_id = aid
            if t.land >= s.land:
                t.outcome = aid
                return "land"
        else:
            t.land, t.land_id = 0, -1
        t.recur = t.recur + 1 if key in t.visits else 0
        t.visits.add(key)
        if t.recur >= s.recur:
            return "recur"
    return ""


def census_at(smap, starts: list, grid: Grid, settings: Settings, *, k0=0,
              known: list | None = None, progress=None) -> tuple[list, list[Attractor], list]:
    """Follow ``starts`` (states or HybridStates, from sample ``k0``: an int or one per start) under
    ``smap``'s parameters; returns (outcome per start: an attractor's index in
    the list returned, or an :data:`OUTCOMES` id; the attractors found; the strobe periods each start was
    integrated).  The chunks run as a bare ensemble (strobe points only, ``events=False``); a start that recurs
    is identified from its last chunk: by a known periodic attractor within two cells, else by Newton (once per
    distinct attractor), else by a record with a tangent vector (chaotic and quasi-periodic sets)."""
    s = settings
    ks = k0 if isinstance(k0, (list, tuple)) else [k0] * len(starts)
    tracks = [Track(st, int(k)) for st, k in zip(starts, ks)]
    found: list[Attractor] = list(known or [])
    owner: dict = {c: i for i, a in enumerate(found) for c in a.cells}
    tried: set = set()          # (period, cell) where Newton failed
    active = list(range(len(tracks)))
    while active:
        orbits = smap.orbits([{}] * len(active), [tracks[i].state for i in active], s.chunk,
                             k0=[tracks[i].k for i in active], batch_size=s.batch_size, events=False)
        keys = _chunk_keys(grid, orbits)
        candidates = []
        for i, o, kk in zip(active, orbits, keys):
            t = tracks[i]
            if o.status != "ok":
                t.outcome = OUTCOMES["escaped" if o.status == "escaped" else "failed"]
                continue
            what = _step_cells(t, kk, owner, s)
            t.last, t.state, t.k, t.periods = o, o.final, t.k + s.chunk, t.periods + s.chunk
            if what == "recur":
                candidates.append(i)
        _identify_candidates(smap, tracks, candidates, grid, s, found, owner, tried)
        for i in active:
            t = tracks[i]
            if t.outcome is None and t.periods >= s.max_periods:
                t.outcome = OUTCOMES["not_converged"]
        done = [i for i in active if tracks[i].outcome is not None]
        if progress is not None and done:
            progress(len(done))
        active = [i for i in active if tracks[i].outcome is None]
    return [t.outcome for t in tracks], found, [t.periods for t in tracks]


def _chunk_keys(grid: Grid, orbits) -> list:
    """The grid cells of every chunk's new points, in one numpy pass over the whole ensemble."""
    rows = [o.points[1:] for o in orbits]
    if not rows:
        return []
    flat = grid.keys(np.vstack(rows))
    out, a = [], 0
    for r in rows:
        out.append(flat[a:a + len(r)])
        a += len(r)
    return out


def _register(a: Attractor, found: list, owner: dict, grid: Grid, q: int) -> int:
    """The index of ``a`` among ``found`` (appended if new); its cells are owned from now on."""
    match = next((j for j, b in enumerate(found) if same_attractor(a, b, grid, q)), None)
    if match is None:
        found.append(a)
        match = len(found) - 1
    else:
        found[match].cells |= a.cells
    for c in a.cells:
        owner.setdefault(c, match)
    return match


def _identify_candidates(smap, tracks, candidates, grid, s: Settings, found: list, owner: dict,
                         tried: set) -> None:
    """Identify each recurring start from its last chunk (known orbit, or Newton once per distinct
    attractor); the rest are recorded ``locate`` periods with a tangent vector (one batch call)."""
    q = smap.forcing_period_steps
    rest = []
    for i in candidates:
        t = tracks[i]
        got = from_chunk(smap, t.last, t.k - s.chunk, grid, found, max_period=s.max_period, tol=s.newton_tol,
                         tried=tried)
        if got is None:
            rest.append(i)
        else:
            t.outcome = got if isinstance(got, int) else _register(got, found, owner, grid, q)
    if not rest:
        return
    recs = smap.orbits([{}] * len(rest), [tracks[i].state for i in rest], s.locate,
                       k0=[tracks[i].k for i in rest], batch_size=s.batch_size, tangent=True)
    for i, o in zip(rest, recs):
        t = tracks[i]
        if o.status != "ok":
            t.outcome = OUTCOMES["escaped" if o.status == "escaped" else "failed"]
            continue
        a = identify(smap, o, t.k, grid, max_period=s.max_period, tol=s.newton_tol, tried=tried)
        t.state, t.k, t.periods = o.final, t.k + s.locate, t.periods + s.locate
        t.recur, t.visits = 0, set()
        if a is None:
            t.tries += 1
            if t.tries >= s.max_tries:       # recorded max_tries times and never decided
                t.outcome = OUTCOMES["not_converged"]
            continue
        t.outcome = _register(a, found, owner, grid, q)


def wilson(k, n, z: float = 1.959963984540054) -> tuple[float, float]:
    """Wilson score interval of a binomial proportion k/n (95 % by default)."""
    if n <= 0:
        return math.nan, math.nan
    p = k / n
    den = 1 + z * z / n
    centre = (p + z * z / (2 * n)) / den
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / den
    return max(0.0, centre - half), min(1.0, centre + half)


def hybrid(y, flags=None) -> HybridState:
    return HybridState(np.asarray(y, dtype=float), flags)
