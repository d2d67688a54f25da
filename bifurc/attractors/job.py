"""The census of one parameter point as a task on the one grid driver (:mod:`bifurc.run.grid`): run on every core or Dask
and kept on disk for a resume (:class:`bifurc.run.parts.Parts`, with :class:`CensusCodec`).

Each value's census uses its fresh starts only, so it is the same whichever process runs it and whatever ran
before: the same ``seed`` gives the same dataset with any ``workers`` and after a resume.  The seeding with the
neighbouring values' periodic attractors runs afterwards, in order, in the calling process (:mod:`.atlas`).
"""
from __future__ import annotations

import json
from dataclasses import dataclass, field, fields

import numpy as np

from maps.hybrid import HybridState

from ..run.parts import Codec, manifest
from .census import Memory, Settings, census_at
from .identify import Attractor, Grid

#: version of the census parts' layout (2: non-periodic sets judged by their lifetime, stored on them; 3: and their
#: area rate, and each value's saddles; 4: and the saddle each start was last seen on; 5: the one resume store of
#: bifurc.run.parts, points as parameter dicts; 6: and each periodic attractor's
#: multipliers, each non-periodic set's lifetime verdict; a resume from parts of an older layout is refused)
CENSUS_PARTS_FORMAT = 6


@dataclass
class ValueCensus:
    """One value's census: the outcome of each fresh start, the attractors found, the periods each start ran, the
    chaotic saddles and long-lived transients it met (so that the seeding does not estimate their lifetimes
    again), and each start's index among them of the one it was last seen on (-1: none; :mod:`.eventual`); with
    ``apportion``, where each saddle's fallen lifetime copies went (:func:`.census.copy_exits`: ids as ``outcomes``);
    and the CPU seconds [s] of its stages in the process that ran it (:data:`.census.STAGES`)."""

    outcomes: list
    found: list
    spent: list
    saddles: list = field(default_factory=list)
    via: list = field(default_factory=list)
    exits: list = field(default_factory=list)
    cpu: dict = field(default_factory=dict)

    @property
    def periods_integrated(self) -> int:
        """Strobe periods its fresh starts ran (the progress bar's measure)."""
        return int(sum(self.spent))


@dataclass
class CensusJob:
    """``problem`` at each of ``points`` (parameter dicts; the task is called with a point's index), the fresh
    ``starts`` (N, d), the ``grid``, the settings."""

    problem: object
    points: tuple
    starts: np.ndarray
    grid: Grid
    settings: Settings
    tol: float = 1e-10

    #: a census value runs thousands of start-periods: a worker is worth its start from 4 values on
    points_per_worker = 4

    @property
    def planned_periods(self) -> int:
        """Start-periods a point runs at least (its starts' first records: the progress bar's planned work)."""
        return len(self.starts) * self.settings.locate

    def _map(self):
        smap = getattr(self, "_smap", None)
        if smap is None:
            from maps.poincare import StroboscopicMap
            smap = self._smap = StroboscopicMap(self.problem, tol=self.tol)
        return smap

    def warm(self) -> None:
        """Compile the integrators in this process (a worker's initializer)."""
        smap = self._map()
        smap.orbits([{}], [self.starts[0]], 1, batch_size=self.settings.batch_size, events=False)

    def __call__(self, index) -> ValueCensus:
        """The census at the point of index ``index``."""
        return self.census(self.points[int(index)])

    def census(self, values: dict) -> ValueCensus:
        """The census of the fresh starts at the parameter ``values`` {name: value} (changes to the problem's)."""
        smap = self._map().at(values)
        memory = Memory()
        out, found, spent = census_at(smap, list(self.starts), self.grid, self.settings, memory=memory)
        return ValueCensus(out, found, spent, memory.saddles, memory.via, memory.exits, memory.cpu)

    def run_many(self, indices) -> list:
        return [self(i) for i in indices]

    def __getstate__(self):
        return {k: v for k, v in self.__dict__.items() if k != "_smap"}


def census_manifest(job: CensusJob) -> dict:
    """What identifies a census' parts: the problem, the starts, the grid, the settings, the points and the code
    (:func:`bifurc.run.parts.manifest`: a census resumed after a change of the code would mix two censuses)."""
    return manifest(job.problem, dict(starts=np.asarray(job.starts).tolist(), grid_low=job.grid.low.tolist(),
                                      grid_width=job.grid.width.tolist(), settings=repr(job.settings), tol=job.tol),
                    job.points, CensusCodec())


def _attractor_to(a: Attractor) -> dict:
    d = {}
    for f in fields(Attractor):
        v = getattr(a, f.name)
        if f.name == "points":
            v = np.asarray(v, dtype=float).tolist()
        elif f.name == "cells":
            v = sorted([list(c) for c in v])
        elif isinstance(f.default, tuple):       # the (low, high) intervals
            v = [repr(float(x)) for x in v]
        elif isinstance(v, float):
            v = repr(v)              # lossless, inf and nan included
        d[f.name] = v
    return d


def _attractor_from(d: dict) -> Attractor:
    kw = {}
    for f in fields(Attractor):
        v = d[f.name]
        if f.name == "points":
            v = np.asarray(v, dtype=float)
        elif f.name == "cells":
            v = {tuple(c) for c in v}
        elif isinstance(f.default, tuple):
            v = tuple(float(x) for x in v)
        elif isinstance(f.default, float):       # stored by repr
            v = float(v)
        kw[f.name] = v
    return Attractor(**kw)


def encode(r: ValueCensus) -> str:
    """A value's census as JSON text (floats by repr: lossless)."""
    return json.dumps({"outcomes": [int(o) for o in r.outcomes], "spent": [int(s) for s in r.spent],
                       "found": [_attractor_to(a) for a in r.found], "saddles": [_attractor_to(a) for a in r.saddles],
                       "via": [int(j) for j in r.via], "exits": [[int(k) for k in e] for e in r.exits],
                       "cpu": {k: float(v) for k, v in r.cpu.items()}},
                      default=lambda o: o.item())


def decode(text: str) -> ValueCensus:
    d = json.loads(text)
    return ValueCensus(d["outcomes"], [_attractor_from(a) for a in d["found"]], d["spent"],
                       [_attractor_from(a) for a in d["saddles"]], d["via"], d.get("exits", []), d.get("cpu", {}))


class CensusCodec(Codec):
    """A point's :class:`ValueCensus` as JSON text in a netCDF part (floats by repr: lossless)."""

    name = "census"
    version = CENSUS_PARTS_FORMAT

    def to_dataset(self, branch, indices, results):
        import xarray as xr
        return xr.Dataset({"index": (("value",), np.asarray(indices, np.int64)),
                           "census": (("value",), np.array([encode(r) for r in results], dtype=object))},
                          attrs={"version": CENSUS_PARTS_FORMAT, "branch": branch})

    def from_dataset(self, ds) -> list:
        return [(str(ds.attrs.get("branch", "independent")), int(i), decode(str(text)))
                for i, text in zip(ds["index"].values, ds["census"].values)]


def seed_state(a: Attractor) -> HybridState:
    return HybridState(np.asarray(a.points[0], dtype=float).copy(), dict(a.flags[0]) if a.flags else None)
