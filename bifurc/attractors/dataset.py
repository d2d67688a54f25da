"""The attractors Dataset (kind "attractors"): dims (the parameter, ``attractor``), plus ``node`` for the
attractors' strobe states and ``start`` for the fresh starts and where each went (basin pictures).
Every variable is a row of :data:`bifurc.storage.schema.ATTRACTOR`."""
from __future__ import annotations

import numpy as np

from maps.provenance import cf_attrs

from .._version import __version__
from ..codes import ClassCode
from ..storage.build import coord, dataset, put
from ..storage.schema import ATTRACTOR, ATTRACTOR_COORDS, ATTRACTOR_EVENTS, flag_variable, state_variable
from .census import OUTCOMES, wilson
from .eventual import eventual_fractions, saddle_groups

__all__ = ["to_dataset", "attractor_count", "eventual_text", "OUTCOME_CODES"]

#: the class code stored for each outcome entry
OUTCOME_CODES = {"escaped": ClassCode.ESCAPED, "not_converged": ClassCode.NOT_CONVERGED, "failed": ClassCode.FAILED,
                 "neutral": ClassCode.NOT_CONVERGED, "transient": ClassCode.NOT_CONVERGED}
assert list(OUTCOME_CODES) == list(OUTCOMES), "one class code per outcome, in the outcomes' order"


def attractor_count(ds) -> int:
    """The distinct attractors an attractors Dataset holds: ids present at some value (the outcome entries, last,
    not counted)."""
    return int((ds.present.values[:, :ds.sizes["attractor"] - len(OUTCOMES)] > 0).any(axis=0).sum())


def eventual_text(ds, i, j) -> str:
    """An attractors dataset's eventual fraction and its interval at (value i, attractor j) as text, where it differs
    from the basin fraction (else, and in datasets written before it existed, empty)."""
    if "eventual_fraction" not in ds or ds.eventual_fraction.values[i, j] == ds.basin_fraction.values[i, j]:
        return ""
    return (f"{ds.eventual_fraction.values[i, j]:.3f} [{ds.eventual_fraction_low.values[i, j]:.3f}, "
            f"{ds.eventual_fraction_high.values[i, j]:.3f}]")


def _columns(values, per_value, outcomes, n_ids, events, transients=None):
    """The ATTRACTOR rows as arrays (values, ids + the outcomes)."""
    n_att = n_ids + len(OUTCOMES)
    sizes = {"v": len(values), "attractor": n_att}
    cols = {v.name: v.empty(sizes, "v") for v in ATTRACTOR}
    keys = list(range(n_ids)) + list(OUTCOMES.values())
    for i, (found, out) in enumerate(zip(per_value, outcomes)):
        out = np.asarray(out)
        n = len(out)
        via, saddles = transients[i] if transients else ([], [])
        cols["eventual_fraction"][i], cols["eventual_fraction_low"][i], cols["eventual_fraction_high"][i] = \
            eventual_fractions(out, via, saddles, keys)
        _put_transient(cols, i, n_ids + list(OUTCOMES).index("transient"), out, via, saddles)
        for col in range(n_att):
            key = keys[col]
            k = int(np.sum(out == key))
            lo, hi = wilson(k, n)
            cols["basin_fraction"][i, col], cols["basin_count"][i, col] = k / n, k
            cols["basin_fraction_low"][i, col], cols["basin_fraction_high"][i, col] = lo, hi
            if col >= n_ids:
                cols["class_code"][i, col] = int(list(OUTCOME_CODES.values())[col - n_ids])
                cols["present"][i, col] = int(k > 0)
                continue
            a = found.get(col)
            if a is not None:
                _put_attractor(cols, i, col, a)
            ev = events.get((i, col))
            if ev is not None:
                cols["event"][i, col] = ATTRACTOR_EVENTS.index(ev[0])
                cols["event_link"][i, col], cols["event_evidence"][i, col] = ev[1], ev[2]
    return cols


def _put_transient(cols, i, col, out, via, saddles) -> None:
    """The "transient" entry's lifetime: that of the saddle (group, :func:`.eventual.saddle_groups`) most of the
    value's transient starts are on, its first estimate (NaN: no transient start)."""
    transient = [v for o, v in zip(out, via) if o == OUTCOMES["transient"] and v >= 0] if len(via) else []
    if not transient:
        return
    group = saddle_groups(saddles)
    top = max(sorted(set(group[v] for v in transient)), key=[group[v] for v in transient].count)
    a = next((sd for j, sd in enumerate(saddles) if group[j] == top and np.isfinite(sd.lifetime_interval[0])), None)
    if a is None:
        return
    cols["lifetime"][i, col] = a.lifetime
    cols["lifetime_low"][i, col], cols["lifetime_high"][i, col] = a.lifetime_interval


