"""Time-history figure of a simulated scene (a Dataset from :func:`maps.simulate`)."""
from __future__ import annotations

import textwrap
from collections import Counter

import numpy as np

from ..storage.files import check_figure_output, save_figure
from ..storage.load import require_kind

#: parameters always named in the title when the scene has them (user-set ones are added)
TITLE_PARAMS = ("V", "relay_hz", "k", "c", "R", "C")
#: short axis names; the units always come from the variable's ``units`` attribute
SHORT_NAMES = {"x": "bar position x", "r": "bar - rig, x1 - x2", "i": "current i",
               "progression": "progression x2(0) - x2(t)"}


def history_panels(ds) -> list[str]:
    """Panels drawn for ``ds``, top to bottom: displacement, progression (2-DOF), current, relay."""
    return (["displacement"] + (["progression"] if "progression" in ds else [])
            + (["current"] if "i" in ds else []) + (["relay"] if "relay" in ds else []))


def _length_scale(values, units):
    """(factor, units) showing a length in mm, or µm when it stays below 1 mm."""
    if units != "m":
        return 1.0, units
    peak = np.nanmax(np.abs(values)) if np.size(values) else 0.0
    return (1e6, "µm") if peak < 1e-3 else (1e3, "mm")


def _ylabel(long_name, units, width=26):
    text = long_name if units in ("", "1", None) else f"{long_name} [{units}]"
    return textwrap.fill(text, width)


def _displacement(ds):
    """The distance the stop acts on: x (1-DOF) or r = x1 - x2 (2-DOF), with name and units."""
    if "x1" in ds:
        return (ds.x1 - ds.x2).values, SHORT_NAMES["r"], ds.x1.attrs.get("units", "")
    return ds.x.values, SHORT_NAMES["x"], ds.x.attrs.get("units", "")


def _draw_displacement(ax, ds):
    t = ds.t.values
    r, name, units = _displacement(ds)
    e = float(ds.attrs.get("param_e", 0.0))
    scale, shown = _length_scale(np.append(r, e), units)
    ax.plot(t, scale * r, lw=0.8, color="C0")
    if "param_e" in ds.attrs:
        ax.axhline(scale * e, color="k", lw=0.8, ls="--", label=f"stop (e = {e:g} {units})")
    ti = ds.impact_time.values if "impact_time" in ds else np.array([])
    ti = ti[(ti >= t.min()) & (ti <= t.max())] if t.size else ti[:0]   # only the window drawn (a time slice
    n_imp = ti.size                                                     # keeps every impact of the run)
    if n_imp:
        ax.plot(ti, np.full_like(ti, scale * e), "v", color="C3", ms=5, label=f"impacts ({n_imp})")
    elif "contact" in ds or "impact_time" in ds:  # the scene has a stop
        ax.plot([], [], "v", color="C3", ms=5, label="no impact")
    if t.size > 1:
        ax.set_xlim(t.min(), t.max())
    ax.set_ylabel(_ylabel(name, shown))
    if ax.get_legend_handles_labels()[0]:
        ax.legend(loc="lower right", bbox_to_anchor=(1.0, 1.0), ncol=2, frameon=False,
                  fontsize=8, borderaxespad=0.2)


def _draw_series(ax, ds, name, color, lw=0.7):
    var = ds[name]
    scale, shown = _length_scale(var.values, var.attrs.get("units", ""))
    ax.plot(ds.t.values, scale * var.values, lw=lw, color=color)
    ax.set_ylabel(_ylabel(SHORT_NAMES.get(name, var.attrs.get("long_name", name)), shown))


def _draw_flag(ax, ds, name, color):
    var = ds[name]
    meanings = var.attrs.get("flag_meanings", "0 1").split()
    values = np.asarray(var.attrs.get("flag_values", [0, 1]))
    ax.fill_between(ds.t.values, var.values, step="post", alpha=0.45, color=color, lw=0)
    ax.set_ylim(values.min() - 0.15, values.max() + 0.15)
    ax.set_yticks(values, meanings)
    ax.set_ylabel("relay" if name == "relay" else name)


