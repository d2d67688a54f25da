"""The orbit and branch Datasets (kinds "orbit" and "branch"): every variable a row of
:mod:`bifurc.storage.schema` (:data:`~bifurc.storage.schema.ORBIT`, ``ORBIT_SCALARS``, ``BRANCH``,
``SPECIAL``, ``CURVE``), written by :func:`bifurc.storage.build.put`; ``param_*`` and the model options
by :meth:`maps.Problem.attrs`.
"""
from __future__ import annotations

import math

import numpy as np

from maps.provenance import cf_attrs

from .._version import __version__
from ..storage.build import coord, dataset, put
from ..storage.schema import (BRANCH, CURVE, CURVE_COORDS, ORBIT, ORBIT_SCALARS, SPECIAL,
                              SPECIAL_KINDS, Variable, advance_variable, curve_parameter, flag_variable,
                              state_variable)

_ORBIT_ROWS = {v.name: v for v in ORBIT + ORBIT_SCALARS}
_ROWS = {v.name: v for v in BRANCH + SPECIAL + CURVE}
_NODE = Variable("node", ("node",), np.int64, 0, "1", "strobe sample of the orbit, k = k0 + node")
_MULTIPLIER = Variable("multiplier", ("multiplier",), np.int64, 0, "1", "Floquet multiplier, by modulus")
_IMPACT = Variable("impact", ("impact",), np.int64, 0, "1", "contact in one period")
_POINT = Variable("point", ("point",), np.int64, 0, "1", "branch point, in arclength order")
_SPECIAL = Variable("special", ("special",), np.int64, 0, "1", "located special point")


def _by_modulus(mu):
    """(moduli, arguments) of the multipliers ``mu``, largest modulus first."""
    mu = np.asarray(mu)[np.argsort(-np.abs(mu))]
    return np.abs(mu), np.angle(mu)


def _put_advance(ds, system, anchor: int, data, dims) -> None:
    """The shift per period of a translation-invariant orbit (its anchor state ``anchor``)."""
    var = advance_variable(system.states[anchor], dims)
    ds[var.name] = (dims, np.asarray(data, dtype=float) if dims else float(data), var.attrs())


def _put_nodes(ds, system, nodes, dims, n_node) -> None:
    """States and mode flags at the strobe nodes: ``nodes`` one list of HybridStates per row (NaN-padded to
    ``n_node``), or one list for a single orbit (``dims`` ("node",))."""
    rows = [nodes] if dims == ("node",) else nodes
    columns = [(state_variable(st, dims, ", at the orbit's strobe samples"), lambda s, j=j: s.y[j])
               for j, st in enumerate(system.states)]
    columns += [(flag_variable(f, dims), lambda s, f=f: float((s.flags or {}).get(f, np.nan)))
                for f in system.flag_names]
    for var, get in columns:
        data = np.full((len(rows), n_node), np.nan)
        for r, row in enumerate(rows):
            data[r, :len(row)] = [get(s) for s in row]
        ds[var.name] = (var.dims, data[0] if dims == ("node",) else data, var.attrs())


