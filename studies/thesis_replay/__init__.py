"""Replay of the thesis' own 1-DOF runs (listings C.1-C.3, C.9-C.13), under each DC-force law.

The thesis' conditions exactly: the matlab-listing numbers (Table C.1: R = 25 ohm, C = 2.8e-4 F,
k = 1e5 N/m, c = 10 N s/m), the listing's AC sign (C.2 subtracts the signed force, which reverses
it), the derivative ("thesis") circuit of eq 4.16, the listings' start on the stop at rest with
i = 0.1 A, and tf = 3 s.  The listing never sets V, so both 25 V (the text's value) and 90 V (the
experiments' upper end) run.  Relay 2, 3, ..., 10 Hz, under each DC law (docs/model.md section 1):
`listing` (C.9 as printed, what the thesis ran), `fit` (eqs 4.6-4.7) and `measured` (Table 4.1
only, zero beyond 29 mm).  Beside each 3 s run, the same run continued to 1000 relay periods.
Nothing is tuned to agree.

Labels are periods of the stroboscopic samples of (x, v) at the relay period (the displacement's
period, which the thesis reads off its plots):
- "3 s supports": samples 1..3W of the 3 s run (the first relay period dropped) recur with
  period n to 1 % of their range (a plot's resolution);
- "1000 periods": the last 400 of 1000 relay periods recur to 1e-6 (the toolkit's tolerance).
  A record without a period up to 16 gets the largest Lyapunov exponent of the relay-period map
  along it (Benettin, `bifurc.labels.lyapunov`, per relay period): "chaotic" above the window's
  threshold 2 ln(400)/400 = 0.030; within it "quasi-periodic" only with positive evidence of a
  torus, as the sweeps require (`bifurc.labels.evidence.torus_evidence`: the 0-1 test's K below
  0.25, a converged rotation number, no recurrence at a nearby fraction's period), else
  "aperiodic" with the reason; "aperiodic" also where the exponent is undetermined.
- "at rest on the stop": x never exceeded 0 over the whole run.
"""
from __future__ import annotations

import math
import time as _time
from pathlib import Path

import numpy as np

from maps.studykit import start_flags

from .. import provenance

NAME = "thesis-replay"
SCENE = "thesis-1dof"
PRESET = "matlab-listing"
AC_SIGN = "listing"
CIRCUIT = "thesis"
LAWS = ("listing", "fit", "measured")
#: the listings' start (C.1): on the stop, at rest, i = 0.1 A
X0 = {"x": 0.0, "v": 0.0, "i": 0.1, "z": 0.0}
T_THESIS = 3.0           # tf = 3 in the listings [s]
SENSOR_MM = 5.0          # the thesis' displacement sensor spans +-5 mm
LONG_PERIODS = 1000         # the long run: enough for a 400-period window after a 600-period transient
LONG_WINDOW = 400        # relay periods classified at the end of the long run (the torus test needs 400)
DT = 1e-3                # sampling step of x for the spectrum and the figure [s]
TOL = 1e-12
FULL = dict(freqs=tuple(range(2, 11)), volts=(25.0, 90.0), long=LONG_PERIODS, window=LONG_WINDOW)
QUICK = dict(freqs=(5, 6), volts=(90.0,), long=120, window=40)     # for the tests: under 2 minutes
NEAR_STOP = 1e-3         # the AC force "at the stop" is its peak while the bar is within 1 mm of it [m]
THESIS_NUMERICAL = {2: 1, 3: 1, 4: 1, 5: 1, 6: 2, 7: 2, 8: 2, 9: 1, 10: 1}  # Fig 4.27, section 4.8


