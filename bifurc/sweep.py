"""One-parameter sweeps: stroboscopic orbits, classification and grazing per value.

``mode="independent"``: every value starts from the same initial state (values
can run in parallel: ``workers`` processes or a Dask ``scheduler``).
``mode="continuation"``: each value starts from the previous value's final
state, swept up then down (dimension ``branch``), to reveal coexisting
attractors and hysteresis.

With ``path`` every completed value is saved at once under ``<path>.parts/``;
an interrupted sweep loses nothing and a rerun with the same arguments resumes.
The final Dataset is written atomically and the parts are removed.
"""
from __future__ import annotations

import hashlib
import json
import math
import os
import pickle
import shutil
import sys
import time as _time
from dataclasses import dataclass, field, fields, replace
from pathlib import Path

import numpy as np

from maps.parameters import ParameterError, validate_value
from maps.poincare import StroboscopicMap, orbit_from_periods
from maps.simulate import resolve

from .classify import DECAY_RATE, classify_orbit, lyapunov_threshold
from .lyapunov import companion_start, largest_lyapunov, lyapunov_along

__all__ = ["SweepPoint", "sweep", "GRAZING_GAP", "GRAZING_SPEED"]

#: an orbit grazes when its smallest clearance is below GRAZING_GAP [m] without contact,
#: or its slowest impact is below GRAZING_SPEED [m/s]
GRAZING_GAP = 1e-6
GRAZING_SPEED = 1e-3
STATUS = ("ok", "escaped", "failed")
#: a located sign change counts as a graze when the bisection shrank the clearance at its end
#: with fewer impacts to this fraction of its value at the grid neighbour
GRAZE_SHRINK = 0.1
#: layout of the per-value results saved under <path>.parts/ (a resume refuses another layout)
PARTS_FORMAT = 2
_MAPS: dict = {}


