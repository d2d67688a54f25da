"""The attractors Dataset (kind "attractors"): dims (the parameter, ``attractor``), plus ``node`` for the
attractors' strobe states and ``start`` for the fresh starts and where each went (basin pictures).
Every variable is a row of :data:`bifurc.storage.schema.ATTRACTOR` (and the multipliers' rows,
:data:`bifurc.storage.schema.ATTRACTOR_MULTIPLIERS`, along ``multiplier``)."""
from __future__ import annotations

import numpy as np

from maps.provenance import cf_attrs

from .._version import __version__
from ..labels.codes import OUTCOMES, ClassCode, Outcome
from ..labels.evidence import rotation_number
from ..storage.build import coord, dataset, put
from ..storage.schema import (ATTRACTOR, ATTRACTOR_COORDS, ATTRACTOR_EVENTS, ATTRACTOR_MULTIPLIERS, LIFETIME_VERDICTS,
                              flag_variable, state_variable)
from .eventual import saddle_groups



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


#: a number as the event evidence writes it (:func:`bifurc.attractors.follow.link_event`)
_NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"


def event_location(ds, i, j) -> tuple[float, float] | None:
    """The parameter value (lo, hi) at which the event of attractor ``j`` between values ``i - 1`` and ``i``
    was located on its continued branch (lo = hi: a located point; lo < hi: a bracket), or None: no event,
    or a global one (no local bifurcation on the branch: only the grid step brackets it)."""
    import re
    if not int(ds.event.values[i, j]) or "event_evidence" not in ds or str(ds.event_link.values[i, j]) == "global":
        return None
    par = ds.attrs["swept_parameter"]
    m = re.search(rf"\b{re.escape(par)} = ({_NUMBER})(?: to ({_NUMBER}))?", str(ds.event_evidence.values[i, j]))
    if m is None:
        return None
    lo = float(m.group(1))
    return lo, float(m.group(2)) if m.group(2) else lo


def event_text(ds, i, j) -> str:
    """"fold located at V = 113.2" / "period_doubling bracketed in V = 1 to 1.1" / "global: between V = 100 and
    120": the event of attractor ``j`` between values ``i - 1`` and ``i`` (empty: none)."""
    ev = int(ds.event.values[i, j])
    if not ev:
        return ""
    par = ds.attrs["swept_parameter"]
    link = str(ds.event_link.values[i, j]) or "global"
    at = event_location(ds, i, j)
    v = ds[par].values
    if at is None:
        near = f"{par} = {v[i - 1]:g} and {v[i]:g}" if i > 0 else f"{par} = {v[i]:g} and the next value"
        return f"{link}: between {near}"
    return f"{link} located at {par} = {at[0]:.10g}" if at[0] == at[1] else \
        f"{link} bracketed in {par} = {at[0]:.10g} to {at[1]:.10g}"


def attractor_text(ds, i, j) -> str:
    """What attractor ``j`` is at value ``i``: "period-1, 1 impact (1:1)", "chaotic", "at rest on the stop"
    (a period-1 orbit without impact, stuck on or in contact with the stop at its node), an outcome's name."""
    from ..labels.classify import CLASS_LABELS, describe
    label = str(ds.attractor_label.values[j])
    if not label.startswith("A"):
        return label.replace("_", " ")
    code = int(ds.class_code.values[i, j])
    if code < 0:
        return "absent"
    if CLASS_LABELS[code] == "periodic-no-impact" and int(ds.period.values[i, j]) == 1 and _resting(ds, i, j):
        return "at rest on the stop"
    if "sample_step" in ds.attrs:
        return flow_text(code, int(ds.period.values[i, j]))
    return describe(code, int(ds.period.values[i, j]), int(ds.impacts_per_period.values[i, j]))


