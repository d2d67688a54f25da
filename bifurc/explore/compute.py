"""What the explorer computes, through the public API only (no second implementation): the problem rebuilt from
a stored dataset's attributes, a value's time history (:func:`maps.simulate`) and periodic orbit
(:func:`bifurc.periodic_orbit`), its branch (:func:`bifurc.continue_orbit`) and a zoomed range computed anew in
warm processes that a newer zoom stops: one per-point task over a finer grid of parameter points, a zoom plan
(:func:`bifurc.sweep` for a diagram, :func:`bifurc.regime_map` for a map's rectangle, :func:`bifurc.attractors`
for a census, each with the stored dataset's settings; :class:`Spares`, :class:`Zoom`).

Nothing here draws: :mod:`bifurc.explore.app` shows what these functions return.
"""
from __future__ import annotations

import copy
import json
import math
import os
import pickle
import signal
import subprocess
import sys
import tempfile
import time as _time
from pathlib import Path

import numpy as np

from maps.parameters import ParameterError

from ..labels.classify import CLASS_LABELS, describe
from ..orbits.branch import continue_orbit
from ..orbits.method import PALC, Shooting
from ..orbits.orbit import periodic_orbit, sweep_point
from ..storage.load import require_kind

#: structural options a dataset records (attribute -> maps.problem keyword); "none": the scene has no such part
OPTION_ATTRS = {"circuit": "circuit", "ac_sign": "ac_sign", "dc_law": "dc_law", "soil": "soil"}
#: at least this many strobe periods in a time history (a whole number of the orbit's periods)
MIN_HISTORY_PERIODS = 8
#: strobe periods of a time history where the value is not periodic
HISTORY_PERIODS = 20
#: samples per strobe period of a time history
SAMPLES_PER_PERIOD = 200
#: values of a zoomed range
ZOOM_VALUES = 200
PERIODIC = (CLASS_LABELS.index("periodic"), CLASS_LABELS.index("periodic-no-impact"))


def problem_kwargs(ds) -> dict:
    """The keywords of :func:`maps.problem` that rebuild what a dataset integrated, from its attributes: scene,
    preset, every ``param_<name>``, the start ``initial_state`` and the structural options (JSON-serialisable)."""
    a = ds.attrs
    if "scene" not in a:
        raise ParameterError("this dataset records no scene (attribute 'scene'): written by another tool")
    params = {k[6:]: float(v) for k, v in a.items() if k.startswith("param_") and not k.endswith(("_units", "_source"))}
    for par in _swept(ds):
        params.pop(par, None)
    x0 = {}
    for item in str(a.get("initial_state", "")).split(","):
        name, sep, value = item.partition("=")
        if sep:
            x0[name.strip()] = float(value)
    out = {"scene": str(a["scene"]), "preset": a.get("preset") or None, "params": params, "x0": x0}
    for attr, key in OPTION_ATTRS.items():
        if a.get(attr, "none") != "none":
            out[key] = str(a[attr])
    if a.get("soil_compaction", "none") != "none":
        out["compaction"] = True
    return out


def _swept(ds) -> tuple:
    """The dataset's swept parameters (one, or two for a regime map or a census over two)."""
    return tuple(ds.attrs[k] for k in ("swept_parameter", "swept_parameter2") if k in ds.attrs)


def problem_of(ds):
    """The :class:`maps.Problem` a stored dataset integrated (:func:`problem_kwargs`)."""
    import maps
    return maps.problem(**problem_kwargs(ds))


def value_rows(ds) -> dict:
    """Per value of a diagram's first branch, the columns the explorer's hover shows: value, class text, n:m,
    exponent with its interval, reason when undecided."""
    par = ds.attrs["swept_parameter"]
    d = ds.isel(branch=0)
    codes = d.class_code.values.astype(int)
    n, m = d.period.values.astype(int), d.impacts_per_period.values.astype(int)
    lyap = d.lyapunov.values
    low = d.lyapunov_low.values if "lyapunov_low" in d else np.full(lyap.shape, np.nan)
    high = d.lyapunov_high.values if "lyapunov_high" in d else np.full(lyap.shape, np.nan)
    reasons = d.class_reason.values if "class_reason" in d else np.full(codes.shape, "")
    rows = {"value": d[par].values.astype(float), "code": codes, "label": [], "text": [], "nm": [], "exponent": [],
            "reason": []}
    for c, pn, pm, ly, lo, hi, why in zip(codes, n, m, lyap, low, high, reasons):
        rows["label"].append(CLASS_LABELS[c] if c >= 0 else "missing")
        rows["text"].append(describe(c, pn, pm) if c >= 0 else "not computed")
        rows["nm"].append(f"{pn}:{pm}" if c in PERIODIC else "-")
        rows["exponent"].append("-" if not np.isfinite(ly) else
                                f"{ly:.4f} [{lo:.4f}, {hi:.4f}] per period" if np.isfinite(lo) and np.isfinite(hi)
                                else f"{ly:.4f} per period")
        rows["reason"].append(str(why) or "-")
    return rows


def nearest(grid, value, name: str, whose: str) -> int:
    """The index of ``grid``'s value nearest to ``value``; more than a grid step outside refused in one line."""
    lo, hi = grid.min(), grid.max()
    step = np.diff(np.sort(grid)).min() if grid.size > 1 else 0.0
    if not lo - step <= float(value) <= hi + step:
        raise ParameterError(f"{name} = {value:g}: outside {whose} {lo:g} to {hi:g}")
    return int(np.argmin(np.abs(grid - float(value))))


def start_sample(ds, index: int) -> int:
    """The last recorded sample of value ``index`` at which the forcing is in its phase at t = 0 (the sample's
    period count a multiple of the forcing period q), so that a simulation started there at t = 0 continues the
    stored trajectory; the last sample when q is 0 (incommensurate) or longer than the record."""
    d = ds.isel(branch=0).isel({ds.attrs["swept_parameter"]: index})
    q, before, n = int(d.forcing_period), int(d.transient_used), ds.sizes["sample"]
    fits = [k for k in range(n) if q > 0 and (before + k) % q == 0 and np.isfinite(float(d[_first_state(ds)][k]))]
    return fits[-1] if fits else n - 1