def _label(points, imps, rtol, atol, max_period=16, lyapunov=math.nan):
    """(text, period) of stroboscopic (x, v) samples: 'period-n (m impacts)', 'period-n, no impact',
    'chaotic', 'quasi-periodic' (given a Lyapunov exponent) or 'aperiodic'."""
    from bifurc.labels import classify_orbit, lyapunov_threshold
    p = np.asarray(points, float)[:, :2]
    if p.shape[0] < 3:
        return "too short", 0
    c = classify_orbit(p, np.asarray(imps), max_period=max_period, rtol=rtol, atol=atol,
                       scale=np.maximum(np.ptp(p, axis=0), atol), lyapunov=lyapunov,
                       lyap_tol=lyapunov_threshold(p.shape[0] - 1))
    if c["label"] == "quasi-periodic":      # positive evidence of a torus, as sweeps require
        from bifurc.labels import torus_evidence
        torus, why, k01, rho = torus_evidence(p / np.maximum(np.ptp(p, axis=0), atol), max_period)
        if not torus:
            return f"aperiodic (lambda {lyapunov:+.2f} near 0, but {why})", 0
        return f"quasi-periodic (lambda {lyapunov:+.2f}, 0-1 K {k01:.2f}, rotation number {rho:.4f})", 0
    if c["label"] == "chaotic":
        return f"{c['label']} (lambda {lyapunov:+.2f})", 0
    if c["label"] == "periodic":
        return f"period-{c['period']} ({c['impacts_per_period']} impact{'s' if c['impacts_per_period'] != 1 else ''})", \
            c["period"]
    if c["label"] == "periodic-no-impact":
        return f"period-{c['period']}, no impact", c["period"]
    if c["label"] in ("escaped", "failed"):
        return c["label"], 0
    return f"aperiodic (n <= {max_period} off by >= {c['recurrence']:.2g} x tol)", 0


def _peak(x, dt):
    """Frequency [Hz] of the largest non-zero bin of x's spectrum (mean removed)."""
    x = np.asarray(x, float)
    x = x[np.isfinite(x)]
    if x.size < 8 or np.ptp(x) == 0.0:
        return math.nan
    spec = np.abs(np.fft.rfft(x - x.mean()))
    f = np.fft.rfftfreq(x.size, dt)
    return float(f[1 + int(np.argmax(spec[1:]))])


def well_frequency(law: str, seconds: float = 30.0) -> float:
    """The DC well's own frequency [Hz]: the dc-only bar released at rest on the stop, FFT of x
    over ``seconds`` (NaN for the measured law, which has no force at the stop)."""
    import maps
    if law == "measured":
        return math.nan
    ds = maps.simulate("dc-only", t_end=seconds, dt=DT, preset=PRESET, dc_law=law, x0={"x": 0.0, "v": 0.0})
    return _peak(ds.x.values, DT)