def flow_text(code: int, period: int) -> str:
    """An autonomous flow's attractor (sampled every ``sample_step``) in the flow's words: a fixed point (the
    sampled map's period-1 point without impact), a limit cycle (an invariant circle of the sampled map: its samples
    turn about it, "quasi-periodic"; or a closed orbit whose period is locked to a whole number of steps), a chaotic
    attractor."""
    from ..labels.classify import CLASS_LABELS, describe
    label = CLASS_LABELS[code]
    if label == "periodic-no-impact":
        return "fixed point" if period == 1 else f"limit cycle of {period} steps"
    if label == "quasi-periodic":
        return "limit cycle"
    if label == "chaotic":
        return "chaotic attractor"
    return describe(code, period, 0)


#: mode flags that hold while the bar rests on the stop (thesis-1dof: stuck_bar; a contact mode: contact)
RESTING_FLAGS = ("flag_stuck_bar", "flag_contact")


def _resting(ds, i, j) -> bool:
    """Stuck on (or in contact with) the stop at every stored node, with no impact: a bar at rest on the stop."""
    for name in RESTING_FLAGS:
        if name in ds:
            c = ds[name].values[i, j]
            c = c[np.isfinite(c)]
            if c.size and bool(np.all(c == 1)):
                return True
    return False


def census_lines(ds) -> list[str]:
    """The census as text: a header, one line per value (each attractor present with its basin fraction and 95 %
    interval, the eventual fraction where it differs, then the outcomes) and one line per event with the
    parameter value where it was located (:func:`event_text`)."""
    par = ds.attrs["swept_parameter"]
    v = ds[par].values
    units = ds[par].attrs.get("units", "")
    unit = f" {units}" if units not in ("", "1") else ""
    secs = ds.attrs.get("census_seconds")
    took = f" in {float(secs):.1f} s" if secs is not None else ""
    lines = [f"{ds.attrs.get('scene', '')}: {par} {v.min():g}..{v.max():g}{unit} ({v.size} values x "
             f"{ds.sizes['start']} starts){took}: {attractor_count(ds)} attractor(s)"]
    labels = [str(s) for s in ds.attractor_label.values]
    frac, lo, hi = ds.basin_fraction.values, ds.basin_fraction_low.values, ds.basin_fraction_high.values
    for i in range(v.size):
        parts, outcomes = [], []
        for j, label in enumerate(labels):
            if frac[i, j] <= 0 and not (label.startswith("A") and ds.present.values[i, j]):
                continue
            then = f", eventually {t}" if (t := eventual_text(ds, i, j)) else ""
            if frac[i, j] <= 0:     # present, yet no fresh start landed: found by seeding from a neighbour
                then += " (no start landed; seeded from a neighbouring value)"
            text = f"{frac[i, j]:.3f} [{lo[i, j]:.3f}, {hi[i, j]:.3f}]{then}"
            if label.startswith("A"):
                parts.append(f"{label} {attractor_text(ds, i, j)} {text}")
            else:
                outcomes.append(f"{label.replace('_', ' ')} {text}")
        lines.append(f"  {par} = {v[i]:g}: " + ("; ".join(parts) or "no attractor")
                     + (f"; outcomes: {'; '.join(outcomes)}" if outcomes else ""))
    events = [(i, j) for i in range(v.size) for j in range(len(labels)) if int(ds.event.values[i, j])]
    meanings = ds.event.attrs["flag_meanings"].split()
    if events:
        lines.append(f"  events ({len(events)}):")
    for i, j in events:
        k = i - 1 if int(ds.event.values[i, j]) == 2 and i > 0 else i     # where it was last / first seen
        lines.append(f"    {labels[j]} ({attractor_text(ds, k, j)}) {meanings[int(ds.event.values[i, j])]}: "
                     f"{event_text(ds, i, j)}")
    return lines