@dataclass(frozen=True)
class SweepPoint:
    """The work for one parameter value (picklable, so it runs in any worker process).

    Calling it with a value returns a dict of numpy arrays and scalars: the
    recorded orbit, its impacts, clearance, classification and run time.
    """

    scene: object  # scene name, or a HybridSystem (runs in this process only)
    param: str
    params: dict
    options: dict = field(default_factory=dict)   # circuit, ac_sign
    x0: dict = field(default_factory=dict)
    transient: int = 300
    record: int = 100
    tol: float = 1e-10
    max_period: int = 16
    rtol: float = 1e-6
    atol: float = 1e-9
    lyapunov: bool = True
    lyapunov_steps: int = 100
    max_impacts: int = 400
    max_transient: int | None = None  # extend a still-converging transient up to this [relay periods]
    batch_size: int = 4               # SIMD lanes of run_many (heyoka batch mode); 1: scalar path

    def warm(self) -> StroboscopicMap:
        """The process-wide map for this scene structure and tolerance (compiled once)."""
        sc, _ = _resolve(self.scene, self.params, **self.options)
        key = (sc.options if sc.options is not None else id(sc.system), self.tol)
        if key not in _MAPS:
            _MAPS[key] = StroboscopicMap(sc if sc.options is not None else sc.system, self.params, tol=self.tol)
        return _MAPS[key]

    def x0_state(self):
        sc, _ = _resolve(self.scene, self.params, **self.options)
        return sc.system.state_vector(sc.initial_state(**self.x0))

    def __call__(self, value, start=None) -> dict:
        """Orbit and class at ``param = value``; ``start = (state, flags)`` overrides x0."""
        smap = self.warm()
        smap.set_params(**dict(self.params, **{self.param: float(value)}))
        y0, flags = (self.x0_state(), None) if start is None else start
        clock = _time.perf_counter()
        o = smap.orbit(y0, self.record, transient=self.transient, flags=flags)
        return self._complete(value, smap, o, clock)

    def _lyapunov_needed(self, o, cls) -> bool:
        return self.lyapunov and o.status == "ok" and cls["label"] not in ("periodic", "periodic-no-impact")

    def _lyapunov_scale(self, o):
        return _state_scale(o.points, self.atol)

    def _classify(self, o, **kw):
        return classify_orbit(o.points, o.impacts_per_step, max_period=self.max_period, rtol=self.rtol,
                              atol=self.atol, status=o.status, **kw)

    def _complete(self, value, smap, o, clock, lyap=None, seconds=None, cls=None) -> dict:
        """Classification (integrating on while still converging, up to ``max_transient``), the
        Lyapunov exponent where not periodic (``lyap``: already computed along ``o``), packing.
        ``cls``: ``o``'s classification without an exponent, if already made."""
        used, steps = self.transient, o.n_steps
        cls = self._classify(o) if cls is None else cls
        limit = self.max_transient if self.max_transient is not None else self.transient
        while self._extends(o, cls, used):  # still converging: integrate on
            extra = max(1, min(used, limit - used))  # doubling, up to the limit
            o = smap.orbit(o.final_state, self.record, transient=extra, flags=o.final_flags,
                           t0=smap.sample_time(used + self.record) - smap.sample_time(0))
            used, steps, lyap = used + self.record + extra, steps + o.n_steps, None
            cls = self._classify(o)
        if self._lyapunov_needed(o, cls):
            if lyap is None:
                scale = self._lyapunov_scale(o)
                if self.lyapunov_steps <= self.record:      # along the recorded window
                    lyap = lyapunov_along(smap.step, o.points[:self.lyapunov_steps + 1], scale=scale, k0=used)
                else:                                        # two trajectories after it
                    lyap = largest_lyapunov(smap.step, o.final_state, self.lyapunov_steps, scale=scale,
                                            k0=used + self.record)
            cls = self._classify(o, lyapunov=lyap, lyap_tol=lyapunov_threshold(self.lyapunov_steps))
        else:
            lyap = math.nan
        return self._pack(value, smap, o, cls, lyap, used, steps,
                          _time.perf_counter() - clock if seconds is None else seconds)

    def _pack(self, value, smap, o, cls, lyap, used, steps, seconds) -> dict:
        status = o.status
        n_imp = o.impact_t.size
        cap = self.max_impacts
        pad = lambda a: np.concatenate([a[:cap], np.full(max(0, cap - a.size), np.nan)])  # noqa: E731
        n_rec = o.points.shape[0]
        points = np.full((self.record + 1, o.points.shape[1]), np.nan)
        points[:n_rec] = o.points
        gaps = o.min_gap_per_step
        speeds = o.min_impact_speed_per_step
        return {
            "value": float(value), "points": points, "n_recorded": n_rec - 1,
            "impacts_per_step": np.pad(o.impacts_per_step, (0, self.record - o.n), constant_values=-1),
            "min_gap_per_step": np.pad(gaps, (0, self.record - gaps.size), constant_values=np.nan),
            "min_impact_speed_per_step": np.pad(speeds, (0, self.record - speeds.size), constant_values=np.nan),
            "min_gap": float(np.min(gaps)) if gaps.size else math.nan,
            "min_impact_speed": float(np.min(speeds)) if speeds.size else math.nan,  # NaN: no step recorded
            "impact_t": pad(o.impact_t), "impact_velocity": pad(o.impact_velocity),
            "impact_phase": pad(o.impact_phase), "impact_penetration": pad(o.impact_penetration),
            "impact_duration": pad(o.impact_duration),
            "min_flight_gap": float(np.min(o.min_flight_gap_per_step)) if gaps.size else math.nan,
            "max_impact_speed": float(np.max(np.abs(o.impact_velocity))) if n_imp else 0.0,
            "n_impacts": n_imp, "status": STATUS.index(status), "failure_time": o.failure_time,
            "failure": o.failure, "lyapunov": lyap, "forcing_period_steps": smap.forcing_period_steps,
            "n_steps": steps, "transient_used": used, "seconds": seconds,
            "final_state": o.final_state, "final_flags": o.final_flags, **{f"class_{k}": v for k, v in cls.items()},
        }

    # ----- many values at once: heyoka batch mode -------------------------------------
    def _batchable(self, smap) -> bool:
        """Batch mode applies: the engine supports the system, and the map samples at whole relay periods."""
        from .batch import unsupported
        system = smap.system
        return (self.batch_size > 1 and unsupported(system) is None and smap.phase == 0.0
                and system.switches[0].frequency == "relay_hz" and smap._period_given is None)

    def run_many(self, values) -> list:
        """The same results as ``[self(v) for v in values]`` (up to round-off), on heyoka's batch
        integrator: the transient on a lean event set, the recorded window with every
        observation guard, then Lyapunov companions along the recorded orbits.  Values that
        are still converging and may integrate on (``max_transient``) continue on the scalar path."""
        from .batch import LaneJob, engine_for
        smap = self.warm()
        if not self._batchable(smap):
            return [self(v) for v in values]
        system = smap.system
        clock = _time.perf_counter()
        params = [system.validate({**smap.params, **self.params, self.param: float(v)}) for v in values]
        y0 = self.x0_state()
        lean = engine_for(system, self.tol, self.batch_size, observations=False)
        full = engine_for(system, self.tol, self.batch_size, observations=True)

        def start_flags(y, t, p):      # as StroboscopicMap.orbit: contact inferred from the gap
            return system.initial_flags(t, p, smap._flags_for(y, t))

        if self.transient:
            first = lean.run([LaneJob(p, y0, start_flags(y0, 0.0, p), transient=self.transient, record=0)
                              for p in params])
        else:
            first = [None] * len(params)
        second = full.run([LaneJob(p, r.final_state, r.final_flags, k0=self.transient, record=self.record, log=True)
                           if r is not None else LaneJob(p, y0, start_flags(y0, 0.0, p), record=self.record, log=True)
                           for p, r in zip(params, first)])
        orbits = []
        for p, pre, r in zip(params, first, second):
            if pre is not None and pre.status != "ok":      # ended in the transient: nothing recorded
                r, times, points, steps = pre, [0.0], [y0], pre.n_steps
            else:
                times, points, steps = r.times, r.points, r.n_steps + (pre.n_steps if pre is not None else 0)
            orbits.append(orbit_from_periods(
                system, p, p["relay_hz"], times, points, r.period_events, status=r.status, failure=r.failure,
                failure_time=r.failure_time, n_steps=steps, final_state=r.final_state, final_flags=r.final_flags))
        # Lyapunov companions where the orbit is not periodic and will not be extended
        lyap = [None] * len(params)
        classes = [self._classify(o) for o in orbits]
        comp, owners = [], []
        for i, (p, o, cls) in enumerate(zip(params, orbits, classes)):
            if self._lyapunov_needed(o, cls) and self.lyapunov_steps <= self.record and not self._extends(o, cls):
                scale = self._lyapunov_scale(o)
                ref = list(o.points[:self.lyapunov_steps + 1])
                z0 = companion_start(ref[0], scale=scale)
                comp.append(LaneJob(p, z0, start_flags(z0, self.transient / p["relay_hz"], p), k0=self.transient,
                                    record=self.lyapunov_steps, reference=ref, scale=scale))
                owners.append(i)
        for i, r in zip(owners, lean.run(comp) if comp else []):
            lyap[i] = r.lyapunov
        share = (_time.perf_counter() - clock) / max(1, len(params))
        out = []
        for v, p, o, lam, cls in zip(values, params, orbits, lyap, classes):
            smap.set_params(**p)
            out.append(self._complete(v, smap, o, _time.perf_counter(), lyap=lam, seconds=share, cls=cls))
        return out

    def _extends(self, o, cls, used=None) -> bool:
        """Still converging and allowed to integrate on (``max_transient``) after ``used`` periods."""
        used = self.transient if used is None else used
        limit = self.max_transient if self.max_transient is not None else self.transient
        return (o.status == "ok" and cls["label"] == "not-converged" and used < limit
                and cls["convergence_rate"] < DECAY_RATE)


