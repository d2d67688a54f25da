"""The impact log of a run: one row per contact, from the recorded guard crossings.

Reads events by their role ("impact": onset, "deepest": maximum penetration,
"release", "flight_minimum"), never by name, and the declared
``system.gap(y, params, t) -> (gap, gap_rate)`` at each event's instant (a moving stop's
clearance and the relative approach speed).
"""
from __future__ import annotations

import numpy as np

def impact_log(system, params, events) -> dict:
    """The one reading of guard crossings by role: ``events`` are ``(name, t [s], state)`` in time
    order (an EventRecord's y_minus, or a map step's crossings).  Returns arrays

    - per contact: ``time`` (onset) [s], ``velocity`` [m/s] (the gap rate at onset: the speed
      relative to the stop, negative toward it), ``penetration`` [m] (>= 0, the deepest point's)
      and ``duration`` [s] (NaN: still in contact at the end), ``event`` (the onset's index);
    - per free-flight minimum: ``flight_time`` [s], ``flight_gap`` [m], ``flight_event``;
    - per event: ``event_gap`` [m] where the gap is read (impact, flight minimum, deepest point;
      NaN elsewhere) and ``event_role``.

    The gap is ``system.gap(y, params, t)`` at each event's instant (a moving stop's clearance)."""
    gap = system.gap or (lambda y, p, t=0.0: (np.nan, np.nan))
    role = system.role_of
    onset, vel, pen, dur, first = [], [], [], [], []
    ft, fg, fe, eg, roles = [], [], [], [], []
    for i, (name, t, y) in enumerate(events):
        r = role(name)
        roles.append(r)
        g = np.nan
        if r == "impact":
            g, rate = gap(y, params, t)
            onset.append(t)
            vel.append(rate)
            pen.append(max(0.0, -g))
            dur.append(np.nan)
            first.append(i)
        elif r == "flight_minimum":
            g = gap(y, params, t)[0]
            ft.append(t)
            fg.append(g)
            fe.append(i)
        elif r == "deepest":
            g = gap(y, params, t)[0]
            if onset:
                pen[-1] = max(pen[-1], -g)
        elif r == "release" and onset and np.isnan(dur[-1]):
            dur[-1] = t - onset[-1]
        eg.append(g)
    ints = dict(dtype=np.int64)
    return {"time": np.array(onset, dtype=float), "velocity": np.array(vel, dtype=float),
            "penetration": np.array(pen, dtype=float), "duration": np.array(dur, dtype=float),
            "event": np.array(first, **ints), "flight_time": np.array(ft, dtype=float),
            "flight_gap": np.array(fg, dtype=float), "flight_event": np.array(fe, **ints),
            "event_gap": np.array(eg, dtype=float), "event_role": roles}


def _run_log(run) -> dict:
    return impact_log(run.system, run.params, ((ev.name, ev.t, ev.y_minus) for ev in run.events))


def impact_table(run) -> dict:
    """Arrays per contact of a run (:func:`impact_log`): onset time ``t`` [s], ``velocity`` [m/s],
    ``penetration`` [m] and ``duration`` [s]."""
    log = _run_log(run)
    return {"t": log["time"], "velocity": log["velocity"], "penetration": log["penetration"],
            "duration": log["duration"]}


def free_flight_minima(run) -> dict:
    """Local minima of the gap in free flight (role "flight_minimum"): time [s] and gap [m]."""
    log = _run_log(run)
    return {"t": log["flight_time"], "gap": log["flight_gap"]}