def _first_state(ds) -> str:
    return next(k for k, v in ds.data_vars.items() if v.dims[-1:] == ("sample",) and not k.startswith("flag_"))


class Computer:
    """One stored diagram's on-demand computations, its problem and integrators built once (heyoka's compiled
    integrators are cached per scene and options: the first click compiles, the next ones reuse)."""

    def __init__(self, ds):
        require_kind(ds, "diagram", "the explorer")
        self.ds = ds
        self.param = ds.attrs["swept_parameter"]
        self.kwargs = problem_kwargs(ds)
        self.problem = problem_of(ds)
        self.tol = float(ds.attrs.get("tol", 1e-10))
        self.values = ds[self.param].values.astype(float)

    def index(self, value) -> int:
        """The stored value nearest to ``value``; outside the grid refused in one line."""
        return nearest(self.values, value, self.param, "the diagram's")

    def on(self, ds) -> "Computer":
        """The same problem and integrators for another diagram of it (a zoom's)."""
        require_kind(ds, "diagram", "the explorer")
        new = copy.copy(self)
        new.ds, new.values = ds, ds[self.param].values.astype(float)
        return new

    def zoom_plan(self) -> dict:
        """What a zoom's processes run: :func:`bifurc.sweep` with the diagram's settings (:func:`diagram_plan`)."""
        return diagram_plan(self)

    def warm(self) -> None:
        """Compile the integrators once (a one-period simulation), before the first click."""
        import maps
        maps.simulate(self.problem.with_values(**{self.param: float(self.values[0])}), periods=1, tol=self.tol,
                      dt=self.problem.with_values(**{self.param: float(self.values[0])}).strobe_period())

    def history(self, value) -> dict:
        """The time history after value's record and, when it is periodic, its periodic orbit:
        {"index", "value", "history" (maps.simulate's dataset), "periods", "impacts", "orbit" (periodic_orbit's
        dataset or None), "orbit_error" (why none, or ""), "seconds"}."""
        import maps
        clock = _time.perf_counter()
        i = self.index(value)
        v = float(self.values[i])
        d = self.ds.isel(branch=0).isel({self.param: i})
        code, n = int(d.class_code), int(d.period)
        periodic = code in PERIODIC and n > 0
        periods = n * max(1, math.ceil(MIN_HISTORY_PERIODS / n)) if periodic else HISTORY_PERIODS
        k = start_sample(self.ds, i)
        start, _ = sweep_point(self.ds, v, sample=k)
        pb = self.problem.with_values(**{self.param: v})
        names = pb.system.state_names
        at = pb.with_start(dict(zip(names, map(float, start.y))), start.flags)
        T = pb.strobe_period()
        h = maps.simulate(at, periods=periods, tol=self.tol, dt=T / SAMPLES_PER_PERIOD)
        orbit, why = None, ""
        if periodic:
            try:
                orbit = periodic_orbit(pb, Shooting(period=n, tol=self.tol, error=False),
                                       start=sweep_point(self.ds, v, sample=k))
            except Exception as exc:  # noqa: BLE001 - Newton's failure is shown, with its reason
                why = " ".join(str(exc).split())[:200]
        else:
            why = f"not periodic ({describe(code, n, int(d.impacts_per_period)) if code >= 0 else 'not computed'})"
        return {"index": i, "value": v, "history": h, "periods": periods, "impacts": int(h.sizes.get("impact", 0)),
                "orbit": orbit, "orbit_error": why, "seconds": _time.perf_counter() - clock}

    def branch(self, value, max_points: int = 200) -> dict:
        """The branch of periodic orbits through the orbit at ``value``, continued toward both ends of the
        diagram: {"value", "branches": [continue_orbit's datasets], "error": why none, "seconds"}."""
        clock = _time.perf_counter()
        i = self.index(value)
        v = float(self.values[i])
        d = self.ds.isel(branch=0).isel({self.param: i})
        code, n = int(d.class_code), int(d.period)
        if code not in PERIODIC or n <= 0:
            return {"value": v, "branches": [], "error": f"{self.param} = {v:g} is not periodic: no branch to "
                                                        f"continue", "seconds": 0.0}
        k = start_sample(self.ds, i)
        method = PALC(period=n, tol=self.tol, max_points=max_points, error=False)
        out, errors = [], []
        for end in (float(self.values.max()), float(self.values.min())):
            if end == v:
                continue
            try:
                out.append(continue_orbit(self.problem, self.param, (v, end), method,
                                          start=sweep_point(self.ds, v, sample=k)))
            except ParameterError as exc:
                errors.append(str(exc))
                break                      # the same refusal the other way
            except Exception as exc:  # noqa: BLE001 - shown with its reason
                errors.append(" ".join(str(exc).split())[:200])
        return {"value": v, "branches": out, "error": "; ".join(errors), "seconds": _time.perf_counter() - clock}


