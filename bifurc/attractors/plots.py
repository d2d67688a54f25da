"""Figures of an attractors dataset: the diagram coloured by attractor with the basin fractions beneath
(``ds.bifurc.plot()``), and the basin picture on a 2-D slice (:func:`plot_basins`)."""
from __future__ import annotations

import numpy as np

from maps.parameters import ParameterError

from ..storage.files import check_figure_output, save_figure
from ..storage.load import require_kind


#: one colour per attractor id; after ten the colours repeat with the next marker of :data:`MARKERS`
COLOURS = ("#0072B2", "#E69F00", "#009E73", "#CC79A7", "#56B4E9", "#D55E00", "#F0E442", "#332288", "#117733",
           "#882255")
#: the strobe points' marker of ids 0-9, 10-19, ... (no triangle: triangles mark the events)
MARKERS = ("o", "s", "D", "P", "X", "*")
OUTCOME_COLOURS = {"escaped": "#000000", "not_converged": "#BBBBBB", "failed": "#777777", "neutral": "#DDCC77",
                   "transient": "#EE99AA"}


def _colour(label: str, j: int) -> str:
    return OUTCOME_COLOURS.get(label, COLOURS[j % len(COLOURS)])


def _marker(j: int) -> str:
    return MARKERS[(j // len(COLOURS)) % len(MARKERS)]


def _scale(ds, state) -> tuple[float, str]:
    """(factor, unit) of a state's axis: metres in mm, as the diagram draws them."""
    unit = ds[state].attrs.get("units", "")
    return (1e3, "mm") if unit == "m" else (1.0, unit)


def _first(ds, j) -> int:
    """The first value at which attractor ``j`` is present (0 if none)."""
    return int(np.argmax(ds.present.values[:, j] > 0))


def _legend(ds, j, state=None) -> str:
    """"A3: period-1, 1 impact (1:1)": an attractor's name and what it is where first present; where another
    attractor has the same text, its place is added ("x 12.5 mm at V = 120") to tell them apart."""
    from .dataset import attractor_text
    label = str(ds.attractor_label.values[j])
    if label in OUTCOME_COLOURS:
        return label.replace("_", " ")
    if not (ds.present.values[:, j] > 0).any():
        return label
    texts = {k: attractor_text(ds, _first(ds, k), k) for k in range(ds.sizes["attractor"])
             if str(ds.attractor_label.values[k]) not in OUTCOME_COLOURS and (ds.present.values[:, k] > 0).any()}
    text = texts[j]
    if list(texts.values()).count(text) > 1:
        par = ds.attrs["swept_parameter"]
        state = state or _states(ds)[0]
        f, unit = _scale(ds, state)
        i = _first(ds, j)
        y = f * ds[state].values[i, j]
        text += f", {state} {np.nanmean(y):.4g} {unit} at {par} = {ds[par].values[i]:g}"
    return f"{label}: {text}"


def _states(ds) -> list[str]:
    par = ds.attrs["swept_parameter"]
    return [k for k in ds.data_vars if ds[k].dims == (par, "attractor", "node")]


def plot_attractors(ds, path=None, state=None, ax=None, overwrite=False):
    """Parameter against the attractors' strobe state ``state`` (default the first; metres drawn in mm), one
    colour per matched attractor (after ten, the colours repeat with another marker), appearances (^) and
    disappearances (v) marked between the two values that bracket them (at the located value where there is
    one); beneath, the basin fractions as stacked bars at the sampled values. The legend sits outside the
    axes. Returns the upper Axes."""
    from .dataset import event_location
    require_kind(ds, "attractors", "plot_attractors")
    if path is not None:
        check_figure_output(path, overwrite)
    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch
    par = ds.attrs["swept_parameter"]
    state = state or _states(ds)[0]
    f, unit = _scale(ds, state)
    if ax is None:
        fig, (ax, ax2) = plt.subplots(2, 1, sharex=True, figsize=(10, 6), gridspec_kw={"height_ratios": [2, 1]},
                                      layout="constrained")
    else:
        fig, ax2 = ax.figure, None
    x = ds[par].values
    labels = [str(s) for s in ds.attractor_label.values]
    handles = []
    for j, label in enumerate(labels):
        if label in OUTCOME_COLOURS or not (ds.present.values[:, j] > 0).any():
            continue
        y = f * ds[state].values[:, j, :]
        xs = np.repeat(x[:, None], y.shape[1], axis=1)
        ax.plot(xs.ravel(), y.ravel(), _marker(j), ms=3, ls="none", color=_colour(label, j))
        handles.append(Line2D([], [], marker=_marker(j), ls="none", ms=5, color=_colour(label, j),
                              label=_legend(ds, j, state)))
        for code, mark in ((1, "^"), (2, "v")):
            for i in np.flatnonzero(ds.event.values[:, j] == code):
                seen = i if code == 1 else max(i - 1, 0)      # the value where it is present
                at = event_location(ds, i, j)
                xe = at[0] if at is not None else 0.5 * (x[max(i - 1, 0)] + x[i])
                ax.plot([xe], [np.nanmean(y[seen])], mark, color=_colour(label, j), ms=8, mfc="none", mew=1.5)
    if handles:
        events = [Line2D([], [], marker="^", ls="none", mfc="none", color="k", ms=7,
                         label="appeared (at its located value, else mid-step)"),
                  Line2D([], [], marker="v", ls="none", mfc="none", color="k", ms=7, label="disappeared")]
        note = (f"after {len(COLOURS)} attractors the colours repeat,\nwith another marker and hatched bars"
                if len(handles) > len(COLOURS) else None)
        ax.legend(handles=handles + events, fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0),
                  borderaxespad=0.0, title=note, title_fontsize=7)
    else:
        ax.text(0.5, 0.5, "no attractor at any value: outcomes only (below)", transform=ax.transAxes, ha="center")
    ax.set_ylabel(f"{state} [{unit}]")
    ax.set_title(ds.attrs.get("title", ""), fontsize=9)
    if ax2 is not None:
        frac = np.nan_to_num(ds.basin_fraction.values)
        colours = [_colour(lb, j) for j, lb in enumerate(labels)]
        step = np.min(np.diff(np.sort(x))) if len(x) > 1 else 0.1 * max(abs(float(x[0])), 1.0)
        below = np.zeros(len(x))
        for j, c in enumerate(colours):      # stacked bars at the sampled values only
            if frac[:, j].max() > 0:
                ax2.bar(x, frac[:, j], bottom=below, width=0.6 * step, color=c, edgecolor="white", lw=0.3,
                        hatch="//" if labels[j] not in OUTCOME_COLOURS and _marker(j) != MARKERS[0] else None)
                below += frac[:, j]
        shown = [Patch(color=c, label=lb.replace("_", " ")) for lb, c, fr in zip(labels, colours, frac.T)
                 if lb in OUTCOME_COLOURS and fr.max() > 0]
        if shown:           # the outcomes' colours (the attractors' are in the legend above)
            ax2.legend(handles=shown, fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0,
                       title="outcomes", title_fontsize=7)
        ax2.set_ylim(0, 1)
        ax2.set_ylabel("basin fraction")
        ax2.set_xlabel(f"{par} [{ds[par].attrs.get('units', '')}]")
        ax2.set_xticks(x if len(x) <= 12 else ax2.get_xticks())
    if path is not None:
        save_figure(fig, path, overwrite=overwrite)
    return ax


def plot_basins(ds, value=None, path=None, ax=None, overwrite=False):
    """The basins on the 2-D slice of a census run with ``starts="slice"``: each grid start coloured by
    the attractor it reached, at the parameter value nearest ``value`` (default the first). Returns the Axes."""
    require_kind(ds, "attractors", "plot_basins")
    if ds.attrs.get("start_kind") != "slice":
        raise ParameterError("plot_basins needs a census on a 2-D slice (starts='slice'); this one used "
                             f"{ds.attrs.get('start_kind')!r} starts")
    if path is not None:
        check_figure_output(path, overwrite)
    import matplotlib.pyplot as plt
    from matplotlib.colors import ListedColormap
    par = ds.attrs["swept_parameter"]
    i = 0 if value is None else int(np.argmin(np.abs(ds[par].values - float(value))))
    a, b = ds.attrs["slice_states"].split()
    n1, n2 = (int(k) for k in np.atleast_1d(ds.attrs["slice_shape"]))
    img = ds.start_attractor.values[i].reshape(n1, n2)
    labels = [str(s) for s in ds.attractor_label.values]
    cmap = ListedColormap([_colour(lb, j) for j, lb in enumerate(labels)])
    if ax is None:
        fig, ax = plt.subplots(figsize=(5, 4.5))
    else:
        fig = ax.figure
    xa, xb = ds[f"start_{a}"].values.reshape(n1, n2)[:, 0], ds[f"start_{b}"].values.reshape(n1, n2)[0]
    ax.pcolormesh(xa, xb, img.T, cmap=cmap, vmin=-0.5, vmax=len(labels) - 0.5, shading="nearest")
    for j, lb in enumerate(labels):
        if (img == j).any():
            ax.plot([], [], "s", color=_colour(lb, j), label=f"{_legend(ds, j)} ({ds.basin_fraction.values[i, j]:.3f})")
    ax.legend(fontsize=7, loc="upper right")
    ax.set_xlabel(f"{a} [{ds[f'start_{a}'].attrs.get('units', '')}]")
    ax.set_ylabel(f"{b} [{ds[f'start_{b}'].attrs.get('units', '')}]")
    ax.set_title(f"basins at {par} = {ds[par].values[i]:g}", fontsize=9)
    if path is not None:
        save_figure(fig, path, overwrite=overwrite)
    return ax
