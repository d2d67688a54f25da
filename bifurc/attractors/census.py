"""The census at one parameter value: every start followed on the batch engine until it lands on a known
attractor or recurs on the state-space grid, then the new attractor identified.

The recurrence test follows the design of Attractors.jl's ``AttractorsViaRecurrences`` (Datseris and
Wagemakers 2022), written anew for hybrid maps: each start is iterated in chunks of ``chunk`` strobe periods
(one batch call for all active starts); each strobe point falls in a grid cell; a start whose ``land``
consecutive points lie in the cells of one known attractor is counted for it (early stop); one whose ``recur``
consecutive points fall in cells it visited before has found an attractor. A recurring start whose last chunk
repeats with a period is identified at once (a known periodic orbit, or Newton: a stable polished orbit). Of
one that recurs without a period, the chunk sharing cells with a known non-periodic attractor counts for it
(one exponent per set, not per start); one on a known chaotic saddle runs on (there Newton is tried only where
the chunk contracts, :func:`.identify.contracting`: the saddle's near returns are chance); the rest are recorded
``locate`` periods with a tangent vector and classified (:mod:`bifurc.labels.classify`). A start's path is its
chunks from its start, whatever the census decides: a record runs beside it (its tangent vector changes the step
sizes, and on a chaotic saddle a start's fate hangs on such differences: thesis-1dof at 136 V, 44 of 200 outcomes
differed between grids of 100 and 200 cells per side while records placed by the grid were part of the paths), and
a periodic orbit a record finds counts a start only once its own path lands there. A new non-periodic set is
an attractor only if its mean lifetime, estimated from perturbed copies started on it, surely exceeds ``persist``
periods (:func:`_persists`, :mod:`.lifetime`); else it is a chaotic saddle or a long-lived chaotic transient (its
lifetime stored on it), and its starts run on to where they settle.  So whether a start ends chaotic, periodic
or not converged does not hinge on when the grid's cells happened to recur.  A start that escapes or fails is that
outcome; one still on a saddle at ``max_periods`` is "transient" (where such starts go: :mod:`.eventual`); a start
whose ``max_tries`` records decide nothing runs on as on a saddle if its set's lifetime is surely below ``persist``
(:func:`_undecided_transient`); one otherwise undecided after ``max_periods`` or ``max_tries`` undecided records (or
on the cells of a start that was) is "not_converged".
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from maps.hybrid import HybridState, IntegrationFailure

from ..labels.codes import OUTCOMES, ClassCode
from ..labels.vocabulary import BUDGET, MAX_PERIOD
from ..labels.classify import candidate_periods
from ..labels.lyapunov import exponent_interval
from .lifetime import Lifetime, estimate_lifetime, periodic_tail
from .identify import (AREA_SKIP, Attractor, Grid, approaching, area_rate, contracting, converging, from_chunk,
                       identify, is_flow, newton_periods, no_contraction, polish_once, same_attractor, same_orbit)



@dataclass(frozen=True)
class Settings:
    """Census settings: periods per chunk, consecutive points to land or recur, periods recorded to
    identify, the budget per start [strobe periods], the period search, Newton's tolerance, SIMD lanes,
    the records (``locate`` periods, doubled at each undecided one) after which a start still undecided is
    "not_converged", and the mean lifetime [strobe periods] that a new non-periodic set's interval must lie above
    for the set to be an attractor (:func:`_persists`; also the periods its copies run at most), and whether a start
    that enters a chaotic saddle whose exits the copies measured stops there (``apportion``: :func:`copy_exits`)."""

    chunk: int = 40
    land: int = 6
    recur: int = 20
    locate: int = 48
    max_periods: int = BUDGET
    max_period: int = MAX_PERIOD
    newton_tol: float = 1e-10
    batch_size: int = 4
    max_tries: int = 6
    persist: int = 4000
    apportion: bool = False


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
    last_keys: list = field(default_factory=list)
    quiet_until: int = 0         # no record before this age: the last one was on a chaotic saddle
    checked: int = 0             # its age when it was last a candidate (:data:`WANDER`)
    saddle: object = None        # the chaotic saddle (an :class:`Attractor` of Memory.saddles) it was last seen on


@dataclass
class Memory:
    """What one value's census learnt besides its attractors: {(period, cell): (mismatch, failures)} where Newton
    failed (:func:`.identify.polish_once`), the chaotic saddles and long-lived transients (non-periodic sets whose
    lifetime is not surely above the horizon), the cells of starts recorded ``max_tries`` times without a
    decision, and for each start the index in ``saddles`` of the saddle it was last seen on (-1: none); with
    ``apportion``, each saddle's fallen lifetime copies (``ends``, by the saddle's id) and where they went (``exits``:
    per saddle, an attractor's index or an :data:`OUTCOMES` id per fallen copy, :func:`copy_exits`); and where its
    CPU time went (``cpu``, :data:`STAGES`)."""

    tried: dict = field(default_factory=dict)
    saddles: list = field(default_factory=list)
    undecided: list = field(default_factory=list)
    via: list = field(default_factory=list)
    ends: dict = field(default_factory=dict)
    exits: list = field(default_factory=list)
    cpu: dict = field(default_factory=lambda: dict.fromkeys(STAGES, 0.0))


#: the stages of a census whose CPU seconds [s] :attr:`Memory.cpu` sums (:func:`time.process_time` of the process
#: running it): "chunks", the bare ensemble of the starts' chunks (strobe points only); "identify", everything else
#: per chunk: the cells walked, landings checked, Newton, the records with a tangent vector and the lifetime copies
#: of new non-periodic sets; "exits", where a measured saddle's fallen copies go (``apportion`` only)
STAGES = ("chunks", "identify", "exits")


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
              known: list | None = None, progress=None,
              memory: Memory | None = None) -> tuple[list, list[Attractor], list]:
    """Follow ``starts`` (states or HybridStates, from sample ``k0``: an int or one per start) under
    ``smap``'s parameters; returns (outcome per start: an attractor's index in
    the list returned, or an :data:`OUTCOMES` id; the attractors found; the strobe periods of each start's path,
    records run beside it not counted).  The chunks run as a bare ensemble (strobe points only, ``events=False``); a start that recurs
    is identified from its last chunk: by a known periodic attractor within two cells, else by Newton (once per
    distinct attractor), else by a record with a tangent vector (chaotic and quasi-periodic sets).  ``memory``
    (a :class:`Memory`, filled) shows what else was learnt: the saddles and long-lived transients with their
    lifetimes."""
    s = settings
    ks = k0 if isinstance(k0, (list, tuple)) else [k0] * len(starts)
    tracks = [Track(st, int(k)) for st, k in zip(starts, ks)]
    found: list[Attractor] = list(known or [])
    owner: dict = {c: i for i, a in enumerate(found) for c in a.cells}
    mem = Memory() if memory is None else memory
    at_once = ACTIVE if is_flow(smap) else len(tracks)   # see ACTIVE
    active, waiting = list(range(min(at_once, len(tracks)))), min(at_once, len(tracks))
    near = candidate_periods(smap.forcing_period_steps, s.max_period)
    while active:
        clock = time.process_time()                                             # stage CPU (Memory.cpu)
        orbits = smap.orbits([{}] * len(active), [tracks[i].state for i in active], s.chunk,
                             k0=[tracks[i].k for i in active], batch_size=s.batch_size, events=False)
        mid = time.process_time()                                               # stage CPU (Memory.cpu)
        mem.cpu["chunks"] += mid - clock                                        # stage CPU (Memory.cpu)
        keys = _chunk_keys(grid, orbits)
        candidates = []
        for i, o, kk in zip(active, orbits, keys):
            t = tracks[i]
            if o.status != "ok":
                t.outcome = OUTCOMES["escaped" if o.status == "escaped" else "failed"]
                continue
            what = _step_cells(t, kk, owner, s)
            t.last, t.last_keys, t.state, t.k, t.periods = o, kk, o.final, t.k + s.chunk, t.periods + s.chunk
            if what == "land" and found[t.outcome].periodic and not converging(o.points, found[t.outcome], grid):
                _landing_checked(smap, t, found, owner, grid, s, mem)
            elif what == "land" and not found[t.outcome].periodic and periodic_tail(o.points[s.chunk // 2:], near):
                # a chunk whose second half repeats does not land on a chaotic set sharing its cells: it is identified
                # (a bar at rest on the stop at 192 V, in the cell of a chaotic set that rests there with another current)
                t.outcome, t.land, t.land_id, what = None, 0, -1, "recur"
            if what == "" and t.periods - t.checked >= WANDER * s.chunk and t.periods >= t.quiet_until:
                what = "recur"       # wandering over new cells: identified from its chunk or a record all the same
            if what == "recur":
                t.checked = t.periods
                candidates.append(i)
        _identify_candidates(smap, tracks, candidates, grid, s, found, owner, mem)
        for i in active:
            t = tracks[i]
            if s.apportion and t.outcome is None and t.saddle is not None and mem.ends.get(id(t.saddle)):
                t.outcome = OUTCOMES["transient"]       # on a saddle whose exits are measured: apportioned by them
            if t.outcome is None and t.periods >= s.max_periods:
                t.outcome = OUTCOMES["transient" if _still_on_saddle(t, mem.saddles, near) else "not_converged"]
        done = [i for i in active if tracks[i].outcome is not None]
        if progress is not None and done:
            progress(len(done))
        active = [i for i in active if tracks[i].outcome is None]
        if waiting < len(tracks) and len(active) < at_once:         # the next starts join as others end
            more = min(len(tracks), waiting + at_once - len(active))
            active, waiting = active + list(range(waiting, more)), more
        mem.cpu["identify"] += time.process_time() - mid                        # stage CPU (Memory.cpu)
    mem.via = [next((j for j, sd in enumerate(mem.saddles) if sd is t.saddle), -1) for t in tracks]
    if s.apportion:
        clock = time.process_time()                                             # stage CPU (Memory.cpu)
        mem.exits = [copy_exits(smap, mem.ends.get(id(sd), ()), grid, s, found, owner, mem) for sd in mem.saddles]
        mem.cpu["exits"] += time.process_time() - clock                         # stage CPU (Memory.cpu)
    return [t.outcome for t in tracks], found, [t.periods for t in tracks]


#: starts followed at once: the next ones join as others end, so that the attractors the first starts found are
#: known before most starts begin (a start then stops as soon as its path lands on one) instead of every start
#: wandering ``WANDER`` chunks before the first record (modified Lorenz-84 flow, docs/howto/autonomous-flows.md,
#: a = 4.7, 5.0, 5.5 with 100 starts each: 501 samples per start on average, 278 with 32 at once, the same fractions;
#: with 1000 starts at 4.7 and 5.0: 115 and 74).  A start's path does not depend on when it runs: its chunks are the
#: same; its outcome can (it stops where it lands on a set found earlier).  Autonomous flows (``sample_step``) only:
#: on thesis-1dof (10 Hz, V = 100, 136, 180, 60 starts, seed 1) it moved 160 of 180 starts' attractor indices and
#: the fractions (transients at the 2000-period budget became orbits; one orbit of 2 starts was no longer found),
#: and the census' checks there (885/885 orbits recovered, 36/36 links) were made following every start at once.
ACTIVE = 32

#: chunks after which a start that has neither landed nor recurred is identified all the same: one that fills an
#: area of the states without recurring on the grid (thesis-1dof under `listing` at 90 V, 10 Hz: 1000-1800 cells of
#: 100 per box side in 2000 periods, the bar swinging up to 125 mm: a chaotic layer of its undamped flight) is
#: recorded instead of running to ``max_periods``
WANDER = 10


def _landing_checked(smap, t: Track, found: list, owner: dict, grid, s: Settings, mem: Memory) -> None:
    """A start landed in a periodic orbit's cells without approaching it geometrically: passing by (it runs on),
    unless its whole chunk stayed in those cells; then Newton from its chunk decides: another stable orbit
    close to it (registered: thesis-1dof at 94 V, a 1:6 orbit within a cell of 100 per side of the state at
    rest), else the orbit it landed on (a slow or chattering approach: at 115 V, chattering on the stop) if the
    chunk approaches it at its multipliers' rate (:func:`.identify.approaching`), else it runs on."""
    aid = t.outcome
    t.outcome, t.land, t.land_id = None, 0, -1
    if not all(owner.get(key) == aid for key in t.last_keys):
        return
    got = polish_once(smap, t.last, t.k - s.chunk, found[aid].period, grid, s.newton_tol, 1e-6, 1e-9, mem.tried)
    if got is None:
        t.outcome = aid if approaching(t.last.points, found[aid], grid) else None
    elif same_orbit(got, found[aid], smap.forcing_period_steps):
        t.outcome = aid
    else:
        t.outcome = _register(got, found, owner, grid, smap.forcing_period_steps)


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