class MapComputer:
    """One stored regime map's clicks: a cell is swept anew as a one-value diagram with the map's own settings
    (:func:`bifurc.sweep`; the map stores no states), whose :class:`Computer` then gives the cell's time history
    and periodic orbit as for a diagram value."""

    def __init__(self, ds):
        require_kind(ds, "map", "the regime map's explorer")
        self.ds = ds
        self.param, self.param2 = ds.attrs["swept_parameter"], ds.attrs["swept_parameter2"]
        self.kwargs = problem_kwargs(ds)
        a = ds.attrs
        transient, record = int(a.get("transient_periods", 300)), int(a.get("recorded_periods", 100))
        self.method = dict(transient=transient, record=record, tol=float(a.get("tol", 1e-10)),
                           budget=max(int(a.get("budget_periods", transient + record)), transient + record),
                           max_period=int(a.get("max_period", 100)), error_sample=0, grazing=False)
        self.values, self.values2 = ds[self.param].values.astype(float), ds[self.param2].values.astype(float)

    def zoom_plan(self) -> dict:
        """What a zoom's processes run: :func:`bifurc.regime_map` with the map's settings (:func:`map_plan`)."""
        return map_plan(self)

    def on(self, ds) -> "MapComputer":
        """The same for another regime map of the problem (a zoom's)."""
        require_kind(ds, "map", "the regime map's explorer")
        new = copy.copy(self)
        new.ds = ds
        new.values, new.values2 = ds[self.param].values.astype(float), ds[self.param2].values.astype(float)
        return new

    def index(self, value, value2) -> tuple[int, int]:
        """The cell nearest to (value, value2); outside the map refused in one line."""
        return (nearest(self.values, value, self.param, "the map's"),
                nearest(self.values2, value2, self.param2, "the map's"))

    def cell(self, value, value2) -> dict:
        """The cell's stored class and, from its one-value diagram, its time history and periodic orbit:
        :meth:`Computer.history`'s dict with "cell" (i, j), "value2" and "stored" (the map's class text)."""
        import maps

        from ..sweeps.method import Diagram
        from ..sweeps.sweep import sweep
        from ..run.where import Run
        clock = _time.perf_counter()
        i, j = self.index(value, value2)
        v, v2 = float(self.values[i]), float(self.values2[j])
        kw = copy.deepcopy(self.kwargs)
        kw["params"][self.param2] = v2
        d = sweep(maps.problem(**kw), self.param, np.array([v]), Diagram(**self.method),
                  run=Run(workers=1, progress=False))
        out = Computer(d).history(v)
        c = self.ds.isel({self.param: i, self.param2: j})
        code = int(c.class_code)
        out.update(cell=(i, j), value2=v2, seconds=_time.perf_counter() - clock,
                   stored=describe(code, int(c.period), int(c.impacts_per_period)) if code >= 0 else "not computed",
                   swept=describe(*(int(d.isel(branch=0)[k].values[0]) for k in ("class_code", "period",
                                                                                  "impacts_per_period"))))
        return out


def map_rows(ds) -> dict:
    """Per cell of a regime map (flat, row-major over (param, param2)): both values, class label and text."""
    p1, p2 = ds.attrs["swept_parameter"], ds.attrs["swept_parameter2"]
    d = ds.transpose(p1, p2)
    codes = d.class_code.values.astype(int).ravel()
    n, m = d.period.values.astype(int).ravel(), d.impacts_per_period.values.astype(int).ravel()
    v1, v2 = np.meshgrid(d[p1].values, d[p2].values, indexing="ij")
    return {"value": v1.ravel().astype(float), "value2": v2.ravel().astype(float),
            "label": [CLASS_LABELS[c] if c >= 0 else "missing" for c in codes],
            "text": [describe(c, a, b) if c >= 0 else "not computed" for c, a, b in zip(codes, n, m)]}


class CensusComputer:
    """One stored census' clicks (an attractors dataset over one parameter): a value's attractors with their
    class, basin fraction and interval, stored strobe states and the fresh starts' basins, and an attractor's time
    history from its stored state (:func:`maps.simulate`)."""

    def __init__(self, ds):
        require_kind(ds, "attractors", "the census' explorer")
        if "swept_parameter2" in ds.attrs:
            raise ParameterError("a census over two parameters: the explorer shows a census over one parameter; "
                                 "ds.bifurc.plot() draws this one")
        self.ds = ds
        self.param = ds.attrs["swept_parameter"]
        self.kwargs = problem_kwargs(ds)
        self.problem = problem_of(ds)
        self.values = ds[self.param].values.astype(float)
        self.states = [k for k in self.problem.system.state_names if k in ds and "node" in ds[k].dims]

    def index(self, value) -> int:
        return nearest(self.values, value, self.param, "the census'")

    def zoom_plan(self) -> dict:
        """What a zoom's processes run: :func:`bifurc.attractors` with the census' settings, starts kind and seed,
        at most :data:`ZOOM_STARTS` starts per value (:func:`census_plan`)."""
        return census_plan(self)

    def on(self, ds) -> "CensusComputer":
        """The same problem for another census of it (a zoom's)."""
        require_kind(ds, "attractors", "the census' explorer")
        new = copy.copy(self)
        new.ds, new.values = ds, ds[self.param].values.astype(float)
        return new

    def attractors(self, value) -> dict:
        """{"index", "value", "rows": one per attractor or outcome a start reached or present (label, class text,
        fraction, low, high, its stored strobe states {state: nodes} for an attractor), "starts": each fresh
        start's state {state: values} and the label it reached}."""
        from ..attractors.dataset import attractor_text
        ds, i = self.ds, self.index(value)
        rows = []
        for j, label in enumerate(ds.attractor_label.values):
            label = str(label)
            frac = float(ds.basin_fraction.values[i, j])
            if not (frac > 0 or ds.present.values[i, j]):
                continue
            nodes = {}
            if label.startswith("A"):
                n = int(ds.period.values[i, j]) if int(ds.period.values[i, j]) > 0 else ds.sizes["node"]
                nodes = {st: ds[st].values[i, j, :n][np.isfinite(ds[st].values[i, j, :n])] for st in self.states}
            rows.append({"j": j, "label": label, "text": attractor_text(ds, i, j) if label.startswith("A")
                         else label.replace("_", " "), "fraction": frac,
                         "low": float(ds.basin_fraction_low.values[i, j]),
                         "high": float(ds.basin_fraction_high.values[i, j]), "nodes": nodes})
        labels = [str(s) for s in ds.attractor_label.values]
        went = ds.start_attractor.values[i] if "start_attractor" in ds else np.array([], int)
        starts = {st: ds[f"start_{st}"].values for st in self.states if f"start_{st}" in ds}
        return {"index": i, "value": float(self.values[i]), "rows": rows, "starts": starts,
                "went": [labels[k] if 0 <= k < len(labels) else "none" for k in went]}

    def history(self, value, label: str, periods: int = HISTORY_PERIODS) -> dict:
        """Attractor ``label``'s time history at ``value`` from its stored strobe state (the node at which the
        forcing is in its phase at t = 0): {"value", "label", "history", "periods", "impacts", "seconds"}."""
        import maps
        clock = _time.perf_counter()
        ds, i = self.ds, self.index(value)
        labels = [str(s) for s in ds.attractor_label.values]
        if label not in labels or not label.startswith("A") or not ds.present.values[i, labels.index(label)]:
            raise ParameterError(f"attractor {label!r}: not an attractor present at {self.param} = "
                                 f"{self.values[i]:g}")
        j = labels.index(label)
        v = float(self.values[i])
        pb = self.problem.with_values(**{self.param: v})
        q = maps.StroboscopicMap(pb).forcing_period_for(dict(pb.values))
        k0 = int(ds.attractor_k0.values[i, j])
        n = max(1, int(ds.period.values[i, j]))
        nodes = [r for r in range(min(n, ds.sizes["node"])) if q <= 1 or (k0 + r) % q == 0] or [0]
        r = nodes[0]
        start = {st: float(ds[st].values[i, j, r]) for st in pb.system.state_names if st in ds}
        flags = {k[5:]: bool(ds[k].values[i, j, r]) for k in ds.data_vars if k.startswith("flag_")
                 and "node" in ds[k].dims}
        periods = n * max(1, math.ceil(MIN_HISTORY_PERIODS / n)) if int(ds.period.values[i, j]) > 0 else periods
        T = pb.strobe_period()
        h = maps.simulate(pb.with_start(start, flags or None), periods=periods,
                          tol=float(ds.attrs.get("tol", 1e-10)), dt=T / SAMPLES_PER_PERIOD)
        return {"value": v, "label": label, "history": h, "periods": periods,
                "impacts": int(h.sizes.get("impact", 0)), "seconds": _time.perf_counter() - clock}