def measure(W: float, V: float, law: str, *, preset=PRESET, ac_sign=AC_SIGN, circuit=CIRCUIT, x0=None,
            long_periods=LONG_PERIODS, long_window=LONG_WINDOW, tol=TOL) -> dict:
    """One replay: relay W [Hz], source amplitude V [V], DC law; the 3 s window and the long run."""
    from maps import Escaped, HybridRun, IntegrationFailure, problem
    pb = problem(SCENE, preset, {"V": V, "relay_hz": W}, X0 if x0 is None else x0, circuit=circuit, ac_sign=ac_sign,
                 dc_law=law)
    p, system, y0 = dict(pb.values), pb.system, pb.state_vector()
    n3 = int(round(T_THESIS * W))
    K = max(int(long_periods), n3)
    t_grid = np.arange(0.0, K / W + 0.5 * DT, DT)
    samples = np.full((t_grid.size, len(system.states)), np.nan)

    def on_segment(c_out, ta, tb):
        lo, hi = np.searchsorted(t_grid, ta, side="left"), np.searchsorted(t_grid, tb, side="right")
        if hi > lo:
            samples[lo:hi] = c_out(t_grid[lo:hi])

    run = HybridRun(system, p, y0, tol=tol, max_events=None)
    strobe, imps, status = [run.y], [], "ok"
    clock = _time.perf_counter()
    try:
        for k in range(1, K + 1):
            run.advance(k / W, on_segment=on_segment)
            strobe.append(run.y)
            imps.append(sum(ev.name == "contact" for ev in run.events))
            run.events = []
    except Escaped:
        status = "escaped"
    except IntegrationFailure:
        status = "failed"
    seconds = _time.perf_counter() - clock
    strobe = np.array(strobe)
    ix = system.state_names.index("x")
    x = samples[:, ix]
    in3 = t_grid <= T_THESIS + 1e-12
    long_from = max(0, len(imps) - int(long_window))
    F_dc, F_ac, i_peak, near = _forces_at_stop(system, p, samples[in3])
    lyap = math.nan
    weight_net = 0.0 if law != "measured" else -p["m"] * p["g"]     # what the weight adds beyond the offset
    if status == "ok" and len(imps) >= K:
        label3, per3 = _label(strobe[1:n3 + 1], imps[1:n3], rtol=1e-2, atol=1e-6, max_period=8)
        labelL, perL = _label(strobe[long_from:], imps[long_from:], rtol=1e-6, atol=1e-9)
        if not perL and int(long_window) >= 3:     # not periodic: the Lyapunov exponent tells chaos apart
            from bifurc.labels import lyapunov_along
            from maps import StroboscopicMap
            smap = StroboscopicMap(pb, tol=tol)
            lyap = lyapunov_along(smap.step, strobe[long_from:], k0=long_from,
                                  scale=np.maximum(np.abs(strobe[long_from:]).max(axis=0), 1e-9))
            labelL, perL = _label(strobe[long_from:], imps[long_from:], rtol=1e-6, atol=1e-9, lyapunov=lyap)
    else:
        label3 = labelL = status
        per3 = perL = 0
    xs3 = x[in3]
    long_mask = t_grid >= long_from / W
    if np.nanmax(x) <= 0.0 and status == "ok":     # the bar never left the stop: say so, not "period-1"
        label3 = labelL = "at rest on the stop"
    return {
        "relay_hz": W, "V": V, "dc_law": law, "ac_sign": ac_sign, "long_periods": K, "long_window": int(long_window),
        "status": status, "t_end": run.t, "seconds": seconds,
        "label_3s": label3, "period_3s": per3, "label_long": labelL, "period_long": perL,
        "fft_peak_3s_hz": _peak(xs3, DT), "fft_peak_long_hz": _peak(x[long_mask], DT),
        "x_min_mm": 1e3 * float(np.nanmin(xs3)), "x_max_mm": 1e3 * float(np.nanmax(xs3)),
        "x_max_long_mm": 1e3 * float(np.nanmax(x)),
        "impacts_per_period_3s": float(sum(imps[:n3])) / n3 if len(imps) >= n3 else math.nan,
        "impacts_per_period_long": float(np.mean(imps[long_from:])) if imps[long_from:] else math.nan,
        "F_dc_stop_N": F_dc, "F_ac_peak_stop_N": F_ac, "weight_N": p["m"] * p["g"], "weight_net_N": weight_net,
        "i_peak_A": i_peak, "lyapunov_long": lyap, "ac_near_stop": near, "t": t_grid[in3], "x": xs3,
    }


