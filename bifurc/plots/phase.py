"""Phase portrait of a time history (a Dataset from :func:`maps.simulate`): velocity against position."""
from __future__ import annotations

import numpy as np

from maps.parameters import ParameterError

from ..storage.files import check_figure_output, save_figure
from ..storage.load import require_kind

def phase_pair(ds, x: str = "x") -> tuple[str, str]:
    """(position, velocity) variables of a phase portrait: ``x`` and its velocity (``x`` -> ``v``,
    ``x1`` -> ``v1``, ``x2`` -> ``v2``; ``r`` -> the relative velocity v1 - v2 of a 2-DOF scene)."""
    if x == "r" and {"x1", "x2", "v1", "v2"} <= set(ds.data_vars):
        return "r", "dr"
    v = "v" + x[1:] if x.startswith("x") else None
    if x not in ds or v not in ds:
        pos = [k for k in ds.data_vars if k.startswith("x") and "v" + k[1:] in ds]
        raise ParameterError(f"phase: no position {x!r} with a velocity in this time history; positions: "
                             f"{', '.join(pos + (['r'] if 'x1' in ds else [])) or 'none'}")
    return x, v


def _values(ds, name):
    if name == "r":
        return (ds.x1 - ds.x2).values, ds.x1.attrs.get("units", "m"), "bar - rig, r = x1 - x2"
    if name == "dr":
        return (ds.v1 - ds.v2).values, ds.v1.attrs.get("units", "m s-1"), "relative velocity, v1 - v2"
    return ds[name].values, ds[name].attrs.get("units", ""), ds[name].attrs.get("long_name", name)


def plot_phase(ds, x: str = "x", t_from: float | None = None, path=None, ax=None, overwrite=False,
               scale: float = 1e3):
    """Phase portrait of a simulated scene: velocity [m/s] against position (x, x1, x2 or r = x1 - x2),
    drawn in mm (``scale`` 1e3 m -> mm), from ``t_from`` [s] on (default: the whole run), with the stop
    (``param_e``) and the impacts marked.  ``path``: also write the figure there (an existing file is
    refused unless ``overwrite``).  Returns the Axes; its first line holds the drawn data
    (``ax.lines[0].get_data()``: position x ``scale``, velocity)."""
    require_kind(ds, "history", "phase")
    if path is not None:
        check_figure_output(path, overwrite)
    px, pv = phase_pair(ds, x)
    sel = ds if t_from is None else ds.sel(t=slice(float(t_from), None))
    if sel.sizes.get("t", 0) < 2:
        raise ParameterError(f"phase: t_from = {t_from} s leaves fewer than 2 samples (the run ends at "
                             f"{float(ds.t.values[-1]):g} s)")
    pos, units, name = _values(sel, px)
    vel, vunits, vname = _values(sel, pv)
    own = ax is None
    if own:
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(6, 5))
    ax.plot(scale * pos, vel, lw=0.7, color="C0")
    ax.set_xlabel(f"{name} [{'mm' if scale == 1e3 and units == 'm' else units}]")
    ax.set_ylabel(f"{vname} [{vunits}]")
    if "param_e" in ds.attrs and px in ("x", "r"):
        ax.axvline(scale * float(ds.attrs["param_e"]), color="k", lw=0.8, ls="--", label="stop")
    ti = ds.impact_time.values if "impact_time" in ds else np.array([])
    t = sel.t.values
    ti = ti[np.isfinite(ti) & (ti >= t[0]) & (ti <= t[-1])]
    if ti.size:
        ax.plot(scale * np.interp(ti, t, pos), np.interp(ti, t, vel), "v", color="C3", ms=4,
                label=f"impacts ({ti.size})")
    if ax.get_legend_handles_labels()[0]:
        ax.legend(loc="best", fontsize=8)
    ax.set_title(f"phase portrait from t = {float(t[0]):.3g} s", fontsize=9)
    if path is not None:
        save_figure(ax.figure, path, overwrite, close=own)
    return ax