class SystemScene:
    """Lets a bare HybridSystem be swept like a scene: every parameter must be given."""

    def __init__(self, system):
        self.system, self.name, self.options, self.preset = system, system.name, None, None

    def initial_state(self, **components):
        x0 = {n: 0.0 for n in self.system.state_names}
        for k, v in components.items():
            if k not in x0:
                raise ParameterError(f"unknown state {k!r} for {self.name!r}; its states are: {', '.join(x0)}")
            x0[k] = float(v)
        return x0

    def parameters(self, preset=None, **values):
        return self.system.validate(values)


def _resolve(scene, params, preset=None, circuit=None, ac_sign=None, dc_law=None):
    """(scene-like, {name: (value, provenance)}) for a scene name, Scene or HybridSystem."""
    from maps.hybrid import HybridSystem
    if isinstance(scene, SystemScene):
        scene = scene.system
    if isinstance(scene, HybridSystem):
        if preset or circuit or ac_sign or dc_law:
            raise ParameterError("preset, circuit, ac_sign and dc_law apply to scenes, not to a bare HybridSystem")
        values = scene.validate(params or {})
        return SystemScene(scene), {k: (v, "set by user") for k, v in values.items()}
    return resolve(scene, params, preset, circuit, ac_sign, dc_law=dc_law)


