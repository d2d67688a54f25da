"""``bifurc.attractors``: the attractor census over parameter points, with global continuation.

The census is a task on the one grid driver (:mod:`bifurc.run.grid`, :class:`.job.CensusJob`): each point's fresh
starts run there (resumed from the one resume store); the seeding with the neighbouring points' periodic
attractors, the matching (:class:`.method.ByDistance`) and the linking then run here in the points' order
(:func:`follow_order`: a full two-parameter grid row by row in a snake), so the same seed gives the same dataset
with any workers and after a resume."""
from __future__ import annotations

import dataclasses
import math
import time as _time
from collections.abc import Mapping

import numpy as np

from maps.parameters import ParameterError
from maps.poincare import StroboscopicMap
from maps.provenance import recorded

from ..run.inputs import analysis_inputs
from ..run.where import Run
from ..run.settings import settle
from ..storage.files import output_guard
from .census import STAGES, Memory, census_at
from .follow import link_event, match
from .identify import Grid, representative, same_orbit
from .job import CensusJob
from .method import ByDistance, Census, sampler_of

#: keywords of bifurc 0.1 that have another name now (CHANGELOG 0.2.0's migration table)
RENAMED = {"max_periods": "budget (Census(budget=...), --budget)", "n_starts": None}


@recorded("bifurc.attractors")
def attractors(problem="thesis-1dof", param: str | None = "V", values=None, method: Census | None = None, *,
               starts=None, match: ByDistance | None = None, run: Run | None = None, **options):
    """Every attractor at each parameter point, its basin fraction and how it continues from point to point.

    Parameters
    ----------
    problem : :class:`maps.Problem` or scene name
        What is integrated.
    param : str
        The parameter varied over ``values`` (None when ``values`` are parameter points).
    values : array_like or list of dict
        1-D values of ``param``, or a list of parameter points ({name: value}, the same names in each), e.g. a
        two-parameter grid (:func:`grid_points`); default: the problem's value of ``param``.
    method : :class:`bifurc.Census`, optional
        The mapper's settings: grid cells, budget per start, period search, tolerance, linking.
    starts : sampler, optional
        The fresh starts, the same at every point: :class:`bifurc.Box` (default: 200 uniform in the scene's box),
        :class:`bifurc.Slice`, :class:`bifurc.SwitchOn`, or an (N, d) array; the keyword forms "box", "slice",
        "switch-on" with ``n_starts``, ``box``, ``seed``, ``shape`` options are accepted.
    match : :class:`bifurc.ByDistance`, optional
        The matcher that continues attractors from one point to the next (``match_threshold`` option).
    run : :class:`bifurc.Run`, optional
        Where it runs (workers, Dask scheduler, ``path`` with resume parts, progress).
    **options
        Problem keywords, :class:`bifurc.Census` or :class:`bifurc.Run` fields by name; ``refine``: branch datasets
        from continuation in ``param`` (:func:`bifurc.continue_orbit`), a value added between each two of their
        located events that share a step (1-D only).

    Returns
    -------
    xarray.Dataset
        ``bifurc_kind`` "attractors": dims (``param``, ``attractor``), or (``param``, ``param2``, ``attractor``) for
        a full two-parameter grid of points, with ``basin_fraction`` and its Wilson 95 % interval, class, periods,
        impacts, exponent, the polished strobe states, the matching and the events.  Outcomes (escaped,
        not_converged, failed, neutral, transient: still on a chaotic saddle at the budget) are attractor entries,
        so the fractions sum to 1; ``eventual_fraction`` apportions the transient starts by where those that left
        their saddle went.  The fractions are computed from the starts' outcomes before the dataset is written
        (``bifurc.attractors.fractions.census_fractions``).  Its cost: ``start_periods`` (the strobe periods each
        fresh start ran), the attributes ``census_seconds``, ``fresh_seconds``, ``seeding_seconds``,
        ``linking_seconds`` [s, wall] and ``fresh_cpu_seconds_chunks``, ``_identify``, ``_exits`` [s, CPU of the
        fresh starts' census by stage, summed over the points] (docs: "Where a census' time goes").
    """
    opts = dict(options)
    for old, new in RENAMED.items():
        if old in opts and new:
            raise ParameterError(f"{old!r} is now {new}")
    sampler = sampler_of(starts, opts)
    matcher = settle(ByDistance, match, {"threshold": opts.pop("match_threshold")} if "match_threshold" in opts else {})
    refine = opts.pop("refine", None)
    pb, m, r = analysis_inputs(problem, Census, method, run, opts)
    if r.time_budget is not None:
        raise ParameterError("time_budget: a census follows every start to where it settles or to its budget; "
                             "bound it with the budget (Census(budget=...), --budget) instead")
    names, points = _points(param, values, pb)
    if refine is not None:
        if len(names) != 1:
            raise ParameterError("refine needs one parameter (values of param), not points of several")
        from .refine import event_values, refined_values
        vals, added = refined_values(np.array([p[names[0]] for p in points]), event_values(refine, names[0], pb))
        points = [{names[0]: float(v)} for v in vals]
    else:
        added = None
    n_starts = getattr(sampler, "n", None) or 0
    if len(points) * max(n_starts, 1) > MAX_START_POINTS and not r.allow_large:
        raise ParameterError(f"{len(points):,} points x {n_starts:,} starts is over {MAX_START_POINTS:,} start-points; "
                             f"reduce them, or pass allow_large=True (--yes) to run it")
    with output_guard(r.path, r.overwrite):
        return _census(pb, names, points, m, sampler, matcher, r, added)


