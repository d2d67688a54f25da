"""Figure of a continued branch: stable parts solid, unstable dashed, special points labelled."""
from __future__ import annotations

import numpy as np

from ..storage.files import check_figure_output, save_figure
from ..storage.load import require_kind
from ..storage.schema import SPECIAL_KINDS

#: short labels of the special points on the figure
SPECIAL_LABELS = {"fold": "LP", "period_doubling": "PD", "neimark_sacker": "NS", "grazing": "G",
                  "impact_lost": "IL", "stick_onset": "ST", "signature_change": "SC", "cusp": "CP",
                  "fold_flip": "LPPD", "grazing_fold": "GLP", "curve_crossing": "X", "resonance": "R"}
_MARKERS = {"fold": "s", "period_doubling": "D", "neimark_sacker": "h", "grazing": "v", "impact_lost": "^",
            "stick_onset": "X", "signature_change": "P", "cusp": "*", "fold_flip": "*", "grazing_fold": "*",
            "curve_crossing": "*", "resonance": "*"}
#: legend text of each special point
_MEANINGS = {"fold": "fold", "period_doubling": "period doubling", "neimark_sacker": "Neimark-Sacker",
             "grazing": "grazing", "impact_lost": "impact lost", "stick_onset": "stick onset",
             "signature_change": "event sequence changes", "cusp": "cusp", "fold_flip": "fold-flip",
             "grazing_fold": "grazing-fold", "curve_crossing": "curves cross", "resonance": "resonance"}
assert set(SPECIAL_LABELS) == set(_MARKERS) == set(_MEANINGS) == set(SPECIAL_KINDS), \
    "the figure's labels must name exactly the special-point kinds of storage.schema.SPECIAL_KINDS"


def plot_branch(ds, path=None, state=None, node: int = 0, ax=None, diagram=None, overwrite=False, **style):
    """The continuation parameter against ``state`` (default the first state) at strobe node
    ``node`` of each branch point: stable parts solid, unstable dashed, one colour per branch;
    special points marked and labelled (LP fold, PD period doubling, NS Neimark-Sacker, G grazing,
    IL impact lost, ST stick onset) with their located values, labels never overlapping, each marker
    in the legend.  Where the strobe section moves (``section_phase`` changes) the line is broken:
    the state at another phase is not a continuation of the curve.

    ``diagram``: a sweep dataset (bifurc.sweep / ``bifurc diagram``) of the same parameter, drawn
    behind as grey dots (every recorded sample); where the branch spans under a tenth of the diagram's height, an
    inset repeats it magnified, with the diagram's points in its window.  Lengths in metres are drawn in mm, as in
    the diagram's own figure.  ``ax``: draw into this Axes.  ``path``: also save
    there (an existing file is refused unless ``overwrite``) and close the figure.  ``style``: ``label`` (the
    legend text) and ``colour`` (the first palette index), to tell several datasets apart on one Axes.
    Returns the Axes (shown once in Jupyter).
    """
    require_kind(ds, "branch", "plot_branch")
    unknown = set(style) - {"label", "colour"}
    if unknown:
        from maps.parameters import ParameterError
        raise ParameterError(f"plot_branch: unknown style {sorted(unknown)[0]!r}; allowed: label, colour")
    label, colour = style.get("label"), int(style.get("colour", 0))
    if path is not None:
        check_figure_output(path, overwrite)
    par = ds.attrs["continuation_parameter"]
    state = state or [v for v in ds.data_vars if ds[v].dims == ("point", "node") and not v.startswith("flag_")][0]
    own = ax is None
    if own:
        import matplotlib.pyplot as plt
        _, ax = plt.subplots(figsize=(11, 5.5), layout="constrained")
    scale = 1e3 if ds[state].attrs.get("units") == "m" else 1.0     # mm, as plot_diagram
    if diagram is not None:
        _draw_diagram(ax, diagram, par, state, scale)
    colours = ["#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9"]
    labels = ds.attrs.get("branch_labels", "").split(" | ")
    phase = ds.section_phase.values if "section_phase" in ds else np.zeros(ds.sizes["point"])
    moved = False
    for b in np.unique(ds.branch_id.values):
        sel = ds.branch_id.values == b
        p, y, stable = ds[par].values[sel], scale * ds[state].values[sel, node], ds.stable.values[sel] == 1
        tint = colours[(int(b) + colour) % len(colours)]
        name = labels[int(b)] if int(b) < len(labels) else f"branch {b}"
        name = name if label is None else f"{label}, {name}"
        same = np.isclose(phase[sel][1:], phase[sel][:-1], rtol=0, atol=1e-12) | np.isnan(phase[sel][1:])
        moved |= not same.all()
        for k in np.flatnonzero(same):    # segment by segment: solid where both ends are stable; none across a move
            ax.plot(p[k:k + 2], y[k:k + 2], color=tint, lw=1.8, ls="-" if stable[k] and stable[k + 1] else "--")
        import textwrap
        ax.plot([], [], color=tint, lw=1.8, label="\n".join(textwrap.wrap(name, 34)))
    _special_points(ax, ds, state, node, scale)
    unit = ds[par].attrs.get("units", "")
    ax.set_xlabel(f"{par} [{unit}]")
    gaps = " (gaps: the strobe section moves there)" if moved else ""
    ax.set_ylabel(f"{state} at strobe node {node} [{'mm' if scale == 1e3 else ds[state].attrs.get('units', '')}]"
                  f"{gaps}")
    ax.set_title(ds.attrs.get("title", ""), fontsize=10)
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0,   # clear of the data
              title="solid: stable, dashed: unstable", title_fontsize=8)
    _spread_labels(ax)
    if diagram is not None:
        _inset_if_flat(ax)
    if path is not None:
        save_figure(ax.figure, path, overwrite=overwrite, close=own)
    return ax