def _manifest(point: SweepPoint, values, mode) -> dict:
    d = {f.name: getattr(point, f.name) for f in fields(point) if f.name != "batch_size"}  # no effect on results
    if not isinstance(d["scene"], str):
        d["scene"] = repr(d["scene"])
    d.update(values=[float(v) for v in values], mode=mode, parts_format=PARTS_FORMAT)
    return d


class _Parts:
    """Completed values on disk, one small pickle each, written atomically."""

    def __init__(self, path, manifest):
        self.dir = Path(str(path) + ".parts")
        self.dir.mkdir(parents=True, exist_ok=True)
        mfile = self.dir / "manifest.json"
        text = json.dumps(manifest, sort_keys=True, default=str)
        if mfile.exists():
            if mfile.read_text() != text:
                raise ParameterError(f"{self.dir} holds a sweep with other arguments; remove it or change -o "
                                     f"(stored hash {hashlib.sha1(mfile.read_bytes()).hexdigest()[:8]})")
        else:
            mfile.write_text(text)

    def _file(self, branch, i):
        return self.dir / f"{branch}-{i:06d}.pkl"

    def load(self, branch, i):
        f = self._file(branch, i)
        if f.exists():
            with open(f, "rb") as fh:
                return pickle.load(fh)
        return None

    def save(self, branch, i, result):
        f = self._file(branch, i)
        tmp = f.with_suffix(".tmp")
        with open(tmp, "wb") as fh:
            pickle.dump(result, fh)
        os.replace(tmp, f)

    def remove(self):
        shutil.rmtree(self.dir, ignore_errors=True)


