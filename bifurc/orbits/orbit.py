"""Find a periodic orbit of a scene or system and describe it as a dataset.

>>> ds = bifurc.periodic_orbit("thesis-1dof", preset="matlab-listing", params={"V": 90, "relay_hz": 8.5},
...                            transient=300)
>>> ds.multiplier_abs, ds.stable, ds.impact_velocity

The orbit may be stable or unstable: Newton by multiple shooting (:mod:`bifurc.orbits.periodic`)
needs only a start near it (a state, the end of a simulation, or a stored sweep point with its
flags, :func:`sweep_point`).
"""
from __future__ import annotations

import math
import time as _time

import numpy as np

from maps.hybrid import HybridState
from maps.parameters import ParameterError, validate_value
from maps.poincare import StroboscopicMap
from maps.problem import problem
from maps.provenance import cf_attrs, recorded

from .periodic import OrbitNotFound, PeriodicOrbit, find_periodic_orbit

__all__ = ["periodic_orbit", "sweep_point", "orbit_dataset", "first_guess", "multiplier_change", "OrbitNotFound"]


def sweep_point(ds, value, *, sample: int = -1, branch=None):
    """``(HybridState, sample index k)`` of a stored sweep at the swept parameter's ``value``
    (nearest stored value), recorded sample ``sample`` (default: the last), ready to start a
    step, a simulation or :func:`periodic_orbit` exactly there."""
    par = ds.attrs["swept_parameter"]
    d = ds.sel(branch=branch) if branch is not None else ds.isel(branch=0)
    d = d.sel({par: value}, method="nearest")
    k = int(np.arange(d.sizes["sample"])[sample])
    states = [name for name in d.data_vars if d[name].dims == ("sample",) and not name.startswith("flag_")]
    y = np.array([float(d[s].values[k]) for s in states])
    flags = {n[5:]: float(d[n].values[k]) for n in d.data_vars if n.startswith("flag_")}
    if not np.all(np.isfinite(y)):
        raise ParameterError(f"the sweep has no state at {par} = {value} sample {k} (escaped or not computed)")
    return HybridState(y, flags or None), int(d.transient_used.values) + k


@recorded("bifurc.periodic_orbit")
def periodic_orbit(scene, *, params=None, preset=None, period: int | None = None, x0=None, start=None,
                   k0: int | None = None, transient: int = 0, tol: float = 1e-12, newton_tol: float | None = None,
                   max_iter: int = 40, error: bool = True, circuit=None, ac_sign=None, dc_law=None,
                   soil=None, compaction=None):
    """A periodic orbit of ``scene`` (name, Scene, HybridSystem or :class:`maps.Problem`) as an xarray Dataset.

    Parameters
    ----------
    period : int
        In strobe periods (relay periods for relay scenes); a multiple of the forcing period q
        (default: q).
    x0 : dict
        Initial state; integrated ``transient`` strobe periods to the first guess.
    start : HybridState, or (HybridState, k) from :func:`sweep_point`
        The first guess itself (instead of x0 and transient), at sample ``k0``.
    tol, newton_tol : float
        Integration tolerance; largest scaled shooting residual accepted (default 10 tol: the
        integration's own noise bounds how far the residual can fall).
    error : bool
        Solve again at tol/100 and store the multipliers' change (``multiplier_error``).
    preset, circuit, ac_sign, dc_law, soil, compaction : as in :func:`maps.problem` (the DC law follows the preset).

    Raises :class:`OrbitNotFound` (with the reason) when Newton does not converge, and
    :class:`~maps.parameters.ParameterError` for bad input (one line, naming the argument).
    """
    clock = _time.perf_counter()
    pb = problem(scene, preset, params, x0, circuit=circuit, ac_sign=ac_sign, dc_law=dc_law, soil=soil,
                 compaction=compaction)
    smap = StroboscopicMap(pb, tol=tol)
    transient = int(validate_value("transient", transient, 0, 1e7))
    newton_tol = 10 * tol if newton_tol is None else validate_value("newton_tol", newton_tol, 0.0, 1.0, low_open=True)
    start, k0, period = first_guess(smap, pb, transient=transient, start=start, k0=k0, period=period)
    orbit = find_periodic_orbit(smap, start, period, k0=k0, tol=newton_tol, max_iter=max_iter)
    err = math.nan
    if error:
        tight = StroboscopicMap(pb, tol=tol / 100)
        again = find_periodic_orbit(tight, orbit.nodes[0], period, k0=k0, tol=newton_tol, max_iter=max_iter)
        err = multiplier_change(orbit.multipliers, again.multipliers)
    return orbit_dataset(orbit, smap, pb, multiplier_error=err, seconds=_time.perf_counter() - clock)