#: the largest census (points x starts) run without allow_large
MAX_START_POINTS = 10_000_000_000


def grid_points(param: str, values, param2: str, values2) -> list:
    """The points of the grid ``values`` (of ``param``) x ``values2`` (of ``param2``), row-major (``param2``
    fastest): the ``values`` of a two-parameter census."""
    return [{param: float(a), param2: float(b)} for a in np.ravel(values) for b in np.ravel(values2)]


def _points(param, values, pb) -> tuple[tuple, list]:
    """(parameter names, [point {name: value}]) of an entry point's ``param`` and ``values``."""
    if values is not None and len(values) and all(isinstance(v, Mapping) for v in values):
        names = tuple(values[0])
        if not names or any(tuple(v) != names for v in values):
            raise ParameterError(f"points: every point names the same parameters; the first names "
                                 f"{', '.join(names) or 'none'}")
        if param is not None and param not in names:
            raise ParameterError(f"param {param!r} is not among the points' parameters ({', '.join(names)})")
        points = [{k: float(v[k]) for k in names} for v in values]
    else:
        if not isinstance(param, str):
            raise ParameterError("param: a parameter name, or values given as points {name: value}")
        names = (param,)
        v = np.atleast_1d(np.asarray(values if values is not None else [pb.values.get(param, np.nan)], dtype=float))
        if v.ndim != 1 or not v.size:
            raise ParameterError(f"values of {param}: a non-empty 1-D list of finite numbers; got {values!r:.60}")
        points = [{param: float(x)} for x in v]
    for k in names:
        pb.parameter(k)     # raises for an unknown name or a well input
    for p in points:
        if not all(np.isfinite(list(p.values()))):
            raise ParameterError(f"points: finite numbers only; got {p}")
        pb.with_values(**p)      # each point valid before anything runs
    return names, points


def _census(pb, names, points, m: Census, sampler, matcher: ByDistance, r: Run, added):
    """The census of ``pb`` at ``points`` (dicts of the parameters ``names``)."""
    clock = _time.perf_counter()
    st = sampler.draw(pb)
    # the grid spans the box drawn from, or for switch-on starts (a spread of a fraction of a millimetre) the
    # scene's declared box: the attractors they reach lie far outside the spread
    scene_box = getattr(pb.scene, "box", {}) or {}
    grid = Grid.over((st.box if st.kind != "switch-on" else scene_box) or scene_box, pb.system, m.cells,
                     pb.state_vector())
    s = m.settings()
    first = pb.with_values(**points[0])
    job = CensusJob(first, tuple(points), np.asarray(st.points, dtype=float), grid, s, m.tol)
    fresh, workers, resumed, parts = _fresh(job, r, names)
    stages = [_time.perf_counter()]
    smap = StroboscopicMap(first, tol=m.tol)
    order = follow_order(names, points)
    exits = [[] for _ in points] if m.apportion else None
    per_value, outcomes, links, n_ids, periods = _follow(smap, points, order, fresh, grid, s, matcher.threshold,
                                                         m.link, exits)
    stages.append(_time.perf_counter())
    events = _link_all(pb, links, m.tol, workers)
    stages.append(_time.perf_counter())
    from .dataset import to_dataset
    from .fractions import census_fractions
    attrs = {"workers": int(workers), "values_resumed": int(resumed), "cells_per_side": int(m.cells),
             "grid_cell_widths": grid.width.tolist(), "fresh_starts": len(st),
             "census_settings": repr(s), "census_method": repr(m), "starts_sampler": repr(sampler),
             "matcher": repr(matcher), "match_threshold_cells": float(matcher.threshold), "tol": m.tol,
             "census_seconds": _time.perf_counter() - clock, "fresh_seconds": stages[0] - clock,
             "seeding_seconds": stages[1] - stages[0], "linking_seconds": stages[2] - stages[1],
             **{f"fresh_cpu_seconds_{k}": float(sum(f.cpu.get(k, 0.0) for f in fresh)) for k in STAGES},
             "links": len(links),
             "periods_per_start_mean": float(np.mean(periods)), "periods_per_start_max": int(np.max(periods)),
             "method": "recurrence on a state-space grid (after Attractors.jl's AttractorsViaRecurrences) on the "
                       "batch engine, early landing on known attractors' cells; periodic attractors polished by "
                       "Newton (exact multipliers); seeding with the neighbouring values' periodic attractors (a "
                       "sweep up the values and one back down) and matching by state-space distance; basin "
                       "fractions with 95 % Wilson intervals; motion without impact or area contraction: neutral"}
    if added is not None:
        attrs["values_added_at_events"] = ", ".join(f"{v:.10g}" for v in added) or "none"
    transients = [(f.via, f.saddles) for f in fresh]
    fractions = census_fractions(outcomes, n_ids, transients, exits)
    ds = to_dataset(pb, names, points, per_value, outcomes, n_ids, events, st, n_node=m.n_node, attrs=attrs,
                    fractions=fractions, transients=transients, spent=[f.spent for f in fresh])
    if r.path is not None:
        from ..run.grid import write_result
        write_result(ds, r.path, parts)
    return ds