def sweep(scene="thesis-1dof", param="relay_hz", values=None, *, mode="independent", transient=300,
          record=100, preset=None, params=None, x0=None, tol=1e-10, max_period=16, rtol=1e-6, atol=1e-9,
          lyapunov=True, grazing=True, grazing_xtol=None, circuit=None, ac_sign=None, dc_law=None, path=None,
          progress=True, workers=1, scheduler=None, error_sample=3, max_transient=None, batch_size=4,
          chunk_size=None):
    """Sweep ``param`` over ``values``; returns an xarray Dataset (see bifurc.storage).

    Parameters
    ----------
    scene, preset, params, x0, circuit, ac_sign, dc_law : as in maps.simulate.
    param : str
        Parameter name to sweep (MODEL.md section 6), e.g. "relay_hz", "V", "k".
    values : array
        The grid (ascending for continuation).
    mode : "independent" or "continuation".
    transient, record : int
        Relay periods discarded, then recorded, per value.
    max_transient : int
        Where a value is not-converged with a geometrically decaying recurrence, integrate on
        (doubling the transient) up to this many relay periods; the transient used is stored.
    tol : float
        heyoka tolerance; ``error_sample`` values are re-run at tol/100 for the error estimate.
    max_period, rtol, atol : classification (bifurc.classify).
    lyapunov : bool
        Compute the largest Lyapunov exponent where the orbit is not periodic.
    grazing : bool
        Locate grazing values between neighbours where the orbit changes between
        impacting and not impacting, by bisection to ``grazing_xtol``.
    path : str
        netCDF output; completed values are kept in ``<path>.parts/`` for resuming.
    workers, scheduler : parallel execution of independent sweeps (bifurc.parallel).
    batch_size : int
        Values integrated together in heyoka's batch mode (SIMD lanes, :mod:`bifurc.batch`);
        1: one value at a time.  Results agree to round-off, amplified by chaotic dynamics.
    chunk_size : int
        Values per task (default: 8 x batch_size, or 1 without batch mode, in this process;
        automatic on workers);
        with ``path``, an interruption loses at most the chunks in flight.
    """
    from . import storage
    if mode not in ("independent", "continuation"):
        raise ParameterError(f"mode {mode!r}; allowed: independent, continuation")
    values = np.asarray(values, dtype=float).ravel()
    if values.size == 0 or not np.all(np.isfinite(values)):
        raise ParameterError("values must be a non-empty array of finite numbers")
    sc, table = _resolve(scene, params, preset, circuit, ac_sign, dc_law)
    base = {k: v for k, (v, _) in table.items()}
    sc.system.parameter(param)  # raises for an unknown name
    for v in values:  # every value must be valid before anything runs
        sc.parameters(preset, **dict(params or {}, **{param: v}))
    sc.initial_state(**(x0 or {}))
    transient = int(validate_value("transient", transient, 0, 1e7))
    record = int(validate_value("record", record, 3, 1e7))
    if scheduler is None:
        workers = int(validate_value("workers", workers, 1, 1024))
    options = {k: v for k, v in dict(circuit=circuit, ac_sign=ac_sign).items() if v is not None}
    if sc.options is not None and sc.options.dc:   # the resolved law (it may follow the preset): workers get no preset
        options["dc_law"] = sc.options.dc_law
    name = sc.name if sc.options is not None else sc.system  # a bare system runs in this process
    if max_transient is not None:
        max_transient = int(validate_value("max_transient", max_transient, transient, 1e8))
    batch_size = int(validate_value("batch_size", batch_size, 1, 64))
    point = SweepPoint(name, param, base, options, dict(x0 or {}), transient, record, float(tol), max_period,
                       rtol, atol, lyapunov, max_transient=max_transient, batch_size=batch_size)
    if chunk_size is None and workers == 1 and scheduler is None:
        chunk_size = 8 * batch_size if batch_size > 1 else 1
    if chunk_size is not None:
        chunk_size = int(validate_value("chunk_size", chunk_size, 1, 1e9))
    branches = ["independent"] if mode == "independent" else ["up", "down"]
    parts = _Parts(path, _manifest(point, values, mode)) if path else None
    results = {b: [None] * values.size for b in branches}
    if parts:
        for b in branches:
            for i in range(values.size):
                results[b][i] = parts.load(b, i)
    todo = sum(r is None for b in branches for r in results[b])
    bar = _progress(todo, progress, f"{sc.name} {param}")
    clock = _time.perf_counter()

    def keep(b, i, r):
        results[b][i] = r
        if parts:
            parts.save(b, i, r)
        bar.update(1)

    try:
        if mode == "independent":
            missing = [i for i in range(values.size) if results["independent"][i] is None]
            if missing:
                from .parallel import map_values

                def on_chunk(start, chunk):
                    for j, r in enumerate(chunk):
                        keep("independent", missing[start + j], r)
                warm = None
                if workers > 1 or scheduler is not None:   # while the workers integrate
                    import threading
                    warm = threading.Thread(target=_warm_xarray, daemon=True)
                    warm.start()
                map_values(point, values[missing], workers=workers, scheduler=scheduler, on_chunk=on_chunk,
                           collect=False, chunk_size=chunk_size)
                if warm is not None:
                    warm.join()
        else:
            start = None
            for b, order in (("up", range(values.size)), ("down", range(values.size - 1, -1, -1))):
                for i in order:
                    r = results[b][i]
                    if r is None:
                        r = point(values[i], start)
                        keep(b, i, r)
                    start = (r["final_state"], r["final_flags"]) if r["status"] == 0 else None
    finally:
        bar.close()
    seconds = _time.perf_counter() - clock
    ds = storage.to_dataset(results, values, point, sc, table, mode)
    ds.attrs["sweep_seconds"] = seconds
    ds.attrs["batch_size"] = batch_size     # SIMD lanes (1: one value at a time); results agree to round-off
    ds.attrs["compile_seconds"] = point.warm()._run.compile_seconds  # once per structure and process
    if grazing:
        ds = storage.add_grazing(ds, _locate_grazing(results, values, point, grazing_xtol))
    if error_sample:
        ds = storage.add_error_estimate(ds, **_error_estimate(results, values, point, branches[0], error_sample))
    if path:
        storage.save(ds, path)
        parts.remove()
    return ds


def _warm_xarray():
    """Import what building the Dataset needs (xarray probes its duck-array modules, dask among
    them: ~1.4 s) while the worker processes integrate, instead of after them."""
    import xarray as xr
    xr.Dataset({"a": ("d", np.zeros(1))})


def _impact_rate(r) -> float:
    """Contacts per recorded period."""
    return r["n_impacts"] / max(1, r["n_recorded"])


