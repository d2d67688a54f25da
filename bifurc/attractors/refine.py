"""Census values refined at located events: a stable window narrower than the parameter step, or two changes in
one step, is seen by the census only at a value between its events.

On thesis-1dof (`matlab-listing`, `measured`, 10 Hz) at 0.5 V steps the thesis-orbits branches hold stable
period-1 and period-2 windows 0.03-0.29 V wide between a fold and a period doubling (124.40-124.43, 128.43-128.48,
135.67-135.71, 164.60-164.82 V) and five events in 110.5-111 V; no census value lies in those windows, so no
appearance or disappearance marks them.  Given branches from continuation (:func:`bifurc.continue_orbit`), a value
is added between each two consecutive distinct located events that share a step, so that each step holds at most
one.
The added values are census values like the others (fresh starts and seeds from their neighbours): no orbit is
taken from the branches.
"""
from __future__ import annotations

import numpy as np

from maps.parameters import ParameterError

from .follow import local_events

#: attributes a branch must share with the census' problem (where both carry them): the model it was computed on
MODEL_ATTRS = ("scene", "circuit", "ac_sign", "relay", "dc_law", "soil", "soil_compaction", "preset")


def event_values(branches, param: str, problem=None) -> np.ndarray:
    """The sorted values of ``param`` [its unit] at which the branch datasets ``branches`` (one or a list, as
    :func:`bifurc.continue_orbit` returns) locate a fold, period doubling, torus, grazing, impact loss or stick
    onset (:func:`.follow.local_events`); each branch must be a continuation in ``param`` and, with ``problem``, of the
    same model and the same other parameter values."""
    bs = [branches] if hasattr(branches, "attrs") else list(branches)
    out = []
    for k, br in enumerate(bs):
        if not hasattr(br, "attrs") or br.attrs.get("bifurc_kind") != "branch":
            raise ParameterError(f"refine: item {k} is not a branch dataset (bifurc.continue_orbit's output)")
        got = br.attrs.get("continuation_parameter")
        if got != param:
            raise ParameterError(f"refine: branch {k} is a continuation in {got!r}, the census sweeps {param!r}")
        if problem is not None:
            _same_model(br, k, problem, param)
        out += [v for _, _, v in local_events(br)]
    return np.sort(np.asarray(out, dtype=float))


def _same_model(br, k: int, problem, param: str) -> None:
    mine = problem.attrs(skip=(param,))
    for key in MODEL_ATTRS:
        if key in br.attrs and key in mine and str(br.attrs[key]) != str(mine[key]):
            raise ParameterError(f"refine: branch {k} was computed with {key} = {br.attrs[key]!r}, the census "
                                 f"runs {mine[key]!r}")
    for name, value in problem.values.items():
        there = br.attrs.get(f"param_{name}")
        if name != param and there is not None and not np.isclose(float(there), float(value), rtol=1e-12, atol=0):
            raise ParameterError(f"refine: branch {k} was computed at {name} = {float(there):g}, the census at "
                                 f"{float(value):g}")


def refined_values(values, events, resolution: float = 1e-4) -> tuple[np.ndarray, np.ndarray]:
    """(``values`` with the added ones, each step's in order from one value to the next; the added ones): in each
    step between consecutive ``values``, the midpoint of each two consecutive ``events`` strictly inside it that
    lie more than ``resolution`` x the step apart.  Closer events are one: a period doubling and its daughter's
    birth, located on the two branches, differ by 1e-7 to 5e-6 V on thesis-1dof (0.5 V steps); a value added
    between them, 1e-7 V from the period doubling, met a daughter not yet told from its parent taken twice."""
    values = np.asarray(values, dtype=float)
    events = np.sort(np.asarray(events, dtype=float))
    out, added = [float(values[0])], []
    for a, b in zip(values[:-1], values[1:]):
        lo, hi = min(a, b), max(a, b)
        inside = events[(events > lo) & (events < hi)]
        distinct = inside[:1].tolist()
        for e in inside[1:]:
            if e - distinct[-1] > resolution * (hi - lo):
                distinct.append(float(e))
        mids = [0.5 * (x + y) for x, y in zip(distinct[:-1], distinct[1:])]
        mids = mids if b >= a else mids[::-1]
        added += mids
        out += mids + [float(b)]
    return np.asarray(out, dtype=float), np.asarray(added, dtype=float)
