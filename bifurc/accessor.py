"""The ``ds.bifurc`` accessor on xarray Datasets written by bifurc.

>>> d = bifurc.sweep("thesis-1dof", "relay_hz", np.linspace(2, 10, 41), preset="matlab-listing")
>>> d.bifurc.plot(); d.bifurc.class_at(6.0); d.bifurc.table(); d.bifurc.report()
"""
from __future__ import annotations

import xarray as xr

from maps.parameters import ParameterError, validate_value

from .storage.load import KINDS, kind_of

__all__ = ["BifurcAccessor", "Markdown"]


class Markdown(str):
    """A markdown string that Jupyter renders (``_repr_markdown_``)."""

    def _repr_markdown_(self) -> str:
        return str(self)


@xr.register_dataset_accessor("bifurc")
class BifurcAccessor:
    """Plot, report, class lookup and a tidy table for a bifurc dataset."""

    def __init__(self, ds: xr.Dataset):
        self._ds = ds

    @property
    def kind(self) -> str | None:
        """"diagram", "map", "simulate", "stability", "accuracy" or None (see :data:`bifurc.storage.load.KINDS`)."""
        return kind_of(self._ds)

    def _need(self, kind: str) -> None:
        if self.kind != kind:
            found = f"a {self.kind} dataset" if self.kind else "not a bifurc dataset"
            raise ParameterError(f"this needs a {kind} dataset (from {KINDS[kind]}); this is {found}")

    def plot(self, **kw):
        """The figure of this dataset: bifurcation diagram, regime map, time history or work-precision plot.

        Keywords go to :func:`bifurc.plot_diagram`, :func:`bifurc.plot_regime_map`, :func:`bifurc.plot_time_history` or
        :func:`bifurc.verification.accuracy.plot_work_precision` (``ax=``, ``path=``, ...); returns the Axes it drew on.
        """
        kind = self.kind
        if kind == "diagram":
            from .plots.diagram import plot_diagram
            return plot_diagram(self._ds, **kw)
        if kind == "map":
            from .plots.map import plot_regime_map
            return plot_regime_map(self._ds, **kw)
        if kind == "simulate":
            from .plots.history import plot_time_history
            return plot_time_history(self._ds, **kw)
        if kind == "accuracy":
            from .verification.accuracy import plot_work_precision
            return plot_work_precision(self._ds, **kw)
        raise ParameterError(f"no figure for {'a ' + kind + ' dataset' if kind else 'this dataset'}; "
                             "plots exist for diagram, map, simulate and accuracy datasets")

    def report(self, at=None) -> Markdown:
        """Markdown classification report of a diagram (``at``: values to tabulate)."""
        from .report import classification_report
        self._need("diagram")
        return Markdown(classification_report(self._ds, at=at))

    def class_at(self, value, branch=None) -> dict:
        """Class of the grid value nearest to ``value`` (see :func:`bifurc.class_at`)."""
        from .report import class_at
        self._need("diagram")
        par = self._ds.attrs["swept_parameter"]
        value = validate_value(par, value, unit=self._ds[par].attrs.get("units", ""))
        branches = [str(b) for b in self._ds.branch.values]
        if branch is not None and branch not in branches:
            raise ParameterError(f"branch {branch!r}; this dataset has: {', '.join(branches)}")
        return class_at(self._ds, value, branch)

    def table(self):
        """One row per (branch, value): class, period, impacts, Lyapunov exponent, clearance, status...

        A tidy pandas DataFrame (``ds.to_dataframe()`` has no rows when a dimension such as
        ``grazing`` is empty). ``df.attrs["units"]`` maps each column to its units.
        """
        from .sweeps.classify import CLASS_LABELS, describe
        self._need("diagram")
        ds = self._ds
        par = ds.attrs["swept_parameter"]
        names = [k for k, v in ds.data_vars.items() if v.dims == ("branch", par)]
        df = ds[names].to_dataframe().reset_index()
        df.insert(2, "class", [CLASS_LABELS[c] if c >= 0 else "missing" for c in df["class_code"]])
        df.insert(3, "description", [describe(c, n, m) if c >= 0 else "missing" for c, n, m in
                                     zip(df["class_code"], df["period"], df["impacts_per_period"])])
        df.attrs["units"] = {k: ds[k].attrs.get("units", "") for k in [par] + names}
        return df
