"""Where the sensitivity study's time goes, and the full form's wall time on 2 cores (issue 30 section 2).

Measured side by side in one run:

1. one sample of the full form (9 inputs, 9 x 9 cells, 200 transient + 60 recorded relay periods,
   prototype 120 periods), split into its regime map, its strokes and its prototype run; the sample is
   the first of the design's Sobol rows with a P1-1 cell (one stroke per such cell);
2. the stroke of those cells two ways: the previous path (``maps.simulate`` over every period at
   dt = T / 1000, tol 1e-12) and ``studies.sensitivity.stroke`` (a bare scalar run at tol 1e-10 without
   observation stops, sampled in the last period only); the values agree to 1e-6 mm;
3. the medium form (the full form's inputs and cells at N = 8: 107 of the 2835 samples) on ``--workers``
   processes, from a fresh output folder (pool start and compilations included).  The full form's wall
   time is EXTRAPOLATED from it, samples x (medium wall / medium samples), and printed as such.

    python benchmarks/sensitivity.py [--workers 2] [--out out/bench-sensitivity] [--skip-medium]
"""
from __future__ import annotations

import argparse
import os
import resource
import shutil
import time

import numpy as np


def one_sample(S, row):
    """(seconds of the map, strokes, prototype; strokes old and new [mm] with their seconds)."""
    import maps
    from bifurc.labels.codes import ClassCode
    from bifurc.sweeps.regime import regime_map
    size = S.FULL
    sample = dict(zip(size["inputs"], map(float, row)))
    vf, n = sample["v_factor"], size["n"]
    params = S._values(sample, ("F_dc_sat", "c_air", "dc_scale", "R", "C", "k", "c"))
    relays, volts = np.linspace(*S.RELAY, n), np.linspace(*S.VOLTS, n) * vf
    t = time.perf_counter()
    ds = regime_map(S.SCENE, "relay_hz", relays, "V", volts, preset=S.PRESET, dc_law=S.LAW, params=params,
                    transient=size["transient"], record=size["record"], workers=1, progress=False,
                    error_sample=0, lyapunov=False)
    t_map = time.perf_counter() - t
    hit = ((ds.period_mechanical == 1) & (ds.impacts_per_period_mechanical == 1)
           & (ds.class_code == ClassCode.PERIODIC)).values
    total = size["transient"] + size["record"]
    old, new, t_old, t_new = [], [], 0.0, 0.0
    for i, j in zip(*np.nonzero(hit)):
        p = dict(params, relay_hz=float(relays[i]), V=float(volts[j]))
        t = time.perf_counter()
        h = maps.simulate(S.SCENE, periods=total, preset=S.PRESET, dc_law=S.LAW, params=p, dt=1e-3 / float(relays[i]))
        old.append(float(np.ptp(h.x.values[h.time.values >= (total - 1) / float(relays[i])])) * 1e3)
        t_old += time.perf_counter() - t
        t = time.perf_counter()
        new.append(S.stroke(p, total) * 1e3)
        t_new += time.perf_counter() - t
    p2 = dict(S._values(sample, ("F_dc_sat", "c_air", "P_max")), V=90.0 * vf, relay_hz=6.0,
              dc_scale=1.44 * sample.get("dc_scale", 1.0))
    t = time.perf_counter()
    maps.simulate("prototype", periods=size["periods_2dof"], dc_law=S.LAW, soil="drift", params=p2)
    t_proto = time.perf_counter() - t
    return t_map, t_proto, old, new, t_old, t_new


def _cpu() -> float:
    """CPU seconds (user + system) of this process and of its finished child processes."""
    own, kids = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + kids.ru_utime + kids.ru_stime


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--out", default="out/bench-sensitivity")
    ap.add_argument("--skip-medium", action="store_true")
    a = ap.parse_args()
    import studies.sensitivity as S
    print(f"load average at start: {os.getloadavg()}; cores: {os.cpu_count()}")
    rows, n_oat = S.design(S.FULL)
    S.evaluate(dict(zip(S.QUICK["inputs"], rows[0][:3])), S.QUICK)   # compile outside the timings
    for k in range(n_oat, len(rows)):
        got = one_sample(S, rows[k])
        if got[2]:
            break
    t_map, t_proto, old, new, t_old, t_new = got
    print(f"sample {k}: map {t_map:.2f} s, prototype {t_proto:.2f} s, {len(old)} P1-1 cells")
    print(f"  strokes [mm] simulate: {np.round(old, 6).tolist()}  stroke(): {np.round(new, 6).tolist()}  "
          f"max |diff| {np.max(np.abs(np.subtract(old, new))):.2e} mm")
    print(f"  stroke time: simulate {t_old:.2f} s, stroke() {t_new:.2f} s, ratio {t_old / max(t_new, 1e-9):.1f}")
    if a.skip_medium:
        return
    shutil.rmtree(a.out, ignore_errors=True)
    t = time.perf_counter()
    cpu0 = _cpu()
    res = S.run(a.out, size=S.MEDIUM, workers=a.workers, progress=True)
    wall, cpu = time.perf_counter() - t, _cpu() - cpu0
    n_full = len(rows)
    print(f"medium form: {res['n_samples']} samples in {wall:.0f} s wall on {a.workers} workers "
          f"({wall / res['n_samples']:.2f} s per sample); samples with a P1-1 cell: "
          f"{int(np.sum(np.asarray(res['outputs_per_sample']['share_p1']) > 0))}")
    print(f"  CPU of this process and its finished workers: {cpu:.0f} s ({cpu / res['n_samples']:.2f} s per sample)")
    print(f"EXTRAPOLATED full form ({n_full} samples), not measured: {n_full * wall / res['n_samples'] / 3600:.2f} h "
          f"wall on {a.workers} workers at this load; {n_full * cpu / res['n_samples'] / 3600:.2f} h of CPU, "
          f"{n_full * cpu / res['n_samples'] / 3600 / a.workers:.2f} h on {a.workers} idle cores")
    print(f"load average at end: {os.getloadavg()}")


if __name__ == "__main__":
    main()