def _forces_at_stop(system, p, samples) -> tuple:
    """The force budget at the stop (x = 0, at rest) over the 3 s window's ``samples``: the law's DC
    force (the cubics' + m g offset cancels the weight, the measured law has none), the AC force at
    the peak current (signed: + away from the stop; within 1 mm of the stop where the bar came that
    near), the peak current [A], and whether the bar came that near."""
    ix, ii = system.state_names.index("x"), system.state_names.index("i")
    y_stop = np.zeros(len(system.states))
    flags = start_flags(system, 0.0, y_stop, p, {"contact": 0.0, "stuck_bar": 0.0})
    F_dc = float(system.evaluate(["F_dc"], y_stop, p, flags)[0])
    i_peak = float(np.nanmax(np.abs(samples[:, ii])))
    near = samples[:, ix] <= NEAR_STOP
    if near.any():     # the AC force the bar felt within 1 mm of the stop, at its largest
        F_ac = max((float(system.evaluate(["F_ac"], y, p, flags)[0]) for y in samples[near]), key=abs)
    else:              # never near the stop: the force it would feel there at the peak current
        y_stop[ii] = i_peak
        F_ac = float(system.evaluate(["F_ac"], y_stop, p, flags)[0])
    return F_dc, F_ac, i_peak, bool(near.any())


def budget(r) -> str:
    """The force budget at the stop of a replay row ``r`` (:func:`measure`), in words."""
    where = "within 1 mm of the stop" if r["ac_near_stop"] else "at the stop (never reached: at the peak current)"
    weight = (f", weight {-r['weight_N']:.2f} N" if r["dc_law"] == "measured"
              else " (the weight cancels the cubic's + m g)")
    return (f"DC force at the stop {r['F_dc_stop_N']:+.2f} N ({r['dc_law']} law), peak AC force {where} "
            f"{r['F_ac_peak_stop_N']:+.2f} N{weight}")


def _motion_cause(r, f_well, short=False) -> str:
    """What the measurements say drives the motion away from the thesis' picture."""
    fx = r["fft_peak_long_hz"]
    if math.isfinite(f_well) and math.isfinite(fx) and abs(fx - f_well) <= r["relay_hz"] / r["long_window"] + 1.0 / T_THESIS:
        if short:
            return (f"the DC force at the stop ({r['F_dc_stop_N']:+.2f} N) outweighs the peak AC force near it "
                    f"({r['F_ac_peak_stop_N']:+.2f} N) and throws the bar across the DC well")
        return (f"x oscillates at the DC well's own frequency ({f_well:.2f} Hz for the dc-only bar released on the "
                f"stop; FFT peak of the long run {fx:.2f} Hz), not locked to the relay: {budget(r)}")
    if r["dc_law"] == "measured" and r["F_ac_peak_stop_N"] > r["weight_N"]:
        reach = (f"flies up to {r['x_max_long_mm']:.0f} mm, into the table's range (x >= 33.5 mm), and back"
                 if r["x_max_long_mm"] >= 33.5 else f"bounces within {r['x_max_long_mm']:.1f} mm of it, below the "
                                                     f"table's range (x >= 33.5 mm)")
        if short:
            return (f"the listing's reversed AC force near the stop ({r['F_ac_peak_stop_N']:+.2f} N, away from it) "
                    f"exceeds the weight ({r['weight_N']:.2f} N)")
        return f"the listing's reversed AC force lifts the bar off the stop ({budget(r)}), and it {reach}"
    return budget(r)