def _special_points(ax, ds, state, node, scale=1.0) -> None:
    """Mark and label the special points (one legend entry per kind present); a point at the place of one
    drawn before it gets a larger hollow marker, so that both show (PD and LP at one orbit)."""
    shown, drawn = set(), []
    par = ds.attrs["continuation_parameter"]
    xs, ys = ds[par].values, scale * ds[state].values[:, node]
    near = 0.01 * max(np.nanmax(xs) - np.nanmin(xs), 1e-300), 0.01 * max(np.nanmax(ys) - np.nanmin(ys), 1e-300)
    for i in range(ds.sizes.get("special", 0)):
        kind = SPECIAL_KINDS[int(ds.special_kind.values[i])]
        value = float(ds.special_value.values[i])
        y = scale * float(ds[state].values[int(ds.special_point.values[i]), node])
        under = sum(abs(value - a) < near[0] and abs(y - b) < near[1] for a, b in drawn)
        ax.plot([value], [y], marker=_MARKERS[kind], color="k", ms=7 + 5 * under, ls="none",
                mfc="none" if under else "k", mew=1.3, zorder=3 - 0.1 * under, gid="special-marker",
                label=None if kind in shown else f"{SPECIAL_LABELS[kind]}: {_MEANINGS[kind]}")
        drawn.append((value, y))
        shown.add(kind)
        ax.annotate(f"{SPECIAL_LABELS[kind]} {value:.6g}", (value, y), textcoords="offset points", xytext=(6, 6),
                    fontsize=8, gid="special-label")


#: label offsets tried in turn [points]: above right, below right, above left, below left, then further out
_OFFSETS = [(6, 6), (6, -14), (-6, 6), (-6, -14)] + [(dx, dy * k) for k in range(2, 7) for dx in (6, -6)
                                                     for dy in (11, -11)]


def _spread_labels(ax) -> None:
    """Place each special point's label at the first offset (:data:`_OFFSETS`) where it overlaps no label placed
    before, no special-point marker, and stays inside the Axes."""
    labels = [t for t in ax.texts if t.get_gid() == "special-label"]
    if not labels:
        return
    ax.autoscale_view()             # the limits the labels will be drawn at
    fig = ax.figure
    fig.draw_without_rendering()    # the layout (legend beside the Axes) settles the Axes' place first
    renderer = fig.canvas.get_renderer()
    frame = ax.get_window_extent(renderer)
    from matplotlib.transforms import Bbox
    markers = []
    for line in ax.lines:
        if line.get_gid() == "special-marker":
            px, py = ax.transData.transform((line.get_xdata()[0], line.get_ydata()[0]))
            half = (0.5 * line.get_markersize() + 1.5) * fig.dpi / 72    # its edge and a margin
            markers.append(Bbox([[px - half, py - half], [px + half, py + half]]))
    placed = []
    for text in sorted(labels, key=lambda t: t.xy[0]):
        for dx, dy in _OFFSETS:
            text.xyann = (dx, dy)
            text.set_ha("left" if dx > 0 else "right")
            box = text.get_window_extent(renderer)
            inside = frame.x0 <= box.x0 and box.x1 <= frame.x1 and frame.y0 <= box.y0 and box.y1 <= frame.y1
            if inside and not any(box.overlaps(o) for o in placed + markers):
                break
        placed.append(text.get_window_extent(renderer))


