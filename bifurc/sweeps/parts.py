"""A diagram's (or regime map's) value results in the resume store (:mod:`bifurc.run.parts`): :class:`ValueCodec`."""
from __future__ import annotations

import json
from dataclasses import fields

import numpy as np

from ..labels.codes import ClassCode, Status
from ..run.parts import Codec, manifest as run_manifest
from .job import ValueResult

#: version of the parts' layout (2: pickles, up to bifurc 0.1.0; 3: netCDF chunks; 8: min_gap, min_flight_gap,
#: min_gap_per_step and impact_t renamed min_clearance, min_flight_clearance, min_clearance_per_step, impact_time;
#: 10: the one resume store of bifurc.run.parts)
PARTS_FORMAT = 10
_FIELDS = [f.name for f in fields(ValueResult)]
_CODES = {"class_code": ClassCode, "status": Status}


def manifest(job, values, mode) -> dict:
    """What identifies a sweep's results: the job's fields (not ``batch_size``: no effect on results; not
    the time budget's ``deadline``: values it cut are kept as they were stored), the problem, the grid, the mode,
    the code and the parts' format version (:func:`bifurc.run.parts.manifest`)."""
    settings = {f.name: getattr(job, f.name) for f in fields(job) if f.name not in ("batch_size", "problem", "deadline")}
    return run_manifest(job.problem, settings, values, ValueCodec(), mode=mode)


class ValueCodec(Codec):
    """:class:`~bifurc.sweeps.job.ValueResult` rows as a netCDF part (every field a variable; lossless)."""

    name = "values"
    version = PARTS_FORMAT

    def to_dataset(self, branch, indices, results):
        import xarray as xr
        data = {"index": (("value",), np.asarray(indices, np.int64))}
        for name in _FIELDS:
            col = [getattr(r, name) for r in results]
            if name == "final_flags":
                col = [json.dumps({k: getattr(v, "item", lambda v=v: v)() for k, v in c.items()}) for c in col]
            elif name == "failure":
                col = [str(c) for c in col]
            arr = np.asarray(col)
            data[name] = (("value",) + tuple(f"{name}_{k}" for k in range(1, arr.ndim)), arr)
        return xr.Dataset(data, attrs={"branch": branch, "version": PARTS_FORMAT})

    def from_dataset(self, ds):
        out = []
        for j, i in enumerate(ds["index"].values):
            kw = {}
            for name in _FIELDS:
                v = ds[name].values[j]
                if name == "final_flags":
                    v = json.loads(str(v))
                elif name in _CODES:
                    v = _CODES[name](int(v))
                elif name == "failure":
                    v = str(v)
                elif np.ndim(v) == 0:
                    v = v.item()
                kw[name] = v
            out.append((str(ds.attrs["branch"]), int(i), ValueResult(**kw)))
        return out