def copy_exits(smap, ends, grid: Grid, s: Settings, found: list, owner: dict, mem: Memory) -> list:
    """Where each fallen lifetime copy of a saddle went (``ends``: :attr:`.lifetime.Lifetime.ends`, each copy's last
    leg and the sample it started at): its outcome's id if it escaped or failed, else the periodic attractor its leg
    settled on (:func:`.identify.from_chunk`: a known one within two cells, else Newton, the orbit registered among
    ``found``), else "not_converged".  The saddle's exit distribution: a trajectory that has stayed on a saddle
    leaves it by its conditionally invariant measure's escaping part, whatever its start (:mod:`.eventual`), so the
    copies' exits stand for every start stopped on it (``Settings.apportion``)."""
    q, out = smap.forcing_period_steps, []
    for o, k in ends:
        if o.status != "ok":
            out.append(OUTCOMES["escaped" if o.status == "escaped" else "failed"])
            continue
        got = from_chunk(smap, o, k, grid, found, max_period=s.max_period, tol=s.newton_tol, tried=mem.tried)
        out.append(OUTCOMES["not_converged"] if got is None else
                   got if isinstance(got, int) else _register(got, found, owner, grid, q))
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
                         mem: Memory) -> None:
    """Identify each recurring start from its last chunk (known orbit, or Newton once per distinct periodic
    attractor).  Of one recurring without a period, the chunk sharing cells with a known non-periodic attractor
    counts for it, one sharing cells with a known chaotic saddle runs on, one mostly on the cells of an undecided
    start is "not_converged", and the rest are recorded ``locate`` periods with a tangent vector (one batch
    call) and classified."""
    q = smap.forcing_period_steps
    rest = []
    for i in candidates:
        t = tracks[i]
        quiet = t.periods < t.quiet_until
        saddle = quiet or _shares_cell(t.last_keys, mem.saddles)     # Newton only where it contracts
        got = from_chunk(smap, t.last, t.k - s.chunk, grid, found, max_period=s.max_period, tol=s.newton_tol,
                         tried=mem.tried, newton="contracting" if saddle else "near")
        if got is not None:
            t.outcome = got if isinstance(got, int) else _register(got, found, owner, grid, q)
        elif _mostly_in(t.last_keys, mem.undecided):
            t.outcome = OUTCOMES["not_converged"]
        elif quiet:
            t.recur = 0              # on a chaotic saddle at its last record: it runs on
        elif near := newton_periods(t.last.points, grid, candidate_periods(q, s.max_period)):
            if _chance_return(t, near, grid, mem.saddles):
                t.quiet_until = t.periods + SADDLE_QUIET * s.chunk      # as a record there would find
            else:
                rest.append(i)       # nearly periodic, Newton failed: the record decides (max_tries of them)
        else:
            t.outcome = _sharing(t.last_keys, found, owner)
            if t.outcome is None and not _on_saddle(t, mem.saddles):
                rest.append(i)
    cap = RECORDS_AT_ONCE if is_flow(smap) else len(rest)   # see RECORDS_AT_ONCE
    for i in rest[cap:]:
        tracks[i].recur = 0          # runs on: it lands on what the first records find, or is a candidate again
    if rest:
        _record_and_classify(smap, tracks, rest[:cap], grid, s, found, owner, mem)