def disagreements(r: dict, f_well: float) -> list[str]:
    """One sentence per disagreement with the thesis, each naming the cause measured in this row."""
    W, out = r["relay_hz"], []
    n_th = THESIS_NUMERICAL.get(int(W))
    if r["status"] != "ok":
        return [f"The run ended {r['status']} at t = {r['t_end']:.3g} s: {budget(r)}."]
    never_left = r["x_max_long_mm"] <= 0.0
    if never_left:
        out.append(f"The bar never leaves the stop in {r['long_periods']} relay periods (x <= 0): {budget(r)}.")
    elif r["period_long"] != n_th:
        lam = r["lyapunov_long"]
        chaos = (f"; largest Lyapunov exponent over the last {r['long_window']} periods {lam:+.2f} per relay period"
                 if math.isfinite(lam) else "")
        if r["period_3s"] == n_th:
            out.append(f"Thesis period-{n_th} (Fig 4.27): the 3 s run supports it, but the last {r['long_window']} of "
                       f"{r['long_periods']} relay periods are {r['label_long']}: the 3 s run is a transient{chaos}.")
        else:
            out.append(f"Thesis period-{n_th} (Fig 4.27), here {r['label_long']} after {r['long_periods']} relay periods "
                       f"and {r['label_3s']} in 3 s: {_motion_cause(r, f_well)}{chaos}.")
    fx = r["fft_peak_3s_hz"]
    if not never_left and math.isfinite(fx) and abs(fx - W) > 1.0 / T_THESIS + 1e-9:
        out.append(f"The spectrum of x over 3 s peaks at {fx:.2f} Hz, not at the relay's {W:g} Hz: "
                   f"{_motion_cause(r, f_well, short=True)}.")
    lo, hi = r["x_min_mm"], r["x_max_mm"]
    if hi > SENSOR_MM or lo < -SENSOR_MM:
        out.append(f"x spans {lo:.1f} to {hi:.1f} mm in 3 s, beyond the thesis' +-{SENSOR_MM:g} mm sensor: "
                   f"{_motion_cause(r, f_well, short=True)}.")
    return out


def figure(rows, V, path):
    """3 s time histories, one panel per relay frequency, one line per DC law; the sensor band shaded.
    Sets no matplotlib backend (the command line picks one; a notebook keeps its own)."""
    import matplotlib.pyplot as plt

    from bifurc.studykit import save_figure
    freqs = sorted({r["relay_hz"] for r in rows if r["V"] == V})
    n = len(freqs)
    cols = min(3, n)
    nrows = math.ceil(n / cols)
    fig, axes = plt.subplots(nrows, cols, figsize=(4.2 * cols, 2.8 * nrows), sharex=True, squeeze=False)
    colours = {"listing": "C3", "fit": "C0", "measured": "C2"}
    for ax, W in zip(axes.ravel(), freqs):
        ax.axhspan(-SENSOR_MM, SENSOR_MM, color="0.9", label="thesis sensor +-5 mm")
        for r in rows:
            if r["V"] == V and r["relay_hz"] == W:
                ax.plot(r["t"], 1e3 * r["x"], lw=0.8, color=colours[r["dc_law"]], label=f"dc_law {r['dc_law']}")
        ax.set_title(f"relay {W:g} Hz, V = {V:g} V", fontsize=9)
        ax.set_ylabel("x [mm]")
        ax.grid(alpha=0.3)
    for ax in axes.ravel()[n:]:
        ax.set_visible(False)
    for ax in axes[-1]:
        ax.set_xlabel("t [s]")
    axes[0, 0].legend(fontsize=7, loc="upper right")
    fig.suptitle("Thesis replay: matlab-listing numbers, listing AC sign, start on the stop (i = 0.1 A), 3 s",
                 fontsize=10)
    fig.tight_layout()
    save_figure(fig, path, overwrite=True, dpi=110)   # the study refused an occupied folder before

