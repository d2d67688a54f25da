"""Continue a periodic orbit of a scene or system in one parameter and describe the branch as a dataset.

>>> ds = bifurc.continue_orbit("impact-oscillator", "e", (0.2, -0.1))
>>> ds.bifurc_special()                     # doctest: +SKIP
>>> bifurc.plot_branch(ds)

The orbit is found by Newton's method (:mod:`bifurc.orbits.periodic`) at the span's first value and
followed by pseudo-arclength continuation (:mod:`bifurc.orbits.continuation`) through folds, stable and
unstable parts alike; folds, period doublings, Neimark-Sacker points and grazings are located and
stored with their tolerance and test function.  With ``branch_switch=True`` the doubled branch
is followed from each period doubling.
"""
from __future__ import annotations

import math
import time as _time
from types import SimpleNamespace

import numpy as np

from maps.parameters import ParameterError
from maps.impacts import impact_log
from maps.poincare import StroboscopicMap
from maps.provenance import recorded

from .arclength import continue_branch
from .continuation import ContinuationProblem, flags_of, in_section
from ..storage.schema import CURVE_KINDS
from ..run.inputs import analysis_inputs
from .dataset import branch_dataset
from .method import PALC
from .orbit import first_guess, multiplier_change
from .periodic import OrbitNotFound, find_periodic_orbit, monodromy
from .relocate import RESOLUTION, measure_codim2, relocate
from .special_points import LOCATED_KINDS

def _check_param(smap, system, param, values):
    """A continuable parameter (its name was checked by ``Problem.parameter``): not the strobe clock under another
    forcing."""
    if param == system.strobe_parameter and system.forcing_frequencies(values):
        raise ParameterError(f"{param} cannot be continued: the system's other forcing repeats in strobe periods "
                             f"only at isolated values of {param} (the thesis model: q = 17 at 8.5 Hz, over 1000 "
                             f"for most values near it), so no continuous branch exists; continue in another "
                             f"parameter at a fixed {param}")


def _sets_period(smap, param) -> bool:
    """``param`` moves the strobe period (the map's derivative then moves the sample instants too:
    :meth:`maps.StroboscopicMap.linearize`)."""
    return smap.period_derivative(param) != 0.0 or param == smap.system.strobe_parameter


@recorded("bifurc.continue_orbit")
def continue_orbit(problem="thesis-1dof", param: str = "V", span=None, method: PALC | None = None, *, start=None,
                   param2: str | None = None, span2=None, progress=None, **options):
    """The branch of periodic orbits through the orbit at ``param = span[0]``, followed toward
    ``span[1]``, as an xarray Dataset (dimension ``point``, not indexed by the parameter, so that
    folds fit; special points along ``special``).

    Parameters
    ----------
    problem : :class:`maps.Problem` or scene name
        What is integrated; its start state ``x0`` is integrated ``transient`` strobe periods to the first guess.
    param : str
        A numeric parameter of the scene, the one that sets the strobe period included (the forcing
        frequency ``Omega`` of a harmonically forced system: the sample instants move with it).
        Refused: ``relay_hz`` under mains forcing (no continuous branch exists).
    span : (float, float)
        Start value and end value; the branch stops where it leaves the interval between them.
    method : :class:`bifurc.PALC`, optional
        Steps, points, branch switching, and the shooting settings of the first orbit (period, k0, transient,
        tolerances).
    start : HybridState, or (HybridState, k) from :func:`sweep_point`
        The first guess itself (instead of x0 and the transient), at sample ``k0``.
    param2, span2 : str, (float, float)
        A second parameter: the branch is computed at ``param2 = span2[0]`` and each located fold,
        period doubling, Neimark-Sacker point and grazing is continued in (param, param2) toward ``span2[1]``
        (:mod:`bifurc.orbits.curves`), staying within ``span`` for ``param``; the curves are stored along
        ``curve_point``.
    progress : callable(str), optional
        Called with a one-line description of each new point.
    **options
        Problem keywords (``preset``, ``params``, ``x0``, ``dc_law``, ...) and :class:`bifurc.PALC` fields by name.
    """
    pb, m, _ = analysis_inputs(problem, PALC, method, None, options, runs=False)
    return _continue_orbit(pb, param, span, m, start, param2, span2, progress)


