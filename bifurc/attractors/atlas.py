"""``bifurc.attractors``: the attractor census over a parameter, with global continuation."""
from __future__ import annotations

import dataclasses
import math
import time as _time

import numpy as np

from maps.parameters import ParameterError, validate_value
from maps.poincare import StroboscopicMap
from maps.problem import problem
from maps.provenance import recorded

from .census import Memory, Settings, census_at
from .job import CensusJob
from .follow import link_event, match
from .identify import Grid, representative, same_orbit
from .starts import make_starts

__all__ = ["attractors"]


def _values(param, values, system) -> np.ndarray:
    if param not in system.param_names:
        raise ParameterError(f"param {param!r} is not a parameter of {system.name!r}; its parameters: "
                             f"{', '.join(system.param_names)}")
    v = np.atleast_1d(np.asarray(values, dtype=float))
    if v.ndim != 1 or not v.size or not np.all(np.isfinite(v)):
        raise ParameterError(f"values of {param}: a non-empty 1-D list of finite numbers; got {values!r}")
    return v


@recorded("bifurc.attractors")
def attractors(problem_or_scene="thesis-1dof", param: str = "V", values=None, *, starts="box", n_starts: int = 100,
               box: dict | None = None, shape=None, seed: int = 0, preset=None, params=None, tol: float = 1e-10,
               cells: int = 100, chunk: int = 40, land: int = 6, recur: int = 20, locate: int = 48,
               max_periods: int = 2000, max_period: int = 16, match_threshold: float = 20.0, link: bool = True,
               n_node: int = 16, batch_size: int = 4, workers: int | None = None, scheduler=None, progress=True,
               path=None, overwrite: bool = False, refine=None,
               circuit=None, ac_sign=None, dc_law=None, soil=None, compaction=None):
    """Every attractor at each of ``values`` of ``param``, its basin fraction and how it continues.

    Parameters
    ----------
    problem_or_scene : a :class:`maps.Problem`, a scene name, Scene or HybridSystem.
    starts : "box" (``n_starts`` uniform in ``box`` {state: (low, high)} [SI], default the scene's declared box;
        other states at the scene's start), "slice" (a ``shape`` grid over the box's two states), "switch-on"
        (the scene's declared switch-on distribution), a :class:`bifurc.attractors.starts.Starts` or an (N, d) array.
        The same fresh starts (``seed``) at every value.
    cells : grid cells per box side (the recurrence grid; other states: their start's magnitude / cells).
    chunk, land, recur, locate, max_periods : strobe periods per batch call; consecutive points in one
        attractor's cells to land on it; consecutive revisits of a start's own cells to call an attractor
        found; periods of a start's first record to identify it (doubled at each undecided one); periods after
        which a start is "not_converged".
    max_period : longest period searched [strobe periods] (a contracting record that repeats at a longer lag, up to
        a quarter of its length, is polished by Newton at that lag); tol : heyoka tolerance.
    match_threshold : largest distance [grid cells] at which an attractor continues one of the previous value.
    link : continue each appearing or disappearing periodic orbit across the step to link the change to a
        located fold, period doubling, torus, grazing or stick onset (else it is flagged "global").
    refine : branch datasets from continuation in ``param`` (:func:`bifurc.continue_orbit`, one or a list, of this
        model): a value is added between each two of their located events that share a step
        (:mod:`.refine`), so that a stable window narrower than the step is a census value too; the added values
        are in the attribute ``values_added_at_events``.

    workers : processes (default every available core, at least 4 values each); ``scheduler`` a Dask scheduler address or Client.  Each
        value's fresh starts are one task; the seeding with the neighbouring values' periodic attractors, the matching and
        the linking run here in order, so the same ``seed`` gives the same dataset with any ``workers``.
    path : with it, each finished value is kept in ``<path>.parts/`` and a run stopped part-way resumes there.

    Returns an xarray Dataset (``bifurc_kind`` "attractors"): dims (``param``, ``attractor``) with
    ``basin_fraction`` and its Wilson 95 % interval, class, periods, impacts, exponent, the polished strobe
    states, the matching and the events; outcomes (escaped, not_converged, failed, neutral: motion that
    dissipates nothing, :func:`.census._neutral`, and transient: still on a chaotic saddle at ``max_periods``,
    with the saddle's mean lifetime) are attractor entries, so the fractions sum to 1.  ``eventual_fraction`` and
    its interval: the transient starts apportioned by where the starts that left their saddle went
    (:mod:`.eventual`).  ``path``: also written as netCDF (refused if it exists unless ``overwrite``).
    """
    clock = _time.perf_counter()
    pb = problem(problem_or_scene, preset, params, circuit=circuit, ac_sign=ac_sign, dc_law=dc_law, soil=soil,
                 compaction=compaction)
    values = _values(param, values if values is not None else [pb.values[param]], pb.system)
    added = None
    if refine is not None:
        from .refine import event_values, refined_values
        values, added = refined_values(values, event_values(refine, param, pb))
    if path is not None:
        from ..storage.files import refuse_existing
        refuse_existing(path, overwrite)
    st = make_starts(pb, starts, n=n_starts, box=box, seed=seed, shape=shape)
    # the grid spans the box drawn from, or for switch-on starts (a spread of a fraction of a millimetre) the
    # scene's declared box: the attractors they reach lie far outside the spread
    scene_box = getattr(pb.scene, "box", {}) or {}
    grid = Grid.over((st.box if st.kind != "switch-on" else scene_box) or scene_box, pb.system,
                     int(validate_value("cells", cells, 2, 1e6)), pb.state_vector())
    s = Settings(chunk=int(chunk), land=int(land), recur=int(recur), locate=int(locate),
                 max_periods=int(max_periods), max_period=int(max_period), batch_size=int(batch_size))
    job = CensusJob(pb.with_values(**{param: float(values[0])}), param, np.asarray(st.points, dtype=float), grid, s,
                    tol)
    fresh, workers, resumed, parts = _fresh(job, values, workers, scheduler, path, progress)
    stages = [_time.perf_counter()]
    smap = StroboscopicMap(pb.with_values(**{param: float(values[0])}), tol=tol)
    per_value, outcomes, links, n_ids, periods = _follow(smap, param, values, fresh, grid, s, match_threshold, link)
    stages.append(_time.perf_counter())
    events = _link_all(pb, param, links, tol, workers)
    stages.append(_time.perf_counter())
    from .dataset import to_dataset
    attrs = {"workers": int(workers), "values_resumed": int(resumed), "cells_per_side": int(cells),
             "grid_cell_widths": grid.width.tolist(), "fresh_starts": len(st),
             "census_settings": repr(s), "match_threshold_cells": float(match_threshold), "tol": tol,
             "census_seconds": _time.perf_counter() - clock, "fresh_seconds": stages[0] - clock,
             "seeding_seconds": stages[1] - stages[0], "linking_seconds": stages[2] - stages[1],
             "links": len(links),
             "periods_per_start_mean": float(np.mean(periods)), "periods_per_start_max": int(np.max(periods)),
             "method": "recurrence on a state-space grid (after Attractors.jl's AttractorsViaRecurrences) on the "
                       "batch engine, early landing on known attractors' cells; periodic attractors polished by "
                       "Newton (exact multipliers); seeding with the neighbouring values' periodic attractors (a "
                       "sweep up the values and one back down) and matching by state-space distance; basin "
                       "fractions with 95 % Wilson intervals; motion without impact or area contraction: neutral"}
    if added is not None:
        attrs["values_added_at_events"] = ", ".join(f"{v:.10g}" for v in added) or "none"
    ds = to_dataset(pb, param, values, per_value, outcomes, n_ids, events, st, n_node=int(n_node), attrs=attrs,
                    transients=[(f.via, f.saddles) for f in fresh])
    if path is not None:
        from ..storage.files import write_netcdf
        write_netcdf(ds, path, overwrite=overwrite)
        parts.remove()
    return ds


