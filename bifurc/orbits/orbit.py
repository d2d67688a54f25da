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
from maps.parameters import ParameterError
from maps.poincare import StroboscopicMap
from maps.provenance import recorded

from ..run.inputs import analysis_inputs
from ..storage.grid import nearest_index
from ..storage.load import require_kind
from .dataset import orbit_dataset
from .method import Shooting
from .periodic import OrbitNotFound, find_periodic_orbit

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
def periodic_orbit(problem="thesis-1dof", method: Shooting | None = None, *, start=None, **options):
    """A periodic orbit of ``problem`` as an xarray Dataset (``bifurc_kind`` "orbit"): its nodes, its Floquet
    multipliers and their change at tol/100, its impacts.

    Parameters
    ----------
    problem : :class:`maps.Problem` or scene name
        What is integrated; its start state ``x0`` is integrated ``transient`` strobe periods to the first guess.
    method : :class:`bifurc.Shooting`, optional
        The period, tolerances and Newton's settings.
    start : HybridState, or (HybridState, k) from :func:`sweep_point`
        The first guess itself (instead of x0 and the transient), at sample ``k0``.
    **options
        Problem keywords (``preset``, ``params``, ``x0``, ``dc_law``, ...) and :class:`bifurc.Shooting` fields by
        name.

    Raises :class:`OrbitNotFound` (with the reason) when Newton does not converge, and
    :class:`~maps.parameters.ParameterError` for bad input (one line, naming the argument).
    """
    pb, m, _ = analysis_inputs(problem, Shooting, method, None, options, runs=False)
    return _periodic_orbit(pb, m, start)


def _periodic_orbit(pb, m: Shooting, start):
    period, k0, transient, tol, newton_tol, max_iter, error = (m.period, m.k0, m.transient, m.tol, m.newton_tol,
                                                                m.max_iter, m.error)
    clock = _time.perf_counter()
    smap = StroboscopicMap(pb, tol=tol)
    newton_tol = 10 * tol if newton_tol is None else newton_tol
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
