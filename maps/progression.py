"""How far and how fast a 2-DOF scene progresses into the soil (issue 18, section 2).

One function, :func:`progression_measures`, turns a record of the rig's position at known times,
the contact onsets and the time the rig is held into the measures every 2-DOF time history
(:func:`maps.simulate`) and sweep (:mod:`bifurc.sweeps.dataset`) stores:

- ``progression_rate`` [m s-1]: mean forward speed over the window, (x2(t_a) - x2(t_b)) / (t_b - t_a);
- ``progression_per_period`` [m]: the same per relay period (rate / relay_hz);
- ``time_to_depth`` [s]: first time the rig is ``TARGET_DEPTH`` = 0.2 m ahead of its start (the
  thesis' measure, Chapter 5), linear between samples; NaN when not reached;
- ``impact_energy_per_period`` [J]: kinetic energy of the bar relative to the rig at contact
  onset, m1 v_rel^2 / 2, summed over the window's contacts per relay period;
- ``stuck_fraction`` [1]: fraction of the window in which the rig is held by the soil
  (:func:`held_mode`: coulomb stuck; drift slider still; never under viscous soil).
"""
from __future__ import annotations

import math

import numpy as np

#: the thesis' progression distance [m]: time to progress 0.2 m (Chapter 5)
TARGET_DEPTH = 0.2

#: name -> (units, long_name) of the measures (bifurc.storage.schema repeats them as rows; a test checks)
MEASURES = {
    "progression_rate": ("m s-1", "mean rate of forward progression into the soil over the window"),
    "progression_per_period": ("m", "forward progression per relay period over the window"),
    "time_to_depth": ("s", f"time to progress {TARGET_DEPTH} m into the soil (NaN: not reached)"),
    "impact_energy_per_period": ("J", "kinetic energy of the bar relative to the rig at contact onset, "
                                      "summed per relay period over the window"),
    "stuck_fraction": ("1", "fraction of the window in which the soil holds the rig"),
}


def held_mode(system) -> tuple | None:
    """``(flag, value)``: the mode in which the soil holds the rig (coulomb: stuck = 1; drift:
    soil_pl = 0, the slider still, so the rig can only deflect the element); None when the soil
    never holds it (viscous) or the system has no soil."""
    if "stuck" in system.flag_names:
        return ("stuck", 1.0)
    if "soil_pl" in system.flag_names:
        return ("soil_pl", 0.0)
    return None


def held_time(flag_log, t_a: float, t_b: float, mode) -> float:
    """Time [s] within [t_a, t_b] spent in ``mode`` = (flag, value), from a run's flag log
    ``[(t, flags), ...]`` (each entry holds until the next; none before the first); 0 without a mode."""
    if mode is None:
        return 0.0
    t_a = max(float(t_a), float(flag_log[0][0]))
    return float(time_in_mode(flag_log, [t_a, t_b], mode)[1]) if t_b > t_a else 0.0


def time_in_mode(flag_log, times, mode) -> np.ndarray:
    """Time [s] spent in ``mode`` = (flag, value) from ``times[0]`` to each of ``times`` (cumulative,
    0 at ``times[0]``), from a run's flag log ``[(t, flags), ...]`` (each entry holds until the next;
    the first must not come after ``times[0]``)."""
    flag, value = mode
    starts = np.array([t for t, _ in flag_log], dtype=float)
    inside = np.array([fl.get(flag) == value for _, fl in flag_log], dtype=float)
    before = np.concatenate([[0.0], np.cumsum(inside[:-1] * np.diff(starts))])   # integral up to each start
    times = np.asarray(times, dtype=float)
    i = np.searchsorted(starts, times, side="right") - 1
    total = before[i] + inside[i] * (times - starts[i])
    return total - total[0]


def progression_measures(t, x2, *, x2_start: float, relay_hz: float | None,
                         impact_time=(), impact_velocity=(), m1: float, held: float = 0.0,
                         window=None) -> dict:
    """The measures over the window [t[0], t[-1]] of the samples ``t`` [s], ``x2`` [m].

    ``x2_start`` [m] is the rig's position at its start (depth 0); a depth already reached at
    the first sample (during a sweep's unrecorded transient) gives NaN.  Samples before
    the window may be included in ``t``, ``x2`` by giving ``window = (t_a, t_b)``, else the
    window is the whole sample range.  ``impact_time``, ``impact_velocity`` [s, m/s]: contact
    onsets and the bar's velocity relative to the rig there (only those in the window count);
    ``held`` [s]: time in the window the soil holds the rig.  Without a relay the per-period
    measures are NaN.
    """
    t, x2 = np.asarray(t, dtype=float), np.asarray(x2, dtype=float)
    t_a, t_b = (float(t[0]), float(t[-1])) if window is None else map(float, window)
    nan = math.nan
    span = t_b - t_a
    ok = np.isfinite(x2)
    out = dict.fromkeys(MEASURES, nan)
    if span <= 0 or not ok.any():
        return out
    xa, xb = np.interp([t_a, t_b], t[ok], x2[ok])
    out["progression_rate"] = (xa - xb) / span
    depth = x2_start - x2
    reached = np.flatnonzero(ok & (depth >= TARGET_DEPTH))
    if reached.size:
        j = int(reached[0])
        if j > 0:       # j = 0: reached before the samples (a sweep's unrecorded transient): not measured
            d0, d1 = depth[j - 1], depth[j]
            out["time_to_depth"] = float(t[j - 1] + (TARGET_DEPTH - d0) / (d1 - d0) * (t[j] - t[j - 1]))
    it, iv = np.asarray(impact_time, dtype=float), np.asarray(impact_velocity, dtype=float)
    inside = np.isfinite(it) & (it >= t_a) & (it <= t_b)
    if relay_hz:
        periods = span * relay_hz
        out["progression_per_period"] = out["progression_rate"] / relay_hz
        out["impact_energy_per_period"] = float(0.5 * m1 * np.sum(iv[inside] ** 2) / periods)
    out["stuck_fraction"] = held / span
    return out