def _columns(values, per_value, outcomes, n_ids, events, fractions, transients=None, step=None):
    """The ATTRACTOR rows as arrays (values, ids + the outcomes); ``fractions``: the census'
    :class:`~bifurc.attractors.fractions.Fractions`; ``step``: an autonomous flow's sampling step [s] (its limit
    cycles' periods)."""
    n_att = n_ids + len(OUTCOMES)
    sizes = {"v": len(values), "attractor": n_att}
    cols = {v.name: v.empty(sizes, "v") for v in ATTRACTOR}
    keys = list(fractions.keys)
    cols["basin_fraction"][:], cols["basin_count"][:] = fractions.fraction, fractions.count
    cols["basin_fraction_low"][:], cols["basin_fraction_high"][:] = fractions.low, fractions.high
    cols["eventual_fraction"][:], cols["eventual_fraction_low"][:], cols["eventual_fraction_high"][:] = \
        fractions.eventual, fractions.eventual_low, fractions.eventual_high
    for i, (found, out) in enumerate(zip(per_value, outcomes)):
        out = np.asarray(out)
        via, saddles = transients[i] if transients else ([], [])
        _put_transient(cols, i, n_ids + list(OUTCOMES).index("transient"), out, via, saddles)
        for col in range(n_att):
            key = keys[col]
            if col >= n_ids:
                cols["class_code"][i, col] = int(Outcome(key).class_code)
                cols["present"][i, col] = int(fractions.count[i, col] > 0)
                continue
            a = found.get(col)
            if a is not None:
                _put_attractor(cols, i, col, a)
                if step is not None and a.code == int(ClassCode.QUASI_PERIODIC):
                    cols["cycle_period"][i, col] = step / rotation_number(a.points)[0]
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
    cols["lifetime_verdict"][i, col] = _verdict(a)


def _verdict(a) -> int:
    """The code of ``a``'s lifetime verdict (:data:`bifurc.storage.schema.LIFETIME_VERDICTS`; 0: none)."""
    v = getattr(a, "lifetime_verdict", "")
    return LIFETIME_VERDICTS.index(v) if v in LIFETIME_VERDICTS else 0


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
    cols["lifetime_verdict"][i, col] = _verdict(a)
    cols["n_points"][i, col] = len(a.points)
    cols["match_distance"][i, col] = getattr(a, "match_distance", np.nan)


def _flat_dataset(pb, param, values, per_value, outcomes, n_ids, events, starts, *, n_node, attrs, fractions,
                  transients=None, skip=(), spent=None):
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
    cols = _columns(values, per_value, outcomes, n_ids, events, fractions, transients, system.sample_step)
    for v in ATTRACTOR:
        put(ds, v, v.finish(cols[v.name]), param=param)
    _put_states(ds, system, param, per_value, len(labels), n_node)
    _put_multipliers(ds, system, param, per_value, len(labels))
    for j, st in enumerate(system.states):
        ds[f"start_{st.name}"] = ("start", starts.points[:, j], {"units": st.unit, "long_name": f"start: {st.long_name}"})
    out = np.asarray(outcomes, dtype=np.int32)
    to_col = {k: n_ids + m for m, k in enumerate(OUTCOMES.values())}
    ds["start_attractor"] = ((param, "start"), np.vectorize(lambda k: to_col.get(k, k))(out).astype(np.int32),
                             {"units": "1", "long_name": "attractor id each fresh start reached"})
    if spent is not None:
        ds["start_periods"] = ((param, "start"), np.asarray(spent, dtype=np.int32),
                               {"units": "1", "long_name": "strobe periods each fresh start ran in its census, records "
                                                           "run beside it not counted"})
    ds.attrs.update({"title": f"{pb.name}: attractors and basins over {param}", "swept_parameter": param,
                     "start_kind": starts.kind, "start_box": ",".join(f"{k}={lo:g}:{hi:g}" for k, (lo, hi)
                                                                     in starts.box.items()),
                     "slice_shape": list(starts.shape), "slice_states": " ".join(starts.slice_states),
                     "bifurc_version": __version__, **attrs, **cf_attrs(f"scene {pb.name}, attractor census in {param}"),
                     **pb.attrs(skip=(param, *skip))})
    if starts.seed is not None:
        ds.attrs["seed"] = int(starts.seed)
    if system.sample_step is not None:
        ds.attrs.update(sample_step=system.sample_step, sample_step_units="s",
                        sampling="an autonomous flow sampled every sample_step: fixed points, limit cycles (invariant "
                                 "circles of the sampled map) and chaotic attractors of the flow")
    return ds