def branch_points(br, state: str) -> tuple[np.ndarray, np.ndarray]:
    """(parameter, state) pairs of a branch dataset's points at every strobe node, for the diagram's overlay."""
    p = br[br.attrs["continuation_parameter"]].values
    y = br[state].values.reshape(p.size, -1)           # (point, node)
    keep = np.isfinite(y)
    return np.repeat(p, y.shape[1])[keep.ravel()], y[keep]


#: values per chunk of a zoom: each chunk is stored on its own, so the page repaints as they land; a multiple of
#: the batch engine's 4 SIMD lanes (a chunk of 5 ran its fifth value alone on 4 lanes: 2 passes for 5 values)
ZOOM_CHUNK = 4
#: at most this many chunks swept together (one :func:`bifurc.sweep` call, then stored chunk by chunk) in a zoom's
#: first picture: a call and its dataset cost about 0.05 s, paid once per group instead of once per chunk
ZOOM_GROUP = 6
#: values of a zoomed census and values per chunk (each chunk is a census of its own)
ZOOM_CENSUS_VALUES, ZOOM_CENSUS_CHUNK = 20, 4
#: at most this many fresh starts per value in a zoomed census (fewer than a stored census with many)
ZOOM_STARTS = 25
#: cells per side of a zoomed regime map (a chunk: one value of the first parameter, every value of the second)
ZOOM_MAP_SIDE = 12


def _stage_methods(ds) -> tuple[dict, list]:
    """A zoom's method settings shared by its stages, and its two stages (name, settings): the first picture (the
    dataset's transient and record, no extension, no exponent, no grazing search), then the anytime labels
    (undecided values extended up to the dataset's budget).  A diagram's and a regime map's alike."""
    a = ds.attrs
    transient, record = int(a.get("transient_periods", 300)), int(a.get("recorded_periods", 100))
    budget = int(a.get("budget_periods", transient + record))
    method = {"transient": transient, "record": record, "tol": float(a.get("tol", 1e-10)),
              "max_period": int(a.get("max_period", 100)), "error_sample": 0}
    return method, [["first picture", dict(budget=transient + record, lyapunov=False, grazing=False)],
                    ["anytime labels", dict(budget=max(budget, transient + record))]]


def _call_of(text) -> tuple:
    """(name, keywords) of a stored settings object's repr such as ``Census(cells=100, link=False)``, its keywords
    literals; (None, {}) when it is not one (an older dataset, or ``Given(36 starts)``)."""
    import ast
    try:
        node = ast.parse(str(text), mode="eval").body
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and not node.args:
            return node.func.id, {k.arg: ast.literal_eval(k.value) for k in node.keywords}
    except (SyntaxError, ValueError):
        pass
    return None, {}


def census_settings(ds) -> dict:
    """The stored census' :class:`bifurc.Census` settings (attribute ``census_method``; an older dataset: its tol
    and grid cells), without the linking (a zoom draws the attractors, not their events)."""
    name, kw = _call_of(ds.attrs.get("census_method", ""))
    if name != "Census":
        kw = {"tol": float(ds.attrs.get("tol", 1e-10)), "cells": int(ds.attrs.get("cells_per_side", 100))}
    return dict(kw, link=False)