def follow_order(names, points) -> list:
    """The order the points are followed in (seeding, matching, linking): as given, except a full two-parameter
    grid, followed row by row in a snake (each step changes one parameter)."""
    if len(names) != 2:
        return list(range(len(points)))
    a = sorted({p[names[0]] for p in points})
    b = sorted({p[names[1]] for p in points})
    where = {(p[names[0]], p[names[1]]): k for k, p in enumerate(points)}
    if len(where) != len(points) or len(a) * len(b) != len(points):
        return list(range(len(points)))
    return [where[x, y] for i, x in enumerate(a) for y in (b if i % 2 == 0 else b[::-1])]


def _seeded(smap, points, order, fresh, grid, s) -> list:
    """Each point's attractors: those of its fresh starts, then those reached from the neighbouring point's
    periodic attractors (one start on each that is not one of its orbits already; not counted in the fractions), in a
    sweep along ``order`` (indices of ``points``) and one back.  A chaotic set is not seeded: the census tells an attractor from a
    saddle by 48 copies' lifetimes, and on thesis-1dof at 21 values x 50 starts seeds on chaotic sets the fresh
    starts had not met (or had met as saddles) spent 61 of the seeding's 64 s in those estimates; a chaotic
    attractor of the neighbour that persists is met by the fresh starts.  The sweep down finds an orbit at the
    values below the one whose fresh starts first met it, down to where it was born.  An orbit is left unseeded
    only if it is there already to the states' tolerance (:func:`.identify.same_orbit`; skipping one within two
    grid cells of an orbit of its period lost orbits next to the state at rest: 5 of thesis-orbits' 848 (value,
    orbit) pairs at 281 values x 200 starts)."""
    found = [list(f.found) for f in fresh]
    memory = [Memory(saddles=list(f.saddles)) for f in fresh]      # each value's saddles, for both sweeps
    q = smap.forcing_period_steps
    short = dataclasses.replace(s, max_periods=min(s.max_periods, SEED_PERIODS))
    for way in (order, order[::-1]):
        prev = None
        for i in way:
            seeds = [a for a in prev or [] if a.periodic and not any(same_orbit(a, b, q) for b in found[i])]
            if seeds:
                found[i] = census_at(smap.at(points[i]), [representative(a) for a in seeds], grid, short, k0=[a.k0 for a in seeds],
                                     known=found[i], memory=memory[i])[1]
            prev = found[i]
    return found


#: strobe periods a seed runs at most: one that has not settled by then continues no attractor of its neighbour
#: (the one it would reach after a long transient is the fresh starts' to find)
SEED_PERIODS = 400


