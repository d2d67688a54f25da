"""The impact log of a run: one row per contact, from the recorded guard crossings."""
from __future__ import annotations

import numpy as np

__all__ = ["impact_table"]


def impact_table(run) -> dict:
    """Arrays per contact: onset time [s], impact velocity [m/s] (relative, negative
    toward the stop), maximum penetration [m] (>= 0) and contact duration [s] (NaN
    for a contact still open at the end of the run)."""
    system = run.system
    r_of = _relative(system)
    onset, vel, pen, dur = [], [], [], []
    for ev in run.events:
        if ev.name == "contact":
            r, rdot = r_of(ev.y_minus)
            onset.append(ev.t)
            vel.append(rdot)
            pen.append(max(0.0, run.params["e"] - r))
            dur.append(np.nan)
        elif ev.name == "deepest" and onset:
            r, _ = r_of(ev.y_minus)
            pen[-1] = max(pen[-1], run.params["e"] - r)
        elif ev.name == "release" and onset and np.isnan(dur[-1]):
            dur[-1] = ev.t - onset[-1]
    return {"t": np.array(onset), "velocity": np.array(vel), "penetration": np.array(pen),
            "duration": np.array(dur)}


def _relative(system):
    names = system.state_names
    if "x1" in names:
        i1, v1, i2, v2 = (names.index(n) for n in ("x1", "v1", "x2", "v2"))
        return lambda y: (y[i1] - y[i2], y[v1] - y[v2])
    ix, iv = names.index("x"), names.index("v")
    return lambda y: (y[ix], y[iv])
