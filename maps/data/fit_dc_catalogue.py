"""Fit the ``catalogue`` DC-force law's shape to thesis Table 4.1 (run: python maps/data/fit_dc_catalogue.py).

The law (docs/model.md section 1): the pull toward the DC solenoid's centre at dc_scale = 1 (20 V DC)

    F(xa) = -F_dc_sat / 2 * [tanh((xa - u_dc) / (2 s_dc)) + tanh((xa + u_dc) / (2 s_dc))]

odd in xa, about 0 near the centre (Table 4.1: 0 N up to 5 mm), a steep rise near |xa| = u_dc
(the bar's end nearing the coil's pole face) and a plateau F_dc_sat where a bar end sits inside the
coil: the plunger regime the catalogue rates.  Anchors, all independent of the thesis' simulations:

- F_dc_sat: the catalogue's magnetic force, 750 g at 24 V DC (Table 3.1, App. A: 7.355 N), scaled to
  Table 4.1's 20 V by the square of the voltage (force ~ current^2, linear magnetic circuit, the
  rule dc_scale already uses): 7.355 (20/24)^2 = 5.108 N.  FIXED, not fitted.
- u_dc, s_dc: least squares on the nine points of Table 4.1 (spring balance, 20 V), unweighted.
- checks (printed, not fitted): the catalogue's 21 mm stroke (the law holds >= 95 % of its plateau
  over the 21 mm before the stop, |xa| in [41.5, 62.5] mm) and the text's "20 V DC balances 80 V AC"
  (the model's AC pull at the stop at 80 V, amplitude and RMS readings, beside the DC pull there).

Writes maps/data/dc_catalogue_fit.json beside this script (committed; maps.presets reads it).
"""
from __future__ import annotations

import datetime
import json
import math
import pathlib
import subprocess

import numpy as np
from scipy.optimize import least_squares

HERE = pathlib.Path(__file__).resolve().parent
G0 = 9.80665                      # standard gravity [m s-2]: 750 g force -> N
F_CATALOGUE_24V = 0.750 * G0      # Table 3.1 "Magnetic Force 750 g" at 24 V DC [N]
STROKE = 0.021                    # Table 3.1 "Maximum Stroke 21 mm" [m]
D_DC = 0.0625                     # stop to DC-solenoid centre [m] (eq 4.5)


def law(xa, F_sat, u0, s):
    """The catalogue law's force along +xa [N] (toward the centre)."""
    xa = np.asarray(xa, dtype=float)
    return -0.5 * F_sat * (np.tanh((xa - u0) / (2 * s)) + np.tanh((xa + u0) / (2 * s)))


def ac_pull_at_stop(V, R=25.0, C=2.8e-4, f=50.0, L0=0.48, A=0.048, B=0.039, d_ac=0.0455):
    """Peak and mean AC pull [N] on a bar held on the stop, steady state of the series RLC at source
    amplitude V [V] (the model's inductance fit, eq 4.13; listing C.1's R and C)."""
    q = d_ac / B
    gA = math.exp(-2 * q * q) * A / B
    c0 = 1 / math.sqrt(math.pi / 2)
    L, dL = L0 + c0 * gA, -4 * c0 * gA * q / B
    w = 2 * math.pi * f
    amp = V / math.hypot(R, w * L - 1 / (w * C))
    return 0.5 * abs(dL) * amp ** 2, 0.25 * abs(dL) * amp ** 2


def fit() -> dict:
    text = (HERE / "dc_force_table_4_1.csv").read_text().splitlines()
    rows = np.array([[float(v) for v in ln.split(",")] for ln in text[2:] if ln.strip()])
    u, T = rows[:, 0], rows[:, 1]
    F_sat = F_CATALOGUE_24V * (20.0 / 24.0) ** 2
    res = least_squares(lambda p: -law(u, F_sat, *p) - T, [0.028, 0.003], bounds=([0.0, 1e-4], [0.06, 0.03]))
    u0, s = map(float, res.x)
    resid = -law(u, F_sat, u0, s) - T
    band = np.linspace(D_DC - STROKE, D_DC, 43)
    ac = {f"{V:g} V {how}": dict(zip(("peak_N", "mean_N"), ac_pull_at_stop(V * k)))
          for V in (80.0,) for how, k in (("amplitude", 1.0), ("RMS", math.sqrt(2)))}
    try:
        commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=HERE, capture_output=True,
                                text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        commit = "unknown"
    return {
        "law": "F(xa) = -F_dc_sat/2 [tanh((xa - u_dc)/(2 s_dc)) + tanh((xa + u_dc)/(2 s_dc))] at 20 V DC",
        "F_dc_sat": F_sat, "u_dc": u0, "s_dc": s,
        "anchors": {"F_dc_sat": "Table 3.1 / App. A: 750 g at 24 V DC = 7.355 N, times (20/24)^2 (force ~ I^2)",
                    "u_dc, s_dc": "least squares on Table 4.1 (9 points, 20 V, unweighted)"},
        "table_4_1_residual_N": {f"{x * 1e3:g} mm": float(r) for x, r in zip(u, resid)},
        "table_4_1_rms_N": float(np.sqrt(np.mean(resid ** 2))),
        "table_4_1_max_abs_N": float(np.max(np.abs(resid))),
        "force_at_stop_20V_N": float(law(-D_DC, F_sat, u0, s)),
        "force_at_stop_24V_N": float(law(-D_DC, F_sat, u0, s) * (24 / 20) ** 2),
        "stroke_check_min_fraction_of_plateau": float(np.min(law(-band, F_sat, u0, s)) / F_sat),
        "balance_check_ac_pull_at_stop_80V": ac,
        "produced_by": "python maps/data/fit_dc_catalogue.py", "commit": commit,
        "date": datetime.date.today().isoformat(),
    }


if __name__ == "__main__":
    out = fit()
    (HERE / "dc_catalogue_fit.json").write_text(json.dumps(out, indent=2) + "\n")
    print(json.dumps(out, indent=2))
