"""Opening bifurc's netCDF files with one-line errors: missing, unreadable, or of another kind.

A file's kind is its ``bifurc_kind`` attribute (:mod:`bifurc.storage.build`); files written before
that attribute existed are recognised by their variables (:func:`kind_of`).  Variables renamed
since (:data:`RENAMED`) get their new names on loading.
"""
from __future__ import annotations

from pathlib import Path

from .build import KIND_ATTR, KINDS
from .files import ELAPSED_ATTRS, LEGACY_ELAPSED_UNITS, STORED_AS, BadFileError, without_time_axis

#: former kind names still accepted
ALIASES = {"simulate": "history"}
#: variables renamed in bifurc 0.x: old name -> new name (old files are read with the new names)
RENAMED = {"min_gap": "min_clearance", "min_flight_gap": "min_flight_clearance",
           "min_gap_per_step": "min_clearance_per_step", "min_flight_gap_per_step": "min_flight_clearance_per_step",
           "impact_t": "impact_time"}
#: attributes that are arrays: netCDF gives a one-element array back as a scalar
ARRAY_ATTRS = ("error_estimate_values",)


def canonical_kind(kind: str | None) -> str | None:
    """``kind`` with a former name replaced ("simulate" -> "history")."""
    return ALIASES.get(kind, kind)


def kind_of(ds) -> str | None:
    """"diagram", "map", "history", "orbit", "branch", "stability", "accuracy", or None for a dataset
    bifurc did not write: the ``bifurc_kind`` attribute, else (older files) guessed from the variables."""
    if KIND_ATTR in ds.attrs:
        return canonical_kind(str(ds.attrs[KIND_ATTR]))
    if "class_code" in ds and "swept_parameter2" in ds.attrs:
        return "map"
    if "class_code" in ds and "swept_parameter" in ds.attrs:
        return "diagram"
    if "multiplier_abs" in ds and "point" in ds.dims:
        return "branch"
    if "multiplier_abs" in ds and "node" in ds.dims:
        return "orbit"
    if "t" in ds.dims and "scene" in ds.attrs:
        return "history"
    if "verdict" in ds:
        return "stability"
    if "reference_precision" in ds.attrs:
        return "accuracy"
    return None


def require_kind(ds, kind: str, what: str = "this") -> None:
    """:class:`~maps.parameters.ParameterError` in one line unless ``ds`` is a ``kind`` dataset:
    "plot_diagram needs a diagram dataset (from ...); this is a history dataset"."""
    found = kind_of(ds) if hasattr(ds, "attrs") and hasattr(ds, "variables") else None
    if found != canonical_kind(kind):
        from maps.parameters import ParameterError
        this = (f"{'an' if found[0] in 'aeiou' else 'a'} {found} dataset" if found
                else "not a bifurc dataset" if hasattr(ds, "attrs") else f"a {type(ds).__name__}")
        raise ParameterError(f"{what} needs a {kind} dataset (from {KINDS[kind]}); this is {this}")


def read(path):
    """Open a netCDF dataset fully into memory (the file is not kept open), old variable names renamed
    and variables stored under another name (CF's case rule) given their names back."""
    import numpy as np
    import xarray as xr
    with xr.open_dataset(path, decode_times=False) as ds:
        ds = ds.load()
    for var in ds.variables.values():
        if var.attrs.get("units") == LEGACY_ELAPSED_UNITS:   # written before 0.2: a nominal epoch
            var.attrs = without_time_axis(var.attrs) | ELAPSED_ATTRS
    if "time" in ds.dims and "t" not in ds.variables and ds["time"].attrs.get("units") == "s":
        ds = ds.rename({"time": "t"})       # a time history written before 0.2 named its elapsed time "time"
        ds["t"].attrs = without_time_axis(ds["t"].attrs)
    for key in ARRAY_ATTRS:
        if key in ds.attrs:
            ds.attrs[key] = np.atleast_1d(ds.attrs[key])
    old = {k: v for k, v in RENAMED.items() if k in ds.variables and v not in ds.variables}
    stored = {k: str(v.attrs.pop(STORED_AS)) for k, v in ds.variables.items() if STORED_AS in v.attrs}
    old.update(stored)   # names stored otherwise to keep CF's case rule (storage.files.stored_names)
    return ds.rename(old) if old else ds


def load(path, kind: str | None = None):
    """Open a bifurc netCDF file fully into memory (``kind``: require that kind, see :data:`KINDS`;
    "simulate" is accepted for "history").

    Raises FileNotFoundError, IsADirectoryError, or :class:`~bifurc.storage.files.BadFileError` for a file
    that is not readable netCDF (truncated, corrupt) or holds another kind of dataset.
    """
    path = Path(path)
    kind = canonical_kind(kind)
    if kind is not None and kind not in KINDS:
        raise ValueError(f"dataset kind {kind!r}; allowed: {', '.join(KINDS)}")
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
        what = (f"{'an' if found[0] in 'aeiou' else 'a'} {found} dataset (from {KINDS.get(found, 'another tool')})"
                if found else "another kind of dataset")
        raise BadFileError(f"{path} holds {what}; this needs a {kind} dataset (from {KINDS[kind]})")
    return ds


#: the two period conventions of a diagram or map: the full state's, the mechanical states' (the thesis')
PERIOD_CONVENTIONS = ("full", "mechanical")


def in_convention(ds, period_of: str = "full"):
    """``ds`` with ``period`` and ``impacts_per_period`` read in the convention ``period_of``: "full"
    (the whole state, as stored) or "mechanical" (the mechanical states alone, the thesis'
    period-n: ``period_mechanical``, ``impacts_per_period_mechanical``); ``attrs["period_convention"]``
    names it.  A file without the mechanical period is refused in one line for "mechanical"."""
    from maps.parameters import ParameterError
    if period_of not in PERIOD_CONVENTIONS:
        raise ParameterError(f"period_of {period_of!r}; allowed: {', '.join(PERIOD_CONVENTIONS)}")
    if period_of == "full":
        return ds
    if "period_mechanical" not in ds:
        raise ParameterError("this dataset stores no mechanical period (written before it was computed): "
                             "use period_of='full'")
    out = ds.copy()
    out["period"] = ds.period_mechanical
    out["impacts_per_period"] = ds.impacts_per_period_mechanical
    out.attrs["period_convention"] = "mechanical"
    return out
