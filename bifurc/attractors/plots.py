"""Figures of an attractors dataset: the diagram coloured by attractor with the basin fractions beneath
(``ds.bifurc.plot()``), and the basin picture on a 2-D slice (:func:`plot_basins`)."""
from __future__ import annotations

import numpy as np

from maps.parameters import ParameterError

from ..storage.files import check_figure_output, save_figure
from ..storage.load import require_kind

#: one colour per attractor id (cycled); outcomes grey shades
COLOURS = ("#0072B2", "#E69F00", "#009E73", "#CC79A7", "#56B4E9", "#D55E00", "#F0E442", "#332288", "#117733",
           "#882255")
OUTCOME_COLOURS = {"escaped": "#000000", "not_converged": "#BBBBBB", "failed": "#777777", "neutral": "#DDCC77",
                   "transient": "#EE99AA"}


def _colour(label: str, j: int) -> str:
    return OUTCOME_COLOURS.get(label, COLOURS[j % len(COLOURS)])


def _legend(ds, j) -> str:
    from ..labels.classify import describe
    label = str(ds.attractor_label.values[j])
    if label in OUTCOME_COLOURS:
        return label.replace("_", " ")
    present = ds.present.values[:, j] > 0
    if not present.any():
        return label
    i = int(np.argmax(present))
    return f"{label}: {describe(int(ds.class_code.values[i, j]), int(ds.period.values[i, j]), int(ds.impacts_per_period.values[i, j]))}"


def plot_attractors(ds, path=None, state=None, ax=None, overwrite=False):
    """Parameter against the attractors' strobe state ``state`` (default the first), one colour per matched
    attractor, appearances (^) and disappearances (v) marked; beneath, the stacked basin fractions.
    Returns the upper Axes."""
    require_kind(ds, "attractors", "plot_attractors")
    if path is not None:
        check_figure_output(path, overwrite)
    import matplotlib.pyplot as plt
    par = ds.attrs["swept_parameter"]
    state = state or [k for k in ds.data_vars if ds[k].dims == (par, "attractor", "node")][0]
    if ax is None:
        fig, (ax, ax2) = plt.subplots(2, 1, sharex=True, figsize=(7, 6), gridspec_kw={"height_ratios": [2, 1]})
    else:
        fig, ax2 = ax.figure, None
    x = ds[par].values
    labels = [str(s) for s in ds.attractor_label.values]
    for j, label in enumerate(labels):
        if label in OUTCOME_COLOURS:
            continue
        y = ds[state].values[:, j, :]
        xs = np.repeat(x[:, None], y.shape[1], axis=1)
        ax.plot(xs.ravel(), y.ravel(), ".", ms=3, color=_colour(label, j), label=_legend(ds, j))
        for code, mark in ((1, "^"), (2, "v")):
            at = ds.event.values[:, j] == code
            if at.any():
                ax.plot(x[at], np.nanmean(y[at], axis=1) if code == 1 else np.full(at.sum(), np.nanmin(y)),
                        mark, color=_colour(label, j), ms=7, mfc="none")
    ax.set_ylabel(f"{state} [{ds[state].attrs.get('units', '')}]")
    if any(lb not in OUTCOME_COLOURS for lb in labels):
        ax.legend(fontsize=7, loc="best")
    else:
        ax.text(0.5, 0.5, "no attractor at any value: outcomes only (below)", transform=ax.transAxes, ha="center")
    ax.set_title(ds.attrs.get("title", ""), fontsize=9)
    if ax2 is not None:
        frac = np.nan_to_num(ds.basin_fraction.values)
        colours = [_colour(lb, j) for j, lb in enumerate(labels)]
        if len(x) > 1:
            areas = ax2.stackplot(x, frac.T, colors=colours, step="mid")
        else:               # one value: a stacked bar (a stack plot over one point has no width)
            below = np.concatenate([[0.0], np.cumsum(frac[0])[:-1]])
            width = 0.1 * max(abs(float(x[0])), 1.0)
            areas = [ax2.bar(x, [f], bottom=[b], width=width, color=c) for f, b, c in zip(frac[0], below, colours)]
        shown = [(a, lb) for a, lb, f in zip(areas, labels, frac.T) if lb in OUTCOME_COLOURS and f.max() > 0]
        if shown:           # the outcomes' colours (the attractors' are in the legend above)
            ax2.legend([a for a, _ in shown], [lb for _, lb in shown], fontsize=7, loc="upper right")
        ax2.set_ylim(0, 1)
        ax2.set_ylabel("basin fraction")
        ax2.set_xlabel(f"{par} [{ds[par].attrs.get('units', '')}]")
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