def _locate_grazing(results, values, point, xtol):
    """Grazing values between neighbours whose number of impacts per period differs.

    From no impact to impacts, one neighbour must be periodic and the other periodic or
    not-converged (near a grazing bifurcation convergence is slow); from m > 0 to m'
    impacts per period both must be periodic.  Between chaotic or quasi-periodic neighbours the sign of the
    clearance brackets nothing meaningful.  The bisection follows the side with fewer impacts (see
    :class:`_BranchFollower`); an attractor that changes under re-computation brackets
    nothing and is skipped.
    """
    from .grazing import locate_grazing
    found = []
    if xtol is None and values.size > 1:  # default: a thousandth of the grid spacing
        xtol = float(np.min(np.abs(np.diff(values)))) * 1e-3
    for b, res in results.items():
        for i in range(values.size - 1):
            ra, rb = res[i], res[i + 1]
            if ra is None or rb is None or ra["status"] or rb["status"]:
                continue
            if ra["class_code"] not in (0, 1, 4) or rb["class_code"] not in (0, 1, 4):
                continue
            if ra["class_code"] == rb["class_code"] == 4:
                continue  # no periodic orbit on either side: no branch whose clearance vanishes
            if _impact_rate(ra) == _impact_rate(rb):
                continue
            if ra["n_impacts"] and rb["n_impacts"] and not (ra["class_code"] == rb["class_code"] == 0):
                continue  # m -> m' > 0 impacts: only between periodic orbits (a transient's count drifts)
            clear = (values[i], ra) if _impact_rate(ra) < _impact_rate(rb) else (values[i + 1], rb)
            follower = _BranchFollower(point, clear[0], clear[1])
            try:
                g = locate_grazing(follower, values[i], values[i + 1], xtol=xtol)
            except ParameterError:
                continue
            g["impacts_below"], g["impacts_above"] = ra["n_impacts"], rb["n_impacts"]
            g["clearance"], g["impact_speed"] = follower.clearance[-1], follower.speed[-1]
            # a graze: the clearance of the branch with fewer impacts vanishes as the bracket shrinks;
            # if it stays finite the branch ends otherwise (a jump, e.g. a saddle-node).  The impact
            # speed past a graze need not be small: the orbit may jump to a distant impacting attractor.
            g["confirmed"] = follower.clearance[-1] <= GRAZE_SHRINK * follower.clearance[0]
            g["clearance_start"] = follower.clearance[0]
            found.append((b, g))
    return found


