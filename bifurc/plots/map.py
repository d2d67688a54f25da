"""Regime-map figure: the cells' classes as categories, the Lyapunov exponent, impacts per period.

The categories read "period-1, 1 impact", "period-2, 2 impacts", ..., "period-1, no impact",
quasi-periodic, chaotic, not-converged, escaped, failed.  Colours: Okabe & Ito's and Paul Tol's
colour-blind-safe palettes (the non-periodic classes keep the diagram's colours,
:data:`bifurc.plots.diagram.CLASS_COLOURS`); tests/test_regime.py checks every pair under
simulated colour blindness.
"""
from __future__ import annotations

import numpy as np

from ..labels.classify import CLASS_LABELS, describe
from ..labels.codes import ClassCode
from ..storage.files import check_figure_output, save_figure
from ..storage.load import in_convention, require_kind
from .diagram import CLASS_COLOURS

#: colours of the periodic categories, most frequent first (beyond them: OTHER_PERIODIC)
#: (no green: quasi-periodic is green; no grey: not-converged is grey; G12 of newcomer review 4)
PERIODIC_COLOURS = ("#0072B2", "#56B4E9", "#CC79A7", "#F0E442", "#332288", "#663333", "#999933", "#004488",
                    "#EECC66")
OTHER_PERIODIC = ("periodic, other n:m", "#FFAABB")
MISSING = ("not computed", "#FFFFFF")
#: hatching of cells where a panel's quantity was not computed (Lyapunov: periodic; impacts: not periodic)
NOT_COMPUTED = "#999999"


def _periodic_text(code, n, m) -> str:
    """'period-2, 2 impacts' / 'period-1, no impact' (bifurc.labels.classify.describe without the n:m)."""
    return describe(code, n, m).split(" (")[0]


def regime_categories(ds, colours=PERIODIC_COLOURS):
    """(category index per cell, [(legend text, colour), ...]) of a regime-map Dataset: the
    periodic n:m categories ordered by period then impacts, then the other classes in code order;
    only categories present.  The ``colours`` go to "period-1, 1 impact" (periodic hammering)
    first, then to the other periodic categories by frequency; the rest share "periodic, other n:m"
    (``colours=None``: every category its own entry, colour None)."""
    code = ds.class_code.values.astype(int)
    n, m = ds.period.values.astype(int), ds.impacts_per_period.values.astype(int)
    periodic = np.isin(code, [ClassCode.PERIODIC, ClassCode.PERIODIC_NO_IMPACT])
    keys = sorted({(int(a), int(c), int(b)) for a, b, c in zip(n[periodic], m[periodic], code[periodic])},
                  key=lambda k: (k[0], k[1] != ClassCode.PERIODIC, k[2]))
    cells = {k: periodic & (n == k[0]) & (code == k[1]) & (m == k[2]) for k in keys}
    hammer = (1, int(ClassCode.PERIODIC), 1)
    ranked = sorted(keys, key=lambda k: (k != hammer, -int(cells[k].sum()), keys.index(k)))
    colour = {k: (colours[i] if colours is not None else None)
              for i, k in enumerate(ranked if colours is None else ranked[:len(colours)])}
    cats, index = [], np.full(code.shape, -1)
    for k in keys:
        if k in colour:
            index[cells[k]] = len(cats)
            cats.append((_periodic_text(k[1], k[0], k[2]), colour[k]))
    other = periodic & (index < 0)
    if other.any():
        index[other] = len(cats)
        cats.append(OTHER_PERIODIC)
    for c in ClassCode:
        if not c.periodic and (code == c).any():
            index[code == c] = len(cats)
            cats.append((c.label, CLASS_COLOURS[CLASS_LABELS[c]] if colours is not None else None))
    if (index < 0).any():
        index[index < 0] = len(cats)
        cats.append(MISSING)
    return index, cats