def _preset(attrs):
    """The preset most parameters came from, read from the ``param_*_source`` attributes."""
    sources = [v.split(":")[0] for k, v in attrs.items() if k.endswith("_source") and ":" in str(v)]
    return Counter(sources).most_common(1)[0][0] if sources else None


def _title(ds):
    a = ds.attrs
    user = [k[len("param_"):-len("_source")] for k, v in a.items()
            if k.startswith("param_") and k.endswith("_source") and v == "set by user"]
    keys = [k for k in TITLE_PARAMS if f"param_{k}" in a] + [k for k in user if k not in TITLE_PARAMS]

    def fmt(k):
        units = a.get(f"param_{k}_units", "")
        star = "*" if k in user else ""
        return f"{k}{star} = {a[f'param_{k}']:g}" + (f" {units}" if units not in ("", "1") else "")

    head = a.get("scene", "")
    preset = _preset(a)
    if preset:
        head += f", preset {preset}"
    if a.get("status", "ok") != "ok":
        head += f" [{a['status'].upper()} at t = {a.get('t_end_reached', float('nan')):.4g} s]"
    line2 = ", ".join(fmt(k) for k in keys)
    options = [f"{label} {a[k]}" for k, label in (("circuit", "circuit"), ("ac_sign", "AC sign"))
               if a.get(k) not in (None, "none")]
    line3 = ", ".join(options + [f"tol {a.get('tol', float('nan')):g}"]) + ("; * set by user" if user else "")
    return f"{head}\n{line2}\n{line3}"


def plot_time_history(ds, path=None, ax=None, overwrite=False):
    """Stacked time histories of a simulated scene: the displacement the stop acts on (x, or
    x1 - x2 for 2-DOF) with the stop and the impacts marked, the rig's progression (2-DOF), the
    AC current i and the relay state. Lengths are shown in mm (µm when below 1 mm).

    Parameters
    ----------
    ds : xarray.Dataset
        From :func:`maps.simulate` (or reopened from its netCDF file).
    path : str or Path, optional
        Also write the figure there (format from the extension, 120 dpi; an existing file is
        refused unless ``overwrite``) and close it if it is this function's own.
    ax : matplotlib Axes or sequence of Axes, optional
        Draw into these instead of a new figure, one per panel of :func:`history_panels`
        in that order; a single Axes gets the displacement panel only.

    Returns
    -------
    The displacement panel's Axes (the others: ``ax.figure.axes``); returning Axes, not the Figure,
    shows the figure once in Jupyter.  Only the impacts inside the plotted time window are marked.
    """
    require_kind(ds, "history", "plot_time_history")
    if path is not None:
        check_figure_output(path, overwrite)
    panels = history_panels(ds)
    if ax is None:
        import matplotlib.pyplot as plt
        heights = [3 if p == "displacement" else (1 if p == "relay" else 2) for p in panels]
        fig, axes = plt.subplots(len(panels), 1, sharex=True, figsize=(9, 2.0 + 0.75 * sum(heights)),
                                 gridspec_kw={"height_ratios": heights}, squeeze=False)
        axes = list(axes[:, 0])
        own = True
    else:
        axes = list(np.atleast_1d(ax))
        panels = panels[:len(axes)]
        fig, own = axes[0].figure, False
    for a, panel in zip(axes, panels):
        if panel == "displacement":
            _draw_displacement(a, ds)
        elif panel == "progression":
            _draw_series(a, ds, "progression", "C2", lw=0.9)
        elif panel == "current":
            _draw_series(a, ds, "i", "C1")
        elif panel == "relay":
            _draw_flag(a, ds, "relay", "C4")
        a.grid(alpha=0.3)
    axes[len(panels) - 1].set_xlabel(f"time [{ds.t.attrs.get('units', 's')}]")
    if own:
        fig.suptitle(_title(ds), fontsize=9)
        fig.align_ylabels(axes)
        fig.tight_layout()
    if path is not None:
        save_figure(fig, path, overwrite=overwrite, dpi=120, close=own)
    return axes[0]
