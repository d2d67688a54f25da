"""Completed values on disk, so that an interrupted sweep resumes where it stopped.

``<path>.parts/`` holds ``manifest.json`` (the sweep's arguments and the parts' format
version: a resume with other arguments, or of another format, is refused) and one small
netCDF file per completed chunk of values, written atomically.  A part that cannot be read
is discarded with a warning and its values are computed again.
"""
from __future__ import annotations

import json
import shutil
import warnings
from dataclasses import fields
from pathlib import Path

import numpy as np

from maps.parameters import ParameterError
from maps.provenance import code_version

from ..codes import ClassCode, Status
from .job import ValueResult
from ..storage.files import write_netcdf

__all__ = ["Parts", "PARTS_FORMAT", "manifest"]

#: version of the parts' layout (2: pickles, up to bifurc 0.1.0; 3: netCDF chunks; 8: min_gap, min_flight_gap,
#: min_gap_per_step and impact_t renamed min_clearance, min_flight_clearance, min_clearance_per_step, impact_time)
PARTS_FORMAT = 9
_FIELDS = [f.name for f in fields(ValueResult)]
_CODES = {"class_code": ClassCode, "status": Status}


def manifest(job, values, mode) -> dict:
    """What identifies a sweep's results: the job's fields (not ``batch_size``: no effect on results; not
    the time budget's ``deadline``: values it cut are kept as they were stored),
    the grid, the mode, the code (:func:`maps.provenance.code_version`: parts another version or commit computed
    are not mixed with this one's) and the parts' format version."""
    args = {f.name: getattr(job, f.name) for f in fields(job) if f.name not in ("batch_size", "problem", "deadline")}
    pb = job.problem
    b = pb.scene.builder
    builder = None if b is None else (f"{b.__module__}.{b.__qualname__}" if hasattr(b, "__qualname__")
                                      else repr(getattr(b, "system", b)))
    args.update(scene=pb.name, builder=builder, options=repr(pb.options), preset=pb.preset, params=dict(pb.values),
                x0=dict(pb.x0), flags0=pb.flags0, code=code_version())
    return {"format": "bifurc sweep parts", "version": PARTS_FORMAT,
            "arguments": dict(args, values=[float(v) for v in values], mode=mode)}


def _to_dataset(branch, indices, results):
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


def _from_dataset(ds):
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
        out.append((int(i), ValueResult(**kw)))
    return out


def _difference(held: str, manifest: dict) -> str:
    """What the stored manifest ``held`` (text) says that ``manifest`` does not: its format version, or
    the first arguments that differ ("a sweep with V = 90, this run has V = 100"); unreadable: says so."""
    try:
        stored = json.loads(held)
    except ValueError:
        stored = None
    if not isinstance(stored, dict):
        return "an unreadable manifest.json (not this bifurc's resume data)"
    version = stored.get("version") or stored.get("parts_format") or "unknown"
    args = stored.get("arguments")
    if version not in (PARTS_FORMAT, "unknown") or not isinstance(args, dict):
        return (f"a sweep with other arguments (or parts of format version {version}; this bifurc writes "
                f"{PARTS_FORMAT})")
    new = json.loads(json.dumps(manifest, sort_keys=True, default=str))["arguments"]
    flat = lambda a: {**{k: v for k, v in a.items() if k != "params"},  # noqa: E731
                      **{k: v for k, v in (a.get("params") or {}).items()}}
    old, now = flat(args), flat(new)
    diff = [k for k in sorted(set(old) | set(now)) if old.get(k) != now.get(k)]
    shown = ", ".join(f"{k} = {_short(old.get(k))}" for k in diff[:3])
    ours = ", ".join(f"{k} = {_short(now.get(k))}" for k in diff[:3])
    return f"a sweep with other arguments: made with {shown}; this run has {ours}"


def _short(value) -> str:
    if isinstance(value, list) and len(value) > 4:
        return f"{len(value)} values {value[0]:g}..{value[-1]:g}" if all(isinstance(v, (int, float)) for v in value) \
            else f"{len(value)} items"
    return f"{value:g}" if isinstance(value, float) else str(value)


class Parts:
    """The completed values of one sweep under ``<path>.parts/``."""

    def __init__(self, path, manifest: dict):
        self.dir = Path(str(path) + ".parts")
        self.dir.mkdir(parents=True, exist_ok=True)
        mfile = self.dir / "manifest.json"
        text = json.dumps(manifest, sort_keys=True, default=str)
        if mfile.exists():
            held = mfile.read_text()
            if held != text:
                raise ParameterError(f"{self.dir} holds {_difference(held, manifest)}; remove it or change -o")
        else:
            mfile.write_text(text)

    def load(self) -> dict:
        """{(branch, index): ValueResult} of every readable part; unreadable parts are removed."""
        import xarray as xr
        done = {}
        for f in sorted(self.dir.glob("*.nc")):
            try:
                with xr.open_dataset(f) as ds:
                    branch = ds.attrs["branch"]
                    for i, r in _from_dataset(ds.load()):
                        done[branch, i] = r
            except Exception as exc:  # noqa: BLE001 - any unreadable part is recomputed
                warnings.warn(f"discarding the unreadable resume part {f.name} ({type(exc).__name__}: {exc}); "
                              "its values are computed again", RuntimeWarning, stacklevel=2)
                f.unlink(missing_ok=True)
        return done

    def save(self, branch, indices, results) -> None:
        """Write the results of ``indices`` (one chunk) as one part, atomically."""
        write_netcdf(_to_dataset(branch, indices, results), self.dir / f"{branch}-{indices[0]:06d}.nc", overwrite=True)

    def remove(self) -> None:
        shutil.rmtree(self.dir, ignore_errors=True)