def _draw_diagram(ax, diagram, par, state, scale=1.0):
    if diagram.attrs.get("swept_parameter") != par:
        from maps.parameters import ParameterError
        raise ParameterError(f"the diagram sweeps {diagram.attrs.get('swept_parameter')!r}, the branch {par!r}: "
                             f"give a diagram of the same parameter")
    d = diagram[state].transpose(..., par, "sample")
    for vals in (d.values.reshape(-1, *d.shape[-2:])):            # each sweep branch
        pp = np.broadcast_to(diagram[par].values[:, None], vals.shape)
        ax.plot(pp.ravel(), scale * vals.ravel(), ",", color="0.6", alpha=0.6, gid="diagram-points")
    ax.plot([], [], ".", color="0.6", label="brute-force diagram (every recorded sample)")


def _inset_if_flat(ax) -> None:
    """Where the branch's lines span under a tenth of the Axes' height (a branch of sub-mm orbits over a diagram
    of 100 mm), an inset at the corner holding the fewest drawn points repeats the branch, its special markers and
    the diagram's points in the branch's window, magnified, with the zoom indicated."""
    branch = [ln for ln in ax.lines if ln.get_gid() != "diagram-points" and len(ln.get_xdata()) > 0]
    if not branch:
        return
    bx = np.concatenate([np.asarray(ln.get_xdata(), float) for ln in branch])
    by = np.concatenate([np.asarray(ln.get_ydata(), float) for ln in branch])
    lo, hi = ax.get_ylim()
    span = np.nanmax(by) - np.nanmin(by)
    if not np.isfinite(span) or span >= 0.1 * (hi - lo):
        return
    pad_y = max(0.15 * span, 1e-3 * (hi - lo))
    pad_x = 0.05 * max(np.nanmax(bx) - np.nanmin(bx), 1e-300)
    window = (np.nanmin(bx) - pad_x, np.nanmax(bx) + pad_x, np.nanmin(by) - pad_y, np.nanmax(by) + pad_y)
    points = np.vstack([np.column_stack([ln.get_xdata(), ln.get_ydata()]) for ln in ax.lines
                        if len(ln.get_xdata()) > 0]).astype(float)
    frac = ax.transAxes.inverted().transform(ax.transData.transform(points[np.all(np.isfinite(points), axis=1)]))
    corners = [[0.04, 0.52, 0.42, 0.42], [0.54, 0.52, 0.42, 0.42], [0.04, 0.06, 0.42, 0.42], [0.54, 0.06, 0.42, 0.42]]
    texts = [t.get_window_extent() for t in ax.texts]
    to_axes = ax.transAxes.inverted()

    def crowd(c):
        x0, y0, w, h = c
        inside = np.sum((frac[:, 0] > x0) & (frac[:, 0] < x0 + w) & (frac[:, 1] > y0) & (frac[:, 1] < y0 + h))
        covered = sum(1 for b in texts if (lambda e: e[0][0] < x0 + w and x0 < e[1][0] and e[0][1] < y0 + h
                                           and y0 < e[1][1])(to_axes.transform(b.get_points())))
        return inside + 1000 * covered
    inset = ax.inset_axes(min(corners, key=crowd))
    for ln in ax.lines:
        x, y = np.asarray(ln.get_xdata(), float), np.asarray(ln.get_ydata(), float)
        if ln.get_gid() == "diagram-points":
            keep = (x >= window[0]) & (x <= window[1]) & (y >= window[2]) & (y <= window[3])
            inset.plot(x[keep], y[keep], ".", color="0.6", ms=2, alpha=0.6)
        elif len(x):
            inset.plot(x, y, color=ln.get_color(), ls=ln.get_linestyle(), lw=ln.get_linewidth(),
                       marker=ln.get_marker(), ms=ln.get_markersize(), mfc=ln.get_markerfacecolor(),
                       mec=ln.get_markeredgecolor())
    inset.set_xlim(window[0], window[1])
    inset.set_ylim(window[2], window[3])
    inset.tick_params(labelsize=7)
    inset.set_title("the branch, magnified", fontsize=7)
    ax.indicate_inset_zoom(inset, edgecolor="0.3")


