"""The explorer's pages, on HoloViz Panel (Bokeh figures): a stored diagram (its hover, a click's time history,
phase portrait and periodic orbit, a branch overlaid on a button's press, a zoomed range swept anew), a regime map
(a cell's time history and orbit, a zoomed rectangle computed anew) and a census (a value's attractors, basins and
orbits, a zoomed range computed anew); the zoom is the pages' shared :class:`Page` machinery.

The same :class:`Explorer` is a Jupyter output (``ds.bifurc.explore()``) and a served page (``bifurc explore``,
:func:`serve`).  Work runs off the page: a click's computation on a thread (a newer click makes an older one's
result stale, and it is dropped), a zoom in warm processes that a newer zoom ends
(:class:`bifurc.explore.compute.Zoom`, streaming its chunks);
a periodic callback moves finished results onto the page and shows progress.
"""
from __future__ import annotations

import math
import time as _time
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from maps.parameters import ParameterError

from ..labels.classify import CLASS_LABELS
from ..plots.diagram import CLASS_COLOURS
from .compute import (ZOOM_CENSUS_VALUES, ZOOM_MAP_SIDE, ZOOM_VALUES, CensusComputer, Computer, MapComputer, Spares,
                      Zoom, branch_points, map_rows, problem_of, value_rows)

#: milliseconds between two looks at the background work
POLL_MS = 150
#: a zoomed view narrower than this fraction of the shown grid's span is swept anew
ZOOM_FRACTION = 0.6
#: seconds the view must rest before a zoom starts
ZOOM_REST = 0.8


def _state(ds) -> str:
    return "x" if "x" in ds else "x1"


def _scale(ds, state) -> tuple[float, str]:
    return (1e3, "mm") if ds[state].attrs.get("units") == "m" else (1.0, ds[state].attrs.get("units", ""))


class OrbitPanels:
    """A clicked value's panels, shared by the diagram's, the regime map's and the census' pages: its time history
    (position with impacts, current, relay), phase portrait with the orbit's strobe nodes, Floquet multipliers on
    the unit circle, and the two texts above them."""

    def __init__(self, pn, problem, title: str = "time history (click a value)"):
        from bokeh.models import ColumnDataSource
        from bokeh.plotting import figure
        state = "x" if "x" in problem.system.state_names else problem.system.state_names[0]
        unit = next(s.unit for s in problem.system.states if s.name == state)
        scale, unit = (1e3, "mm") if unit == "m" else (1.0, unit)
        self.state, self.y, self.unit = state, scale, unit
        self.vel = "v" if "v" in problem.system.state_names else "v1"
        self.history_source = ColumnDataSource(dict(t=[], y=[], i=[], relay=[], v=[]))
        self.impact_source = ColumnDataSource(dict(t=[], y=[]))
        self.node_source = ColumnDataSource(dict(y=[], v=[]))
        self.multiplier_source = ColumnDataSource(dict(re=[], im=[]))
        h = figure(height=220, sizing_mode="stretch_width", name="history", title=title,
                   x_axis_label="time after the start [s]", y_axis_label=f"{state} [{unit}]",
                   tools="xpan,xwheel_zoom,reset")
        h.line("t", "y", source=self.history_source, color="#0072B2")
        h.scatter("t", "y", source=self.impact_source, marker="triangle", size=8, color="#D55E00",
                  legend_label="impacts")
        h.legend.location = "top_right"
        self.figures = [h]
        if "i" in problem.system.state_names:
            c = figure(height=150, sizing_mode="stretch_width", x_range=h.x_range, y_axis_label="current i [A]",
                       tools="", toolbar_location=None)
            c.line("t", "i", source=self.history_source, color="#009E73")
            self.figures.append(c)
        if problem.options is not None and problem.options.relay != "none":
            r = figure(height=110, sizing_mode="stretch_width", x_range=h.x_range, y_axis_label="relay",
                       x_axis_label="time [s]", tools="", toolbar_location=None)
            r.step("t", "relay", source=self.history_source, color="#666666", mode="after")
            self.figures.append(r)
        self.phase = figure(height=300, width=320, name="phase", title="phase portrait; dots: the orbit's strobe nodes",
                            x_axis_label=f"{state} [{unit}]", y_axis_label=f"{self.vel} [m/s]",
                            tools="pan,wheel_zoom,reset")
        self.phase.line("y", "v", source=self.history_source, color="#0072B2")
        self.phase.scatter("y", "v", source=self.node_source, size=6, color="black")
        self.circle = figure(frame_height=220, frame_width=220, name="multipliers", title="Floquet multipliers",
                             x_range=(-1.3, 1.3), y_range=(-1.3, 1.3), tools="", toolbar_location=None)
        t = np.linspace(0, 2 * np.pi, 200)
        self.circle.line(np.cos(t), np.sin(t), color="#999999")
        self.circle.scatter("re", "im", source=self.multiplier_source, size=9, color="#D55E00")
        self.history_pane = pn.pane.Markdown("", name="history_text", css_classes=["history-text"])
        self.orbit_pane = pn.pane.Markdown("", name="orbit_text", css_classes=["orbit-text"])

    def row(self, pn, *right):
        """The panels as one row: history text and figures; phase portrait, multipliers, orbit text and ``right``."""
        return pn.Row(pn.Column(self.history_pane, *[pn.pane.Bokeh(f, sizing_mode="stretch_width")
                                                     for f in self.figures], sizing_mode="stretch_width"),
                      pn.Column(pn.pane.Bokeh(self.phase), pn.pane.Bokeh(self.circle), self.orbit_pane, *right,
                                width=340))

    def show_history(self, h, text: str) -> None:
        """Draw the time history ``h`` (maps.simulate's dataset) and write ``text`` above it."""
        y = h[self.state].values * self.y
        t = h["t"].values
        self.history_source.data = dict(t=t, y=y, i=h["i"].values if "i" in h else np.zeros(t.size),
                                        relay=h["relay"].values if "relay" in h else np.zeros(t.size),
                                        v=h[self.vel].values if self.vel in h else np.zeros(t.size))
        ti = h["impact_time"].values if "impact_time" in h else np.array([])
        ti = ti[np.isfinite(ti)]
        self.impact_source.data = dict(t=ti, y=np.interp(ti, t, y))
        _set(self.history_pane, text)

    def show_orbit(self, o, why: str = "") -> bool:
        """Draw periodic_orbit's dataset ``o`` (its strobe nodes and multipliers) and its text; None: say ``why``
        there is none.  True when an orbit is shown."""
        if o is None:
            self.multiplier_source.data = dict(re=[], im=[])
            self.node_source.data = dict(y=[], v=[])
            _set(self.orbit_pane, f"No periodic orbit: {why}")
            return False
        mu = o.multiplier_abs.values * np.exp(1j * o.multiplier_arg.values)
        self.multiplier_source.data = dict(re=mu.real, im=mu.imag)
        nodes = o[self.state].values * self.y
        self.node_source.data = dict(y=nodes, v=o[self.vel].values if self.vel in o else np.zeros(nodes.size))
        listed = ", ".join(f"{a:.4g}" + (f" (arg {b:+.3f})" if abs(b) > 1e-9 else "")
                           for a, b in zip(o.multiplier_abs.values, o.multiplier_arg.values))
        _set(self.orbit_pane, f"**Periodic orbit**: period {int(o.period)}, {int(o.impacts_per_period)} impacts per "
                              f"period, {'stable' if int(o.stable) else 'unstable'}; Floquet multipliers "
                              f"|mu| = {listed}; Newton residual {float(o.newton_residual):.1e}")
        return True


