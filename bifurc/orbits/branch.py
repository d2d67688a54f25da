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

from maps.parameters import ParameterError, validate_value
from maps.impacts import impact_log
from maps.poincare import StroboscopicMap
from maps.problem import problem
from maps.provenance import cf_attrs, recorded

from .arclength import continue_branch
from .continuation import ContinuationProblem, flags_of, in_section
from .orbit import first_guess, multiplier_change
from .periodic import OrbitNotFound, find_periodic_orbit, monodromy
from .special_points import LOCATED_KINDS

__all__ = ["continue_orbit", "branch_dataset"]


def _check_param(smap, system, param, values):
    if param not in system.param_names:
        raise ParameterError(f"param {param!r} is not a parameter of {system.name!r}; its parameters: "
                             f"{', '.join(system.param_names)}")
    if param == system.strobe_parameter and system.forcing_frequencies(values):
        raise ParameterError(f"{param} cannot be continued: the system's other forcing repeats in strobe periods "
                             f"only at isolated values of {param} (the thesis model: q = 17 at 8.5 Hz, over 1000 "
                             f"for most values near it), so no continuous branch exists; continue in another "
                             f"parameter at a fixed {param}")
    moved = dict(values, **{param: values[param] * (1 + 1e-6) + 1e-9})
    if smap.period_for(moved) != smap.period_for(values):
        raise ParameterError(f"param {param!r} sets the strobe period: the map's derivative at a fixed sample "
                             f"index would move its start time too, which is not implemented; continue in another "
                             f"parameter (or rescale time so that the period is fixed)")


@recorded("bifurc.continue_orbit")
def continue_orbit(scene, param: str, span, *, params=None, preset=None, period: int | None = None, x0=None,
                   start=None, k0: int | None = None, transient: int = 300, tol: float = 1e-12,
                   newton_tol: float | None = None, step: float = 0.02, max_step: float = 0.1,
                   max_points: int = 200, branch_switch: bool = False, error: bool = True, progress=None,
                   param2: str | None = None, span2=None, circuit=None, ac_sign=None, dc_law=None, soil=None,
                   compaction=None):
    """The branch of periodic orbits through the orbit at ``param = span[0]``, followed toward
    ``span[1]``, as an xarray Dataset (dimension ``point``, not indexed by the parameter, so that
    folds fit; special points along ``special``).

    Parameters
    ----------
    param : str
        A numeric parameter of the scene.  Refused: ``relay_hz`` under mains forcing (no continuous
        branch exists) and any parameter that sets the strobe period.
    span : (float, float)
        Start value and end value; the branch stops where it leaves the interval between them.
    period, x0, start, k0, transient, preset, circuit, ac_sign, dc_law, soil, compaction : as in
        :func:`periodic_orbit`.
    tol, newton_tol : float
        Integration tolerance; largest scaled shooting residual accepted (default 10 tol).
    step, max_step : float
        First and largest arclength step, in the scaled unknowns (states by the orbit's magnitude,
        the parameter by the span's length).
    max_points : int
        Branch points per branch at most.
    branch_switch : bool
        Follow the doubled branch from each located period doubling.
    error : bool
        At each special point, solve the orbit again at tol/100 and store the multipliers' change.
    progress : callable(str), optional
        Called with a one-line description of each new point.
    param2, span2 : str, (float, float)
        A second parameter: the branch is computed at ``param2 = span2[0]`` and each located fold,
        period doubling and grazing is continued in (param, param2) toward ``span2[1]``
        (:mod:`bifurc.orbits.curves`), staying within ``span`` for ``param``; the curves are stored along
        ``curve_point``.
    """
    clock = _time.perf_counter()
    a, b = _span("span", span, "from, to")
    values_in = dict(params or {}, **{param: a})
    if param2 is not None:
        if param2 == param:
            raise ParameterError(f"param2 must differ from param ({param!r})")
        a2, b2 = _span("span2", span2, "from2, to2")
        values_in[param2] = a2
    pb = problem(scene, preset, values_in, x0, circuit=circuit, ac_sign=ac_sign, dc_law=dc_law, soil=soil,
                 compaction=compaction)
    system, values = pb.system, dict(pb.values)
    smap = StroboscopicMap(pb, tol=tol)
    _check_param(smap, system, param, values)
    system.validate(dict(values, **{param: b}))             # the end value must be allowed too
    if param2 is not None:
        _check_param(smap, system, param2, values)
        system.validate(dict(values, **{param2: b2}))
    max_points = int(validate_value("max_points", max_points, 2, 100_000))
    step = validate_value("step", step, 0.0, 1.0, low_open=True)
    max_step = validate_value("max_step", max_step, step, 10.0)
    newton_tol = 10 * tol if newton_tol is None else validate_value("newton_tol", newton_tol, 0.0, 1.0, low_open=True)
    transient = int(validate_value("transient", transient, 0, 1e7))
    start, k0, period = first_guess(smap, pb, transient=transient, start=start, k0=k0, period=period)
    orbit = find_periodic_orbit(smap, start, period, k0=k0, tol=newton_tol)
    say = (lambda pt, label: progress(_describe(pt, label, param))) if progress else None
    cont = ContinuationProblem(smap, param, period, k0, scale=orbit.scale, p_scale=abs(b - a), p_ref=a,
                                  tol=newton_tol)
    branches = [continue_branch(cont, orbit, a, b, step=step, max_step=max_step, max_points=max_points,
                                progress=(lambda pt: say(pt, "main")) if say else None)]
    if branch_switch:
        for sp in [s for s in branches[0].special if s.kind == "period_doubling" and s.point is not None]:
            branches.append(_switch(smap, cont, sp, (a, b), step, max_step, max_points, say))
    curves = []
    if param2 is not None:
        curves = _curves(cont, branches, param2, (a2, b2), (a, b), max_points, progress)
    if error:
        for br in branches:
            for sp in br.special:
                sp.multiplier_error = _multiplier_error(system, values, param, sp, br, tol, newton_tol)
    return branch_dataset(branches, cont, pb, curves=curves, seconds=_time.perf_counter() - clock)


