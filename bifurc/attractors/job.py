"""The census of one parameter value as a task: run on every core or on Dask (:mod:`bifurc.sweeps.executor`)
and kept on disk for a resume (:class:`bifurc.sweeps.resume.Parts`'s folder and manifest).

Each value's census uses its fresh starts only, so it is the same whichever process runs it and whatever ran
before: the same ``seed`` gives the same dataset with any ``workers`` and after a resume.  The seeding with the
neighbouring values' periodic attractors runs afterwards, in order, in the calling process (:mod:`.atlas`).
"""
from __future__ import annotations

import json
from dataclasses import dataclass, field, fields

import numpy as np

from maps.hybrid import HybridState
from maps.provenance import code_version

from ..sweeps.resume import Parts
from .census import Memory, Settings, census_at
from .identify import Attractor, Grid

__all__ = ["CensusJob", "ValueCensus", "CensusParts", "census_manifest"]

#: version of the census parts' layout (2: non-periodic sets judged by their lifetime, stored on them; 3: and their
#: area rate, and each value's saddles; 4: and the saddle each start was last seen on; a resume from parts of an
#: older layout is refused)
CENSUS_PARTS_FORMAT = 4


@dataclass
class ValueCensus:
    """One value's census: the outcome of each fresh start, the attractors found, the periods each start ran, the
    chaotic saddles and long-lived transients it met (so that the seeding does not estimate their lifetimes
    again), and each start's index among them of the one it was last seen on (-1: none; :mod:`.eventual`)."""

    outcomes: list
    found: list
    spent: list
    saddles: list = field(default_factory=list)
    via: list = field(default_factory=list)


@dataclass
class CensusJob:
    """``problem`` with ``param`` set to each value, the fresh ``starts`` (N, d), the ``grid``, the settings."""

    problem: object
    param: str
    starts: np.ndarray
    grid: Grid
    settings: Settings
    tol: float = 1e-10

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

    def __call__(self, value) -> ValueCensus:
        smap = self._map()
        smap.set_params(**{self.param: float(value)})
        memory = Memory()
        out, found, spent = census_at(smap, list(self.starts), self.grid, self.settings, memory=memory)
        return ValueCensus(out, found, spent, memory.saddles, memory.via)

    def run_many(self, values) -> list:
        return [self(v) for v in values]

    def __getstate__(self):
        return {k: v for k, v in self.__dict__.items() if k != "_smap"}


def census_manifest(job: CensusJob, values, extra: dict) -> dict:
    """What identifies a census' parts: the problem, the starts, the grid, the settings, the values and the code
    (:func:`maps.provenance.code_version`: a census resumed after a change of the code would mix two censuses)."""
    pb = job.problem
    args = dict(code=code_version(), scene=pb.name, options=repr(pb.options), preset=pb.preset,
                params=dict(pb.values), x0=dict(pb.x0), param=job.param, starts=np.asarray(job.starts).tolist(),
                grid_low=job.grid.low.tolist(), grid_width=job.grid.width.tolist(), settings=repr(job.settings),
                tol=job.tol, values=[float(v) for v in values], **extra)
    return {"format": "bifurc attractor census parts", "version": CENSUS_PARTS_FORMAT, "arguments": args}


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
                       "via": [int(j) for j in r.via]},
                      default=lambda o: o.item())


def decode(text: str) -> ValueCensus:
    d = json.loads(text)
    return ValueCensus(d["outcomes"], [_attractor_from(a) for a in d["found"]], d["spent"],
                       [_attractor_from(a) for a in d["saddles"]], d["via"])


class CensusParts(Parts):
    """The completed values of one census under ``<path>.parts/`` (one netCDF file per chunk of values)."""

    def load(self) -> dict:
        """{index: ValueCensus} of every readable part (unreadable ones are removed and computed again)."""
        import warnings

        import xarray as xr
        done = {}
        for f in sorted(self.dir.glob("census-*.nc")):
            try:
                with xr.open_dataset(f) as ds:
                    for i, text in zip(ds["index"].values, ds["census"].values):
                        done[int(i)] = decode(str(text))
            except Exception as exc:  # noqa: BLE001 - any unreadable part is recomputed
                warnings.warn(f"discarding the unreadable resume part {f.name} ({type(exc).__name__}: {exc})",
                              RuntimeWarning, stacklevel=2)
                f.unlink(missing_ok=True)
        return done

    def save(self, indices, results) -> None:
        """Write the censuses of ``indices`` (one chunk) as one part, atomically."""
        import xarray as xr

        from ..storage.files import write_netcdf
        ds = xr.Dataset({"index": (("value",), np.asarray(indices, np.int64)),
                         "census": (("value",), np.array([encode(r) for r in results], dtype=object))},
                        attrs={"version": CENSUS_PARTS_FORMAT})
        write_netcdf(ds, self.dir / f"census-{indices[0]:06d}.nc", overwrite=True)


def seed_state(a: Attractor) -> HybridState:
    return HybridState(np.asarray(a.points[0], dtype=float).copy(), dict(a.flags[0]) if a.flags else None)