class Page:
    """What every explorer page shares: one background thread for the clicks' work (a newer click makes an older
    result stale: it is dropped), a periodic callback that moves finished work onto the page, the status line and
    progress bar, and the zoom: a view that rests on a narrower range (a rectangle of a map) is computed anew on a
    finer grid by warm processes (:class:`bifurc.explore.compute.Spares`, started once the first click is shown,
    and :class:`bifurc.explore.compute.Zoom`), repainted as its chunks land; a newer zoom ends the stale one.

    A page defines ``KIND`` (what it shows), ``_show_dataset(ds, span)`` (paint the stored dataset or a zoom's)
    and ``zoom(...)``; it calls :meth:`_start_zoom` and :meth:`_watch_ranges` with its figure's ranges."""

    KIND = "dataset"

    def _start_page(self, pn, ds, computer, title, default: str) -> None:
        pn.extension(notifications=False)
        self.stored, self.computer, self.stored_computer = ds, computer, computer
        self.title = title or str(ds.attrs.get("title", default))
        self._pool = ThreadPoolExecutor(max_workers=1, thread_name_prefix="bifurc-explore")
        self._generation = 0
        self._pending: list = []             # (generation, kind, future, started)
        self._callback = None
        self.status_pane = pn.pane.Markdown("Loading the integrators...", name="status", css_classes=["status"])
        self.progress = pn.indicators.Progress(value=0, max=100, visible=False, sizing_mode="stretch_width", height=12)
        self._zoom, self._spares, self._ranges = None, None, ()

    def _start_zoom(self, pn, zoom: bool, workers: int | None) -> None:
        """The zoom's state, its warm processes (started after the first click) and its two widgets."""
        self.workers = workers
        self._zoom_refilled = False
        self._range_seen = (None, 0.0)       # (view, when it last changed)
        self._spares = Spares(self.stored_computer, workers) if zoom else None
        self.whole_button = pn.widgets.Button(label=f"Whole stored {self.KIND}", disabled=True)
        self.whole_button.on_click(lambda event: self.whole())
        self.zoom_check = pn.widgets.Checkbox(label="recompute a zoomed range", value=zoom)

    def _watch_ranges(self, *ranges) -> None:
        """The figure's ranges whose rested view starts a zoom (a map: both axes)."""
        self._ranges = ranges
        for r in ranges:
            r.on_change("start", self._on_range)
            r.on_change("end", self._on_range)

    def _on_range(self, attr, old, new) -> None:
        view = [(r.start, r.end) for r in self._ranges]
        if all(a is not None and b is not None for a, b in view):
            self._range_seen = (tuple((float(a), float(b)) for a, b in view), _time.monotonic())

    def _set_view(self, span) -> None:
        """Show ``span`` ((lo, hi) per watched range): the grid shown, against which a zoom is measured."""
        self._span = tuple(span)
        for r, (a, b) in zip(self._ranges, self._span):
            r.start, r.end = a, b
        self._range_seen = (self._span, _time.monotonic())

    def _submit(self, kind, fn, *args, wait=False):
        self._generation += 1
        for _, _, waiting, _ in self._pending:
            waiting.cancel()                 # stale: not started yet, never started (a running one is dropped)
        self.progress.visible, self.progress.value = True, -1          # indeterminate while it runs
        future = self._pool.submit(fn, *args)
        self._pending.append((self._generation, kind, future, _time.perf_counter()))
        if wait:
            future.result()
            self._poll()
        return self

    def _poll(self) -> None:
        """Move finished work onto the page (stale results dropped), then look at the zoom."""
        for entry in list(self._pending):
            generation, kind, future, started = entry
            if not future.done():
                continue
            self._pending.remove(entry)
            if generation != self._generation or future.cancelled():
                continue                     # a newer click came since: stale
            self.progress.visible = False
            try:
                result = future.result()
            except Exception as exc:  # noqa: BLE001 - one line on the page, never a traceback
                self.status = f"error: {' '.join(str(exc).split())[:300]}"
                continue
            getattr(self, f"_show_{kind}")(result, _time.perf_counter() - started)
            if self._spares is not None and not self._spares.children and self._zoom is None:
                self._spares.fill()          # the first click is shown: warm processes for a zoom
        self._poll_zoom()

    def _begin_zoom(self, *args, **kw) -> Zoom:
        """Start a :class:`Zoom` of the stored dataset (a running one is ended first)."""
        if self._zoom is not None:
            self._zoom.close()
            self._zoom = None
        self._zoom = z = Zoom(self.stored_computer, *args, workers=self.workers, spares=self._spares, **kw)
        self._zoom_refilled = False
        self.progress.visible, self.progress.value = True, 0
        self.status = f"zoom {z.text}: computing {z.total} {z.unit}..." + (f" ({z.note})" if z.note else "")
        return z

    def whole(self) -> None:
        """Back to the stored dataset (a running zoom is stopped)."""
        if self._zoom is not None:
            self._zoom.close()
            self._zoom = None
        self._show_dataset(self.stored)
        if self._spares is not None:
            self._spares.fill()
        self.whole_button.disabled = True
        self.progress.visible = False
        self.status = f"the stored {self.KIND}"

    def _poll_zoom(self) -> None:
        """Start a zoom when the view rests on a narrower range, and move a running zoom's chunks onto the page."""
        if not self._ranges:
            return
        view, since = self._range_seen
        if self.zoom_check.value and view is not None and _time.monotonic() - since > ZOOM_REST and \
                any(hi - lo < ZOOM_FRACTION * (b - a) for (lo, hi), (a, b) in zip(view, self._span)) and \
                (self._zoom is None or self._zoom.view != view):
            self._range_seen = (view, math.inf)   # once per resting view
            try:
                self.zoom(*(x for pair in view for x in pair))
            except ParameterError as exc:          # a range outside a parameter's allowed one: said in one line
                self.status = f"zoom refused: {exc}"
                self.progress.visible = False
        z = self._zoom
        if z is None:
            return
        s = z.poll()
        if s["dataset"] is not None:
            self._show_dataset(s["dataset"], span=z.span)
            self.whole_button.disabled = False
        if s["stage"] >= 1 and not self._zoom_refilled and self._spares is not None:
            self._spares.fill()              # the first picture is shown: warm processes for the next zoom
            self._zoom_refilled = True
        note = f"; {z.note}" if z.note else ""
        if s["error"]:
            self.status = f"zoom failed: {s['error']}"
            z.close()
            self._zoom, self.progress.visible = None, False
        elif s["stage"] >= len(z.stages):
            self.status = f"zoom {z.text}: {z.stages[-1][0]} shown ({s['seconds']:.1f} s){note}"
            z.close()
            self._zoom, self.progress.visible = None, False
        else:
            self.progress.value = int(100 * s["done"] / s["total"])
            self.status = (f"zoom {z.text}, {s['name']}: {s['done']} of {s['total']} {z.unit} "
                           f"({s['seconds']:.1f} s){note}")

    status = property(lambda self: self.status_pane.object, lambda self, text: _set(self.status_pane, text),
                      doc="the status line: what runs, its progress, how long a result took")
    history_text = property(lambda self: self.panels.history_pane.object,
                            doc="the clicked value: its class, the periods of its time history and their impacts")
    orbit_text = property(lambda self: self.panels.orbit_pane.object,
                          doc="the clicked value's periodic orbit with its Floquet multipliers, or why none")
    multiplier_source = property(lambda self: self.panels.multiplier_source, doc="the shown multipliers (re, im)")

    def start(self):
        """Start the periodic look at the background work (in a served session or a live notebook)."""
        import panel as pn
        if self._callback is None:
            self._callback = pn.state.add_periodic_callback(self._poll, period=POLL_MS)
            if self.status.startswith("Loading"):
                self.status = self.HINT
        return self

    def servable(self):
        """The page's layout, with its periodic callback started."""
        self.start()
        return self.layout

    def _repr_mimebundle_(self, include=None, exclude=None):
        self.start()
        return self.layout._repr_mimebundle_(include, exclude)

    def close(self) -> None:
        """Stop the background work (the thread, a zoom's processes and the warm ones)."""
        if self._zoom is not None:
            self._zoom.close()
        if self._spares is not None:
            self._spares.close()
            self._spares = None
        if self._callback is not None:
            self._callback.stop()
        self._pool.shutdown(wait=False, cancel_futures=True)


