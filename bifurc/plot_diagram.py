"""Bifurcation-diagram figure: stroboscopic points coloured by class, with a class strip."""
from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402

from .classify import CLASS_LABELS  # noqa: E402

__all__ = ["plot_diagram", "CLASS_COLOURS"]

CLASS_COLOURS = {"periodic": "#1f77b4", "periodic-no-impact": "#17becf", "quasi-periodic": "#2ca02c",
                 "chaotic": "#d62728", "not-converged": "#7f7f7f", "escaped": "#ff7f0e", "failed": "#000000"}


def plot_diagram(ds, path=None, state=None, branch=None):
    """Parameter against the stroboscopic state ``state`` (default the bar position),
    points coloured by class; grazing values marked; a strip of classes and periods below.

    ``branch``: which branch to show ("up", "down", "independent"); default all
    (continuation branches are drawn with different markers). Returns the Figure.
    """
    par = ds.attrs["swept_parameter"]
    state = state or ("x" if "x" in ds else "x1")
    branches = [branch] if branch else list(ds.branch.values)
    fig, (ax, strip) = plt.subplots(2, 1, sharex=True, figsize=(10, 6.5),
                                    gridspec_kw={"height_ratios": [5, 1 + 0.5 * (len(branches) - 1)]})
    pvals = ds[par].values
    markers = {"independent": ".", "up": ".", "down": "x"}
    y_scale = 1e3 if ds[state].attrs.get("units") == "m" else 1.0
    for b in branches:
        sub = ds.sel(branch=b)
        codes = sub.class_code.values
        for code, label in enumerate(CLASS_LABELS):
            sel = codes == code
            if not sel.any():
                continue
            pts = sub[state].values[sel]  # (values, samples)
            px = np.repeat(pvals[sel], pts.shape[1])
            ax.plot(px, y_scale * pts.ravel(), markers[b], ms=1.6 if markers[b] == "." else 2.5,
                    color=CLASS_COLOURS[label], alpha=0.6, rasterized=True)
    if "grazing_value" in ds and ds.sizes.get("grazing", 0):
        for g in ds.grazing_value.values:
            ax.axvline(g, color="#9467bd", lw=0.8, ls=":")
        ax.plot([], [], ls=":", color="#9467bd", label=f"grazing ({ds.sizes['grazing']}, bisection)")
    unit = "mm" if y_scale == 1e3 else ds[state].attrs.get("units", "")
    ax.set_ylabel(f"{ds[state].attrs.get('long_name', state)} [{unit}]")
    present = sorted({int(c) for c in np.ravel(ds.class_code.values) if c >= 0})
    handles = [Patch(color=CLASS_COLOURS[CLASS_LABELS[c]], label=CLASS_LABELS[c]) for c in present]
    handles += ax.get_legend_handles_labels()[0]
    ax.legend(handles=handles, fontsize=8, loc="upper right", framealpha=0.85)
    ax.grid(alpha=0.3)
    # class strip: one row per branch, periodic cells annotated n:m
    width = np.diff(pvals).min() if pvals.size > 1 else 1.0
    for row, b in enumerate(branches):
        sub = ds.sel(branch=b)
        for p, c, n, m in zip(pvals, sub.class_code.values, sub.period.values, sub.impacts_per_period.values):
            if c < 0:
                continue
            strip.add_patch(plt.Rectangle((p - width / 2, row), width, 0.9, color=CLASS_COLOURS[CLASS_LABELS[c]],
                                          lw=0))
            if CLASS_LABELS[c] == "periodic" and pvals.size <= 60:
                strip.text(p, row + 0.45, f"{n}:{m}", ha="center", va="center", fontsize=6, color="white")
    strip.set_ylim(0, len(branches))
    strip.set_yticks(np.arange(len(branches)) + 0.45, branches, fontsize=8)
    strip.set_xlim(pvals.min() - width, pvals.max() + width)
    strip.set_xlabel(f"{ds[par].attrs.get('long_name', par)} {par} [{ds[par].attrs.get('units', '')}]")
    a = ds.attrs
    keys = [k for k in ("V", "relay_hz", "R", "C", "k", "c") if f"param_{k}" in a]
    params = ", ".join(f"{k} = {a[f'param_{k}']:g} {a[f'param_{k}_units']}" for k in keys)
    err = a.get("error_map_points_rel")
    err_txt = f"; map-point error vs tol/100: {err:.1e}" if err is not None else ""
    fig.suptitle(f"{a['scene']} ({a['mode']}): {params}\n{a['transient_periods']} transient + "
                 f"{a['recorded_periods']} recorded relay periods, tol {a['tol']:g}{err_txt}", fontsize=9)
    fig.tight_layout()
    if path:
        fig.savefig(path, dpi=130)
        plt.close(fig)
    return fig
