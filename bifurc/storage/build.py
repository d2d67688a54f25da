"""The one generic dataset builder: a Dataset that records its kind, and schema rows written into it.

Every dataset bifurc writes is made by :func:`dataset`, so ``attrs["bifurc_kind"]`` says what it
is (:data:`KINDS`); the per-kind builders live next to their producers
(:mod:`bifurc.sweeps.dataset`, :mod:`bifurc.orbits.dataset`, :mod:`bifurc.verification`) and
write their variables with :func:`put`, one row of :mod:`bifurc.storage.schema` each.
:func:`maps.simulate.to_dataset` (``maps`` never imports ``bifurc``) writes the same attribute itself.
"""
from __future__ import annotations

import numpy as np

from .schema import PARAM, Variable

#: the attribute naming a dataset's kind
KIND_ATTR = "bifurc_kind"
#: dataset kinds and what writes them
KINDS = {"diagram": "`bifurc diagram` or bifurc.sweep", "map": "`bifurc map` or bifurc.regime_map",
         "history": "`bifurc simulate` or maps.simulate", "orbit": "`bifurc orbit` or bifurc.periodic_orbit",
         "branch": "`bifurc continue` or bifurc.continue_orbit", "stability": "`bifurc verify`",
         "accuracy": "`bifurc accuracy`", "attractors": "`bifurc attractors` or bifurc.attractors"}


def dataset(kind: str, coords=None, attrs=None):
    """An xarray Dataset of ``kind`` (one of :data:`KINDS`) with ``coords`` and ``attrs``."""
    import xarray as xr
    if kind not in KINDS:
        raise ValueError(f"dataset kind {kind!r}; allowed: {', '.join(KINDS)}")
    ds = xr.Dataset(coords=coords or {})
    ds.attrs[KIND_ATTR] = kind
    ds.attrs.update(attrs or {})
    return ds


def coord(var: Variable, data=None, **attrs) -> tuple:
    """The coordinate of the schema row ``var`` (default data: 0, 1, ... n-1 with ``data`` an int n)."""
    data = np.arange(data) if isinstance(data, (int, np.integer)) else data
    return (var.dims, np.asarray(data, dtype=str) if var.dtype is str else np.asarray(data, dtype=var.dtype),
            var.attrs(**attrs))


def put(ds, var: Variable, data, param: str | None = None, units: str | None = None) -> None:
    """Write ``data`` as the schema row ``var``: its dims (``PARAM``: ``param``), dtype and CF attributes;
    ``units`` replaces a row's ``PARAM`` units (the parameter's own), ``{param}`` in the long name is filled."""
    arr = np.asarray(data, dtype=str) if var.dtype is str else np.asarray(data, dtype=var.dtype)
    override = {"long_name": var.long_name.format(param=param)} if param is not None else {}
    if var.units == PARAM:
        override["units"] = units
    ds[var.name] = (var.dims_for(param), arr, var.attrs(**override))
