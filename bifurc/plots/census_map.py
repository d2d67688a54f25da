"""The figure of a census over two parameters: the dominant attractor of each cell with its basin fraction, and
each attractor's basin fraction as a map."""
from __future__ import annotations

import numpy as np

from ..storage.files import check_figure_output, save_figure

#: the most attractors drawn as fraction maps (the most widespread first)
MAX_MAPS = 6


def _labels(ds) -> list:
    """A short label per attractor entry: its id and class at the cell where its basin is largest."""
    from ..labels.classify import describe
    frac = ds.basin_fraction.values.reshape(-1, ds.sizes["attractor"])
    code = ds.class_code.values.reshape(frac.shape)
    period = ds.period.values.reshape(frac.shape)
    impacts = ds.impacts_per_period.values.reshape(frac.shape)
    out = []
    for j, name in enumerate(ds.attractor_label.values):
        name = str(name)
        if not name.startswith("A"):
            out.append(name.replace("_", " "))
            continue
        k = int(np.argmax(frac[:, j]))
        out.append(f"{name}: {describe(int(code[k, j]), int(period[k, j]), int(impacts[k, j]))}")
    return out


def plot_census_map(ds, path=None, overwrite=False):
    """Left: the attractor holding the largest basin fraction in each cell of the (param, param2) grid, its
    fraction written in the cell; right: the basin fraction of each of the most widespread attractors (at most
    :data:`MAX_MAPS`).  Cells are drawn at the sampled values (their edges halfway between).  Returns the Figure."""
    import matplotlib.pyplot as plt
    from matplotlib.colors import BoundaryNorm, ListedColormap
    if path is not None:
        check_figure_output(path, overwrite)
    p1, p2 = ds.attrs["swept_parameter"], ds.attrs["swept_parameter2"]
    frac = ds.basin_fraction.transpose(p1, p2, "attractor").values
    present = [j for j in range(frac.shape[2]) if np.nanmax(frac[..., j]) > 0]
    top = np.argmax(np.nan_to_num(frac), axis=2)
    labels = _labels(ds)
    order = sorted(present, key=lambda j: -np.nansum(frac[..., j]))[:MAX_MAPS]
    fig, axes = plt.subplots(1, 1 + len(order), figsize=(4.2 * (1 + len(order)), 3.8), squeeze=False,
                             constrained_layout=True)
    x, y = ds[p2].values, ds[p1].values
    colours = plt.get_cmap("tab20").colors
    index = {j: n for n, j in enumerate(present)}
    cmap = ListedColormap([colours[n % len(colours)] for n in range(len(present))] or ["white"])
    ax = axes[0, 0]
    grid = np.vectorize(lambda j: index.get(int(j), 0))(top)
    ax.pcolormesh(_edges(x), _edges(y), grid, cmap=cmap, norm=BoundaryNorm(np.arange(len(present) + 1) - 0.5,
                                                                             max(len(present), 1)), shading="flat")
    for a in range(len(y)):
        for b in range(len(x)):
            ax.text(x[b], y[a], f"{frac[a, b, top[a, b]]:.2f}", ha="center", va="center", fontsize=7)
    ax.set(xlabel=_axis(ds, p2), ylabel=_axis(ds, p1), title="largest basin (its fraction in each cell)")
    handles = [plt.Rectangle((0, 0), 1, 1, color=cmap(index[j])) for j in present]
    fig.legend(handles, [labels[j] for j in present], loc="outside lower center", ncol=min(4, max(len(present), 1)),
               fontsize=8, title="attractor (class where its basin is largest)")
    for n, j in enumerate(order):
        ax = axes[0, n + 1]
        m = ax.pcolormesh(_edges(x), _edges(y), frac[..., j], vmin=0.0, vmax=1.0, cmap="viridis", shading="flat")
        ax.set(xlabel=_axis(ds, p2), title=labels[j])
        fig.colorbar(m, ax=ax, label="basin fraction")
    if path is not None:
        save_figure(fig, path, overwrite=overwrite)
    return fig


def _edges(v) -> np.ndarray:
    """Cell edges halfway between sampled values (a single value: a unit-wide cell)."""
    v = np.asarray(v, float)
    if v.size == 1:
        return np.array([v[0] - 0.5, v[0] + 0.5])
    mid = 0.5 * (v[1:] + v[:-1])
    return np.concatenate([[v[0] - (mid[0] - v[0])], mid, [v[-1] + (v[-1] - mid[-1])]])


def _axis(ds, name) -> str:
    unit = ds[name].attrs.get("units", "")
    return f"{name} [{unit}]" if unit and unit != "1" else name