def orbit_dataset(orbit, smap, pb, *, multiplier_error=math.nan, seconds=math.nan):
    """The dataset of a converged orbit: nodes (states, flags, signatures), multipliers, impacts."""
    system = smap.system
    n, k0, T = orbit.period, orbit.k0, smap.period
    t0 = smap.sample_time(k0) - smap.phase * T
    o = smap.orbit(orbit.nodes[0], n, t0=t0)       # the orbit's own events, one period
    mu_abs, mu_arg = _by_modulus(orbit.multipliers)
    ds = dataset("orbit", {"node": coord(_NODE, n, long_name=f"strobe sample of the orbit, k = {k0} + node"),
                           "multiplier": coord(_MULTIPLIER, mu_abs.size), "impact": coord(_IMPACT, o.impact_time.size)})
    _put_nodes(ds, system, orbit.nodes, ("node",), n)
    columns = {"multiplier_abs": mu_abs, "multiplier_arg": mu_arg,
               "signature": [",".join(sig) for sig in orbit.signatures],
               "impact_time": o.impact_time - t0, "impact_velocity": o.impact_velocity,
               "impact_phase": ((o.impact_time - t0) / T) % 1.0, "period": n,
               "impacts_per_period": orbit.impacts_per_period, "stable": int(orbit.stable),
               "newton_residual": orbit.residual, "multiplier_error": multiplier_error,
               "min_clearance": float(np.min(o.min_clearance_per_step)) if o.n else math.nan,
               "min_flight_clearance": float(np.min(o.min_flight_clearance_per_step)) if o.n else math.nan,
               "run_seconds": seconds}
    for name, data in columns.items():
        put(ds, _ORBIT_ROWS[name], data)
    if orbit.reduced:      # a translation-invariant system (2-DOF: bar and rig shifted together)
        anchor = [s for s in system.state_names if s not in orbit.reduced][0]
        _put_advance(ds, system, system.state_names.index(anchor), orbit.advance, ())
        ds.attrs["reduced_coordinates"] = ", ".join(orbit.reduced)
        ds.attrs["reduced_coordinates_note"] = (f"solved with {anchor} = 0 at every node: the multipliers are those "
                                                f"of the reduced map (the translation's multiplier 1 removed)")
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


def _point_columns(points, clearances, n_mu) -> dict:
    """The BRANCH rows of the branch points [(branch index, BranchPoint)] in arclength order."""
    mus = [_by_modulus(pt.multipliers) for _, pt in points]
    return {"branch_id": [i for i, _ in points], "period": [len(pt.nodes) for _, pt in points],
            "multiplier_abs": np.array([m[0] for m in mus]).reshape(len(points), n_mu),
            "multiplier_arg": np.array([m[1] for m in mus]).reshape(len(points), n_mu),
            "stable": [int(pt.stable) for _, pt in points],
            "impacts_per_period": [pt.impacts_per_period for _, pt in points],
            "min_clearance": [c[0] for c in clearances], "min_flight_clearance": [c[1] for c in clearances],
            "signature": [";".join(",".join(s) for s in pt.signatures) for _, pt in points],
            "newton_iterations": [pt.iterations for _, pt in points],
            "newton_residual": [pt.residual for _, pt in points],
            "section_phase": [pt.phase for _, pt in points], "section_k0": [pt.k0 for _, pt in points]}


def _special_columns(branches, n_mu) -> dict:
    """The SPECIAL rows of every branch's special points, branch after branch."""
    specials = [(i, sp) for i, br in enumerate(branches) for sp in br.special]
    offsets = np.cumsum([0] + [len(br.points) for br in branches])
    smu = [_by_modulus(sp.point.multipliers) if sp.point is not None else (np.full(n_mu, np.nan),) * 2
           for _, sp in specials]
    return {"special_kind": [SPECIAL_KINDS.index(sp.kind) for _, sp in specials],
            "special_value": [sp.p for _, sp in specials], "special_tolerance": [sp.tolerance for _, sp in specials],
            "special_test_function": [sp.test_function for _, sp in specials],
            "special_test_value": [sp.test_value for _, sp in specials],
            "special_point": [int(offsets[i] + max(sp.index, 0)) for i, sp in specials],
            "special_branch": [i for i, _ in specials],
            "special_multiplier_abs": np.array([m[0] for m in smu]).reshape(len(specials), n_mu),
            "special_multiplier_arg": np.array([m[1] for m in smu]).reshape(len(specials), n_mu),
            "special_multiplier_error": [sp.multiplier_error for _, sp in specials],
            "special_note": [sp.note for _, sp in specials]}