def branch_curves(ds) -> list:
    """[(p1 values, p2 values, label)] of the two-parameter curves of a branch dataset, ready to draw
    over a regime map of the same two parameters."""
    if "curve_id" not in ds:
        return []
    p1, p2 = ds.attrs["curve_parameters"].split()
    out = []
    for c in range(ds.sizes["curve"]):
        sel = ds.curve_id.values == c
        kind = SPECIAL_KINDS[int(ds.curve_kind.values[c])]
        out.append((ds[f"curve_{p1}"].values[sel], ds[f"curve_{p2}"].values[sel], f"{SPECIAL_LABELS[kind]} curve"))
    return out


def codim2_points(ds) -> list:
    """[(kind, curve index, p1, p2, tolerance)] of the codimension-two points located on the curves of a
    branch dataset (cusp, fold_flip, grazing_fold), read from its ``curve_codim2`` attribute."""
    import re
    number = r"([-+\d.eE]+|nan|inf)"
    pattern = rf"(\w+) on curve (\d+): \([^)]*\) = \({number}, {number}\) \+- {number}"
    return [(kind, int(c), float(a), float(b), float(tol))
            for kind, c, a, b, tol in re.findall(pattern, ds.attrs.get("curve_codim2", ""))]


def plot_curves(ds, path=None, ax=None, overwrite=False):
    """The two-parameter curves of a branch dataset (folds LP, period doublings PD, grazings G) in the
    (param, param2) plane, each from its special point (a dot), with the codimension-two points on them
    (stars: CP cusp, LPPD fold-flip, GLP grazing-fold).  ``ax``: draw into it (e.g. over a
    regime map of the same parameters); ``path``: also save there.  Returns the Axes."""
    if path is not None:
        check_figure_output(path, overwrite)
    require_kind(ds, "branch", "plot_curves")
    curves = branch_curves(ds)
    if not curves:
        from maps.parameters import ParameterError
        raise ParameterError("the dataset holds no two-parameter curve: continue with param2= / --param2")
    own = ax is None
    if own:
        import matplotlib.pyplot as plt
        _, ax = plt.subplots(figsize=(7, 5.5))
    styles = {"LP curve": ("#0072B2", "-"), "PD curve": ("#D55E00", "--"), "G curve": ("#009E73", "-.")}
    for x, y, label in curves:
        colour, ls = styles.get(label, ("k", ":"))
        ax.plot(x, y, color=colour, ls=ls, lw=1.8, label=label)
        ax.plot(x[:1], y[:1], "o", color=colour, ms=5)
    for kind, _, a, b, _ in codim2_points(ds):
        ax.plot([a], [b], _MARKERS[kind], color="k", ms=11, label=f"{SPECIAL_LABELS[kind]} {_MEANINGS[kind]}")
        ax.annotate(SPECIAL_LABELS[kind], (a, b), textcoords="offset points", xytext=(6, 6), fontsize=8)
    p1, p2 = ds.attrs["curve_parameters"].split()
    ax.set_xlabel(f"{p1} [{ds[f'curve_{p1}'].attrs.get('units', '')}]")
    ax.set_ylabel(f"{p2} [{ds[f'curve_{p2}'].attrs.get('units', '')}]")
    ax.set_title(f"{ds.attrs.get('scene', '')}: two-parameter curves", fontsize=10)
    handles, labels = ax.get_legend_handles_labels()
    unique = dict(zip(labels, handles))
    ax.legend(unique.values(), unique.keys(), fontsize=8)
    if path is not None:
        save_figure(ax.figure, path, overwrite=overwrite, close=own)
    return ax
