"""Opening bifurc's netCDF files with one-line errors: missing, unreadable, or of another kind."""
from __future__ import annotations

from pathlib import Path

from .files import BadFileError

__all__ = ["KINDS", "kind_of", "load"]

#: dataset kinds and what writes them
KINDS = {"diagram": "`bifurc diagram` or bifurc.sweep", "map": "`bifurc map` or bifurc.regime_map", "simulate": "`bifurc simulate` or maps.simulate",
         "stability": "`bifurc verify`", "accuracy": "`bifurc accuracy`",
         "orbit": "`bifurc orbit` or bifurc.periodic_orbit"}


def kind_of(ds) -> str | None:
    """"diagram", "map", "simulate", "stability", "accuracy", "orbit", or None for a dataset bifurc did not write."""
    if "class_code" in ds and "swept_parameter2" in ds.attrs:
        return "map"
    if "class_code" in ds and "swept_parameter" in ds.attrs:
        return "diagram"
    if "multiplier_abs" in ds and "node" in ds.dims:
        return "orbit"
    if "time" in ds.dims and "scene" in ds.attrs:
        return "simulate"
    if "verdict" in ds:
        return "stability"
    if "reference_precision" in ds.attrs:
        return "accuracy"
    return None


def load(path, kind: str | None = None):
    """Open a bifurc netCDF file fully into memory (``kind``: require that kind, see :data:`KINDS`).

    Raises FileNotFoundError, IsADirectoryError, or :class:`~bifurc.storage.files.BadFileError` for a file
    that is not readable netCDF (truncated, corrupt) or holds another kind of dataset.
    """
    from .sweep_dataset import load as read
    path = Path(path)
    if not path.exists():
        raise FileNotFoundError(f"no dataset at {path}")
    if path.is_dir():
        raise IsADirectoryError(f"{path} is a folder, not a netCDF file")
    try:
        ds = read(path)
    except Exception as exc:  # noqa: BLE001 - any reader failure means the same to the user
        reason = ("an empty file" if path.stat().st_size == 0 else "no netCDF or HDF5 signature"
                  if "did not find a match" in str(exc) else " ".join(str(exc).split())[:100])
        raise BadFileError(f"{path} is not a readable netCDF file (truncated or corrupt?): {reason}") from None
    found = kind_of(ds)
    if kind is not None and found != kind:
        what = f"{'an' if found[0] in 'aeiou' else 'a'} {found} dataset (from {KINDS[found]})" if found else "another kind of dataset"
        raise BadFileError(f"{path} holds {what}; this needs a {kind} dataset (from {KINDS[kind]})")
    return ds