def branch_dataset(branches, problem, pb, *, clearances, curves=(), seconds=math.nan):
    """The dataset of continued branches: points in arclength order, branch after branch;
    ``clearances``: (min_clearance, min_flight_clearance) of every point in that order."""
    system, param = problem.smap.system, problem.param
    p = system.parameter(param)
    points = [(i, pt) for i, br in enumerate(branches) for pt in br.points]
    n_node, n_mu = max([br.period for br in branches] + [1]), problem.d
    columns = {**_point_columns(points, clearances, n_mu), **_special_columns(branches, n_mu)}
    ds = dataset("branch", {"point": coord(_POINT, len(points)), "node": coord(_NODE, n_node),
                            "multiplier": coord(_MULTIPLIER, n_mu),
                            "special": coord(_SPECIAL, len(columns["special_kind"]))})
    ds[param] = ("point", np.array([pt.p for _, pt in points], float),
                 {"units": p.unit, "long_name": f"{param}: {p.long_name}" if getattr(p, "long_name", "") else param})
    _put_nodes(ds, system, [pt.nodes for _, pt in points], ("point", "node"), n_node)
    for name in [v.name for v in BRANCH]:
        put(ds, _ROWS[name], columns[name], param=param, units=p.unit)
    if problem.co.a is not None:
        _put_advance(ds, system, problem.co.a, [pt.advance for _, pt in points], ("point",))
    for name in [v.name for v in SPECIAL]:
        put(ds, _ROWS[name], columns[name], param=param, units=p.unit)
    if curves:
        _put_curves(ds, curves, system)
    ds.attrs.update({
        "title": f"{pb.name}: branch of periodic orbits in {param}", "scene": pb.name,
        "continuation_parameter": param, "continuation_parameter_units": p.unit, "k0": problem.k0,
        "strobe_period_s": problem.smap.period_for(dict(problem.smap.params, **{param: problem.p_ref})),
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
        **cf_attrs(f"scene {pb.name}, continuation in {param}"),
        **pb.attrs(skip=(param,))})
    if problem.co.a is not None:
        ds.attrs["reduced_coordinates"] = ", ".join(problem.co.names)
    return ds


def _put_curves(ds, curves, system) -> None:
    """Two-parameter curves along ``curve_point`` (their kinds and stop reasons along ``curve``): schema.CURVE."""
    p1, p2 = curves[0].params
    n_points = sum(len(c.p1) for c in curves)
    ds.coords.update({v.name: coord(v, n) for v, n in zip(CURVE_COORDS, (n_points, len(curves)))})
    columns = {"curve_id": np.concatenate([np.full(len(c.p1), i) for i, c in enumerate(curves)]),
               "curve_residual": np.concatenate([np.asarray(c.residual, float) for c in curves]),
               "curve_kind": [SPECIAL_KINDS.index(c.kind) for c in curves],
               "curve_special": [c.start for c in curves], "curve_stop_reason": [c.stop_reason for c in curves]}
    put(ds, _ROWS["curve_id"], columns["curve_id"])
    for name, attr in ((p1, "p1"), (p2, "p2")):
        put(ds, curve_parameter(name), np.concatenate([np.asarray(getattr(c, attr), float) for c in curves]),
            units=system.parameter(name).unit)
    for name in ("curve_residual", "curve_kind", "curve_special", "curve_stop_reason"):
        put(ds, _ROWS[name], columns[name])
    ds.attrs["curve_parameters"] = f"{p1} {p2}"
    ds.attrs["curve_codim2"] = "; ".join(f"{kind} on curve {i}: ({p1}, {p2}) = ({a:.17g}, {b:.17g}) +- "
                                         f"{_rounded_up(tol):.2g}" + (" (the bracket: its re-location at tol/100 "
                                                                      "failed, not a measured bound)"
                                                                      if j in c.unmeasured else "")
                                         for i, c in enumerate(curves)
                                         for j, (kind, a, b, tol) in enumerate(c.special))


def _rounded_up(x: float) -> float:
    """``x`` rounded up to two significant digits (a stated tolerance printed never below its value)."""
    if not (math.isfinite(x) and x > 0):
        return x
    unit = 10.0 ** (math.floor(math.log10(x)) - 1)
    return math.ceil(x / unit * (1 - 1e-12)) * unit