#: records run at most at once (two batches of 4 lanes): the other candidates of the chunk run on, and land on the
#: attractors these records find (or recur and are recorded later).  The modified Lorenz-84 flow at a = 4.7
#: (docs/howto/autonomous-flows.md, 200 box starts): every start wandered 10 chunks over new cells before the first
#: record and all 200 were recorded together (768 samples each with a tangent vector, its 0-1 test and 96 exact
#: Jacobians), every one finding the one limit cycle: 26 of the census' 28 s of CPU.  Autonomous flows only, as
#: :data:`ACTIVE`
RECORDS_AT_ONCE = 8


def _shares_cell(keys: list, sets: list) -> bool:
    """Whether a chunk's cells ``keys`` meet any of ``sets`` (of known chaotic saddles: :class:`Attractor`)."""
    cells = {c for c in keys if c is not None}
    return any(sd.cells & cells for sd in sets)


def _chance_return(t: Track, near: list, grid: Grid, saddles: list) -> bool:
    """Whether a nearly periodic chunk is a known chaotic saddle's chance near return: the start's records were
    never undecided, the chunk contracts at none of its ``near`` periods (:func:`.identify.contracting`) and shares
    a cell with a saddle (it then runs on without a record, :func:`_on_saddle`; a start settling on a periodic orbit
    there contracts at a later chunk and meets Newton).  On thesis-1dof at 122 V 186 of the census' 188 records were
    such chunks, and 181 of them found the saddle again (at 178 V 391 of 414, 9 in 10 the saddle again)."""
    return (t.tries == 0 and not any(contracting(t.last.points, grid, n) for n in near)
            and _on_saddle(t, saddles))


