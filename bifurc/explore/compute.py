"""What the explorer computes, through the public API only (no second implementation): the problem rebuilt from
a stored dataset's attributes, a value's time history (:func:`maps.simulate`) and periodic orbit
(:func:`bifurc.periodic_orbit`), its branch (:func:`bifurc.continue_orbit`) and a zoomed range swept anew
(:func:`bifurc.sweep` on a :class:`bifurc.Run`, in a child process that a newer zoom stops).

Nothing here draws: :mod:`bifurc.explore.app` shows what these functions return.
"""
from __future__ import annotations

import copy
import json
import math
import os
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
    params.pop(a.get("swept_parameter"), None)
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
        lo, hi = self.values.min(), self.values.max()
        step = np.diff(np.sort(self.values)).min() if self.values.size > 1 else 0.0
        if not lo - step <= float(value) <= hi + step:
            raise ParameterError(f"{self.param} = {value:g}: outside the diagram's {lo:g} to {hi:g}")
        return int(np.argmin(np.abs(self.values - float(value))))

    def on(self, ds) -> "Computer":
        """The same problem and integrators for another diagram of it (a zoom's)."""
        require_kind(ds, "diagram", "the explorer")
        new = copy.copy(self)
        new.ds, new.values = ds, ds[self.param].values.astype(float)
        return new

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


def branch_points(br, state: str) -> tuple[np.ndarray, np.ndarray]:
    """(parameter, state) pairs of a branch dataset's points at every strobe node, for the diagram's overlay."""
    p = br[br.attrs["continuation_parameter"]].values
    y = br[state].values.reshape(p.size, -1)           # (point, node)
    keep = np.isfinite(y)
    return np.repeat(p, y.shape[1])[keep.ravel()], y[keep]


class Zoom:
    """A range of the diagram swept anew in a child process (:func:`bifurc.sweep` on a :class:`bifurc.Run` with
    every core), in two stages: a first picture (the dataset's transient and record, no extension, no exponent
    and no grazing search: the points and the periodic classes), then the
    anytime labels (undecided values extended up to the dataset's budget).  :meth:`stop` ends the child and its
    workers (a newer zoom replaces a stale one); :meth:`poll` tells the stage, values done and a finished
    stage's dataset."""

    def __init__(self, computer: Computer, lo: float, hi: float, n: int = ZOOM_VALUES, workers: int | None = None):
        a = computer.ds.attrs
        if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
            raise ParameterError(f"zoom range {lo:g} to {hi:g}: need two finite values, the first below the second")
        self.values = np.linspace(lo, hi, int(n))
        self.folder = Path(tempfile.mkdtemp(prefix="bifurc-explore-"))
        transient, record = int(a.get("transient_periods", 300)), int(a.get("recorded_periods", 100))
        budget = int(a.get("budget_periods", transient + record))
        self.chunk = max(1, int(n) // 20)
        self.stages = [("first picture", dict(budget=transient + record, lyapunov=False, grazing=False)),
                       ("anytime labels", dict(budget=max(budget, transient + record)))]
        spec = {"problem": computer.kwargs, "param": computer.param, "values": self.values.tolist(),
                "method": {"transient": transient, "record": record, "tol": computer.tol,
                           "max_period": int(a.get("max_period", 100)), "error_sample": 0},
                "stages": [dict(name=s, out=str(self.folder / f"stage{j}.nc"), **kw)
                           for j, (s, kw) in enumerate(self.stages)],
                "workers": workers, "chunk": self.chunk}
        (self.folder / "spec.json").write_text(json.dumps(spec))
        self.started = _time.perf_counter()
        with open(self.folder / "stderr.txt", "wb") as err:
            self.child = subprocess.Popen([sys.executable, "-c", "from bifurc.explore.compute import zoom_main; "
                                           "zoom_main()", str(self.folder / "spec.json")], start_new_session=True,
                                          stdout=subprocess.DEVNULL, stderr=err)
        self.seen = -1

    def poll(self) -> dict:
        """{"stage" (0, 1; 2 when done), "name", "done" (values of the running stage finished), "total",
        "dataset" (a newly finished stage's dataset, else None), "error", "seconds"}."""
        from ..storage.load import load
        finished = [j for j in range(len(self.stages)) if (self.folder / f"stage{j}.nc").exists()]
        stage = len(finished)
        out = {"stage": stage, "name": self.stages[min(stage, len(self.stages) - 1)][0], "total": self.values.size,
               "done": 0, "dataset": None, "error": "", "seconds": _time.perf_counter() - self.started}
        if finished and finished[-1] > self.seen:
            self.seen = finished[-1]
            out["dataset"] = load(self.folder / f"stage{self.seen}.nc", "diagram")
        if stage < len(self.stages):
            parts = self.folder / f"stage{stage}.nc.tmp.nc.parts"
            n_parts = len(list(parts.glob("*.nc"))) if parts.is_dir() else 0
            out["done"] = min(self.values.size, n_parts * self.chunk)
            if self.child.poll() not in (None, 0):
                out["error"] = " ".join((self.folder / "stderr.txt").read_text(errors="replace").split())[-300:] \
                    or f"the zoom's process ended with code {self.child.returncode}"
        return out

    @property
    def running(self) -> bool:
        return self.child.poll() is None

    def stop(self) -> None:
        """End the child process and its workers (their own process group)."""
        if self.child.poll() is None:
            try:
                os.killpg(self.child.pid, signal.SIGTERM)
            except ProcessLookupError:
                pass
            self.child.wait(timeout=10)

    def close(self) -> None:
        """Stop it and remove its folder (spec, stage files, resume parts)."""
        import shutil
        self.stop()
        shutil.rmtree(self.folder, ignore_errors=True)


def zoom_main() -> None:
    """The zoom's child process: ``python -c ... spec.json`` (see :class:`Zoom`)."""
    import maps

    from ..run.where import Run
    from ..sweeps.method import Diagram
    from ..sweeps.sweep import sweep
    spec = json.loads(Path(sys.argv[1]).read_text())
    pb = maps.problem(**spec["problem"])
    values = np.asarray(spec["values"])
    for stage in spec["stages"]:
        tmp = stage["out"] + ".tmp.nc"
        settings = {k: v for k, v in stage.items() if k not in ("name", "out")}
        sweep(pb, spec["param"], values, Diagram(**settings, **spec["method"]),
              run=Run(workers=spec["workers"], path=tmp, chunk_size=spec["chunk"], progress=False))
        os.replace(tmp, stage["out"])
