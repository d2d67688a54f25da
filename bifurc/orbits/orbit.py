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
from maps.provenance import recorded

from ..storage.grid import nearest_index
from ..storage.load import require_kind
from .dataset import orbit_dataset
from .periodic import OrbitNotFound, find_periodic_orbit

__all__ = ["periodic_orbit", "sweep_point", "orbit_dataset", "first_guess", "multiplier_change", "OrbitNotFound"]


def sweep_point(ds, value, *, sample: int = -1, branch=None):
    """``(HybridState, sample index k)`` of a stored sweep at the swept parameter's ``value``
    (nearest stored value), recorded sample ``sample`` (default: the last), ready to start a
    step, a simulation or :func:`periodic_orbit` exactly there.  A value outside the grid is refused,
    one half a grid step or more from every grid value warned about (:func:`bifurc.storage.grid.nearest_index`)."""
    require_kind(ds, "diagram", "sweep_point")
    par = ds.attrs["swept_parameter"]
    d = ds.sel(branch=branch) if branch is not None else ds.isel(branch=0)
    d = d.isel({par: nearest_index(ds[par].values, value, par, ds[par].attrs.get("units", ""))})
    n = d.sizes["sample"]
    if not -n <= int(sample) < n:
        raise ParameterError(f"sample = {sample}: the sweep recorded {n} samples per value; allowed {-n} to {n - 1}")
    k = int(np.arange(n)[sample])
    states = [name for name in d.data_vars if d[name].dims == ("sample",) and not name.startswith("flag_")]
    y = np.array([float(d[s].values[k]) for s in states])
    flags = {n[5:]: float(d[n].values[k]) for n in d.data_vars if n.startswith("flag_")}
    if not np.all(np.isfinite(y)):
        raise ParameterError(f"the sweep has no state at {par} = {value} sample {k} (escaped or not computed)")
    return HybridState(y, flags or None), int(d.transient_used.values) + k


@recorded("bifurc.periodic_orbit")
def periodic_orbit(scene, *, params=None, preset=None, period: int | None = None, x0=None, start=None,
                   k0: int | None = None, transient: int = 300, tol: float = 1e-12, newton_tol: float | None = None,
                   max_iter: int = 40, error: bool = True, circuit=None, ac_sign=None, dc_law=None,
                   soil=None, compaction=None):
    """A periodic orbit of ``scene`` (name, Scene, HybridSystem or :class:`maps.Problem`) as an xarray Dataset.

    Parameters
    ----------
    period : int
        In strobe periods (relay periods for relay scenes); a multiple of the forcing period q
        (default: q).
    x0 : dict
        Initial state; integrated ``transient`` strobe periods to the first guess (default 300, as
        `bifurc orbit --transient` and :func:`bifurc.continue_orbit`).
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