class Explorer(Page):
    """A stored diagram explored in the browser: hover a value for its class, click it for its time history and
    orbit, press "Continue branch" for its branch, zoom for a finer grid.

    ``select(value, wait=True)``, ``continue_branch(wait=True)`` and ``zoom(lo, hi)`` do from Python what the
    clicks do; ``status``, ``history_text`` and ``orbit_text`` hold what the page shows.
    """

    HINT = "hover a value for its class; click it for its time history and orbit"
    KIND = "diagram"

    def __init__(self, ds, title: str | None = None, workers: int | None = None, zoom: bool = True):
        import panel as pn
        self._start_page(pn, ds, Computer(ds), title, "diagram")
        self._selected = None
        self._warm = self._pool.submit(self.computer.warm)
        self._start_zoom(pn, zoom, workers)
        self._build(pn)
        self._show_dataset(ds)

    # ----- the page ------------------------------------------------------------------------------------------
    def _build(self, pn) -> None:
        from bokeh.models import ColumnDataSource, HoverTool, TapTool
        from bokeh.plotting import figure
        ds, par = self.stored, self.computer.param
        state = _state(ds)
        scale, unit = _scale(ds, state)
        self._state, self._y = state, scale
        units = ds[par].attrs.get("units", "")
        self.points = ColumnDataSource(dict(p=[], y=[], colour=[]))
        self.columns = ColumnDataSource(dict(left=[], right=[], value=[], text=[], nm=[], exponent=[], reason=[],
                                             colour=[], label=[], bottom=[], top=[]))
        self.branch_source = ColumnDataSource(dict(p=[], y=[]))
        tips = [(f"{par} [{units}]", "@value{0.[0000]}"), ("class", "@text"), ("n:m", "@nm"),
                ("exponent", "@exponent"), ("reason", "@reason")]
        d = figure(height=360, sizing_mode="stretch_width", tools="xpan,xwheel_zoom,box_zoom,reset",
                   toolbar_location="above", name="diagram", y_axis_label=f"{state} [{unit}] at the strobe",
                   title=f"{self.title}: hover a value, click it for its orbit")
        d.scatter("p", "y", source=self.points, size=2.5, color="colour", alpha=0.7)
        cols = d.quad(left="left", right="right", bottom="bottom", top="top", source=self.columns, fill_alpha=0,
                      line_alpha=0, hover_fill_color="black", hover_fill_alpha=0.08, selection_fill_alpha=0.12,
                      selection_fill_color="black", nonselection_fill_alpha=0, nonselection_line_alpha=0)
        d.scatter("p", "y", source=self.branch_source, size=3, color="black", marker="diamond",
                  legend_label="branch (continued)")
        d.legend.location, d.legend.visible = "top_left", False
        self._branch_legend = d.legend
        d.add_tools(HoverTool(renderers=[cols], tooltips=tips), TapTool(renderers=[cols]))
        strip = figure(height=110, sizing_mode="stretch_width", x_range=d.x_range, tools="", toolbar_location=None,
                       name="strip", x_axis_label=f"{ds[par].attrs.get('long_name', par)} {par} [{units}]",
                       y_axis_label="class")
        rects = strip.quad(left="left", right="right", bottom=0, top=1, source=self.columns, fill_color="colour",
                           line_color="white", line_width=0.5, hover_fill_alpha=0.6, nonselection_fill_alpha=0.9)
        strip.yaxis.visible = False
        strip.ygrid.visible = False
        strip.add_tools(HoverTool(renderers=[rects], tooltips=tips), TapTool(renderers=[rects]))
        self.columns.selected.on_change("indices", self._on_tap)
        self._watch_ranges(d.x_range)
        self.diagram_figure, self.strip_figure = d, strip
        # the clicked value's panels
        self.panels = OrbitPanels(pn, self.computer.problem)
        self.branch_button = pn.widgets.Button(label="Continue branch", color="primary", disabled=True,
                                               css_classes=["branch-button"])
        self.branch_button.on_click(lambda event: self.continue_branch())
        self.layout = pn.Column(
            pn.pane.Bokeh(d, sizing_mode="stretch_width"), pn.pane.Bokeh(strip, sizing_mode="stretch_width"),
            pn.Row(self.branch_button, self.whole_button, self.zoom_check), self.progress, self.status_pane,
            self.panels.row(pn), sizing_mode="stretch_width", name="bifurc explore")

    def _show_dataset(self, ds, span=None) -> None:
        """Paint ``ds`` (the stored diagram or a zoom's) on the diagram and the strip; clicks then refer to it;
        ``span``: the shown range (a zoom's whole range while its chunks land), else the values' own."""
        self.computer = self.stored_computer if ds is self.stored else self.stored_computer.on(ds)
        rows = value_rows(ds)
        vals = rows["value"]
        width = np.diff(vals).min() if vals.size > 1 else 1.0
        sub = ds.isel(branch=0)
        pts = sub[self._state].values * self._y                     # (value, sample)
        colours = [CLASS_COLOURS.get(lab, "#000000") for lab in rows["label"]]
        keep = np.isfinite(pts)
        self.points.data = dict(p=np.repeat(vals, pts.shape[1])[keep.ravel()], y=pts[keep],
                                colour=np.repeat(np.asarray(colours), pts.shape[1])[keep.ravel()].tolist())
        finite = pts[keep]
        lo, hi = (float(finite.min()), float(finite.max())) if finite.size else (0.0, 1.0)
        pad = 0.05 * (hi - lo or 1.0)
        self.columns.selected.indices = []
        self.columns.data = dict(left=vals - width / 2, right=vals + width / 2, value=vals, text=rows["text"],
                                 nm=rows["nm"], exponent=rows["exponent"], reason=rows["reason"], colour=colours,
                                 label=rows["label"], bottom=np.full(vals.size, lo - pad),
                                 top=np.full(vals.size, hi + pad))
        self.branch_source.data = dict(p=[], y=[])
        self._branch_legend.visible = False
        self._set_view(span or ((float(vals.min() - width), float(vals.max() + width)),))

    # ----- what a click does -----------------------------------------------------------------------------------
    def _on_tap(self, attr, old, new) -> None:
        if new:
            self.select(float(self.columns.data["value"][new[0]]))

    def select(self, value, wait: bool = False):
        """Show ``value``'s time history, phase portrait and periodic orbit (the nearest grid value); ``wait``:
        return when they are shown (from Python), else in the background (a click)."""
        i = self.computer.index(value)
        self._selected = float(self.computer.values[i])
        self.branch_button.disabled = True
        par = self.computer.param
        self.status = f"computing {par} = {self._selected:g}: time history and orbit..."
        return self._submit("history", self.computer.history, self._selected, wait=wait)

    def continue_branch(self, wait: bool = False):
        """Continue the selected value's periodic orbit along the swept parameter to both ends of the diagram and
        overlay its strobe points (:func:`bifurc.continue_orbit`)."""
        if self._selected is None:
            raise ParameterError("no value selected: click a periodic value first")
        self.status = f"continuing the branch through {self.computer.param} = {self._selected:g}..."
        return self._submit("branch", self.computer.branch, self._selected, wait=wait)

    # ----- results ----------------------------------------------------------------------------------------------
    def _show_history(self, r, wall) -> None:
        par, units = self.computer.param, self.computer.ds[self.computer.param].attrs.get("units", "")
        row = self.columns.data
        j = int(np.argmin(np.abs(np.asarray(row["value"]) - r["value"])))
        per = "relay periods" if par == "relay_hz" or "relay_hz" in self.computer.problem.values else "periods"
        self.panels.show_history(r["history"], f"**{par} = {r['value']:g} {units}: {row['text'][j]}.** Time history "
                                               f"over {r['periods']} {per} after the record: "
                                               f"**{r['impacts']} impacts**")
        self.branch_button.disabled = not self.panels.show_orbit(r["orbit"], r["orbit_error"])
        self.status = f"{par} = {r['value']:g}: shown in {wall:.2f} s"

    def _show_branch(self, r, wall) -> None:
        ps, ys = [], []
        for br in r["branches"]:
            p, y = branch_points(br, self._state)
            ps.append(p)
            ys.append(y * self._y)
        self.branch_source.data = dict(p=np.concatenate(ps) if ps else [], y=np.concatenate(ys) if ys else [])
        self._branch_legend.visible = bool(ps)
        points = sum(br.sizes["point"] for br in r["branches"])
        self.status = (f"branch through {self.computer.param} = {r['value']:g}: {points} points in {wall:.2f} s"
                       + (f"; {r['error']}" if r["error"] else "") if points else f"no branch: {r['error']}")

    # ----- zoom -------------------------------------------------------------------------------------------------
    def zoom(self, lo: float, hi: float, n: int = ZOOM_VALUES):
        """Sweep ``lo`` to ``hi`` anew on ``n`` values in warm processes (every core): a first picture, then the
        anytime labels; the diagram repaints as their chunks land."""
        return self._begin_zoom(float(lo), float(hi), n)