def report(rows, wells, quick, seconds, physical=()) -> str:
    size = QUICK if quick else FULL
    lines = [f"# {NAME}: the thesis' own runs, replayed", "", (__doc__ or "").strip(), "",
             f"Size: {'quick' if quick else 'full'}: relay {', '.join(f'{w:g}' for w in size['freqs'])} Hz, "
             f"V = {', '.join(f'{v:g}' for v in size['volts'])} V, laws {', '.join(LAWS)}; long runs "
             f"{size['long']} relay periods, the last {size['window']} classified; "
             f"{len(rows)} runs in {seconds:.0f} s (heyoka tol {TOL:g}).", "", provenance(NAME, quick), "",
             "The DC well's own frequency (dc-only bar released at rest on the stop, FFT over 30 s): "
             + ", ".join(f"{law} {f:.2f} Hz" if math.isfinite(f) else f"{law}: no force at the stop"
                         for law, f in wells.items()) + ".", ""]
    for V in size["volts"]:
        lines += [f"## V = {V:g} V (figure: `replay_{V:g}V.png`)", "",
                  f"| relay [Hz] | DC law | thesis (Fig 4.27) | 3 s run supports | {size['long']} relay periods | "
                  "FFT peak of x, 3 s [Hz] | x range in 3 s [mm] (thesis +-5) | impacts per relay period, 3 s / long | "
                  "at the stop: DC, peak AC, weight [N] |",
                  "|---|---|---|---|---|---|---|---|---|"]
        notes = []
        for r in rows:
            if r["V"] != V:
                continue
            W = r["relay_hz"]
            weight = f"{-r['weight_N']:.2f}" + (" (cancelled by + m g)" if r["dc_law"] != "measured" else "")
            lines.append(
                f"| {W:g} | {r['dc_law']} | period-{THESIS_NUMERICAL.get(int(W))} | {r['label_3s']} | {r['label_long']} | "
                f"{r['fft_peak_3s_hz']:.2f} (relay {W:g}) | {r['x_min_mm']:.1f} .. {r['x_max_mm']:.1f} | "
                f"{r['impacts_per_period_3s']:.2f} / {r['impacts_per_period_long']:.2f} | "
                f"{r['F_dc_stop_N']:+.2f}, {r['F_ac_peak_stop_N']:+.2f}, {weight} |")
            for s in disagreements(r, wells[r["dc_law"]]):
                notes.append(f"- {W:g} Hz, dc_law {r['dc_law']}: {s}")
        lines += ["", "Disagreements with the thesis, each with its measured cause:", ""]
        lines += notes or ["None."]
        lines.append("")
    if physical:
        lines += ["## The measured law with the physical AC sign", "",
                  "The same runs (listings' start on the stop at rest, i = 0.1 A) under `measured` with the AC force "
                  "of eq 4.8 as derived (toward the AC solenoid, i.e. down onto the stop): no DC force acts at the "
                  "stop (xa = -62.5 mm lies outside Table 4.1).", "",
                  f"| V [V] | relay [Hz] | highest x in {size['long']} relay periods [mm] | DC at the stop [N] | "
                  "peak AC near the stop [N] | weight [N] |", "|---|---|---|---|---|---|"]
        for r in physical:
            lines.append(f"| {r['V']:g} | {r['relay_hz']:g} | {r['x_max_long_mm']:.3g} | {r['F_dc_stop_N']:+.2f} | "
                         f"{r['F_ac_peak_stop_N']:+.2f} | {-r['weight_N']:.2f} |")
        left = [r for r in physical if r["x_max_long_mm"] > 0.0]
        lines += ["", ("Under `measured` with the physical AC sign a bar at rest on the stop never leaves it: "
                       "every force at the stop points into it." if not left else
                       f"{len(left)} of these runs leave the stop: " + ", ".join(
                           f"{r['relay_hz']:g} Hz at {r['V']:g} V" for r in left) + "."), ""]
    return "\n".join(lines)


def run(out, quick=False, progress=True, overwrite=False) -> dict:
    """Every replay into folder ``out``: ``report.md``, ``replay_<V>V.png``, ``replay.csv`` (an
    existing report refused unless ``overwrite``)."""
    from bifurc.studykit import refuse_existing
    out = Path(out)
    refuse_existing(out / "report.md", overwrite, hint="use --force")
    out.mkdir(parents=True, exist_ok=True)
    size = QUICK if quick else FULL
    clock = _time.perf_counter()
    wells = {law: well_frequency(law) for law in LAWS}
    rows = []
    for V in size["volts"]:
        for W in size["freqs"]:
            for law in LAWS:
                r = measure(float(W), V, law, long_periods=size["long"], long_window=size["window"])
                rows.append(r)
                if progress:
                    print(f"V {V:g} V, relay {W:g} Hz, {law:8s}: 3 s {r['label_3s']}; long {r['label_long']}; "
                          f"FFT {r['fft_peak_3s_hz']:.2f} Hz ({r['seconds']:.1f} s)", flush=True)
    physical = []   # the finding: under the measured law with the physical AC sign the bar stays on the stop
    for V in size["volts"]:
        for W in size["freqs"]:
            physical.append(measure(float(W), V, "measured", ac_sign="physical", long_periods=size["long"],
                                    long_window=size["window"]))
    seconds = _time.perf_counter() - clock
    for V in size["volts"]:
        figure(rows, V, out / f"replay_{V:g}V.png")
    (out / "report.md").write_text(report(rows, wells, quick, seconds, physical))
    _csv(rows, out / "replay.csv")
    return {"rows": rows, "wells": wells, "seconds": seconds, "physical": physical}