def first_guess(smap, pb, *, transient=0, start=None, k0=None, period=None):
    """(HybridState, sample k0, period) to start Newton from: ``start`` (a state, a HybridState or
    :func:`sweep_point`'s pair) at k0, else the end of ``transient`` strobe periods from the
    problem ``pb``'s start; the period defaults to the forcing period q."""
    if start is not None:
        if isinstance(start, tuple):
            start, k_start = start
            k0 = k_start if k0 is None else k0
        if not isinstance(start, HybridState):
            start = HybridState(np.asarray(pb.system.state_vector(start), dtype=float), None)
        k0 = 0 if k0 is None else int(k0)
    else:
        o = smap.orbit(dict(pb.x0), 1, transient=transient, flags=pb.flags0)
        if o.status != "ok":
            raise OrbitNotFound(f"the transient from x0 ends {o.status}: {o.failure}")
        start, k0 = o.state(0), transient
    q = smap.forcing_period_steps
    period = q if period is None and q else period
    if period is None:
        raise ParameterError("the forcing never repeats within 1000 strobe periods (q = 0): no periodic orbit; "
                             "choose parameters with f_mains/relay_hz rational")
    try:
        period = int(period)
    except (TypeError, ValueError):
        raise ParameterError(f"period must be a whole number of strobe periods, got {period!r}") from None
    return start, k0, period


def multiplier_change(a, b) -> float:
    """Largest distance between two multiplier sets, matched greedily (nearest first)."""
    b = list(b)
    worst = 0.0
    for m in sorted(a, key=lambda z: -abs(z)):
        j = int(np.argmin([abs(m - x) for x in b]))
        worst = max(worst, abs(m - b.pop(j)))
    return worst


def orbit_dataset(orbit: PeriodicOrbit, smap, pb, *, multiplier_error=math.nan, seconds=math.nan):
    """The dataset of a converged orbit: nodes (states, flags, signatures), multipliers, impacts."""
    import xarray as xr

    from ..storage.schema import ORBIT, ORBIT_SCALARS, flag_variable, state_variable
    system = smap.system
    n, k0 = orbit.period, orbit.k0
    T = smap.period
    t0 = smap.sample_time(k0) - smap.phase * T
    o = smap.orbit(orbit.nodes[0], n, t0=t0)       # the orbit's own events, one period
    rows = {v.name: v for v in ORBIT + ORBIT_SCALARS}
    mu = orbit.multipliers[np.argsort(-np.abs(orbit.multipliers))]
    ds = xr.Dataset(coords={
        "node": ("node", np.arange(n), {"units": "1", "long_name": f"strobe sample of the orbit, k = {k0} + node"}),
        "multiplier": ("multiplier", np.arange(mu.size), {"units": "1", "long_name": "Floquet multiplier, by modulus"}),
        "impact": ("impact", np.arange(o.impact_t.size), {"units": "1", "long_name": "contact in one period"})})
    for j, st in enumerate(system.states):
        var = state_variable(st, ("node",), ", at the orbit's strobe samples")
        ds[st.name] = ("node", np.array([s.y[j] for s in orbit.nodes]), var.attrs())
    for name in system.flag_names:
        var = flag_variable(name, ("node",))
        ds[var.name] = ("node", np.array([float((s.flags or {}).get(name, np.nan)) for s in orbit.nodes]),
                        var.attrs())

    def put(name, data):
        v = rows[name]
        ds[name] = (v.dims, np.asarray(data, dtype=v.dtype) if v.dtype is not str else np.asarray(data, dtype=str),
                    v.attrs())
    put("multiplier_abs", np.abs(mu))
    put("multiplier_arg", np.angle(mu))
    put("signature", [",".join(sig) for sig in orbit.signatures])
    put("impact_time", o.impact_t - t0)
    put("impact_velocity", o.impact_velocity)
    put("impact_phase", ((o.impact_t - t0) / T) % 1.0)
    put("period", n)
    put("impacts_per_period", orbit.impacts_per_period)
    put("stable", int(orbit.stable))
    put("newton_residual", orbit.residual)
    put("multiplier_error", multiplier_error)
    put("min_clearance", float(np.min(o.min_gap_per_step)) if o.n else math.nan)
    put("min_flight_clearance", float(np.min(o.min_flight_gap_per_step)) if o.n else math.nan)
    put("run_seconds", seconds)
    if orbit.reduced:      # a translation-invariant system (2-DOF: bar and rig shifted together)
        anchor = [s for s in system.state_names if s not in orbit.reduced][0]
        ds["advance_per_period"] = ((), orbit.advance, {
            "units": system.states[system.state_names.index(anchor)].unit,
            "long_name": f"shift of {anchor} along the system's translation over one period of the orbit "
                         f"(2-DOF: the rig; -advance is the progression into the soil)"})
        ds.attrs["reduced_coordinates"] = ", ".join(orbit.reduced)
        ds.attrs["reduced_coordinates_note"] = (f"solved with {anchor} = 0 at every node: the multipliers are those "
                                                f"of the reduced map (the translation's multiplier 1 removed)")
    from .._version import __version__
    ds.attrs.update({
        "title": f"{pb.name}: periodic orbit, period {n}", "k0": k0,
        "strobe_period_s": T, "forcing_period": smap.forcing_period_steps, "tol": smap.tol,
        "newton_iterations": orbit.iterations,
        "conditioning_multiple_shooting": orbit.conditioning.get("multiple_shooting", math.nan),
        "conditioning_single_shooting": orbit.conditioning.get("single_shooting", math.nan),
        "method": "Newton by multiple shooting over the strobe periods; exact Jacobians (variational "
                  "equations with saltation); multipliers: eigenvalues of the monodromy matrix",
        "bifurc_version": __version__,
        **cf_attrs(f"scene {pb.name}, periodic orbit of period {n}"),
        **pb.attrs()})
    return ds