def _follow(smap, points, order, fresh, grid, s, match_threshold, link, exits=None):
    """Point by point along ``order``: the attractors of each (:func:`_seeded`) matched to the previous point's and
    (``link``) the appearances and disappearances noted: (per_value, outcomes, links, n_ids, periods spent per start),
    the first two in the points' own order; ``exits`` (a list per point, filled) gets each point's saddles' copy exits
    (:attr:`.job.ValueCensus.exits`) in the same ids as the outcomes."""
    n = len(points)
    per_value, outcomes, links, prev, n_ids, periods = [None] * n, [None] * n, [], {}, 0, []
    seeded = _seeded(smap, points, order, fresh, grid, s)
    for step, i in enumerate(order):
        found = seeded[i]
        periods.extend(fresh[i].spent)
        ids, n_ids = _assign(prev, found, grid, smap.at(points[i]), match_threshold, n_ids)
        here = {ids[j]: a for j, a in enumerate(found)}
        if step and link:
            links += _changes(points[order[step - 1]], points[i], prev, here, i)
        per_value[i] = here
        outcomes[i] = [ids[k] if k >= 0 else k for k in fresh[i].outcomes]
        if exits is not None:
            exits[i] = [[ids[k] if k >= 0 else k for k in e] for e in fresh[i].exits]
        prev = here
    return per_value, outcomes, links, n_ids, periods


def _fresh(job, r: Run, names):
    """Each point's census from its fresh starts, on the one grid driver (:func:`bifurc.run.grid.run_points`):
    resumed from ``<path>.parts`` where stored, the rest on ``r.workers`` processes (default every core, at least
    :attr:`CensusJob.points_per_worker` points each) or a Dask scheduler; returns (censuses, workers, resumed,
    parts)."""
    from ..run.grid import run_points
    from ..run.parts import Parts
    from .job import CensusCodec, census_manifest
    parts = Parts(r.path, census_manifest(job), CensusCodec()) if r.path is not None else None
    index = np.arange(len(job.points), dtype=float)
    results, resumed, _, workers = run_points(job, index, "independent", parts, r.workers, r.scheduler, 1,
                                              r.progress, f"attractor census {' x '.join(names)}", unit="points")
    return results["independent"], workers, resumed, parts


def _assign(prev: dict, found: list, grid, smap, threshold, n_ids) -> tuple[list, int]:
    """Global ids of ``found`` (at ``smap``'s value): the matched previous attractor's id, else a new one."""
    keys = list(prev)
    pairs = match([prev[k] for k in keys], found, grid, smap.forcing_period_steps, threshold, smap=smap)
    ids = []
    for j, a in enumerate(found):
        if j in pairs:
            ids.append(keys[pairs[j][0]])
            a.match_distance = pairs[j][1]
        else:
            ids.append(n_ids)
            a.match_distance = math.nan
            n_ids += 1
    return ids, n_ids


def _changes(before: dict, now: dict, prev: dict, here: dict, i: int) -> list:
    """The appearances and disappearances between two points: ((i, id), what, attractor, step), where step is
    (the parameter that changed, its value where the attractor is, where it is not, the other parameters) or None
    when several parameters change at once (no branch to continue)."""
    moved = [k for k in now if now[k] != before[k]]

    def step(at, other):
        if len(moved) != 1:
            return None
        k = moved[0]
        return k, at[k], other[k], {n: v for n, v in at.items() if n != k}
    gone = [((i, gid), "disappeared", a, step(before, now)) for gid, a in prev.items() if gid not in here]
    new = [((i, gid), "appeared", a, step(now, before)) for gid, a in here.items() if gid not in prev]
    return gone + new


def _link_all(pb, links: list, tol: float, workers: int) -> dict:
    """{(point index, id): (what, kind, evidence)}: each change linked by continuing its orbit in the parameter that
    changed (:func:`.follow.link_event`), on ``workers`` processes when there are several (each link is independent);
    a step that changes several parameters at once is "global"."""
    from ..run.executor import WorkerPool, result_of, submit_all
    from ..run.grid import travels
    tasks, fixed = [], {}
    for key, what, a, step in links:
        if step is None:
            fixed[key] = ("global", "the step between the two points changes several parameters at once: no branch "
                                    "to continue")
            continue
        k, here, there, others = step
        tasks.append((key, (1.0, link_event, (pb.with_values(**others) if others else pb, k, a, here, there, tol))))
    periodic = sum(a.periodic for _, _, a, step in links if step is not None)
    jobs = [t for _, t in tasks]
    if workers > 1 and periodic > 1 and travels(pb):
        with WorkerPool(None, min(workers, periodic)) as pool:
            got = [result_of(f) for f in submit_all(jobs, pool)]
    else:
        got = [f.result() for f in submit_all(jobs)]
    out = {key: kw for key, kw in zip([k for k, _ in tasks], got)}
    out.update(fixed)
    return {key: (what, *out[key]) for key, what, *_ in links}