def _curves(problem, branches, param2, span2, span, max_points, progress):
    """Each located fold, period doubling and grazing of the branches, continued in (param, param2)."""
    from .curves import CurveProblem, follow_curve
    out, index = [], 0
    for br in branches:
        for sp in br.special:
            index += 1
            if sp.kind not in ("fold", "period_doubling", "grazing") or sp.point is None:
                continue
            base = problem if br.period == problem.n else ContinuationProblem(
                problem.smap, problem.param, br.period, br.k0, scale=problem.scale, p_scale=problem.p_scale,
                p_ref=problem.p_ref, tol=problem.tol)
            with in_section(base, sp.point):
                cp = CurveProblem(base, sp.kind, param2, span2[0], abs(span2[1] - span2[0]),
                                  node=sp.data.get("node", 0))
                w0 = cp.pack(sp.point.nodes, sp.p, span2[0], sp.data.get("t_g"))
                curve = follow_curve(cp, w0, flags_of(sp.point), span2[1], span, max_points=max_points)
                problem.smap.set_params(**{param2: span2[0]})
            curve.start = index - 1
            out.append(curve)
            if progress:
                progress(f"{sp.kind} curve from {problem.param} = {sp.p:.8g}: {len(curve.p1)} points; "
                         f"{curve.stop_reason}")
    return out


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
    mu = float(np.max(np.abs(pt.multipliers)))
    return (f"{label} point: {param} = {pt.p:.8g}, {'stable' if pt.stable else 'unstable'} "
            f"(max |mu| {mu:.4g}), {pt.impacts} impact{'' if pt.impacts == 1 else 's'} per period, "
            f"{pt.iterations} Newton iterations")


def _switch(smap, problem, sp, span, step, max_step, max_points, say):
    """Follow the period-2n branch born at the period doubling ``sp``: start on the doubled orbit,
    tangent along the multiplier -1's eigenvector v at node 0 (v_{j+1} = J_j v_j, then -v)."""
    pt = sp.point
    smap.phase = pt.phase                     # the section the period doubling was located in
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
    return min(at_nodes + flight + ([0.0] if pt.impacts else [])), low