def _put_attractor(cols, i, col, a) -> None:
    cols["present"][i, col] = 1
    cols["class_code"][i, col] = a.code
    cols["period"][i, col], cols["period_mechanical"][i, col] = a.period, a.period_mechanical
    cols["impacts_per_period"][i, col] = a.impacts
    cols["impacts_per_period_mechanical"][i, col] = a.impacts_mechanical
    cols["lyapunov"][i, col] = a.lyapunov
    cols["lyapunov_low"][i, col], cols["lyapunov_high"][i, col] = a.lyapunov_interval
    cols["max_multiplier"][i, col], cols["newton_residual"][i, col] = a.max_multiplier, a.residual
    cols["lifetime"][i, col] = a.lifetime
    cols["lifetime_low"][i, col], cols["lifetime_high"][i, col] = a.lifetime_interval
    cols["area_rate"][i, col] = a.area_rate
    cols["area_rate_low"][i, col], cols["area_rate_high"][i, col] = a.area_rate_interval
    cols["n_points"][i, col] = len(a.points)
    cols["match_distance"][i, col] = getattr(a, "match_distance", np.nan)


def to_dataset(pb, param, values, per_value, outcomes, n_ids, events, starts, *, n_node, attrs, transients=None):
    """The Dataset of a census: ``per_value[i]`` {id: Attractor}, ``outcomes[i]`` the fresh starts' ids,
    ``transients[i]`` (each start's saddle index, the saddles) for the eventual fractions (:mod:`.eventual`)."""
    system = pb.system
    p = system.parameter(param)
    labels = [f"A{j}" for j in range(n_ids)] + list(OUTCOMES)
    ds = dataset("attractors", coords={param: (param, np.asarray(values, float),
                                               {"units": p.unit, "long_name": f"{param}: {p.long_name}"}),
                                       "attractor": coord(ATTRACTOR_COORDS[0], len(labels)),
                                       "node": ("node", np.arange(n_node)),
                                       "start": ("start", np.arange(len(starts)))})
    ds["attractor_label"] = coord(ATTRACTOR_COORDS[1], labels)
    cols = _columns(values, per_value, outcomes, n_ids, events, transients)
    for v in ATTRACTOR:
        put(ds, v, v.finish(cols[v.name]), param=param)
    _put_states(ds, system, param, per_value, len(labels), n_node)
    for j, st in enumerate(system.states):
        ds[f"start_{st.name}"] = ("start", starts.points[:, j], {"units": st.unit, "long_name": f"start: {st.long_name}"})
    out = np.asarray(outcomes, dtype=np.int32)
    to_col = {k: n_ids + m for m, k in enumerate(OUTCOMES.values())}
    ds["start_attractor"] = ((param, "start"), np.vectorize(lambda k: to_col.get(k, k))(out).astype(np.int32),
                             {"units": "1", "long_name": "attractor id each fresh start reached"})
    ds.attrs.update({"title": f"{pb.name}: attractors and basins over {param}", "swept_parameter": param,
                     "start_kind": starts.kind, "start_box": ",".join(f"{k}={lo:g}:{hi:g}" for k, (lo, hi)
                                                                     in starts.box.items()),
                     "slice_shape": list(starts.shape), "slice_states": " ".join(starts.slice_states),
                     "bifurc_version": __version__, **attrs, **cf_attrs(f"scene {pb.name}, attractor census in {param}"),
                     **pb.attrs(skip=(param,))})
    if starts.seed is not None:
        ds.attrs["seed"] = int(starts.seed)
    return ds


def _put_states(ds, system, param, per_value, n_att, n_node) -> None:
    """The attractors' strobe states (node 0 ... n_points - 1, NaN beyond) and their flags."""
    d = len(system.states)
    y = np.full((len(per_value), n_att, n_node, d), np.nan)
    fl = np.full((len(per_value), n_att, n_node, len(system.flag_names)), np.nan)
    k0 = np.full((len(per_value), n_att), -1, np.int64)
    for i, found in enumerate(per_value):
        for col, a in found.items():
            m = min(len(a.points), n_node)
            y[i, col, :m] = a.points[:m]
            k0[i, col] = a.k0
            for j in range(m):
                fl[i, col, j] = [a.flags[j].get(f, np.nan) if a.flags and a.flags[j] else np.nan
                                 for f in system.flag_names]
    dims = (param, "attractor", "node")
    for j, st in enumerate(system.states):
        v = state_variable(st, dims, " on the attractor at the strobe samples")
        ds[v.name] = (dims, y[..., j], v.attrs())
    for j, f in enumerate(system.flag_names):
        v = flag_variable(f, dims)
        ds[v.name] = (dims, fl[..., j], v.attrs())
    ds["attractor_k0"] = ((param, "attractor"), k0, {"units": "1", "long_name": "strobe sample index of node 0"})