def plot_regime_map(ds, path=None, ax=None, curves=None, overwrite=False, period_of="full"):
    """Three panels over (param, param2): the categories, the largest Lyapunov exponent [1/relay
    period] where computed, and impacts per period where periodic.

    ``curves``: [(param values, param2 values, label), ...] drawn over every panel, e.g.
    two-parameter bifurcation curves from continuation.  ``ax``: three Axes to draw into
    instead of a new figure.  ``path``: also save the figure there (an existing file is
    refused unless ``overwrite``) and close it.  Cells where a panel's quantity was not computed
    (the exponent of periodic cells, impacts of non-periodic ones) are hatched, unlike any colour
    of a colour bar (the exponent's white is lambda = 0).  Returns the regime panel's Axes (the others: ``ax.figure.axes``).
    """
    require_kind(ds, "map", "plot_regime_map")
    ds = in_convention(ds, period_of)     # "mechanical": categories by the bar's period (the thesis')
    from matplotlib.colors import BoundaryNorm, ListedColormap
    from matplotlib.patches import Patch
    if path is not None:
        check_figure_output(path, overwrite)
    par, par2 = ds.attrs["swept_parameter"], ds.attrs["swept_parameter2"]
    x, y = ds[par].values, ds[par2].values
    if ax is None:
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(1, 3, figsize=(17, 5.2), constrained_layout=True)
    fig = ax[0].figure
    index, cats = regime_categories(ds)
    cmap = ListedColormap([c for _, c in cats])
    ax[0].pcolormesh(x, y, index.T, cmap=cmap, norm=BoundaryNorm(np.arange(len(cats) + 1) - 0.5, len(cats)),
                     shading="nearest", edgecolors="none")
    ax[0].set_title("regime")
    ax[0].legend(handles=[Patch(facecolor=c, edgecolor="0.3", label=t) for t, c in cats], loc="upper left",
                 bbox_to_anchor=(0.0, -0.13), ncol=3, fontsize=8, frameon=False)
    lyap = np.ma.masked_invalid(ds.lyapunov.values.T)
    span = float(np.nanmax(np.abs(ds.lyapunov.values))) if np.isfinite(ds.lyapunov.values).any() else 1.0
    im = ax[1].pcolormesh(x, y, lyap, cmap="PuOr_r", vmin=-span, vmax=span, shading="nearest")
    fig.colorbar(im, ax=ax[1], label="largest Lyapunov exponent [1/relay period]")
    ax[1].set_title("Lyapunov exponent (hatched: exponent not computed)")
    _impacts_panel(ax[2], fig, x, y, ds.impacts_per_period.values)
    ax[2].set_title("impacts per period (hatched: not periodic)")
    for a in ax:
        a.set_xlabel(f"{par} [{ds[par].attrs.get('units', '')}]")
        a.set_ylabel(f"{par2} [{ds[par2].attrs.get('units', '')}]")
        a.set_facecolor("white")
        for cx, cy, label in curves or ():
            a.plot(cx, cy, color="black", lw=1.2, label=label)
        a.set_xlim(*_edges(x))
        a.set_ylim(*_edges(y))
        if a is not ax[0]:
            _hatch_missing(a, x, y)
    if curves:
        ax[1].legend(loc="upper right", fontsize=8)
    fig.suptitle(ds.attrs.get("title", ""))
    if path is not None:
        save_figure(fig, path, overwrite=overwrite)
    return ax[0]


def _impacts_panel(ax, fig, x, y, impacts) -> None:
    """Impacts per period of the periodic cells, one colour band per count present (a rare large count does
    not squeeze the common small ones into one colour), each band's tick its count."""
    from matplotlib import colormaps
    from matplotlib.colors import BoundaryNorm
    counts = np.unique(impacts[impacts >= 0]).astype(int)
    if not counts.size:
        counts = np.array([0])
    rank = np.full(impacts.shape, np.nan)
    for r, c in enumerate(counts):
        rank[impacts == c] = r
    cmap = colormaps["cividis"].resampled(max(counts.size, 2))
    im = ax.pcolormesh(x, y, np.ma.masked_invalid(rank.T), cmap=cmap, shading="nearest",
                       norm=BoundaryNorm(np.arange(counts.size + 1) - 0.5, cmap.N))
    bar = fig.colorbar(im, ax=ax, label="impacts per period (one band per count present)")
    bar.set_ticks(np.arange(counts.size), labels=[str(c) for c in counts])


def _hatch_missing(ax, x, y) -> None:
    """Hatch the panel behind its cells: masked cells (not computed) show it."""
    from matplotlib.patches import Rectangle
    (x0, x1), (y0, y1) = _edges(x), _edges(y)
    ax.add_patch(Rectangle((x0, y0), x1 - x0, y1 - y0, facecolor="white", edgecolor=NOT_COMPUTED, hatch="////",
                           lw=0, zorder=0.5, label="not computed"))


def _edges(v):
    return v.min() - 0.5 * _step(v), v.max() + 0.5 * _step(v)


def _step(v) -> float:
    return float(np.min(np.abs(np.diff(v)))) if v.size > 1 else 1.0
