"""The one resume store: the completed points of a grid on disk, so that an interrupted run resumes where it stopped.

``<path>.parts/`` holds ``manifest.json`` (what identifies the run: the problem, the method's settings, the points,
the code version and the parts' format version; a resume with another manifest is refused, naming what differs)
and one small netCDF file per completed chunk of points, written atomically.  What a chunk holds is the task's
business: a codec (:class:`Codec`) turns its results into a Dataset and back.  A part that cannot be read is
discarded with a warning and its points are computed again.
"""
from __future__ import annotations

import json
import shutil
import warnings
from pathlib import Path

from maps.parameters import ParameterError
from maps.provenance import code_version

from ..storage.files import write_netcdf


class Codec:
    """How one kind of result is stored in a part: ``name`` (the parts' file prefix and the manifest's "format"),
    ``version`` (of the layout: parts of another version are refused), :meth:`to_dataset` and :meth:`from_dataset`."""

    name = "results"
    version = 1

    def to_dataset(self, branch: str, indices, results):
        raise NotImplementedError

    def from_dataset(self, ds) -> list:
        """[(branch, index, result)] of a part."""
        raise NotImplementedError


def problem_key(pb) -> dict:
    """What identifies a problem in a manifest: scene, builder, options, preset, parameter values, start."""
    b = pb.scene.builder
    builder = None if b is None else (f"{b.__module__}.{b.__qualname__}" if hasattr(b, "__qualname__")
                                      else repr(getattr(b, "system", b)))
    return dict(scene=pb.name, builder=builder, options=repr(pb.options), preset=pb.preset, params=dict(pb.values),
                x0=dict(pb.x0), flags0=pb.flags0)


def manifest(pb, settings: dict, points, codec: Codec, **extra) -> dict:
    """The manifest of a run: ``pb``'s key (:func:`problem_key`), the method's ``settings`` {name: value}, the
    ``points`` (parameter values, or dicts of them), the code (:func:`maps.provenance.code_version`: parts another
    version or commit computed are not mixed with this one's) and ``extra`` entries."""
    pts = [{k: float(v) for k, v in p.items()} if isinstance(p, dict) else float(p) for p in points]
    args = dict(problem_key(pb), **settings, code=code_version(), points=pts, **extra)
    return {"format": f"bifurc {codec.name} parts", "version": codec.version, "arguments": args}


def _difference(held: str, manifest: dict, version_now) -> str:
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
    if version not in (version_now, "unknown") or not isinstance(args, dict):
        return (f"a run with other arguments (or parts of format version {version}; this bifurc writes "
                f"{version_now})")
    new = json.loads(json.dumps(manifest, sort_keys=True, default=str))["arguments"]
    flat = lambda a: {**{k: v for k, v in a.items() if k != "params"},  # noqa: E731
                      **{k: v for k, v in (a.get("params") or {}).items()}}
    old, now = flat(args), flat(new)
    diff = [k for k in sorted(set(old) | set(now)) if old.get(k) != now.get(k)]
    shown = ", ".join(f"{k} = {_short(old.get(k))}" for k in diff[:3])
    ours = ", ".join(f"{k} = {_short(now.get(k))}" for k in diff[:3])
    return f"a run with other arguments: made with {shown}; this run has {ours}"


def _short(value) -> str:
    if isinstance(value, list) and len(value) > 4:
        return f"{len(value)} values {value[0]:g}..{value[-1]:g}" if all(isinstance(v, (int, float)) for v in value) \
            else f"{len(value)} items"
    return f"{value:g}" if isinstance(value, float) else str(value)


class Parts:
    """The completed points of one run under ``<path>.parts/``, stored by ``codec``."""

    def __init__(self, path, manifest: dict, codec: Codec):
        self.dir = Path(str(path) + ".parts")
        self.codec = codec
        self.dir.mkdir(parents=True, exist_ok=True)
        mfile = self.dir / "manifest.json"
        text = json.dumps(manifest, sort_keys=True, default=str)
        if mfile.exists():
            held = mfile.read_text()
            if held != text:
                raise ParameterError(f"{self.dir} holds {_difference(held, manifest, codec.version)}; remove it or "
                                     f"change -o")
        else:
            mfile.write_text(text)

    def load(self) -> dict:
        """{(branch, index): result} of every readable part; unreadable parts are removed."""
        import xarray as xr
        done = {}
        for f in sorted(self.dir.glob(f"{self.codec.name}-*.nc")):
            try:
                with xr.open_dataset(f) as ds:
                    for branch, i, r in self.codec.from_dataset(ds.load()):
                        done[branch, i] = r
            except Exception as exc:  # noqa: BLE001 - any unreadable part is recomputed
                warnings.warn(f"discarding the unreadable resume part {f.name} ({type(exc).__name__}: {exc}); "
                              "its points are computed again", RuntimeWarning, stacklevel=2)
                f.unlink(missing_ok=True)
        return done

    def save(self, branch: str, indices, results) -> None:
        """Write the results of ``indices`` (one chunk of ``branch``) as one part, atomically."""
        write_netcdf(self.codec.to_dataset(branch, indices, results),
                     self.dir / f"{self.codec.name}-{branch}-{indices[0]:06d}.nc", overwrite=True)

    def remove(self) -> None:
        shutil.rmtree(self.dir, ignore_errors=True)
