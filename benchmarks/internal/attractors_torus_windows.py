"""Which records the torus evidence decides, on thesis-1dof's own sets (issue 31; not run in CI).

    python benchmarks/internal/attractors_torus_windows.py

thesis-1dof, `matlab-listing`, 10 Hz relay.  (1) For each (law, V): 24 box starts (x = 0-30 mm, v = -1.5-1.5 m/s,
seed 2) run 300 periods, then 6144 periods with a tangent vector, cut into 768-period windows.  Each window's
exponent verdict as the census' classifier reads it (C: its interval above the threshold 2 ln(768)/768, Q: within
+-threshold, S: the exponent within it but its interval reaching above it, P: its interval below -threshold
(contracting), O: otherwise, F: x constant to 1e-6, a fixed point) and
whether it shows the torus evidence (t) or not (-), one row per trajectory.  (2) The switch-on sets at 80 and 95 V
under `listing`: per window the rotation number, the lag-b distance (b the denominator of the nearest fraction with
b <= 16) and its fitted rate per period, and the torus verdict; at 95 V the period-6 orbit Newton finds from the
record and its multipliers.
"""
from __future__ import annotations

import math
import time
from fractions import Fraction

import numpy as np

import maps
from bifurc.attractors.starts import make_starts
from bifurc.orbits.periodic import find_periodic_orbit
from bifurc.labels.classify import lyapunov_threshold
from bifurc.labels.evidence import locked_lag, rotation_number, torus_evidence
from bifurc.labels.lyapunov import exponent_interval
from maps.poincare import StroboscopicMap

W, N, BOX = 768, 6144, {"x": (0.0, 0.03), "v": (-1.5, 1.5)}
SCALE = np.array([0.03, 3.0])     # the census grid's box widths [m, m/s]


def _setup(law: str, volts: float):
    pb = maps.problem("thesis-1dof", preset="matlab-listing", params={"relay_hz": 10.0}, dc_law=law)
    smap = StroboscopicMap(pb, tol=1e-10)
    smap = smap.at(dict(V=volts))
    names = list(pb.system.state_names)
    return pb, smap, [names.index("x"), names.index("v")]


def _stretch(o) -> np.ndarray:
    return o.tangent_stretch(np.maximum(np.nanmax(np.abs(o.points), axis=0), 1e-9))


def windows(law: str, volts: float, n_starts: int = 24) -> None:
    pb, smap, xv = _setup(law, volts)
    starts = list(np.asarray(make_starts(pb, "box", n=n_starts, box=BOX, seed=2).points, dtype=float))
    pre = smap.orbits([{}] * len(starts), starts, 300, batch_size=4, events=False)
    runs = smap.orbits([{}] * len(starts), [o.final for o in pre], N, k0=300, batch_size=4, tangent=True)
    thr, tally = lyapunov_threshold(W), {}
    for o in runs:
        p, s, row = o.points[:, xv] / SCALE, _stretch(o), []
        for a in range(0, N - W + 1, W):
            lam, lo, hi = exponent_interval(s[a:a + W])
            kind = ("F" if np.ptp(p[a:a + W, 0]) < 1e-6 else "C" if lo > thr else
                    "Q" if -thr <= lo and hi <= thr else "S" if lo <= thr <= hi and abs(lam) <= thr else
                    "P" if hi < -thr else "O")
            key = kind + ("t" if torus_evidence(p[a:a + W], 16)[0] else "-")
            tally[key] = tally.get(key, 0) + 1
            row.append(key)
        print("   " + " ".join(row))
    print(f"{law} {volts:g} V: windows by verdict {dict(sorted(tally.items()))} (threshold {thr:.4f})")


def switch_on_set(law: str, volts: float) -> None:
    pb, smap, xv = _setup(law, volts)
    start = np.asarray(make_starts(pb, "switch-on", n=1, seed=1).points, dtype=float)[0]
    o = smap.orbits([{}], [start], N, batch_size=4, tangent=True)[0]
    p, s = o.points[:, xv] / SCALE, _stretch(o)
    print(f"{law} {volts:g} V switch-on: {np.mean(o.impacts_per_step):.3f} impacts per period")
    for a in range(0, N - W + 1, W):
        w = p[a:a + W]
        rho = rotation_number(w)[0]
        b = Fraction(rho).limit_denominator(16).denominator
        extent = float(np.max(np.ptp(w, axis=0)))
        d = np.max(np.abs(w[b:] - w[:-b]), axis=1)
        k = np.arange(d.size)
        rate = math.exp(np.polyfit(k[d > 0], np.log(d[d > 0]), 1)[0])
        torus, why, k01, _ = torus_evidence(w, 16)
        print(f"   periods {a:5d}-{a + W:5d}: exponent {np.mean(s[a:a + W]):+.4f}, rotation number {rho:.5f}, lag-{b} "
              f"distance up to {d.max() / extent:.2e} of the extent, its rate 1 {1 - rate:+.1e} per period, locked lag "
              f"{locked_lag(w)[0]}, 0-1 K {k01:.2f}: torus {torus} {why[:70]}")
    if volts == 95.0:
        po = find_periodic_orbit(smap, o.state(2000), 6, k0=2000, tol=1e-10, atol=1e-9)
        print(f"   Newton at period 6 from period 2000: residual {po.residual:.2g}, |multipliers| "
              f"{np.round(np.sort(np.abs(po.multipliers))[::-1], 6)}, stable {po.stable}")


def main() -> None:
    clock = time.perf_counter()
    for law, volts in (("listing", 80.0), ("listing", 220.0), ("measured", 99.5), ("measured", 179.5),
                       ("measured", 213.0)):
        windows(law, volts)
    for volts in (80.0, 95.0):
        switch_on_set("listing", volts)
    print(f"{time.perf_counter() - clock:.0f} s")


if __name__ == "__main__":
    main()
