"""The impact log of a run: one row per contact, from the recorded guard crossings.

Reads events by their role ("impact": onset, "deepest": maximum penetration,
"release", "flight_minimum"), never by name, and the declared
``system.gap(y, params, t) -> (gap, gap_rate)`` at each event's instant (a moving stop's
clearance and the relative approach speed).
"""
from __future__ import annotations

import numpy as np

__all__ = ["impact_table", "free_flight_minima"]


def impact_table(run) -> dict:
    """Arrays per contact: onset time [s], impact velocity [m/s] (gap rate at onset, the
    speed relative to the stop, negative toward it), maximum penetration [m] (>= 0) and contact duration [s]
    (NaN for a contact still open at the end of the run)."""
    gap = run.system.gap or (lambda y, p, t=0.0: (np.nan, np.nan))
    role = run.system.role_of
    onset, vel, pen, dur = [], [], [], []
    for ev in run.events:
        r = role(ev.name)
        if r == "impact":
            g, rate = gap(ev.y_minus, run.params, ev.t)
            onset.append(ev.t)
            vel.append(rate)
            pen.append(max(0.0, -g))
            dur.append(np.nan)
        elif r == "deepest" and onset:
            pen[-1] = max(pen[-1], -gap(ev.y_minus, run.params, ev.t)[0])
        elif r == "release" and onset and np.isnan(dur[-1]):
            dur[-1] = ev.t - onset[-1]
    return {"t": np.array(onset), "velocity": np.array(vel), "penetration": np.array(pen),
            "duration": np.array(dur)}


def free_flight_minima(run) -> dict:
    """Local minima of the gap in free flight (role "flight_minimum"): time [s] and gap [m]."""
    t, g = [], []
    for ev in run.events:
        if run.system.role_of(ev.name) == "flight_minimum":
            t.append(ev.t)
            g.append(run.system.gap(ev.y_minus, run.params, ev.t)[0])
    return {"t": np.array(t), "gap": np.array(g)}
