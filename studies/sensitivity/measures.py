"""The sensitivity study's per-sample measures: how far one run is from the thesis' regime, its stroke.

The thesis' regime (docs/model.md, studies/dc_well): the bar's motion repeats every relay period with one
impact per relay period and a stroke of at most :data:`FEW_MM`.  :func:`regime_gap` turns that into one
continuous number in [0, 1] from what a recorded window of a run gives: the impacts per relay period, the
impacts' phases in the relay period and the stroke.  It is 0 exactly in the regime and grows as a run leaves
it by any of the three.
"""
from __future__ import annotations

import math

import numpy as np

#: the thesis' period-1 moved the bar a few millimetres (its LVDT read +-5 mm) [mm]
FEW_MM = 10.0


def regime_gap(impact_times, period: float, t0: float, n_periods: int, stroke_mm: float) -> dict:
    """The distance of a recorded window to the regime: {"gap", "off_count", "phase_spread", "stroke_excess"}.

    The window is ``n_periods`` relay periods of ``period`` [s] from ``t0`` [s]; ``impact_times`` [s] are the
    impacts' onsets (those outside the window are ignored); ``stroke_mm`` is x's range over the window.

    - ``off_count``: the share of the window's relay periods that do not hold exactly one impact;
    - ``phase_spread``: the circular variance 1 - |mean exp(2 pi i phase)| of the impacts' phases in the relay
      period (0: every impact at one phase; 1 without impacts);
    - ``stroke_excess``: max(0, S - FEW_MM) / S for the stroke S (0 up to FEW_MM, towards 1 for long strokes;
      1 when the stroke is not finite, e.g. the run escaped);
    - ``gap``: their mean, in [0, 1]; 0 exactly when every relay period holds one impact at one phase and the
      stroke is at most FEW_MM.
    """
    t = np.asarray(impact_times, dtype=float)
    t = t[(t >= t0) & (t < t0 + n_periods * period)]
    k = np.floor((t - t0) / period).astype(int)
    counts = np.bincount(k, minlength=n_periods)[:n_periods]
    off = float(np.mean(counts != 1))
    if t.size:
        phase = (t - t0) / period - k
        spread = float(1.0 - abs(np.mean(np.exp(2j * math.pi * phase))))
    else:
        spread = 1.0
    s = float(stroke_mm)
    excess = max(0.0, s - FEW_MM) / s if math.isfinite(s) and s > 0 else (0.0 if s == 0 else 1.0)
    spread = max(0.0, spread)          # rounding: a single phase gives -1e-16
    return {"gap": (off + spread + excess) / 3.0, "off_count": off, "phase_spread": spread, "stroke_excess": excess}