def to_dataset(pb, names, points, per_value, outcomes, n_ids, events, starts, *, n_node, attrs, fractions,
               transients=None, spent=None):
    """The Dataset of a census at ``points`` ({name: value} of the parameters ``names``): dims (name, ``attractor``)
    for one parameter; (name, name2, ``attractor``) for a full two-parameter grid; else (``point``, ``attractor``)
    with one coordinate per parameter along ``point``.  ``per_value[i]`` {id: Attractor}, ``outcomes[i]`` the fresh
    starts' ids, ``fractions`` their basin and eventual fractions (:func:`.fractions.census_fractions`),
    ``transients[i]`` (each start's saddle index, the saddles) for the transient entry's lifetime, ``spent[i]`` the
    strobe periods each fresh start ran."""
    first = names[0]
    flat = _flat_dataset(pb, first, [p[first] for p in points], per_value, outcomes, n_ids, events, starts,
                         n_node=n_node, attrs=attrs, fractions=fractions, transients=transients,
                         skip=names[1:], spent=spent)
    if len(names) == 1:
        return flat
    flat = flat.rename({first: "point"}).drop_vars("point")
    for k in names:
        p = pb.system.parameter(k)
        flat.coords[k] = ("point", np.array([q[k] for q in points], float),
                          {"units": p.unit, "long_name": f"{k}: {p.long_name}"})
    flat.attrs.update(swept_parameters=" ".join(names), title=f"{pb.name}: attractors and basins over "
                                                              f"{' and '.join(names)}")
    if len(names) == 2:
        grid = _as_grid(flat, names)
        if grid is not None:
            return grid
    return flat


def _as_grid(flat, names):
    """``flat`` (dimension ``point``) on the full grid of its two parameters (dims name, name2), or None where the
    points are not a full grid."""
    import xarray as xr
    a, b = (np.unique(flat[k].values) for k in names)
    if a.size * b.size != flat.sizes["point"]:
        return None
    ia = np.searchsorted(a, flat[names[0]].values)
    ib = np.searchsorted(b, flat[names[1]].values)
    if len(set(zip(ia.tolist(), ib.tolist()))) != flat.sizes["point"]:
        return None
    order = np.empty((a.size, b.size), np.int64)
    order[ia, ib] = np.arange(flat.sizes["point"])
    out = {}
    for name, var in flat.data_vars.items():
        if "point" not in var.dims:
            out[name] = var
            continue
        rest = tuple(d for d in var.dims if d != "point")
        moved = var.transpose("point", *rest)
        data = moved.values[order.ravel()].reshape(a.size, b.size, *moved.shape[1:])
        out[name] = xr.Variable((names[0], names[1]) + rest, data, var.attrs, var.encoding)
    coords = {k: v for k, v in flat.coords.items() if "point" not in v.dims}
    coords[names[0]] = (names[0], a, flat[names[0]].attrs)
    coords[names[1]] = (names[1], b, flat[names[1]].attrs)
    ds = xr.Dataset(out, coords=coords, attrs=flat.attrs)
    ds.attrs["swept_parameter2"] = names[1]
    return ds


def _put_multipliers(ds, system, param, per_value, n_att) -> None:
    """Every polished periodic attractor's Floquet multipliers (modulus and argument, largest first; NaN beyond its
    own count or where none were computed), along a ``multiplier`` dimension of one per state."""
    d = len(system.states)
    ds.coords["multiplier"] = coord(ATTRACTOR_COORDS[2], d)
    data = {v.name: v.empty({"v": len(per_value), "attractor": n_att, "multiplier": d}, "v")
            for v in ATTRACTOR_MULTIPLIERS}
    for i, found in enumerate(per_value):
        for col, a in found.items():
            m = min(len(a.multiplier_abs), d)
            data["multiplier_abs"][i, col, :m] = a.multiplier_abs[:m]
            data["multiplier_arg"][i, col, :m] = a.multiplier_arg[:m]
    for v in ATTRACTOR_MULTIPLIERS:
        put(ds, v, data[v.name], param=param)


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