class _BranchFollower:
    """Signed clearance along the branch with fewer impacts, for bisection.

    On that branch (``m`` contacts in the record, possibly 0) it is the smallest
    clearance: the whole orbit's for m = 0, the lowest free-flight minimum for m > 0;
    both reach 0 at the graze.  Past it (more contacts) it is minus the slowest impact
    speed, which also reaches 0 at the graze.
    An orbit with more impacts may coexist just before grazing, and a parameter jump excites a
    transient about as large as the change of the forced response, which can touch the
    stop and land on it.  So each evaluation ramps the parameter from the last clear
    value in ``substeps`` steps (transient split between them) and, when the result is
    clear, becomes the new starting point: the branch is followed up to its graze.
    """

    def __init__(self, point, value, result, substeps=8):
        self.point, self.substeps = replace(point, lyapunov=False), substeps
        self.value, self.start = value, (result["final_state"], result["final_flags"])
        self.impacts = result["n_impacts"]
        self.clearance, self.speed = [], []  # every positive and negative value returned, in order

    def __call__(self, p):
        f = self._evaluate(p)
        if math.isfinite(f):
            (self.clearance if f > 0 else self.speed).append(abs(f))
        return f

    def _evaluate(self, p):
        if p == self.value:
            r = self.point(p, self.start)
        else:
            start, short = self.start, replace(self.point, transient=max(1, self.point.transient // self.substeps),
                                               record=3)
            for j in range(1, self.substeps):
                r = short(self.value + (p - self.value) * j / self.substeps, start)
                if r["status"]:
                    return math.nan
                start = (r["final_state"], r["final_flags"])
            r = self.point(p, start)
        if r["status"]:
            return math.nan
        if r["n_impacts"] > self.impacts:
            return -r["min_impact_speed"]
        self.value, self.start = p, (r["final_state"], r["final_flags"])
        return r["min_gap"] if self.impacts == 0 else r["min_flight_gap"]


def _error_estimate(results, values, point, branch, sample, step_points=32) -> dict:
    """Re-run ``sample`` values at tol/100 and compare (keywords of storage.add_error_estimate).

    - ``step_err``: one relay period from the same recorded state at tol and at tol/100, at up
      to ``step_points`` states of each sampled value: the error of each map step, meaningful
      for every class (chaotic ones included).
    - ``point_err``, ``time_err``: whole re-runs from the same start, largest difference of the
      recorded points and contact times, over periodic values only: there it is the global
      error.  Elsewhere the difference grows with the dynamics' sensitivity whatever the
      tolerance; it is reported apart (``sensitive_err``).  Periodic values are sampled first.
      A continuation value is re-run from the same start (the previous value's final state).
    NaN: nothing of that kind was sampled.
    """
    ok = [i for i in range(values.size) if results[branch][i] is not None and not results[branch][i]["status"]]
    good = [i for i in ok if results[branch][i]["class_code"] in (0, 1)]
    pick = lambda pool, k: [pool[j] for j in np.unique(np.linspace(0, len(pool) - 1, k).round().astype(int))] \
        if pool and k > 0 else []  # noqa: E731
    idx = pick(good, min(sample, len(good)))
    idx += pick([i for i in ok if i not in good], sample - len(idx))
    idx = sorted(idx)
    tight = replace(point, tol=point.tol / 100, lyapunov=False)
    point_err, sensitive_err, step_err, time_err, counts_differ = math.nan, math.nan, math.nan, 0.0, 0
    clock = _time.perf_counter()
    if branch == "independent":      # one batch pass for the whole sample
        reruns = dict(zip(idx, tight.run_many([values[i] for i in idx]))) if idx else {}
    for i in idx:
        a = results[branch][i]
        step_err = np.fmax(step_err, _map_step_error(a, values[i], point, tight, step_points))
        if branch == "independent":
            b = reruns[i]
        else:
            prev = results[branch][i - 1] if i > 0 else None
            start = (prev["final_state"], prev["final_flags"]) if prev is not None and prev["status"] == 0 else None
            b = tight(values[i], start)
        if b["status"]:
            counts_differ += 1
            continue
        err = float(np.nanmax(np.abs(a["points"] - b["points"]) / _state_scale(a["points"], point.atol)))
        if i in good:
            point_err = np.fmax(point_err, err)
        else:
            sensitive_err = np.fmax(sensitive_err, err)
        if a["n_impacts"] == b["n_impacts"]:
            if a["n_impacts"] and i in good:
                time_err = max(time_err, float(np.nanmax(np.abs(a["impact_t"] - b["impact_t"]))))
        else:
            counts_differ += 1
    return dict(sample_values=values[idx], point_err=float(point_err), time_err=time_err,
                counts_differ=counts_differ, seconds=_time.perf_counter() - clock, tight_tol=point.tol / 100,
                sensitive_err=float(sensitive_err), n_sensitive=len([i for i in idx if i not in good]),
                step_err=float(step_err))


def _state_scale(points, atol):
    """Each state component's largest magnitude over recorded ``points`` (NaN padding ignored), >= atol."""
    return np.maximum(np.nanmax(np.abs(points), axis=0), atol)


def _map_step_error(r, value, point, tight, n_points) -> float:
    """Largest scaled difference of one relay period at ``point.tol`` and at ``tight.tol`` from the
    same recorded states of result ``r`` (flags from the state, as StroboscopicMap.step)."""
    pts = r["points"][:r["n_recorded"] + 1]
    ks = np.unique(np.linspace(0, pts.shape[0] - 2, min(n_points, pts.shape[0] - 1)).round().astype(int))
    scale = _state_scale(pts, point.atol)
    params = dict(point.params, **{point.param: float(value)})
    worst = math.nan
    maps_ = point.warm(), tight.warm()
    for smap in maps_:
        smap.set_params(**params)
    for k in ks:
        try:
            a, b = (smap.step(pts[k], r["transient_used"] + int(k)) for smap in maps_)
        except Exception:  # noqa: BLE001 - a failed step leaves this point out
            continue
        worst = np.fmax(worst, float(np.max(np.abs(a - b) / scale)))
    return float(worst)


class _NoBar:
    def update(self, n=1):
        pass

    def close(self):
        pass


def _progress(total, progress, desc):
    if not progress or total == 0:
        return _NoBar()
    from tqdm import tqdm
    return tqdm(total=total, desc=desc, unit="value", file=sys.stderr, smoothing=0.1)
