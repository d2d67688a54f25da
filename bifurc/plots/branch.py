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
    behind as grey dots (every recorded sample).  ``ax``: draw into this Axes.  ``path``: also save
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
        _, ax = plt.subplots(figsize=(9, 5.5))
    if diagram is not None:
        _draw_diagram(ax, diagram, par, state)
    colours = ["#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9"]
    labels = ds.attrs.get("branch_labels", "").split(" | ")
    phase = ds.section_phase.values if "section_phase" in ds else np.zeros(ds.sizes["point"])
    moved = False
    for b in np.unique(ds.branch_id.values):
        sel = ds.branch_id.values == b
        p, y, stable = ds[par].values[sel], ds[state].values[sel, node], ds.stable.values[sel] == 1
        tint = colours[(int(b) + colour) % len(colours)]
        name = labels[int(b)] if int(b) < len(labels) else f"branch {b}"
        name = name if label is None else f"{label}, {name}"
        same = np.isclose(phase[sel][1:], phase[sel][:-1], rtol=0, atol=1e-12) | np.isnan(phase[sel][1:])
        moved |= not same.all()
        for k in np.flatnonzero(same):    # segment by segment: solid where both ends are stable; none across a move
            ax.plot(p[k:k + 2], y[k:k + 2], color=tint, lw=1.8, ls="-" if stable[k] and stable[k + 1] else "--")
        ax.plot([], [], color=tint, lw=1.8, label=f"{name} (solid: stable, dashed: unstable)")
    _special_points(ax, ds, state, node)
    unit = ds[par].attrs.get("units", "")
    ax.set_xlabel(f"{par} [{unit}]")
    gaps = " (gaps: the strobe section moves there)" if moved else ""
    ax.set_ylabel(f"{state} at strobe node {node} [{ds[state].attrs.get('units', '')}]{gaps}")
    ax.set_title(ds.attrs.get("title", ""), fontsize=10)
    ax.legend(fontsize=8, loc="best")
    _spread_labels(ax)
    if path is not None:
        save_figure(ax.figure, path, overwrite=overwrite, close=own)
    return ax


def _special_points(ax, ds, state, node) -> None:
    """Mark and label the special points (one legend entry per kind present)."""
    shown = set()
    for i in range(ds.sizes.get("special", 0)):
        kind = SPECIAL_KINDS[int(ds.special_kind.values[i])]
        value = float(ds.special_value.values[i])
        y = float(ds[state].values[int(ds.special_point.values[i]), node])
        ax.plot([value], [y], marker=_MARKERS[kind], color="k", ms=7, ls="none",
                label=None if kind in shown else f"{SPECIAL_LABELS[kind]}: {_MEANINGS[kind]}")
        shown.add(kind)
        ax.annotate(f"{SPECIAL_LABELS[kind]} {value:.6g}", (value, y), textcoords="offset points", xytext=(6, 6),
                    fontsize=8, gid="special-label")


def _spread_labels(ax) -> None:
    """Move the special points' labels up, one line at a time, until none overlaps another."""
    labels = [t for t in ax.texts if t.get_gid() == "special-label"]
    if len(labels) < 2:
        return
    ax.autoscale_view()             # the limits the labels will be drawn at
    renderer = ax.figure.canvas.get_renderer()
    placed = []
    for text in sorted(labels, key=lambda t: t.xy[0]):
        for _ in range(len(labels) + 1):
            box = text.get_window_extent(renderer).expanded(1.02, 1.1)
            if not any(box.overlaps(other) for other in placed):
                break
            x, y = text.get_position()
            text.set_position((x, y + 11))
        placed.append(text.get_window_extent(renderer))


def _draw_diagram(ax, diagram, par, state):
    if diagram.attrs.get("swept_parameter") != par:
        from maps.parameters import ParameterError
        raise ParameterError(f"the diagram sweeps {diagram.attrs.get('swept_parameter')!r}, the branch {par!r}: "
                             f"give a diagram of the same parameter")
    d = diagram[state].transpose(..., par, "sample")
    for vals in (d.values.reshape(-1, *d.shape[-2:])):            # each sweep branch
        pp = np.broadcast_to(diagram[par].values[:, None], vals.shape)
        ax.plot(pp.ravel(), vals.ravel(), ",", color="0.6", alpha=0.6)
    ax.plot([], [], ".", color="0.6", label="brute-force diagram (every recorded sample)")


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