def zoom_starts(ds, states, limit: int = ZOOM_STARTS) -> tuple[dict, int, int]:
    """A zoomed census' fresh starts: the stored sampler's kind, box and seed (attribute ``starts_sampler``) with
    at most ``limit`` starts (a slice's sides scaled alike); starts given as an array: ``limit`` of the stored
    ones, evenly picked.  Returns (the starts as JSON, their count, the stored census' count)."""
    name, kw = _call_of(ds.attrs.get("starts_sampler", ""))
    stored = int(ds.attrs.get("fresh_starts", ds.sizes.get("start", 0)))
    box = {k: list(v) for k, v in kw["box"].items()} if kw.get("box") else None
    if name == "Slice":
        a, b = kw.get("shape", (14, 14))
        if a * b > limit:
            f = math.sqrt(limit / (a * b))
            a, b = max(1, int(a * f)), max(1, int(b * f))
        return {"kind": "slice", "shape": [a, b], "box": box}, a * b, stored
    if name in ("Box", "SwitchOn"):
        n = min(int(kw.get("n", stored)), limit)
        seed = int(kw.get("seed", ds.attrs.get("seed", 0)))
        return {"kind": "box" if name == "Box" else "switch-on", "n": n, "box": box, "seed": seed}, n, stored
    pts = np.stack([ds[f"start_{s}"].values for s in states], axis=1)
    keep = np.unique(np.linspace(0, len(pts) - 1, min(len(pts), limit)).round().astype(int))
    return {"kind": "given", "points": pts[keep].tolist()}, keep.size, stored


def _sampler(spec: dict):
    """The sampler of :func:`zoom_starts`' JSON (an (N, d) array for starts given)."""
    from ..attractors.method import Box, Slice, SwitchOn
    box = {k: tuple(v) for k, v in spec["box"].items()} if spec.get("box") else None
    if spec["kind"] == "slice":
        return Slice(shape=tuple(spec["shape"]), box=box)
    if spec["kind"] == "box":
        return Box(n=spec["n"], box=box, seed=spec["seed"])
    if spec["kind"] == "switch-on":
        return SwitchOn(n=spec["n"], seed=spec["seed"])
    return np.asarray(spec["points"], float)


def _plan(kind, computer, method, stages, warm, **more) -> dict:
    """What a zoom process runs (JSON): the task ``kind`` ("diagram": :func:`bifurc.sweep`, "map":
    :func:`bifurc.regime_map` over rows of the first parameter, "census": :func:`bifurc.attractors`), the problem,
    the parameter(s), the settings shared by the stages and each stage's, and ``warm``: the one-point task that
    compiles the integrators before any zoom."""
    return dict({"kind": kind, "problem": computer.kwargs, "param": computer.param, "param2": None, "method": method,
                 "stages": stages, "chunk": ZOOM_CHUNK, "group": ZOOM_GROUP, "unit": "values", "warm": warm,
                 "starts": None, "note": ""}, **more)


def diagram_plan(computer) -> dict:
    method, stages = _stage_methods(computer.ds)
    return _plan("diagram", computer, method, stages, {"values": [float(computer.values[0])], "settings": {}})


def map_plan(computer) -> dict:
    method, stages = _stage_methods(computer.ds)
    return _plan("map", computer, dict(method, mode="independent"), stages,
                 {"values": [float(computer.values[0])], "values2": [float(computer.values2[0])], "settings": {}},
                 param2=computer.param2, unit="cells")


def census_plan(computer, limit: int = ZOOM_STARTS) -> dict:
    ds = computer.ds
    settings = census_settings(ds)
    starts, n, stored = zoom_starts(ds, computer.problem.system.state_names, limit)
    first = [[float(ds[f"start_{s}"].values[0]) for s in computer.problem.system.state_names]]
    note = (f"{n} starts per value (the stored census had {stored})" if n < stored else f"{n} starts per value") + \
        f"; chunks of {ZOOM_CENSUS_CHUNK} values, each a census of its own: colours by class"
    return _plan("census", computer, settings, [["census", {}]],
                 {"values": [float(computer.values[0])], "settings": {"budget": min(settings.get("budget", 200), 200)},
                  "starts": {"kind": "given", "points": first}},
                 chunk=ZOOM_CENSUS_CHUNK, group=1, starts=starts, note=note, n_starts=n)


def _zoom_task(plan: dict, pb, values, settings: dict, values2=None, starts=None):
    """One chunk of a zoom through the public API, in this process: ``plan``'s kind at ``values``."""
    from ..run.where import Run
    run = Run(workers=1, progress=False)
    if plan["kind"] == "census":
        from ..attractors.atlas import attractors
        from ..attractors.method import Census
        return attractors(pb, plan["param"], values, Census(**settings), starts=_sampler(starts), run=run)
    from ..sweeps.method import Diagram
    if plan["kind"] == "map":
        from ..sweeps.regime import regime_map
        return regime_map(pb, plan["param"], values, plan["param2"], np.asarray(values2, float), Diagram(**settings),
                          run=run)
    from ..sweeps.sweep import sweep
    return sweep(pb, plan["param"], values, Diagram(**settings), run=run)


#: the folder holding this bifurc package: a zoom process imports it from there, not a checkout in its working folder
_PACKAGE_ROOT = str(Path(__file__).resolve().parents[2])


def child_argv(code: str, *args: str) -> list[str]:
    """``python -c code args...`` with this bifurc's folder first on the child's path (``-c`` puts the working
    folder first, where another checkout would shadow the page's code)."""
    return [sys.executable, "-c", f"import sys; sys.path.insert(0, {_PACKAGE_ROOT!r}); {code}", *args]


def _start_child(warm: dict, ready_dir: Path) -> subprocess.Popen:
    """One zoom process, in its own process group: it imports this bifurc (from :data:`_PACKAGE_ROOT`, first on its
    path: ``python -c`` would otherwise put its working folder first), rebuilds the problem and compiles its
    integrators on a one-value first picture (then touches ``ready-<pid>`` in ``ready_dir``), and waits on its
    standard input for a zoom's job (:func:`zoom_worker`)."""
    err = Path(tempfile.mkstemp(prefix="stderr-", suffix=".txt", dir=ready_dir)[1])
    with open(err, "wb") as sink:
        child = subprocess.Popen(child_argv("from bifurc.explore.compute import zoom_worker; zoom_worker()",
                                            str(ready_dir)), start_new_session=True, stdin=subprocess.PIPE,
                                 stdout=subprocess.DEVNULL, stderr=sink)
    child.err_path = err
    child.stdin.write((json.dumps(warm) + "\n").encode())
    child.stdin.flush()
    return child