def _mostly_in(keys: list, sets: list) -> bool:
    """Whether at least half of a chunk's distinct cells lie in one of ``sets`` (cells of undecided starts): the
    start is on a set the records could not decide, so that its own records would not either."""
    cells = {c for c in keys if c is not None}
    return bool(cells) and any(2 * len(cells & u) >= len(cells) for u in sets)


def _known_saddle(cells: set, saddles: list) -> Attractor | None:
    """The first of ``saddles`` sharing a grid cell with ``cells`` (which then join its cells), or None."""
    for sd in saddles:
        if sd.cells & cells:
            sd.cells |= cells
            return sd
    return None


def _on_saddle(t: Track, saddles: list) -> bool:
    """Whether the start's last chunk shares a cell with a known saddle (its cells then join the saddle's, and the
    start is noted on it): it runs on without a record, its recurrence counted afresh."""
    sd = _known_saddle({c for c in t.last_keys if c is not None}, saddles)
    if sd is not None:
        t.recur, t.visits, t.saddle = 0, set(), sd
    return sd is not None


def _still_on_saddle(t: Track, saddles: list, periods) -> bool:
    """Whether a start at the periods' budget is in chaotic motion on a known saddle: the second half of its last
    chunk shares a cell with one and does not repeat with any of ``periods`` (a start that fell onto an orbit in
    that chunk is still approaching it, not on the saddle); the start is then noted on that saddle.  (Whether the
    chunk contracts towards a near period tells nothing here: on the open map of tests/test_eventual.py 11 of 300
    starts on the saddle at the budget had chunks that did, by chance.)"""
    half = t.last.points[len(t.last.points) // 2:]
    if periodic_tail(half, periods):
        return False
    cells = {c for c in t.last_keys[len(t.last_keys) // 2:] if c is not None}
    sd = next((sd for sd in saddles if sd.cells & cells), None)
    if sd is not None:
        t.saddle = sd
    return sd is not None


def _sharing(keys: list, found: list, owner: dict) -> int | None:
    """The known non-periodic attractor sharing the most cells with a chunk's ``keys`` (its cells then own
    the chunk's too), or None."""
    shared: dict = {}
    for key in keys:
        aid = owner.get(key)
        if aid is not None and not found[aid].periodic:
            shared[aid] = shared.get(aid, 0) + 1
    if not shared:
        return None
    aid = max(sorted(shared), key=shared.get)
    cells = {c for c in keys if c is not None}
    found[aid].cells |= cells
    for c in cells:
        owner.setdefault(c, aid)
    return aid


def record_length(tries: int, s: Settings) -> int:
    """Strobe periods of a start's record after ``tries`` undecided ones: ``locate`` doubled at each (at most
    ``max_periods``), so that an exponent the shorter records' intervals straddled is resolved by a longer one, as a
    diagram's anytime labels extend an undecided record.  Thesis-1dof (`matlab-listing`, `measured`, 10 Hz, 1000
    box starts): at 99.5 V 83 starts on a chaotic set chattering on the stop, which records of 48 periods (bound
    0.16 per period) left undecided, were "not_converged"; at 179.5 V a set is chaotic over 384 periods (exponent
    0.055, 0.032-0.078) (benchmarks/reports/attractors-recovery/undecided-f537126.txt)."""
    return int(min(s.locate * 2 ** tries, max(s.locate, s.max_periods)))


def _record_and_classify(smap, tracks, rest, grid, s: Settings, found: list, owner: dict, mem: Memory) -> None:
    """Record the starts ``rest`` (:func:`record_length` periods) with a tangent vector (one batch call, beside their
    paths) and identify each (:func:`.identify.identify`): a start on a non-periodic attractor counts for it (and
    its record's periods for it); a periodic orbit found is registered and the start runs on from where its record
    began, to land there along its own path; an undecided one runs on, "not_converged" after ``max_tries`` records;
    a new non-periodic set is an attractor only if it persists (:func:`_persists`), else a saddle the start runs on
    from."""
    q = smap.forcing_period_steps
    lengths = [record_length(tracks[i].tries, s) for i in rest]
    recs = smap.orbits([{}] * len(rest), [tracks[i].state for i in rest], lengths,
                       k0=[tracks[i].k for i in rest], batch_size=s.batch_size, tangent=True)
    for i, o, length in zip(rest, recs, lengths):
        t = tracks[i]
        if o.status != "ok":
            t.outcome = OUTCOMES["escaped" if o.status == "escaped" else "failed"]
            continue
        a = identify(smap, o, t.k, grid, max_period=s.max_period, tol=s.newton_tol, tried=mem.tried,
                     last=t.tries + 1 >= s.max_tries)
        if a is not None and _on_an_equilibrium(smap, a, grid):
            a = None                 # undecided: it runs on until it leaves the equilibrium
        if _neutral(smap, o, t.k, a):
            t.outcome, t.periods = OUTCOMES["neutral"], t.periods + length
            continue
        # an undecided start runs on from where its record began (the record ran beside its path: :func:`census_at`)
        t.recur, t.visits = 0, set()
        if a is None:
            t.tries += 1
            if t.tries >= s.max_tries:       # recorded max_tries times and never decided
                sd = _undecided_transient(smap, o, t.k, grid, s, mem)
                if sd is not None:           # a transient all the same: it runs on, as on a chaotic saddle
                    t.saddle, t.quiet_until, t.tries = sd, t.periods + SADDLE_QUIET * s.chunk, 0
                    continue
                t.outcome = OUTCOMES["not_converged"]
                mem.undecided.append({c for c in grid.keys(o.points) if c is not None})
            continue
        if not a.periodic and (sd := _saddle_of(smap, a, o, t.k, grid, s, found, q, mem)) is not None:
            t.quiet_until = t.periods + SADDLE_QUIET * s.chunk     # on a saddle: it runs on without records
            t.saddle = sd
            continue
        aid = _register(a, found, owner, grid, q)
        if a.periodic and a.period <= min(s.max_period, s.chunk // 2):
            continue                 # its path, not the record beside it, must land there (it runs on)
        # a non-periodic attractor, or an orbit of a period beyond the search (:func:`.identify.identify` polishes it
        # where the record repeats at that lag; the record approaches it, :func:`.identify.polish_once`), which no
        # chunk is matched to (:func:`.identify.from_chunk`) and whose cells may be shared with an orbit beside it:
        # thesis-1dof (`matlab-listing`, `listing`, 10 Hz, 160 V), a 12-impact and a 10-impact period-18 orbit; or one
        # too long for a chunk to show a path approaching it (two of its periods: :func:`.identify.approaching`):
        # (`fit`, 10 Hz, 170 V, periods up to 100) a 45:24 orbit, whose starts ended not_converged
        t.outcome, t.periods = aid, t.periods + length
        if found[aid] is a and not a.periodic and math.isnan(a.area_rate):
            _with_area_rate(smap, a, o, t.k)          # once per new non-periodic attractor


def _on_an_equilibrium(smap, a: Attractor, grid: Grid) -> bool:
    """Whether a non-periodic set ``a`` of an autonomous flow (``sample_step``) spans less than a grid cell: a start still
    on an unstable equilibrium, stretching at its rate, not a chaotic set.  The Hopf normal form of
    tests/test_census_flows.py past its Hopf point: the seed from the neighbouring value's fixed point (the origin,
    an equilibrium at every value) sits on it to 1e-17 and its record's exponent is mu dt > 0; it was listed as a
    chaotic attractor."""
    return bool(is_flow(smap) and not a.periodic
                and np.max(np.ptp(grid.gridded(a.points), axis=0)) < 1.0)


def _with_area_rate(smap, a: Attractor, record, k0: int) -> Attractor:
    """``a`` with the area rate of its record (:func:`.identify.area_rate`; 48 exact one-period Jacobians, so it is
    computed only for a new attractor or an impact-free record).  An autonomous flow's records are ``locate`` = 768
    samples long and its area rate is stored, not judged (its neutrality is :func:`volume_rate`'s): its first
    AREA_SKIP + VOLUME_SAMPLES samples, as many batch means as the volume rate's (768 exact Jacobians, 1.7 s of CPU,
    per new limit cycle or chaotic set of the modified Lorenz-84 flow)."""
    flow = is_flow(smap)
    rate, lo, hi = area_rate(smap, record, k0, steps=AREA_SKIP + VOLUME_SAMPLES if flow else None)
    a.area_rate, a.area_rate_interval = rate, (lo, hi)
    return a


def _neutral(smap, record, k0: int, a) -> bool:
    """Whether a record that is no periodic orbit (``a``: what :func:`.identify.identify` made of it, or None) shows
    motion that dissipates nothing: not one impact over it, and the 95 % interval of its area rate
    (:func:`.identify.area_rate`) contains 0 (:func:`.identify.no_contraction`) and is at most NEUTRAL_WIDTH wide.
    Such motion does not settle: it is an invariant torus or layer of conservative motion, not an attractor
    (thesis-1dof under the `listing` and `fit` laws, whose flight between impacts is undamped: at 90 V, 10 Hz, 15 of
    the 16 non-periodic sets the census met; their 146 undecided starts ran to the periods' budget)."""
    if a is not None and a.periodic or np.any(np.asarray(record.impacts_per_step)):
        return False
    if is_flow(smap):      # a flow's own direction neither stretches nor contracts
        lo, hi = volume_rate(smap, record, k0)[1:]
        return bool(no_contraction(lo, hi) and hi - lo <= NEUTRAL_WIDTH)
    lo, hi = _with_area_rate(smap, a, record, k0).area_rate_interval if a is not None else \
        area_rate(smap, record, k0)[1:]
    return bool(no_contraction(lo, hi) and hi - lo <= NEUTRAL_WIDTH)


def volume_rate(smap, record, k0: int) -> tuple[float, float, float]:
    """(rate, low, high): the mean log |det J| [per sample] of the exact one-sample Jacobians over a record, with
    the 95 % batch-means interval (:func:`bifurc.labels.lyapunov.exponent_interval`): the sum of all Lyapunov
    exponents, the flow's divergence times the step.  The neutrality test of an autonomous flow (``sample_step``):
    on its limit cycle one exponent is 0 along the flow, so the two leading exponents' sum (the area rate) is the
    transverse one alone, near 0 close to a Hopf point although the cycle attracts; the whole volume's rate is 0
    only where the flow dissipates nothing (the modified Lorenz-84 flow of docs/howto/autonomous-flows.md: divergence
    -1 everywhere, yet with the area rate 11 of 20 starts at a = 5 were "neutral").  The record's first
    VOLUME_SAMPLES steps (each an exact Jacobian).  NaN where a step fails."""
    s = []
    try:
        for j in range(min(len(record.points) - 1, VOLUME_SAMPLES)):
            with np.errstate(divide="ignore"):
                s.append(float(np.log(abs(np.linalg.det(smap.linearize(record.state(j), k0 + j).J)))))
    except (IntegrationFailure, ValueError, ZeroDivisionError, np.linalg.LinAlgError):
        return math.nan, math.nan, math.nan
    return exponent_interval(np.asarray(s))


#: steps of a record whose Jacobians give :func:`volume_rate` (96 batches-means samples; the modified Lorenz-84 flow's
#: divergence is -1 everywhere, its rate exactly -sample_step)
VOLUME_SAMPLES = 96

#: widest interval of the area rate [per strobe period] that can show a record to be neutral
NEUTRAL_WIDTH = 0.2


def _saddle_of(smap, a: Attractor, record, k0: int, grid, s: Settings, found: list, q: int,
               mem: Memory) -> Attractor | None:
    """The saddle the non-periodic set ``a`` is, or None where it is an attractor: one of the known ``saddles``
    (sharing a cell) or a new set, matching no attractor in ``found``, whose mean lifetime is not surely above
    ``s.persist`` periods (:func:`_persists`): a saddle, or a long-lived chaotic transient (appended to ``saddles``,
    its lifetime on it; either way its starts run on to where they settle, so that the two verdicts give the same
    fractions; its fallen copies noted in ``mem.ends``)."""
    saddles = mem.saddles
    if (sd := _known_saddle(a.cells, saddles)) is not None:
        return sd
    if any(same_attractor(a, b, grid, q) for b in found):
        return None
    life = _persists(smap, record, k0, s)
    a.lifetime, a.lifetime_interval = life.tau, (life.low, life.high)
    verdict = a.lifetime_verdict = life.verdict(s.persist)
    a.how += f"; {life.text()}: " + {"attractor": "an attractor", "saddle": "a chaotic saddle (lifetime surely below "
                                     f"{s.persist} periods)", "long-lived": "a chaotic transient, not shown to "
                                     f"persist (its lifetime's interval reaches {s.persist} periods)"}[verdict]
    if verdict == "attractor":
        return None
    saddles.append(a)
    mem.ends[id(a)] = life.ends
    return a


def _undecided_transient(smap, record, k0: int, grid, s: Settings, mem: Memory) -> Attractor | None:
    """The set of a start whose ``max_tries`` records decided nothing, where it is a transient: a known saddle sharing
    a cell with ``record``, else a new set whose mean lifetime (:func:`_persists`) is not surely above ``s.persist``
    periods (appended to ``saddles``); None where it may persist (the start is then "not_converged").  Thesis-1dof
    (`matlab-listing`, `measured`, 10 Hz) at 190 V: 2 starts' records stayed undecided within 9 cells of the 1:2
    orbit and 92 more starts on their cells were "not_converged" at 360-400 periods; run on, 39 of them settled
    within the 2000 periods' budget and 86 within 6000.  Its fallen copies are noted in ``mem.ends``."""
    saddles = mem.saddles
    cells = {c for c in grid.keys(record.points) if c is not None}
    if (sd := _known_saddle(cells, saddles)) is not None:
        return sd
    life = _persists(smap, record, k0, s)
    if (verdict := life.verdict(s.persist)) == "attractor":
        return None
    a = Attractor(int(ClassCode.NOT_CONVERGED), points=np.asarray(record.points, dtype=float).copy(), k0=k0,
                  cells=cells, lifetime=life.tau, lifetime_interval=(life.low, life.high), lifetime_verdict=verdict,
                  how=f"{s.max_tries} records undecided; {life.text()}: a transient")
    saddles.append(a)
    mem.ends[id(a)] = life.ends
    return a


#: chunks a start recorded on a chaotic saddle runs before another record (it lands or recurs periodically
#: meanwhile, or is recorded again then: a saddle's start may also reach a chaotic attractor)
SADDLE_QUIET = 10

def _persists(smap, record, k0: int, s: Settings) -> Lifetime:
    """The mean lifetime [strobe periods] of the non-periodic set recorded in ``record`` (from sample ``k0``), from
    :data:`.lifetime.COPIES` perturbed copies started on its points (:func:`.lifetime.estimate_lifetime`, horizon
    ``s.persist``): its verdict is "attractor" only where the lifetime's interval lies above ``s.persist``.  A
    chaotic saddle's trajectories all fall onto periodic orbits, however long their chaos lasts (thesis-1dof at
    122 V: 5 of 200 starts still chaotic after 3000 relay periods, benchmarks/README.md).  The copies start on the
    record's first ``locate`` periods: a longer record (:func:`record_length`) may have left the set (on the open map
    of tests/test_eventual.py, copies spread over 1536 periods put the mean lifetime below 82 steps, for 1000)."""
    return estimate_lifetime(smap, record, k0, s.persist, max_period=s.max_period, batch_size=s.batch_size,
                             window=s.locate, ends=s.apportion)


def outcome_labels(outcomes, found: list) -> list:
    """Each start's outcome in words: its attractor's label (``found`` as :func:`census_at` returns it), or the
    outcome's name."""
    names = {k: n for n, k in OUTCOMES.items()}
    return [names[o] if o < 0 else found[o].label() for o in outcomes]


def hybrid(y, flags=None) -> HybridState:
    return HybridState(np.asarray(y, dtype=float), flags)
