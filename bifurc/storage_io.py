"""Atomic netCDF writing: a reader never sees a half-written file (kept for callers; see bifurc.files)."""
from __future__ import annotations

from .files import write_netcdf

__all__ = ["write_netcdf_atomic"]


def write_netcdf_atomic(ds, path):
    """Write ``ds`` to ``path`` through a temporary file and ``os.replace``, replacing any file there
    (callers refuse an existing output first: :func:`bifurc.files.refuse_existing`)."""
    return write_netcdf(ds, path, overwrite=True)