class MapExplorer(Page):
    """A stored regime map in the browser: hover a cell for its class, click it for its time history and periodic
    orbit (the cell swept anew as a one-value diagram with the map's settings, :class:`MapComputer`); zoom into a
    rectangle (box zoom) and it is computed anew on a finer grid of cells with the map's settings
    (:func:`bifurc.regime_map`, in warm processes).

    ``select(value, value2, wait=True)`` and ``zoom(lo, hi, lo2, hi2)`` do from Python what the clicks do."""

    HINT = "hover a cell for its class; click it for its time history and orbit; box zoom for a finer grid"
    KIND = "map"

    def __init__(self, ds, title: str | None = None, workers: int | None = None, zoom: bool = True):
        import panel as pn
        from bokeh.models import ColumnDataSource, HoverTool, TapTool
        from bokeh.plotting import figure
        self._start_page(pn, ds, MapComputer(ds), title, "regime map")
        self._start_zoom(pn, zoom, workers)
        p1, p2 = self.computer.param, self.computer.param2
        self.cells = ColumnDataSource(dict(left=[], right=[], bottom=[], top=[], value=[], value2=[], text=[],
                                           colour=[]))
        u1, u2 = (ds[p].attrs.get("units", "") for p in (p1, p2))
        f = figure(height=380, sizing_mode="stretch_width", name="map", tools="pan,wheel_zoom,box_zoom,reset",
                   title=f"{self.title}: hover a cell, click it for its orbit", x_range=(0, 1), y_range=(0, 1),
                   x_axis_label=f"{p1} [{u1}]", y_axis_label=f"{p2} [{u2}]")
        quads = f.quad(left="left", right="right", bottom="bottom", top="top", source=self.cells, fill_color="colour",
                       line_color="white", hover_line_color="black", hover_fill_alpha=0.7, selection_line_color="black",
                       selection_line_width=2, nonselection_fill_alpha=0.9)
        f.add_tools(HoverTool(renderers=[quads], tooltips=[(f"{p1} [{u1}]", "@value{0.[0000]}"),
                                                          (f"{p2} [{u2}]", "@value2{0.[0000]}"), ("class", "@text")]),
                    TapTool(renderers=[quads]))
        self.cells.selected.on_change("indices", self._on_tap)
        self.map_figure = f
        self._watch_ranges(f.x_range, f.y_range)
        self.panels = OrbitPanels(pn, problem_of(ds), title="time history (click a cell)")
        self.layout = pn.Column(pn.pane.Bokeh(f, sizing_mode="stretch_width"), pn.Row(self.whole_button,
                                                                                        self.zoom_check),
                                self.progress, self.status_pane, self.panels.row(pn), sizing_mode="stretch_width",
                                name="bifurc explore")
        self._show_dataset(ds)

    def _show_dataset(self, ds, span=None) -> None:
        """Paint ``ds`` (the stored map or a zoom's) as cells; clicks then refer to it; ``span``: the shown
        rectangle (a zoom's whole one while its rows land), else the cells' own."""
        self.computer = self.stored_computer if ds is self.stored else self.stored_computer.on(ds)
        rows = map_rows(ds)
        grids = (self.computer.values, self.computer.values2)
        half = [np.diff(np.sort(g)).min() / 2 if g.size > 1 else 0.5 for g in grids]
        self.cells.selected.indices = []
        self.cells.data = dict(left=rows["value"] - half[0], right=rows["value"] + half[0],
                               bottom=rows["value2"] - half[1], top=rows["value2"] + half[1], value=rows["value"],
                               value2=rows["value2"], text=rows["text"],
                               colour=[CLASS_COLOURS.get(lab, "#000000") for lab in rows["label"]])
        self._set_view(span or tuple((float(g.min() - h), float(g.max() + h)) for g, h in zip(grids, half)))

    @property
    def cell_count(self) -> int:
        """The cells the map shows (the stored map's, or a zoom's stored so far)."""
        return len(self.cells.data["value"])

    def zoom(self, lo: float, hi: float, lo2: float, hi2: float, n: int = ZOOM_MAP_SIDE, n2: int = ZOOM_MAP_SIDE):
        """Compute the rectangle ``lo`` to ``hi`` (of the first parameter) by ``lo2`` to ``hi2`` (of the second)
        anew on ``n`` x ``n2`` cells with the map's settings, row by row in warm processes: a first picture, then
        the anytime labels; the map repaints as the rows land."""
        return self._begin_zoom(float(lo), float(hi), n, second=(float(lo2), float(hi2), n2))

    def _on_tap(self, attr, old, new) -> None:
        if new:
            d = self.cells.data
            self.select(float(d["value"][new[0]]), float(d["value2"][new[0]]))

    def select(self, value, value2, wait: bool = False):
        """Show the cell nearest (``value``, ``value2``): its time history and periodic orbit."""
        i, j = self.computer.index(value, value2)
        v, v2 = float(self.computer.values[i]), float(self.computer.values2[j])
        self.status = (f"computing the cell {self.computer.param} = {v:g}, {self.computer.param2} = {v2:g}: "
                       f"swept anew, then its time history and orbit...")
        return self._submit("cell", self.computer.cell, v, v2, wait=wait)

    def _show_cell(self, r, wall) -> None:
        p1, p2 = self.computer.param, self.computer.param2
        per = "relay periods" if "relay_hz" in (p1, p2) or "relay_hz" in self.computer.kwargs["params"] else "periods"
        self.panels.show_history(r["history"], f"**{p1} = {r['value']:g}, {p2} = {r['value2']:g}: {r['stored']}.** "
                                               f"Time history over {r['periods']} {per} after the cell's record: "
                                               f"**{r['impacts']} impacts**")
        self.panels.show_orbit(r["orbit"], r["orbit_error"])
        self.status = f"{p1} = {r['value']:g}, {p2} = {r['value2']:g}: shown in {wall:.2f} s"