def branch_dataset(branches, problem, pb, *, curves=(), seconds=math.nan):
    """The dataset of continued branches: points in arclength order, branch after branch."""
    import xarray as xr

    from .._version import __version__
    from ..storage.schema import BRANCH, SPECIAL, SPECIAL_KINDS, flag_variable, state_variable
    system, param = problem.smap.system, problem.param
    unit = system.parameter(param).unit
    points = [(i, pt) for i, br in enumerate(branches) for pt in br.points]
    specials = [(i, br, sp) for i, br in enumerate(branches) for sp in br.special]
    offsets = np.cumsum([0] + [len(br.points) for br in branches])
    n_node = max([br.period for br in branches] + [1])
    n_mu = problem.d
    base = dict(pb.values)
    ds = xr.Dataset(coords={
        "point": ("point", np.arange(len(points)), {"units": "1", "long_name": "branch point, in arclength order"}),
        "node": ("node", np.arange(n_node), {"units": "1", "long_name": "strobe sample of the orbit, k = k0 + node"}),
        "multiplier": ("multiplier", np.arange(n_mu), {"units": "1", "long_name": "Floquet multiplier, by modulus"}),
        "special": ("special", np.arange(len(specials)), {"units": "1", "long_name": "located special point"})})
    p_attrs = {"units": unit, "long_name": f"{param}: {system.parameter(param).long_name}"
               if getattr(system.parameter(param), "long_name", "") else param}
    ds[param] = ("point", np.array([pt.p for _, pt in points], float), p_attrs)
    for j, st in enumerate(system.states):
        var = state_variable(st, ("point", "node"), ", at the orbit's strobe samples")
        data = np.full((len(points), n_node), np.nan)
        for r, (_, pt) in enumerate(points):
            data[r, :len(pt.nodes)] = [s.y[j] for s in pt.nodes]
        ds[st.name] = (var.dims, data, var.attrs())
    for name in system.flag_names:
        var = flag_variable(name, ("point", "node"))
        data = np.full((len(points), n_node), np.nan)
        for r, (_, pt) in enumerate(points):
            data[r, :len(pt.nodes)] = [float((s.flags or {}).get(name, np.nan)) for s in pt.nodes]
        ds[var.name] = (var.dims, data, var.attrs())
    rows = {v.name: v for v in BRANCH + SPECIAL}

    def put(name, data, **attrs):
        v = rows[name]
        units = unit if v.units == "<param>" else v.units
        arr = np.asarray(data, dtype=str) if v.dtype is str else np.asarray(data, dtype=v.dtype)
        ds[name] = (v.dims, arr, v.attrs(units=units, long_name=v.long_name.format(param=param), **attrs))

    def by_modulus(mu):
        mu = np.asarray(mu)[np.argsort(-np.abs(mu))]
        return np.abs(mu), np.angle(mu)
    clear = [_clearances(system, dict(base, **{param: pt.p}), pt) for _, pt in points]
    put("branch_id", [i for i, _ in points])
    put("period", [len(pt.nodes) for _, pt in points])
    mus = [by_modulus(pt.multipliers) for _, pt in points]
    put("multiplier_abs", np.array([m[0] for m in mus]).reshape(len(points), n_mu))
    put("multiplier_arg", np.array([m[1] for m in mus]).reshape(len(points), n_mu))
    put("stable", [int(pt.stable) for _, pt in points])
    put("impacts_per_period", [pt.impacts for _, pt in points])
    put("min_clearance", [c[0] for c in clear])
    put("min_flight_clearance", [c[1] for c in clear])
    put("signature", [";".join(",".join(s) for s in pt.signatures) for _, pt in points])
    put("newton_iterations", [pt.iterations for _, pt in points])
    put("newton_residual", [pt.residual for _, pt in points])
    put("section_phase", [pt.phase for _, pt in points])
    put("section_k0", [pt.k0 for _, pt in points])
    if problem.co.a is not None:
        anchor = system.state_names[problem.co.a]
        ds["advance_per_period"] = ("point", np.array([pt.advance for _, pt in points]), {
            "units": system.states[problem.co.a].unit,
            "long_name": f"shift of {anchor} along the system's translation over one period of the orbit"})
    put("special_kind", [SPECIAL_KINDS.index(sp.kind) for _, _, sp in specials])
    put("special_value", [sp.p for _, _, sp in specials])
    put("special_tolerance", [sp.tolerance for _, _, sp in specials])
    put("special_test_function", [sp.test_function for _, _, sp in specials])
    put("special_test_value", [sp.test_value for _, _, sp in specials])
    put("special_point", [int(offsets[i] + max(sp.index, 0)) for i, _, sp in specials])
    put("special_branch", [i for i, _, _ in specials])
    smu = [by_modulus(sp.point.multipliers) if sp.point is not None else (np.full(n_mu, np.nan),) * 2
           for _, _, sp in specials]
    put("special_multiplier_abs", np.array([m[0] for m in smu]).reshape(len(specials), n_mu))
    put("special_multiplier_arg", np.array([m[1] for m in smu]).reshape(len(specials), n_mu))
    put("special_multiplier_error", [sp.multiplier_error for _, _, sp in specials])
    put("special_note", [sp.note for _, _, sp in specials])
    if curves:
        _put_curves(ds, curves, system)
    name = pb.name
    ds.attrs.update({
        "title": f"{name}: branch of periodic orbits in {param}", "scene": name, "continuation_parameter": param,
        "continuation_parameter_units": unit, "k0": problem.k0, "strobe_period_s": problem.smap.period,
        "tol": problem.smap.tol, "newton_tol": problem.tol,
        "branch_labels": " | ".join(br.label for br in branches),
        "branch_stop_reasons": " | ".join(br.stop_reason for br in branches),
        "newton_iterations_total": int(sum(br.newton_iterations for br in branches)),
        "run_seconds": seconds,
        "method": "pseudo-arclength continuation of the multiple-shooting system (Newton on the bordered system, "
                  "exact Jacobians from variational equations with saltation); special points located by Illinois "
                  "false position on test functions along the arclength; grazing by Newton on the augmented "
                  "system orbit + (gap, gap rate) = 0 at the grazing time",
        "bifurc_version": __version__,
        **cf_attrs(f"scene {name}, continuation in {param}"),
        **pb.attrs(skip=(param,))})
    if problem.co.a is not None:
        ds.attrs["reduced_coordinates"] = ", ".join(problem.co.names)
    return ds