def _end(child: subprocess.Popen) -> None:
    """End a zoom process and whatever it started (its own process group)."""
    if child.poll() is None:
        try:
            os.killpg(child.pid, signal.SIGTERM)
        except ProcessLookupError:
            pass
    try:
        child.wait(timeout=10)
    except subprocess.TimeoutExpired:
        os.killpg(child.pid, signal.SIGKILL)
        child.wait(timeout=10)
    if child.stdin is not None and not child.stdin.closed:
        try:
            child.stdin.close()
        except OSError:
            pass


class Spares:
    """Warm zoom processes kept ready for the next zoom (one per worker): started after the first click, each has
    imported bifurc and compiled the problem's integrators (on its page's zoom plan's one-point task) before a zoom
    needs it, so that a zoom's first chunk lands within a second.  :meth:`take` hands them to a :class:`Zoom`;
    :meth:`fill` starts new ones.  ``computer``: a diagram's, regime map's or census' computer."""

    def __init__(self, computer, workers: int | None = None):
        from ..run.executor import available_cores
        self.n = int(workers or available_cores())
        self.warm = computer.zoom_plan()
        self.dir = Path(tempfile.mkdtemp(prefix="bifurc-explore-spares-"))
        self.children: list = []

    def fill(self) -> "Spares":
        """Start warm processes up to one per worker."""
        self.children = [c for c in self.children if c.poll() is None]
        while len(self.children) < self.n:
            self.children.append(_start_child(self.warm, self.dir))
        return self

    def ready(self) -> int:
        """How many of the waiting processes have compiled their integrators."""
        return sum((self.dir / f"ready-{c.pid}").exists() for c in self.children if c.poll() is None)

    def take(self, n: int) -> list:
        """Up to ``n`` waiting processes (the ready ones first), no longer this object's."""
        alive = sorted((c for c in self.children if c.poll() is None),
                       key=lambda c: not (self.dir / f"ready-{c.pid}").exists())
        out = alive[:n]
        self.children = alive[n:]
        return out

    def close(self) -> None:
        import shutil
        for c in self.children:
            _end(c)
        self.children = []
        shutil.rmtree(self.dir, ignore_errors=True)


def _check_corners(plan: dict, values, values2) -> None:
    """A zoom's range refused in one line before any process starts when one of its ends (a map: corners) is
    outside a parameter's allowed range."""
    import maps
    pb = maps.problem(**plan["problem"])
    for v in (values[0], values[-1]):
        for w in ((None,) if values2 is None else (values2[0], values2[-1])):
            pb.with_values(**{plan["param"]: float(v)}, **({} if w is None else {plan["param2"]: float(w)}))


def _grid(lo, hi, n, what: str) -> np.ndarray:
    if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
        raise ParameterError(f"zoom range {lo:g} to {hi:g}: need two finite values, the first below the second")
    if int(n) < 2:
        raise ParameterError(f"zoom {what} {n}: need at least 2")
    return np.linspace(lo, hi, int(n))


