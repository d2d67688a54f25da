"""The ``ds.bifurc`` accessor on xarray Datasets written by bifurc.

>>> d = bifurc.sweep("thesis-1dof", "relay_hz", np.linspace(2, 10, 41), preset="matlab-listing")
>>> d.bifurc.plot(); d.bifurc.class_at(6.0); d.bifurc.table(); d.bifurc.report()
"""
from __future__ import annotations

import xarray as xr

from maps.parameters import ParameterError, validate_value

from .storage.load import KINDS, kind_of, require_kind

#: the plot function of each dataset kind that has a figure: (module, function)
PLOTS = {"diagram": ("plots.diagram", "plot_diagram"), "map": ("plots.map", "plot_regime_map"),
         "history": ("plots.history", "plot_time_history"), "orbit": ("plots.orbit", "plot_orbit"),
         "branch": ("plots.branch", "plot_branch"), "accuracy": ("verification.accuracy", "plot_work_precision"),
         "attractors": ("attractors.plots", "plot_attractors")}


def _plotter(kind):
    """The plot function of ``kind`` (imported on use: matplotlib and heyoka load only when drawing), or None."""
    if kind not in PLOTS:
        return None
    import importlib
    module, name = PLOTS[kind]
    return getattr(importlib.import_module(f".{module}", __package__), name)


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
        """"diagram", "map", "history", "orbit", "branch", "stability", "accuracy" or None: the dataset's
        ``bifurc_kind`` attribute (see :data:`bifurc.storage.build.KINDS`)."""
        return kind_of(self._ds)

    def _need(self, kind: str) -> None:
        require_kind(self._ds, kind)

    def plot(self, **kw):
        """The figure of this dataset: bifurcation diagram, regime map, time history, orbit, branch or
        work-precision plot.

        Keywords go to :func:`bifurc.plot_diagram`, :func:`bifurc.plot_regime_map`,
        :func:`bifurc.plot_time_history`, :func:`bifurc.plot_orbit`, :func:`bifurc.plot_branch` or
        :func:`bifurc.verification.accuracy.plot_work_precision` (``ax=``, ``path=``, ...); returns the Axes it drew on.
        """
        kind = self.kind
        plot = _plotter(kind)
        if kind == "attractors" and "swept_parameter2" in self._ds.attrs:   # a census over two parameters
            from .plots.census_map import plot_census_map as plot
        if plot is None:
            raise ParameterError(f"no figure for {'a ' + kind + ' dataset' if kind else 'this dataset'}; "
                                 f"plots exist for {', '.join(PLOTS)} datasets")
        return plot(self._ds, **kw)

    def report(self, at=None) -> Markdown:
        """Markdown report of this dataset: the classification report of a diagram (``at``: values to
        tabulate), a short summary of any other kind (:func:`bifurc.report.report`)."""
        from .report import report
        kind = self.kind
        if kind is None:
            raise ParameterError(f"not a bifurc dataset (no bifurc_kind attribute); reports exist for "
                                 f"{', '.join(KINDS)} datasets")
        return Markdown(report(self._ds, kind, **({"at": at} if kind == "diagram" else {})))

    def spectrum(self, var: str = "x", t_from=None, n_peaks: int = 5):
        """Amplitude spectrum of a time history's ``var`` with its largest peaks listed
        (:func:`bifurc.spectrum.spectrum`)."""
        from .spectrum import spectrum
        return spectrum(self._ds, var, t_from, n_peaks)

    def phase(self, x: str = "x", t_from=None, path=None, ax=None, overwrite=False):
        """Phase portrait of a time history: the velocity against position ``x`` ("x", "x1", "x2" or "r" =
        x1 - x2), from ``t_from`` [s], stop and impacts marked; returns the Axes
        (:func:`bifurc.plots.phase.plot_phase`)."""
        from .plots.phase import plot_phase
        return plot_phase(self._ds, x, t_from=t_from, path=path, ax=ax, overwrite=overwrite)

    def explore(self, workers: int | None = None, zoom: bool = True):
        """This diagram, regime map or census in Jupyter, interactive (the explore extra: HoloViz Panel).  A
        diagram: hover a value for its class, click it for its time history, phase portrait and periodic orbit,
        continue its branch, zoom to sweep a range anew (:class:`bifurc.explore.app.Explorer`; its ``select``,
        ``continue_branch`` and ``zoom`` do from Python what the clicks do; ``workers``: a zoom's processes,
        default every core; ``zoom``: compute a zoomed range anew).  A regime map: click a cell for its time
        history and orbit, zoom into a rectangle for a finer grid of cells (:class:`bifurc.explore.app.MapExplorer`).
        A census: click a value for its attractors, basins and orbits, zoom for a finer grid of values
        (:class:`bifurc.explore.app.CensusExplorer`).  Returns the page (shown as the output)."""
        if self.kind not in ("diagram", "map", "attractors"):
            raise ParameterError(f"explore needs a diagram, map or attractors dataset; this is "
                                 f"{'a ' + self.kind if self.kind else 'another kind of'} dataset")
        from .explore.app import explorer_of
        return explorer_of(self._ds, workers=workers, zoom=zoom)

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
        """One row per (branch, value): class, period, impacts, Lyapunov exponent, clearance, status...; on an
        attractor census one row per (value, attractor present or outcome reached): fraction, periods, impacts,
        exponent interval, lifetime verdict, every Floquet multiplier, the state at the section
        (:func:`bifurc.report.census_table`).

        A tidy pandas DataFrame (``ds.to_dataframe()`` has no rows when a dimension such as
        ``grazing`` is empty). ``df.attrs["units"]`` maps each column to its units.
        """
        from .labels.classify import CLASS_LABELS, describe
        if self.kind == "attractors":
            from .report import census_table
            return census_table(self._ds)
        self._need("diagram")
        ds = self._ds
        par = ds.attrs["swept_parameter"]
        names = [k for k, v in ds.data_vars.items() if v.dims == ("branch", par)]
        df = ds[names].to_dataframe().reset_index()
        df.insert(2, "class", [CLASS_LABELS[c] if c >= 0 else "missing" for c in df["class_code"]])
        df.insert(3, "description", [describe(c, n, m) if c >= 0 else "missing" for c, n, m in
                                     zip(df["class_code"], df["period"], df["impacts_per_period"])])
        if "record_used" in df:      # a label from a finite record says how long it held
            chaotic = df["class"] == "chaotic"
            df.loc[chaotic, "description"] = [
                f"chaotic for at least {int(r)} relay periods (after {int(t)}): whether the set persists is the "
                f"census' lifetime verdict (bifurc.attractors)" for r, t in
                zip(df.loc[chaotic, "record_used"], df.loc[chaotic, "transient_used"])]
        df.attrs["units"] = {k: ds[k].attrs.get("units", "") for k in [par] + names}
        return df