def _put_curves(ds, curves, system):
    """Two-parameter curves along ``curve_point`` (their kinds and stop reasons along ``curve``)."""
    from .curves import CURVE_KINDS
    p1, p2 = curves[0].params
    ids = np.concatenate([np.full(len(c.p1), i) for i, c in enumerate(curves)]).astype(np.int16)
    ds.coords["curve_point"] = ("curve_point", np.arange(ids.size), {"units": "1", "long_name": "point of a curve"})
    ds.coords["curve"] = ("curve", np.arange(len(curves)), {"units": "1", "long_name": "two-parameter curve"})
    ds["curve_id"] = ("curve_point", ids, {"units": "1", "long_name": "curve the point belongs to"})
    for name, attr in ((p1, "p1"), (p2, "p2")):
        ds[f"curve_{name}"] = ("curve_point", np.concatenate([np.asarray(getattr(c, attr), float) for c in curves]),
                               {"units": system.parameter(name).unit, "long_name": f"{name} along the curve"})
    ds["curve_residual"] = ("curve_point", np.concatenate([np.asarray(c.residual, float) for c in curves]),
                            {"units": "1", "long_name": "largest scaled residual of the defining system"})
    ds["curve_kind"] = ("curve", np.array([CURVE_KINDS.index(c.kind) for c in curves], np.int8),
                        {"units": "1", "long_name": "what the curve continues", "flag_values":
                         np.arange(len(CURVE_KINDS), dtype=np.int8), "flag_meanings": " ".join(CURVE_KINDS)})
    ds["curve_special"] = ("curve", np.array([c.start for c in curves], np.int32),
                           {"units": "1", "long_name": "the special point the curve starts from"})
    ds["curve_stop_reason"] = ("curve", np.array([c.stop_reason for c in curves], dtype=str),
                               {"units": "1", "long_name": "why the curve stopped"})
    ds.attrs["curve_parameters"] = f"{p1} {p2}"