class Zoom:
    """A range of a stored diagram, census or regime map computed anew through the public API (the computer's
    :meth:`zoom_plan`: :func:`bifurc.sweep`, :func:`bifurc.attractors`, or :func:`bifurc.regime_map` over the
    rectangle ``second`` = (lo2, hi2, n2) of the second parameter) by one process per worker (warm ones from
    :class:`Spares` when given, else new ones), each claiming the next group of chunks of the plan's values as it
    ends its last (:func:`zoom_groups`; the first picture's groups hold up to ``plan["group"]`` chunks, the other
    stages' one) and storing each chunk as its group ends, stage by stage: for a diagram and a map, first the
    first picture of all its
    chunks (the dataset's transient and record, no extension, no exponent and no grazing search), then their
    anytime labels (undecided values extended up to the dataset's budget); for a census, one stage.
    :meth:`poll` gathers the chunks stored so far into one dataset (each value at its latest stage), so the page
    repaints from the first chunk; :meth:`stop` ends the processes (a newer zoom replaces a stale one)."""

    def __init__(self, computer, lo: float, hi: float, n: int | None = None, workers: int | None = None,
                 spares: Spares | None = None, second: tuple | None = None):
        from ..run.executor import available_cores
        plan = spares.warm if spares is not None else computer.zoom_plan()
        self.kind, self.unit, self.note = plan["kind"], plan["unit"], plan["note"]
        self.values = _grid(lo, hi, n or {"diagram": ZOOM_VALUES, "census": ZOOM_CENSUS_VALUES}.get(
            self.kind, ZOOM_MAP_SIDE), "values")
        self.param, self.param2 = plan["param"], plan["param2"]
        self.values2 = None
        if self.kind == "map":
            if second is None:
                raise ParameterError(f"a regime map's zoom needs the range of {self.param2} too (lo2, hi2)")
            lo2, hi2, *n2 = second
            self.values2 = _grid(float(lo2), float(hi2), n2[0] if n2 else ZOOM_MAP_SIDE, "values2")
        _check_corners(plan, self.values, self.values2)
        self.view = ((float(self.values[0]), float(self.values[-1])),) + \
            (((float(self.values2[0]), float(self.values2[-1])),) if self.values2 is not None else ())
        self.span = tuple((a - (b - a) / (g.size - 1), b + (b - a) / (g.size - 1))
                          for (a, b), g in zip(self.view, (self.values, self.values2)))
        self.folder = Path(tempfile.mkdtemp(prefix="bifurc-explore-"))
        self.stages = plan["stages"]
        step = 1 if self.kind == "map" else plan["chunk"]     # a map's chunk: one row of cells
        self.chunk = step
        self.chunks = [(j, min(j + step, self.values.size)) for j in range(0, self.values.size, step)]
        k = max(1, min(int(workers or available_cores()), len(self.chunks)))
        self.started = _time.perf_counter()
        self.children = spares.take(k) if spares is not None else []
        while len(self.children) < k:
            self.children.append(_start_child(plan, self.folder))
        groups = [zoom_groups(len(self.chunks), k, plan.get("group", 1) if s == 0 else 1)
                  for s in range(len(self.stages))]
        job = {"folder": str(self.folder), "values": self.values.tolist(), "chunks": self.chunks, "groups": groups,
               "values2": None if self.values2 is None else self.values2.tolist()}
        for child in self.children:
            child.stdin.write((json.dumps(job) + "\n").encode())
            child.stdin.close()
        self._stage_of = np.full(len(self.chunks), -1)         # the latest stage stored, per chunk
        self._parts: dict = {}                                 # chunk -> its latest dataset
        self._seen: set = set()

    @property
    def total(self) -> int:
        """The zoom's values (a map: its cells)."""
        return self.values.size * (1 if self.values2 is None else self.values2.size)

    @property
    def text(self) -> str:
        """The zoomed range, as the page says it: "8.45 to 8.55" (a map: "Omega 1.26 to 1.29, r 0.72 to 0.78")."""
        if self.values2 is None:
            return f"{self.values[0]:g} to {self.values[-1]:g}"
        return ", ".join(f"{p} {a:g} to {b:g}" for p, (a, b) in zip((self.param, self.param2), self.view))

    def _gather(self) -> bool:
        """Load the chunks stored since the last look; True if any."""
        new = False
        for f in sorted(self.folder.glob("s[0-9]-c*.pickle")):
            if f.name in self._seen:
                continue
            self._seen.add(f.name)
            stage, chunk = int(f.name[1]), int(f.stem.split("-c")[1])
            if stage > self._stage_of[chunk]:
                self._stage_of[chunk] = stage
                with open(f, "rb") as fh:           # written by this zoom's own processes, in its private folder
                    self._parts[chunk] = pickle.load(fh)
                new = True
        return new

    def picture(self):
        """The chunks stored so far as one dataset of the stored kind (each value at its latest stage), or None
        before the first.  A diagram's or map's variables along the parameter are joined array by array
        (xarray's concat of 40 chunks costs 0.5 s, paid again at each new chunk), from each part's variables
        (``part[name]`` builds a DataArray with its coordinates: 50 chunks of 40 variables cost 0.5 s); a census'
        with :func:`join_censuses`."""
        import xarray as xr
        if not self._parts:
            return None
        parts = [self._parts[c].variables for c in sorted(self._parts)]
        if self.kind == "census":
            return join_censuses([self._parts[c] for c in sorted(self._parts)])
        first, par = self._parts[min(self._parts)], self.param

        def join(name, v):
            if par not in v.dims:
                return v.dims, v.values, v.attrs
            return v.dims, np.concatenate([p[name].values for p in parts], axis=v.dims.index(par)), v.attrs
        return xr.Dataset({k: join(k, v) for k, v in first.data_vars.items() if all(k in p for p in parts)},
                          coords={k: join(k, v) for k, v in first.coords.items()}, attrs=first.attrs)

    def poll(self) -> dict:
        """{"stage" (0 while the first stage runs, 1 the next, ... len(stages) when done), "name", "done" (values of
        the running stage stored; a map: cells), "total", "dataset" (every value stored so far, when a chunk landed
        since the last look; else None), "error", "seconds"}."""
        codes = [c.poll() for c in self.children]            # before the look: a process stores, then ends
        new = self._gather()
        per = 1 if self.values2 is None else self.values2.size
        sizes = np.array([(b - a) * per for a, b in self.chunks])
        stage = int(self._stage_of.min()) + 1
        out = {"stage": stage, "name": self.stages[min(stage, len(self.stages) - 1)][0], "total": self.total,
               "done": int(sizes[self._stage_of >= min(stage, len(self.stages) - 1)].sum()),
               "dataset": self.picture() if new else None, "error": "",
               "seconds": _time.perf_counter() - self.started}
        if stage < len(self.stages):
            failed = [c for c, code in zip(self.children, codes) if code not in (None, 0)]
            if failed or all(code == 0 for code in codes):
                errs = " ".join(" ".join(c.err_path.read_text(errors="replace").split()) for c in failed
                                if c.err_path.exists())
                out["error"] = errs[-300:] or (f"a zoom process ended with code {failed[0].returncode}" if failed
                                               else "the zoom's processes ended before every chunk was stored")
        return out

    @property
    def running(self) -> bool:
        return any(c.poll() is None for c in self.children)

    def stop(self) -> None:
        """End the zoom's processes and their workers (their own process groups)."""
        for c in self.children:
            _end(c)

    def close(self) -> None:
        """Stop it and remove its folder (stored chunks, resume parts)."""
        import shutil
        self.stop()
        shutil.rmtree(self.folder, ignore_errors=True)