def _seeded(smap, param, values, fresh, grid, s) -> list:
    """Each value's attractors: those of its fresh starts, then those reached from the neighbouring value's
    periodic attractors (one start on each that is not one of its orbits already; not counted in the fractions), in a
    sweep up the values and one back down.  A chaotic set is not seeded: the census tells an attractor from a
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
    for order in (range(len(values)), range(len(values) - 1, -1, -1)):
        prev = None
        for i in order:
            seeds = [a for a in prev or [] if a.periodic and not any(same_orbit(a, b, q) for b in found[i])]
            if seeds:
                smap.set_params(**{param: float(values[i])})
                found[i] = census_at(smap, [representative(a) for a in seeds], grid, short, k0=[a.k0 for a in seeds],
                                     known=found[i], memory=memory[i])[1]
            prev = found[i]
    return found


#: strobe periods a seed runs at most: one that has not settled by then continues no attractor of its neighbour
#: (the one it would reach after a long transient is the fresh starts' to find)
SEED_PERIODS = 400


def _follow(smap, param, values, fresh, grid, s, match_threshold, link):
    """Value by value: the attractors of each (:func:`_seeded`) matched to the previous value's and (``link``) the
    appearances and disappearances noted: (per_value, outcomes, links, n_ids, periods spent per start)."""
    per_value, outcomes, links, prev, n_ids, periods = [], [], [], {}, 0, []
    seeded = _seeded(smap, param, values, fresh, grid, s)
    for i, v in enumerate(values):
        smap.set_params(**{param: float(v)})
        found = seeded[i]
        periods.extend(fresh[i].spent)
        ids, n_ids = _assign(prev, found, grid, smap, match_threshold, n_ids)
        here = {ids[j]: a for j, a in enumerate(found)}
        if i and link:
            links += _changes(values[i - 1], v, prev, here, i)
        per_value.append(here)
        outcomes.append([ids[k] if k >= 0 else k for k in fresh[i].outcomes])
        prev = here
    return per_value, outcomes, links, n_ids, periods


def _fresh(job, values, workers, scheduler, path, progress):
    """Each value's census from its fresh starts: resumed from ``<path>.parts`` where stored, the rest on
    ``workers`` processes (default every core) or a Dask ``scheduler``; returns (censuses, workers, resumed,
    parts)."""
    from ..sweeps.executor import available_cores, map_values
    from ..sweeps.sweep import travels
    from .job import CensusParts, census_manifest
    if scheduler is not None:
        workers = 0
    elif workers is None:
        workers = max(1, min(available_cores(), len(values) // 4)) if travels(job.problem) else 1
    else:
        workers = int(validate_value("workers", workers, 1, 1024))
    parts = CensusParts(path, census_manifest(job, values, {})) if path is not None else None
    done = parts.load() if parts is not None else {}
    missing = np.array([i for i in range(len(values)) if i not in done], dtype=np.int64)
    bar = _bar(progress, len(values) * len(job.starts))
    if bar:
        bar.update(len(done) * len(job.starts))

    def take(start, results):
        idx = missing[start:start + len(results)]
        for i, r in zip(idx, results):
            done[int(i)] = r
        if parts is not None:
            parts.save([int(i) for i in idx], results)
        if bar:
            bar.update(len(results) * len(job.starts))

    try:
        if missing.size:
            map_values(job, values[missing], workers=max(1, workers), scheduler=scheduler, collect=False,
                       chunk_size=1, on_chunk=take)
    finally:
        if bar:
            bar.close()
    return [done[i] for i in range(len(values))], workers, len(values) - missing.size, parts


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


def _changes(before, now, prev: dict, here: dict, i: int) -> list:
    """The appearances and disappearances between two values: ((i, id), what, attractor, here, there)."""
    gone = [((i, gid), "disappeared", a, before, now) for gid, a in prev.items() if gid not in here]
    new = [((i, gid), "appeared", a, now, before) for gid, a in here.items() if gid not in prev]
    return gone + new


def _link_all(pb, param, links: list, tol: float, workers: int) -> dict:
    """{(value index, id): (what, kind, evidence)}: each change linked by continuing its orbit
    (:func:`.follow.link_event`), on ``workers`` processes when there are several (each link is independent)."""
    from ..sweeps.executor import WorkerPool, result_of, submit_all
    tasks = [(1.0, link_event, (pb, param, a, here, there, tol)) for _, _, a, here, there in links]
    periodic = sum(a.periodic for _, _, a, _, _ in links)
    from ..sweeps.sweep import travels
    if workers > 1 and periodic > 1 and travels(pb):
        with WorkerPool(None, min(workers, periodic)) as pool:
            got = [result_of(f) for f in submit_all(tasks, pool)]
    else:
        got = [f.result() for f in submit_all(tasks)]
    return {key: (what, kind, why) for (key, what, *_), (kind, why) in zip(links, got)}


class _Bar:
    def __init__(self, total):
        from ..progress import tqdm_class      # no TqdmWarning in Jupyter without ipywidgets
        self.t = tqdm_class()(total=total, unit="start", desc="attractor census", leave=False)

    def update(self, n):
        self.t.update(n)

    def close(self):
        self.t.close()


def _bar(progress, total):
    return _Bar(total) if progress else None