class CensusExplorer(Page):
    """A stored census (attractors dataset over one parameter) in the browser: its figure (each attractor's strobe
    states against the parameter, the basin fractions beneath); hover a value for its attractors, click it for
    each attractor's class, basin fraction with its 95 % interval, the fresh starts' basins on their slice, the
    attractors' stored strobe states, and a representative's time history (the largest basin's; the menu picks
    another); zoom into a range and it is computed anew on a finer grid of values (:func:`bifurc.attractors`
    with the census' settings, starts kind and seed, at most
    :data:`bifurc.explore.compute.ZOOM_STARTS` starts per value, in warm processes).

    ``select(value, wait=True)``, ``show_attractor(label, wait=True)`` and ``zoom(lo, hi)`` do from Python what
    the clicks do; ``attractors_text`` holds the table the page shows."""

    HINT = "hover a value for its attractors; click it for their basins and orbits; zoom for a finer grid"
    KIND = "census"

    def __init__(self, ds, title: str | None = None, workers: int | None = None, zoom: bool = True):
        import panel as pn
        from bokeh.models import ColumnDataSource, HoverTool, TapTool
        from bokeh.plotting import figure
        self._start_page(pn, ds, CensusComputer(ds), title, "census")
        self._start_zoom(pn, zoom, workers)
        c, par = self.computer, self.computer.param
        state = c.states[0]
        scale, unit = _scale(ds, state)
        self._y, self._census_state = scale, state
        units = ds[par].attrs.get("units", "")
        self.census_points = ColumnDataSource(dict(p=[], y=[], colour=[], label=[]))
        self.census_bars = ColumnDataSource(dict(p=[], bottom=[], top=[], colour=[], label=[], left=[], right=[]))
        self.columns = ColumnDataSource(dict(left=[], right=[], value=[], text=[], bottom=[], top=[]))
        tips = [(f"{par} [{units}]", "@value{0.[0000]}"), ("attractors", "@text")]
        f = figure(height=320, sizing_mode="stretch_width", name="census", tools="xpan,xwheel_zoom,xbox_zoom,reset",
                   title=f"{self.title}: hover a value, click it for its attractors", x_range=(0, 1),
                   y_axis_label=f"{state} [{unit}] at the strobe")
        f.scatter("p", "y", source=self.census_points, size=6, color="colour")
        cols = f.quad(left="left", right="right", bottom="bottom", top="top", source=self.columns, fill_alpha=0,
                      line_alpha=0, hover_fill_color="black", hover_fill_alpha=0.08, selection_fill_alpha=0.12,
                      selection_fill_color="black", nonselection_fill_alpha=0, nonselection_line_alpha=0)
        f.add_tools(HoverTool(renderers=[cols], tooltips=tips), TapTool(renderers=[cols]))
        fr = figure(height=140, sizing_mode="stretch_width", x_range=f.x_range, name="fractions", tools="",
                    toolbar_location=None, y_axis_label="basin fraction", y_range=(0, 1),
                    x_axis_label=f"{ds[par].attrs.get('long_name', par)} {par} [{units}]")
        fq = fr.quad(left="left", right="right", bottom="bottom", top="top", source=self.census_bars,
                     fill_color="colour", line_color="white")
        fr.add_tools(HoverTool(renderers=[fq], tooltips=[("attractor", "@label")]))
        self.columns.selected.on_change("indices", self._on_tap)
        self.census_figure = f
        self._watch_ranges(f.x_range)
        # the clicked value: basins on the slice, the attractors' strobe states, a representative's history
        self.start_source = ColumnDataSource(dict(a=[], b=[], colour=[], label=[]))
        self.node_sources = ColumnDataSource(dict(a=[], b=[], colour=[], label=[]))
        sa, sb = (ds.attrs.get("slice_states", "") or " ".join(c.states[:2])).split()[:2] \
            if len(c.states) > 1 else (state, state)
        self._pair = (sa, sb)
        ua, ub = (_scale(ds, s)[1] for s in (sa, sb))
        basin = figure(height=300, width=340, name="basins", tools="pan,wheel_zoom,reset",
                       title="basins: each fresh start by the attractor it reached",
                       x_axis_label=f"{sa} [{ua}] at the start", y_axis_label=f"{sb} [{ub}]")
        basin.scatter("a", "b", source=self.start_source, size=9, marker="square", color="colour", legend_field="label")
        basin.scatter("a", "b", source=self.node_sources, size=10, marker="star", color="black")
        basin.legend.location = "top_left"
        basin.legend.label_text_font_size = "8pt"
        self.attractor_pane = pn.pane.Markdown("", name="attractors_text", css_classes=["attractors-text"])
        self.attractor_select = pn.widgets.Select(name="time history of", options=[], disabled=True)
        self.attractor_select.param.watch(self._on_select, "value")
        self.panels = OrbitPanels(pn, c.problem, title="time history of an attractor (click a value)")
        self.layout = pn.Column(pn.pane.Bokeh(f, sizing_mode="stretch_width"),
                                pn.pane.Bokeh(fr, sizing_mode="stretch_width"),
                                pn.Row(self.whole_button, self.zoom_check), self.progress, self.status_pane,
                                pn.Row(self.attractor_pane, pn.pane.Bokeh(basin)), self.attractor_select,
                                self.panels.row(pn), sizing_mode="stretch_width", name="bifurc explore")
        self._shown = None
        self._show_dataset(ds)

    def _show_dataset(self, ds, span=None) -> None:
        """Paint ``ds`` (the stored census or a zoom's): each attractor's strobe states in its colour, the basin
        fractions stacked beneath, a hover column per value; clicks then refer to it; ``span``: the shown range (a
        zoom's whole range while its chunks land), else the values' own."""
        c = self.computer = self.stored_computer if ds is self.stored else self.stored_computer.on(ds)
        state, scale, vals = self._census_state, self._y, c.values
        width = np.diff(np.sort(vals)).min() if vals.size > 1 else 0.1 * max(1.0, abs(vals[0]))
        labels = [str(x) for x in ds.attractor_label.values]
        # the stored census' attractors are matched from value to value: one colour each; a zoom's chunks are
        # censuses of their own, so its attractors are coloured by their class (the same colour across chunks)
        by_class: dict = {}
        colour = (lambda x: self._colours[x["label"]]) if ds is self.stored else \
            (lambda x: by_class.setdefault(x["text"], PALETTE[len(by_class) % len(PALETTE)]))
        self._colours = {lab: PALETTE[j % len(PALETTE)] for j, lab in enumerate(labels)}
        summary = []
        pts = {"p": [], "y": [], "colour": [], "label": []}
        bars = {"p": [], "bottom": [], "top": [], "colour": [], "label": []}
        firsts = {}
        for v in vals:
            rows = c.attractors(v)["rows"]
            summary.append("; ".join(f"{x['label']} {x['text']} {x['fraction']:.2f}" for x in rows))
            below = 0.0
            for x in rows:
                firsts.setdefault(x["label"], colour(x))
                for y in x["nodes"].get(state, []):
                    pts["p"].append(v)
                    pts["y"].append(float(y) * scale)
                    pts["colour"].append(colour(x))
                    pts["label"].append(x["label"])
                bars["p"].append(v)
                bars["bottom"].append(below)
                bars["top"].append(below + x["fraction"])
                bars["colour"].append(colour(x))
                bars["label"].append(f"{x['label']}: {x['text']}")
                below += x["fraction"]
        self._colours.update(firsts)        # the basins' colours: each attractor's where it first appears
        ys = np.asarray(pts["y"], float)
        lo, hi = (float(ys.min()), float(ys.max())) if ys.size else (0.0, 1.0)
        pad = 0.05 * (hi - lo or 1.0)
        bars["left"] = [p - width * 0.4 for p in bars["p"]]
        bars["right"] = [p + width * 0.4 for p in bars["p"]]
        self.columns.selected.indices = []
        self.census_points.data = pts
        self.census_bars.data = bars
        self.columns.data = dict(left=vals - width / 2, right=vals + width / 2, value=vals, text=summary,
                                 bottom=np.full(vals.size, lo - pad), top=np.full(vals.size, hi + pad))
        self._set_view(span or ((float(vals.min() - width), float(vals.max() + width)),))

    @property
    def value_count(self) -> int:
        """The values the census figure shows (the stored census', or a zoom's stored so far)."""
        return len(self.columns.data["value"])

    def zoom(self, lo: float, hi: float, n: int = ZOOM_CENSUS_VALUES):
        """Compute the census anew on ``n`` values from ``lo`` to ``hi`` (the stored settings, starts kind and seed,
        fewer starts per value when it had many), chunk by chunk in warm processes; the figure repaints as they
        land."""
        return self._begin_zoom(float(lo), float(hi), n)

    attractors_text = property(lambda self: self.attractor_pane.object,
                               doc="the clicked value's attractors: class, basin fraction with its 95 % interval")

    def _on_tap(self, attr, old, new) -> None:
        if new:
            self.select(float(self.columns.data["value"][new[0]]))

    def select(self, value, wait: bool = False):
        """Show ``value``'s attractors (the nearest stored value) and the time history of its largest basin's."""
        r = self.computer.attractors(value)
        self._shown, self._shown_computer = r, self.computer      # a zoom's repaint may replace self.computer
        par = self.computer.param
        lines = [f"**{par} = {r['value']:g}: {sum(x['label'].startswith('A') for x in r['rows'])} attractors**", "",
                 "| attractor | class | basin fraction [95 %] |", "|---|---|---|"]
        for x in r["rows"]:
            lines.append(f"| {x['label']} | {x['text']} | {x['fraction']:.3f} [{x['low']:.3f}, {x['high']:.3f}] |")
        _set(self.attractor_pane, "\n".join(lines))
        sa, sb = self._pair
        starts = r["starts"]
        if sa in starts and sb in starts:
            fa, fb = (_scale(self.stored, s)[0] for s in (sa, sb))
            self.start_source.data = dict(a=starts[sa] * fa, b=starts[sb] * fb, label=r["went"],
                                          colour=[self._colours.get(w, "#999999") for w in r["went"]])
        nodes = [x for x in r["rows"] if x["nodes"]]
        fa, fb = (_scale(self.stored, s)[0] for s in (sa, sb))
        self.node_sources.data = dict(a=np.concatenate([x["nodes"][sa] * fa for x in nodes]) if nodes else [],
                                      b=np.concatenate([x["nodes"][sb] * fb for x in nodes]) if nodes else [],
                                      colour=["black"] * sum(x["nodes"][sa].size for x in nodes),
                                      label=sum(([x["label"]] * x["nodes"][sa].size for x in nodes), []))
        present = [x for x in r["rows"] if x["label"].startswith("A") and x["nodes"]]
        options = {f"{x['label']}: {x['text']}": x["label"] for x in present}
        top = max(present, key=lambda x: x["fraction"])["label"] if present else None
        self._selecting = True
        self.attractor_select.options = options
        self.attractor_select.disabled = not options
        self.attractor_select.value = top
        self._selecting = False
        if top is None:
            self.status = f"{par} = {r['value']:g}: no attractor present"
            return self
        return self.show_attractor(top, wait=wait)

    def _on_select(self, event) -> None:
        if not getattr(self, "_selecting", False) and event.new:
            self.show_attractor(event.new)

    def show_attractor(self, label: str, wait: bool = False):
        """The time history of attractor ``label`` at the shown value, from its stored strobe state."""
        if self._shown is None:
            raise ParameterError("no value selected: click a value first")
        self.status = f"computing {label}'s time history at {self.computer.param} = {self._shown['value']:g}..."
        return self._submit("attractor", self._shown_computer.history, self._shown["value"], label, wait=wait)

    def _show_attractor(self, r, wall) -> None:
        x = next(x for x in self._shown["rows"] if x["label"] == r["label"])
        self.panels.show_history(r["history"], f"**{r['label']} at {self.computer.param} = {r['value']:g}: "
                                               f"{x['text']}.** Time history over {r['periods']} periods from its "
                                               f"stored strobe state: **{r['impacts']} impacts**")
        j = x["j"]
        i = self._shown["index"]
        ds = self._shown_computer.ds
        if "multiplier_abs" in ds and np.isfinite(ds.multiplier_abs.values[i, j]).any():
            ab, arg = ds.multiplier_abs.values[i, j], ds.multiplier_arg.values[i, j]
            keep = np.isfinite(ab)
            mu = ab[keep] * np.exp(1j * arg[keep])
            self.panels.multiplier_source.data = dict(re=mu.real, im=mu.imag)
            _set(self.panels.orbit_pane, f"**{r['label']}**: {x['text']}; stored Floquet multipliers |mu| = "
                                         + ", ".join(f"{a:.4g}" for a in ab[keep]))
        else:
            self.panels.multiplier_source.data = dict(re=[], im=[])
            _set(self.panels.orbit_pane, f"**{r['label']}**: {x['text']}; no multipliers stored")
        n = x["nodes"]
        st, vel = self.panels.state, self.panels.vel
        self.panels.node_source.data = dict(y=n.get(st, np.array([])) * self.panels.y,
                                            v=n.get(vel, np.zeros(len(n.get(st, [])))))
        self.status = f"{r['label']} at {self.computer.param} = {r['value']:g}: shown in {wall:.2f} s"