def _continue_orbit(pb, param, span, m: PALC, start, param2, span2, progress):
    period, k0, transient, tol, newton_tol, step, max_step, max_points, branch_switch, error = (
        m.period, m.k0, m.transient, m.tol, m.newton_tol, m.step, m.max_step, m.max_points, m.branch_switch, m.error)
    clock = _time.perf_counter()
    a, b = _span("span", span, "from, to")
    for name in (param, param2):
        if name is not None:
            pb.parameter(name)     # an unknown name or a well input: one line, before any value is placed
    values_in = {param: a}
    if param2 is not None:
        if param2 == param:
            raise ParameterError(f"param2 must differ from param ({param!r})")
        a2, b2 = _span("span2", span2, "from2, to2")
        values_in[param2] = a2
    pb = pb.with_values(**values_in)
    system, values = pb.system, dict(pb.values)
    smap = StroboscopicMap(pb, tol=tol)
    _check_param(smap, system, param, values)
    system.validate(dict(values, **{param: b}))             # the end value must be allowed too
    if param2 is not None:
        _check_param(smap, system, param2, values)
        system.validate(dict(values, **{param2: b2}))
    newton_tol = 10 * tol if newton_tol is None else newton_tol
    start, k0, period = first_guess(smap, pb, transient=transient, start=start, k0=k0, period=period)
    if smap.forcing_period_steps and any(_sets_period(smap, name) for name in (param, param2) if name):
        k0 = k0 % smap.forcing_period_steps   # the same map; d t_k / dp = (k + phase) dT/dp stays small
    orbit = find_periodic_orbit(smap, start, period, k0=k0, tol=newton_tol)
    say = (lambda pt, label: progress(_describe(pt, label, param))) if progress else None
    cont = ContinuationProblem(smap, param, period, k0, scale=orbit.scale, p_scale=abs(b - a), p_ref=a, tol=newton_tol)
    branches = [continue_branch(cont, orbit, a, b, step=step, max_step=max_step, max_points=max_points,
                                progress=(lambda pt: say(pt, "main")) if say else None)]
    if branch_switch:
        for sp in [s for s in branches[0].special if s.kind == "period_doubling" and s.point is not None]:
            branches.append(_switch(smap, cont, sp, (a, b), step, max_step, max_points, say))
    curves = []
    if param2 is not None:
        measure = (system, tol, newton_tol) if error else None
        curves = _curves(cont, branches, param2, (a2, b2), (a, b), max_points, progress, measure)
    if error:
        _errors(system, values, param, branches, cont, tol, newton_tol)
    clear = [_clearances(system, dict(values, **{param: pt.p}), pt) for br in branches for pt in br.points]
    return branch_dataset(branches, cont, pb, clearances=clear, curves=curves, seconds=_time.perf_counter() - clock)


def _curves(problem, branches, param2, span2, span, max_points, progress, measure=None):
    """Each located fold, period doubling, Neimark-Sacker point and grazing of the branches, continued in
    (param, param2); with ``measure`` = (system, tol, newton_tol) the codimension-two points on them are
    stated with measured tolerances (:func:`bifurc.orbits.relocate.measure_codim2`)."""
    from .curves import CurveProblem, follow_curve
    out, index = [], 0
    for br in branches:
        for sp in br.special:
            index += 1
            if sp.kind not in CURVE_KINDS or sp.point is None:
                continue
            base = problem if br.period == problem.n else ContinuationProblem(
                problem.smap, problem.param, br.period, br.k0, scale=problem.scale, p_scale=problem.p_scale,
                p_ref=problem.p_ref, tol=problem.tol)
            with in_section(base, sp.point):
                cp = CurveProblem(base, sp.kind, param2, span2[0], abs(span2[1] - span2[0]),
                                  node=sp.data.get("node", 0))
                w0 = cp.pack(sp.point.nodes, sp.p, span2[0], _angle(sp) if sp.kind == "neimark_sacker"
                             else sp.data.get("t_g"))
                curve = follow_curve(cp, w0, flags_of(sp.point), span2[1], span, max_points=max_points)
                if measure is not None and curve.special:
                    measure_codim2(cp, curve, *measure)
                problem.smap = problem.smap.at({param2: span2[0]})
            curve.start = index - 1
            out.append(curve)
            if progress:
                progress(f"{sp.kind} curve from {problem.param} = {sp.p:.8g}: {len(curve.p1)} points; "
                         f"{curve.stop_reason}")
    return out


def _angle(sp) -> float:
    """The argument in (0, pi) of the located Neimark-Sacker point's multiplier pair nearest the unit circle."""
    mu = np.asarray(sp.point.multipliers)
    mu = mu[mu.imag > 0] if np.any(mu.imag > 0) else mu
    return float(abs(np.angle(mu[np.argmin(np.abs(np.abs(mu) - 1.0))])))


def _span(name, span, what):
    """Two different finite numbers, or a one-line error naming ``name``."""
    try:
        a, b = (float(v) for v in span)
    except (TypeError, ValueError):
        raise ParameterError(f"{name} must be two numbers ({what}), got {span!r}") from None
    if not (math.isfinite(a) and math.isfinite(b)) or a == b:
        raise ParameterError(f"{name} must be two different finite numbers ({what}), got {span!r}")
    return a, b