def join_censuses(parts):
    """Censuses of consecutive ranges of one parameter (a zoom's chunks) as one attractors dataset: each part's
    attractors keep their own entries (renamed A0, A1, ... in order: a part's attractors are not matched with
    another's), the outcomes (escaped, ...) are shared, every variable along the attractors padded with its
    schema's fill where a part has no such entry, and each fresh start's attractor renumbered."""
    import xarray as xr

    from ..storage.schema import ATTRACTOR, ATTRACTOR_MULTIPLIERS
    first = parts[0]
    par = first.attrs["swept_parameter"]
    labels = [[str(s) for s in p.attractor_label.values] for p in parts]
    ids = [sum(s.startswith("A") for s in lab) for lab in labels]
    outcomes = list(dict.fromkeys(s for lab, n in zip(labels, ids) for s in lab[n:]))
    total = sum(ids)
    offsets = np.cumsum([0] + ids[:-1])
    maps_ = [np.array([off + j if j < n else total + outcomes.index(lab[j]) for j in range(len(lab))])
             for lab, n, off in zip(labels, ids, offsets)]
    size = total + len(outcomes)
    fills = {v.name: v.fill for v in ATTRACTOR + ATTRACTOR_MULTIPLIERS}
    out = {}
    for name, v in first.data_vars.items():
        if name == "attractor_label" or not all(name in p for p in parts):
            continue
        if par not in v.dims:
            out[name] = (v.dims, v.values, v.attrs)
        elif "attractor" not in v.dims:
            vals = [p[name].values for p in parts]
            if name == "start_attractor":
                vals = [m[x] for m, x in zip(maps_, vals)]
            out[name] = (v.dims, np.concatenate(vals, axis=v.dims.index(par)), v.attrs)
        else:
            order = (par, "attractor", *[d for d in v.dims if d not in (par, "attractor")])
            rest = [first.sizes[d] for d in order[2:]]
            fill = fills.get(name, np.nan if v.dtype.kind == "f" else 0)
            arr = np.full([sum(p.sizes[par] for p in parts), size, *rest], fill, dtype=v.dtype)
            at = 0
            for p, m in zip(parts, maps_):
                x = p[name].transpose(*order).values
                arr[at:at + x.shape[0], m] = x
                at += x.shape[0]
            out[name] = (order, arr, v.attrs)
    coords = {par: (par, np.concatenate([p[par].values for p in parts]), first[par].attrs),
              "attractor": ("attractor", np.arange(size, dtype=first.attractor.dtype), first.attractor.attrs)}
    coords.update({k: (c.dims, c.values, c.attrs) for k, c in first.coords.items() if k not in coords})
    ds = xr.Dataset(out, coords=coords, attrs=first.attrs)
    ds["attractor_label"] = ("attractor", [f"A{k}" for k in range(total)] + outcomes,
                             first.attractor_label.attrs)
    return ds


def zoom_worker() -> None:
    """A zoom process (``python -c ... <ready folder>``, see :func:`_start_child`): the first line on its standard
    input is its page's zoom plan (:func:`_plan`), whose one-point task it runs to compile the integrators; the
    second, a zoom's job (folder, values, chunks, each stage's groups of chunks), runs the plan's task on each
    group it claims at each stage and stores each chunk as ``s<stage>-c<chunk>.pickle`` in the folder
    (atomically: the page never reads half a file).  It ends after the group it is on when the page's process has
    ended (in its own process group, nothing else would stop it)."""
    import maps
    parent = os.getppid()
    plan = json.loads(sys.stdin.readline())
    pb = maps.problem(**plan["problem"])
    warm, first = plan["warm"], plan["stages"][0][1]
    _zoom_task(plan, pb, np.asarray(warm["values"]), dict(plan["method"], **first, **warm["settings"]),
               values2=warm.get("values2"), starts=warm.get("starts"))
    (Path(sys.argv[1]) / f"ready-{os.getpid()}").touch()
    line = sys.stdin.readline()
    if not line.strip():
        return
    job = json.loads(line)
    try:
        _run_job(plan, pb, job, parent)
    except ParameterError as exc:        # one line for the page's status, not a traceback
        sys.stderr.write(" ".join(str(exc).split()) + "\n")
        sys.exit(2)


def zoom_groups(n: int, workers: int, cap: int) -> list[tuple[int, int]]:
    """A stage's ``n`` chunks as consecutive groups [i, j) of chunks, which the zoom's ``workers`` processes claim
    in order, each as it ends its last (:func:`_run_job`): one chunk each first (the first progress within a
    second), then guided self-scheduling (the next group of the r chunks left holds ceil(r / (2 workers)) of them,
    at most ``cap``), down to one chunk at the end, so that the processes finish together."""
    out, i = [], 0
    while i < n:
        size = 1 if len(out) < workers else max(1, min(int(cap), math.ceil((n - i) / (2 * workers))))
        out.append((i, min(n, i + size)))
        i += size
    return out


def _claim(path: Path) -> bool:
    """True for the one process that creates ``path`` (a group of chunks is then its to run)."""
    try:
        os.close(os.open(path, os.O_CREAT | os.O_EXCL | os.O_WRONLY))
    except FileExistsError:
        return False
    return True


def _drawn(ds, plan: dict):
    """What the page draws and clicks of a diagram's or map's chunk: the variables along the parameter(s), the
    branch and the strobe samples (the impacts' own dimensions dropped before the pickle, not after it)."""
    if plan["kind"] == "census":
        return ds
    keep = {"branch", plan["param"], "sample", plan["param2"]}
    return ds.drop_vars([k for k, v in ds.variables.items() if not set(v.dims) <= keep])


def _run_job(plan: dict, pb, job: dict, parent: int) -> None:
    """A zoom process' job: at each stage, the groups of chunks it claims first (:func:`zoom_groups`), each run
    as one task of the plan and stored chunk by chunk as it ends (:func:`zoom_worker`)."""
    folder, values, chunks = Path(job["folder"]), np.asarray(job["values"]), job["chunks"]
    for s, (_, settings) in enumerate(plan["stages"]):
        for g, (i, j) in enumerate(job["groups"][s]):
            if os.getppid() != parent:
                return                  # the page's process ended (Ctrl-C, a closed server): nobody to show it to
            if not _claim(folder / f"claim-s{s}-g{g:04d}"):
                continue
            a, b = chunks[i][0], chunks[j - 1][1]
            ds = _drawn(_zoom_task(plan, pb, values[a:b], dict(plan["method"], **settings), values2=job["values2"],
                                   starts=plan["starts"]), plan)
            for c in range(i, j):
                part = ds if j - i == 1 else ds.isel({plan["param"]: slice(chunks[c][0] - a, chunks[c][1] - a)})
                out = folder / f"s{s}-c{c:04d}.pickle"
                with open(folder / f"tmp-{out.name}", "wb") as f:     # a pickle: a netCDF file costs 0.3 s to write
                    pickle.dump(part, f, protocol=pickle.HIGHEST_PROTOCOL)
                os.replace(folder / f"tmp-{out.name}", out)