#: attractor colours of the census page (Okabe-Ito, then greys)
PALETTE = ["#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9", "#F0E442", "#000000", "#999999",
           "#666666"]


def explorer_of(ds, title: str | None = None, workers: int | None = None, zoom: bool = True):
    """The page of a stored dataset by its kind: a diagram's :class:`Explorer`, a regime map's :class:`MapExplorer`,
    a census' :class:`CensusExplorer`; another kind refused in one line."""
    from ..storage.load import kind_of
    kind = kind_of(ds)
    if kind == "map":
        return MapExplorer(ds, title=title, workers=workers, zoom=zoom)
    if kind == "attractors":
        return CensusExplorer(ds, title=title, workers=workers, zoom=zoom)
    if kind != "diagram":
        raise ParameterError(f"the explorer needs a diagram, map or attractors dataset (from `bifurc diagram`, "
                             f"`bifurc map` or `bifurc attractors`); this is "
                             f"{'a ' + kind if kind else 'another kind of'} dataset")
    return Explorer(ds, title=title, workers=workers, zoom=zoom)


def _set(pane, text: str) -> None:
    pane.object = text


def serve(ds, port: int, show: bool = True, title: str | None = None, workers: int | None = None):
    """Serve an :class:`Explorer` of ``ds`` on 127.0.0.1:``port`` (a new one per browser session) until Ctrl-C;
    ``show``: open the user's browser."""
    import panel as pn

    def page():
        ex = explorer_of(ds, title=title, workers=workers)
        pn.state.on_session_destroyed(lambda context: ex.close())     # a closed tab: its thread and processes end
        return ex.servable()
    return pn.serve({"/": page}, address="127.0.0.1", port=port, show=show, title=title or "bifurc explore",
                    websocket_origin=[f"127.0.0.1:{port}", f"localhost:{port}"], threaded=False, verbose=False,
                    print_url=False)