_UNITS = {"relay_hz": "Hz", "V": "V", "t_end": "s", "seconds": "s", "fft_peak_3s_hz": "Hz", "fft_peak_long_hz": "Hz",
          "x_min_mm": "mm", "x_max_mm": "mm", "x_max_long_mm": "mm", "impacts_per_period_3s": "1",
          "impacts_per_period_long": "1", "F_dc_stop_N": "N", "F_ac_peak_stop_N": "N", "weight_N": "N",
          "weight_net_N": "N", "i_peak_A": "A"}


def _csv(rows, path):
    keys = [k for k in rows[0] if k not in ("t", "x")]
    head = ",".join(f"{k} [{_UNITS[k]}]" if k in _UNITS else k for k in keys)
    body = [",".join(f'"{r[k]}"' if isinstance(r[k], str) else f"{r[k]:.10g}" for k in keys) for r in rows]
    Path(path).write_text("# thesis replay (studies/thesis_replay/): one row per run\n" + head + "\n"
                          + "\n".join(body) + "\n")


def findings(results, quick) -> list:
    """What the report states, per run (V, relay frequency, DC law): the label a 3 s run supports and the
    long run's label (texts, exact), x's spectral peak over 3 s (+- one frequency bin, 1/3 Hz) and x's
    range over 3 s (+- 0.1 mm); the DC force at the stop (+- 0.01 N); the DC well's own frequency per law
    (+- 0.05 Hz); and, under the measured law with the physical AC sign, the largest height the bar
    reaches (+- 0.01 mm)."""
    from bifurc.studykit import Finding
    out = [Finding(f"DC well's own frequency, {law}", float(f), 0.05, "Hz") for law, f in results["wells"].items()]
    for r in results["rows"]:
        tag = f"{r['V']:g} V, {r['relay_hz']:g} Hz, {r['dc_law']}"
        out += [Finding(f"{tag}: 3 s run supports", _plain(r["label_3s"])),
                Finding(f"{tag}: long run", _plain(r["label_long"])),
                Finding(f"{tag}: x's spectral peak over 3 s", float(r["fft_peak_3s_hz"]), 1 / T_THESIS, "Hz"),
                Finding(f"{tag}: x's largest value over 3 s", float(r["x_max_mm"]), 0.1, "mm"),
                Finding(f"{tag}: DC force at the stop", float(r["F_dc_stop_N"]), 0.01, "N")]
    for r in results["physical"]:
        out.append(Finding(f"{r['V']:g} V, {r['relay_hz']:g} Hz, measured, physical AC sign: x's largest value "
                           "over 3 s", float(r["x_max_mm"]), 0.01, "mm"))
    return out


def _plain(label: str) -> str:
    """A label without its numbers' noise: a period's text with decimals dropped ("period-1 (20 impacts)"),
    any other class by its words alone ("aperiodic", "chaotic", "quasi-periodic")."""
    import re
    text = str(label).replace("|", "/")
    if text.startswith("period"):
        return re.sub(r"[-+]?\d+\.\d+(e[-+]?\d+)?", "#", text)
    return text.split(" (")[0]