def _describe(pt, label, param) -> str:
    mu, n = float(np.max(np.abs(pt.multipliers))), pt.impacts_per_period
    return (f"{label} point: {param} = {pt.p:.8g}, {'stable' if pt.stable else 'unstable'} "
            f"(max |mu| {mu:.4g}), {n} impact{'' if n == 1 else 's'} per period, "
            f"{pt.iterations} Newton iterations")


def _switch(smap, problem, sp, span, step, max_step, max_points, say):
    """Follow the period-2n branch born at the period doubling ``sp``: start on the doubled orbit,
    tangent along the multiplier -1's eigenvector v at node 0 (v_{j+1} = J_j v_j, then -v)."""
    pt = sp.point
    smap = smap.at(phase=pt.phase)            # the section the period doubling was located in
    w, V = np.linalg.eig(monodromy(pt.jacobians))
    v = np.real(V[:, int(np.argmin(np.abs(w + 1.0)))])
    vs = []
    for J in pt.jacobians:
        vs.append(v / problem.scale)
        v = J @ v
    t = np.concatenate(vs + [-x for x in vs] + [np.zeros(1)])
    doubled = ContinuationProblem(smap, problem.param, 2 * problem.n, pt.k0, scale=problem.scale,
                                  p_scale=problem.p_scale, p_ref=problem.p_ref, tol=problem.tol)
    start = SimpleNamespace(nodes=list(pt.nodes) * 2)
    label = f"period-{2 * problem.n} from the period doubling at {problem.param} = {sp.p:.8g}"
    br = continue_branch(doubled, start, pt.p, span[1], tangent=t, step=step, max_step=max_step,
                         max_points=max_points, bounds=span, label=label,
                         progress=(lambda q: say(q, f"period-{2 * problem.n}")) if say else None)
    return br


def _errors(system, values, param, branches, cont, tol, newton_tol) -> None:
    """Each special point's multiplier error and measured tolerance (both from tol/100 re-runs)."""
    for br in branches:
        for sp in br.special:
            sp.multiplier_error = _multiplier_error(system, values, param, sp, br, tol, newton_tol)
            _measure_tolerance(system, values, param, sp, br, cont, tol, newton_tol)


def _measure_tolerance(system, values, param, sp, br, cont, tol, newton_tol) -> None:
    """A located point's tolerance as a measured bound: the larger of its own bracket (or Newton update) and
    |p - p2| + the re-location's bracket, p2 located again with the integration and Newton at tol/100 (the
    re-location's bracket at least RESOLUTION |p2|)."""
    if sp.kind not in LOCATED_KINDS or not math.isfinite(sp.tolerance):
        return
    p2, width2 = relocate(system, values, param, sp, br, cont, tol, newton_tol)
    if not math.isfinite(p2):
        sp.note = (sp.note + "; " if sp.note else "") + "tolerance not measured: the re-location at tol/100 failed"
        return
    own = max(width2 if math.isfinite(width2) else 0.0, RESOLUTION * abs(p2))
    sp.tolerance = max(sp.tolerance, abs(sp.p - p2) + own)
    sp.note = (sp.note + "; " if sp.note else "") + f"re-located at tol/100: {p2:.15g}"


def _multiplier_error(system, values, param, sp, br, tol, newton_tol) -> float:
    if sp.point is None or not math.isfinite(sp.tolerance) or sp.kind not in LOCATED_KINDS:
        return math.nan                 # an event that stopped the branch: the point is the last one before it
    tight = StroboscopicMap(system, dict(values, **{param: sp.p}), tol=tol / 100, phase=sp.point.phase)
    try:
        again = find_periodic_orbit(tight, sp.point.nodes[0], br.period, k0=sp.point.k0, tol=newton_tol)
    except OrbitNotFound:
        return math.nan
    return multiplier_change(sp.point.multipliers, again.multipliers)


def _crossings(pt):
    """A branch point's guard crossings as (name, t, state before) in time order."""
    return ((ev.name, ev.t, ev.y_minus) for evs in pt.events for ev in evs)


def _clearances(system, params, pt):
    """(smallest gap over nodes, impacts and flight minima; lowest flight minimum) of a branch point."""
    if system.gap is None:
        return math.nan, math.nan
    flight = list(impact_log(system, params, _crossings(pt))["flight_gap"])
    at_nodes = [system.gap(s.y, params)[0] for s in pt.nodes]
    low = min(flight) if flight else math.inf
    return min(at_nodes + flight + ([0.0] if pt.impacts_per_period else [])), low
