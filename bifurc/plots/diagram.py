"""Bifurcation-diagram figure: stroboscopic points coloured by class, with a class strip."""
from __future__ import annotations

import numpy as np

from ..labels.classify import CLASS_LABELS
from ..storage.files import check_figure_output, save_figure
from ..storage.load import in_convention, require_kind

#: Okabe & Ito's colour-blind-safe palette, a darker grey for not-converged (distinct from the grazing
#: purple under deuteranopia); tests/test_api.py checks every pair under simulated colour blindness
CLASS_COLOURS = {"periodic": "#0072B2", "periodic-no-impact": "#56B4E9", "quasi-periodic": "#009E73",
                 "chaotic": "#D55E00", "not-converged": "#666666", "escaped": "#E69F00", "failed": "#000000"}
GRAZE = "#CC79A7"


def plot_diagram(ds, path=None, state=None, branch=None, ax=None, overwrite=False, period_of="full"):
    """Parameter against the stroboscopic state ``state`` (default the bar position),
    points coloured by class; located grazing values (dotted lines) and orbits flagged
    as grazing (triangles) marked; a strip of classes with n:m (period-n, m impacts)
    below, one row per branch.

    ``branch``: which branch to show ("up", "down", "independent"); default all
    (follow mode: "up" filled dots, "down" open circles).
    ``ax``: draw into this Axes (the diagram only) or pair of Axes (diagram, class strip)
    instead of a new figure. ``path``: also save the figure there (format from the
    extension; an existing file is refused unless ``overwrite``) and close it.
    Returns the diagram's Axes (the class strip is ``ax.figure.axes[1]`` in a new figure).
    Returning Axes, not the Figure, shows the figure once in Jupyter (a returned Figure is
    displayed again by the inline backend).
    """
    require_kind(ds, "diagram", "plot_diagram")
    ds = in_convention(ds, period_of)     # "mechanical": the strip's n:m of the bar alone (the thesis')
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch
    if path is not None:
        check_figure_output(path, overwrite)
    par = ds.attrs["swept_parameter"]
    state = state or ("x" if "x" in ds else "x1")
    branches = [branch] if branch else [str(b) for b in ds.branch.values]
    if ax is None:
        import matplotlib.pyplot as plt
        fig, (ax, strip) = plt.subplots(2, 1, sharex=True, figsize=(10, 7.2), layout="constrained",
                                        gridspec_kw={"height_ratios": [5, 1 + 0.5 * (len(branches) - 1)]})
        own = True
    else:
        own = False
        ax, strip = (ax, None) if not np.iterable(ax) else tuple(ax)
        fig = ax.figure
    pvals = ds[par].values
    style = {"independent": dict(marker=".", ms=2.2), "up": dict(marker=".", ms=2.2),
             "down": dict(marker="o", ms=3.2, mfc="none", mew=0.6)}
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
            ax.plot(px, y_scale * pts.ravel(), ls="none", color=CLASS_COLOURS[label], alpha=0.6,
                    rasterized=True, **style[b])
    handles = []
    for code in sorted({int(c) for c in np.ravel(ds.class_code.sel(branch=branches).values) if c >= 0}):
        label = CLASS_LABELS[code]
        handles.append(Patch(color=CLASS_COLOURS[label], label=_legend_label(ds, branches, code, label)))
    if len(branches) > 1:
        for b in branches:
            handles.append(Line2D([], [], ls="none", color="0.3", label=f"branch {b}", **style[b]))
    handles += _grazing_marks(ds, ax, strip, branches, pvals)
    unit = "mm" if y_scale == 1e3 else ds[state].attrs.get("units", "")
    ax.set_ylabel(f"{ds[state].attrs.get('long_name', state)} [{unit}]")
    if own:       # below the class strip, clear of the points (G14: it covered 7.5-10 Hz)
        fig.legend(handles=handles, fontsize=8, loc="outside lower center", ncol=min(3, len(handles)), frameon=False)
    else:         # beside the given Axes
        ax.legend(handles=handles, fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
    ax.grid(alpha=0.3)
    xlabel = f"{ds[par].attrs.get('long_name', par)} {par} [{ds[par].attrs.get('units', '')}]"
    if strip is None:
        ax.set_xlabel(xlabel)
    else:
        _class_strip(ds, strip, branches, pvals, xlabel)
    if own:
        fig.suptitle(_title(ds), fontsize=9)
    if path is not None:
        save_figure(fig, path, overwrite=overwrite, dpi=130, close=own)
    return ax


def _grazing_marks(ds, ax, strip, branches, pvals) -> list:
    """Orbits flagged as grazing (triangles on top), located grazing values (dotted lines; dashed where
    the impact count jumps without a graze), diamonds on the class strip; returns their legend handles."""
    from matplotlib.lines import Line2D
    handles = []
    ylo, yhi = ax.get_ylim()
    if "grazing_flag" in ds:
        flagged = (ds.grazing_flag.sel(branch=branches) == 1).any("branch").values
        if flagged.any():
            ax.plot(pvals[flagged], np.full(flagged.sum(), yhi), ls="none", marker="v", ms=5, color=GRAZE,
                    clip_on=False)
            handles.append(Line2D([], [], ls="none", marker="v", color=GRAZE,
                                  label="orbit grazes (slow impact or tiny clearance)"))
    if "grazing_value" in ds and ds.sizes.get("grazing", 0):
        keep = np.isin(ds.grazing_branch.values, branches)
        graze = ds.grazing_confirmed.values.astype(bool) if "grazing_confirmed" in ds else np.ones(keep.size, bool)
        for g, b, ok in zip(ds.grazing_value.values[keep], ds.grazing_branch.values[keep], graze[keep]):
            colour = GRAZE if ok else "0.45"
            ax.axvline(g, color=colour, lw=0.9, ls=":" if ok else "--")
            if strip is not None:
                strip.plot([g], [branches.index(b) + 0.45], marker="D" if ok else "X", ms=4, color=colour,
                           mec="white", mew=0.5)
        n_ok, n_jump = int((keep & graze).sum()), int((keep & ~graze).sum())
        if n_ok:
            handles.append(Line2D([], [], ls=":", color=GRAZE, label=f"grazing located ({n_ok}, bisection)"))
        if n_jump:
            handles.append(Line2D([], [], ls="--", color="0.45", label=f"impact count jumps, no graze ({n_jump})"))
    return handles


def _class_strip(ds, strip, branches, pvals, xlabel):
    """One row per branch, one cell per value coloured by class; periodic cells annotated n:m."""
    from matplotlib.patches import Rectangle
    width = np.diff(pvals).min() if pvals.size > 1 else 1.0
    for row, b in enumerate(branches):
        sub = ds.sel(branch=b)
        for p, c, n, m in zip(pvals, sub.class_code.values, sub.period.values, sub.impacts_per_period.values):
            if c < 0:
                continue
            strip.add_patch(Rectangle((p - width / 2, row), width, 0.9, color=CLASS_COLOURS[CLASS_LABELS[c]], lw=0))
            if CLASS_LABELS[c] == "periodic" and pvals.size <= 60:
                strip.text(p, row + 0.45, f"{n}:{m}", ha="center", va="center", fontsize=6, color="white",
                           rotation=90 if pvals.size > 45 else 0)
    strip.set_ylim(0, len(branches))
    rows = [f"swept {b}" for b in branches] if len(branches) > 1 else []
    strip.set_yticks(np.arange(len(branches)) + 0.45 if rows else [], rows, fontsize=8)
    mech = ds.attrs.get("period_convention") == "mechanical"
    strip.set_ylabel("orbit class\n(n:m = " + ("mechanical " if mech else "") + "period:impacts)", fontsize=8)
    strip.set_xlim(pvals.min() - width, pvals.max() + width)
    strip.set_xlabel(xlabel)


def _legend_label(ds, branches, code, label):
    """Class label, with the n:m types present for periodic orbits (n: period, m: impacts)."""
    if label not in ("periodic", "periodic-no-impact"):
        return label
    sel = ds.class_code.sel(branch=branches).values == code
    n = ds.period.sel(branch=branches).values[sel]
    m = ds.impacts_per_period.sel(branch=branches).values[sel]
    kinds = sorted({(int(a), int(b)) for a, b in zip(n, m)})
    text = ", ".join(f"{a}:{b}" if label == "periodic" else f"period-{a}" for a, b in kinds[:6])
    return f"{label} ({text}{', ...' if len(kinds) > 6 else ''})"


def _title(ds) -> str:
    a = ds.attrs
    keys = [k for k in ("V", "relay_hz", "R", "C", "k", "c") if f"param_{k}" in a] or \
        [k[6:] for k in a if k.startswith("param_") and not k.endswith(("_units", "_source"))][:8]
    params = ", ".join(f"{k} = {a[f'param_{k}']:g} {_unit(a.get(f'param_{k}_units', ''))}".rstrip() for k in keys)
    per = "relay periods" if "param_relay_hz" in a or a.get("swept_parameter") == "relay_hz" else "periods"
    err = a.get("error_map_step_rel")
    err_txt = (f"; estimated numerical error of each point: {err:.1e} of the state's size"
               if err is not None and np.isfinite(err) else "")
    law = f", {a['dc_law']} DC law" if a.get("dc_law") not in (None, "none") else ""
    budget = f" (undecided values extended up to {a['budget_periods']})" if "budget_periods" in a else ""
    return (f"{a['scene']} ({a['mode']}): {params}{law}\n{a['transient_periods']} transient + "
            f"{a['recorded_periods']} recorded {per}{budget}, tol {a['tol']:g}{err_txt}")


def _unit(u: str) -> str:
    return "" if u in ("1", "-") else u
