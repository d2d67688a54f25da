"""The prototype's progression into the soil against the thesis' Tables 5.2-5.5 (issue 18, section 4).

Every rate is a sweep on the batch engine (``bifurc.sweep``, progression measures of
:mod:`maps.progression` over the recorded window), under each soil law (viscous, coulomb, drift).
Nothing is tuned: the scene's own values (``prototype``: dynamics-listing numbers, dc_scale 1.44,
the listing C.9 DC law) and the drift law's assumed defaults (docs/model.md).

Conventions this study assumes, stated in its report:
- the thesis' AC voltages (40-110 V) are RMS: the source amplitude is V = sqrt(2) x RMS (docs/model.md 4);
- the thesis gives no actuator-voltage-to-force mapping: F_static = 3.11 N/V x actuator volts, i.e.
  proportional to the actuator's DC voltage and 31.1 N (listing C.14) at Table 5.5's 10 V;
- the measured scatter: two runs at the same nominal settings (6 Hz, AC 90 V, actuator 10 V) gave
  4.92 mm/s (Table 5.4) and 7.93 mm/s (Table 5.5), so a measured rate is compared within the band
  [x 4.92/7.93, x 7.93/4.92] = [x 0.62, x 1.61].

"Thesis geometry" is the scene as it stands: no rear stop, no coil delay, the DC well's rest at d_dc = 62.5 mm.
The stated variants (studies/prototype_progression/variants.py) add the rear stop, the coil delay, both, and the
dc-well study's rest height of 3 mm; the escaped frequencies are re-run as time histories; and the 1-DOF model's
4 Hz mechanical period-1 cells under `listing` are swept in V.  Every finding names its variant.
"""
from __future__ import annotations

import math
import time as _time
from pathlib import Path

import numpy as np

from .. import provenance

NAME = "prototype-progression"
SCENE = "prototype"
LAWS = ("viscous", "coulomb", "drift")
RMS_TO_AMPLITUDE = math.sqrt(2.0)
#: assumed actuator mapping [N per actuator volt]: 31.1 N (listing C.14) at Table 5.5's 10 V
ACTUATOR_N_PER_V = 3.11
#: Tables 5.4 and 5.5 at the same nominal settings (6 Hz, AC 90 V, actuator 10 V) [mm/s]
SAME_SETTINGS = (4.9237, 7.9334)
BAND = (SAME_SETTINGS[0] / SAME_SETTINGS[1], SAME_SETTINGS[1] / SAME_SETTINGS[0])
REF = dict(relay_hz=6.0, ac_rms=90.0, actuator=10.0)      # the reference condition (both tables)
TOL = 1e-10

FULL = dict(freqs=tuple(np.round(np.arange(4.0, 8.81, 0.2), 1)), volts=tuple(range(40, 111, 10)),
            actuator=tuple(range(6, 21, 2)), ac_levels=(50, 70, 90), transient=100, record=100,
            map_force=tuple(np.round(np.geomspace(10, 1000, 9), 1)),
            map_threshold={"coulomb": tuple(np.round(np.geomspace(30, 1000, 9), 1)),
                           "drift": tuple(np.round(np.geomspace(10, 300, 9), 1))},
            map_freqs=tuple(np.round(np.arange(4.0, 8.81, 0.6), 1)), map_volts=(40, 60, 80, 100),
            depth_freqs=(4.0, 6.0, 8.0), depth_t_max=90.0, fig_5_22_t_max=1500.0,
            variant_freqs=(4.0, 4.4, 4.6, 5.2, 6.0, 7.0, 8.0, 8.8))
QUICK = dict(freqs=(4.4, 5.2, 6.0, 8.0), volts=(50, 90), actuator=(6, 20), ac_levels=(90,), transient=10, record=10,
             map_force=(31.1, 300.0), map_threshold={"coulomb": (100.0, 1000.0), "drift": (30.0, 100.0)},
             map_freqs=(5.0, 7.0), map_volts=(50, 90), depth_freqs=(6.0,), depth_t_max=15.0, fig_5_22_t_max=None,
             variant_freqs=(4.4, 5.2, 6.0, 8.0))


def _sweep(param, values, law, size, dc_law=None, options=None, **params):
    """Progression rate [mm/s], impact energy per period [J], class and status over ``values`` (``options``: the
    problem's structural options of a variant, e.g. ``rear_stop=True``)."""
    import bifurc
    import maps
    base = {"V": RMS_TO_AMPLITUDE * REF["ac_rms"], "F_static": ACTUATOR_N_PER_V * REF["actuator"]}
    base.update(params)
    pb = maps.problem(SCENE, params=base, soil=law, dc_law=dc_law, **(options or {}))
    ds = bifurc.sweep(pb, param, np.asarray(values, float),
                      bifurc.Diagram(transient=size["transient"], record=size["record"], tol=TOL, lyapunov=False,
                                     grazing=False, error_sample=0), run=bifurc.Run(workers=1, progress=False))
    sub = ds.isel(branch=0)
    return {"rate": 1e3 * sub.progression_rate.values,
            "energy": sub.impact_energy_per_period.values, "class": sub.class_code.values,
            "period": sub.period.values, "status": sub.status.values, "failure_time": sub.failure_time.values}


def measure(size, progress=True) -> dict:
    """Every sweep of the study: {"freq": {law: ...}, "volt": ..., "static": {(law, ac): ...}, maps, checks}."""
    from maps.studykit import load_table
    out = {"freq": {}, "volt": {}, "static": {}, "map_force": {}, "map_fv": {}, "dc_laws": {}}
    say = print if progress else (lambda *a, **k: None)
    for law in LAWS:
        clock = _time.perf_counter()
        out["freq"][law] = _sweep("relay_hz", size["freqs"], law, size)
        out["volt"][law] = _sweep("V", [RMS_TO_AMPLITUDE * v for v in size["volts"]], law, size,
                                  relay_hz=REF["relay_hz"])
        for ac in size["ac_levels"]:
            out["static"][(law, ac)] = _sweep("F_static", [ACTUATOR_N_PER_V * a for a in size["actuator"]], law,
                                              size, relay_hz=REF["relay_hz"], V=RMS_TO_AMPLITUDE * ac)
        for dc_law in ("fit", "measured"):
            out["dc_laws"][(law, dc_law)] = _sweep("relay_hz", [REF["relay_hz"]], law, size, dc_law=dc_law)
        say(f"{law}: frequency, voltage, static-force sweeps in {_time.perf_counter() - clock:.1f} s", flush=True)
    for law in ("coulomb", "drift"):
        clock = _time.perf_counter()
        name = "soil_friction" if law == "coulomb" else "P_max"
        out["map_force"][law] = (name, np.array([_sweep("F_static", size["map_force"], law, size, **{name: thr})["rate"]
                                                 for thr in size["map_threshold"][law]]))
        out["map_fv"][law] = np.array([_sweep("relay_hz", size["map_freqs"], law, size,
                                              V=RMS_TO_AMPLITUDE * v)["rate"] for v in size["map_volts"]])
        say(f"{law}: maps in {_time.perf_counter() - clock:.1f} s", flush=True)
    for law in LAWS:
        out.setdefault("reference", {})[law] = {V: reference(law, size, V) for V in (REF["ac_rms"], 0.0)}
    from . import depth
    out["depth"] = depth.measure(size, RMS_TO_AMPLITUDE * REF["ac_rms"], ACTUATOR_N_PER_V * REF["actuator"], say)
    from . import variants
    out["variants"] = variants.measure(size, _sweep, RMS_TO_AMPLITUDE * REF["ac_rms"], ACTUATOR_N_PER_V * REF["actuator"],
                                       quick=size is QUICK, say=say)
    from bifurc import Status
    gone = [f for f, st in zip(size["freqs"], out["freq"]["drift"]["status"]) if st == Status.ESCAPED]
    out["variants"]["escape_periods"] = size["transient"] + size["record"]
    out["variants"]["escapes"] = variants.escapes(gone, size["transient"] + size["record"],
                                                  RMS_TO_AMPLITUDE * REF["ac_rms"], ACTUATOR_N_PER_V * REF["actuator"])
    out["table55"] = load_table("progression_vs_frequency")
    out["tables52_54"] = load_table("progression_vs_static")
    return out


def reference(law, size, ac_rms) -> dict:
    """The reference condition (6 Hz, F_static 31.1 N) as one scalar-engine run of transient + record
    relay periods: rate over the record [mm/s], time-weighted fraction held by the soil, slider
    releases per relay period (the slider starts to yield, the rig to slip), impact energy per relay period [J]."""
    from maps.studykit import held_mode, held_time, impact_table, progression_measures
    from maps import run_scene
    W = REF["relay_hz"]
    p = {"relay_hz": W, "V": RMS_TO_AMPLITUDE * ac_rms, "F_static": ACTUATOR_N_PER_V * REF["actuator"]}
    samples = []
    t_a, t_b = size["transient"] / W, (size["transient"] + size["record"]) / W
    t = np.linspace(t_a, t_b, size["record"] + 1)

    def on_segment(c_out, ta, tb):
        for tk in t[(t >= ta) & (t <= tb)]:
            samples.append((tk, float(c_out(tk)[2])))
    run = run_scene(SCENE, t_b, params=p, soil=law, tol=TOL, on_segment=on_segment)
    ts, x2 = (np.array(v) for v in zip(*sorted(dict(samples).items())))
    imp = impact_table(run)
    m = progression_measures(ts, x2, x2_start=0.0, relay_hz=W, impact_time=imp["t"], impact_velocity=imp["velocity"],
                             m1=run.params["m1"], held=held_time(run.flag_log, t_a, t_b, held_mode(run.system)),
                             window=(t_a, t_b))
    mode = held_mode(run.system)       # releases: the held mode left within the window (guards and settle alike)
    n_moves = 0 if mode is None else sum(
        1 for (t0, f0), (t1, f1) in zip(run.flag_log, run.flag_log[1:])
        if t_a <= t1 <= t_b and f0.get(mode[0]) == mode[1] and f1.get(mode[0]) != mode[1])
    return {"status": run.status, "rate": 1e3 * m["progression_rate"], "held": m["stuck_fraction"],
            "energy": m["impact_energy_per_period"], "moves_per_period": n_moves / size["record"]}


def _fmt(x):
    return "nan" if not math.isfinite(x) else (f"{x:.3g}" if abs(x) >= 1e-3 or x == 0 else f"{x:.2e}")


def _cell(sw, i) -> str:
    """A rate [mm/s] from a sweep's measures, or how the value ended (escaped, failed)."""
    from bifurc import Status
    st = int(sw["status"][i])
    return _fmt(float(sw["rate"][i])) if st == Status.OK else Status(st).name.lower()


def _ratio(model, thesis):
    if not (math.isfinite(model) and thesis > 0):
        return math.nan
    return model / thesis


def disagreements(m, size) -> list[str]:
    """One sentence per disagreement at the reference condition and per trend, each naming its measured cause."""
    return _at_reference(m) + _voltage_trends(m, size) + _frequency_trends(m, size) + _static_force_trends(m, size)


def _at_reference(m) -> list[str]:
    """Each soil law's rate at the reference condition against Table 5.5's, where it leaves the band."""
    t55 = m["table55"]
    thesis = float(np.interp(REF["relay_hz"], t55["relay_Hz"], t55["rate_mm_per_s"]))
    lo, hi = thesis * BAND[0], thesis * BAND[1]
    out = []
    where = (f"at {REF['relay_hz']:g} Hz, AC {REF['ac_rms']:g} V RMS, F_static "
             f"{ACTUATOR_N_PER_V * REF['actuator']:.3g} N")
    for law in LAWS:
        ref, off = m["reference"][law][REF["ac_rms"]], m["reference"][law][0.0]
        r, s, E = ref["rate"], ref["held"], ref["energy"]
        if ref["status"] != "ok":
            out.append(f"{law}: {where} the run ended {ref['status']}: the bar left the model's domain.")
            continue
        if lo <= r <= hi:
            continue
        side = f"{law}: {where} the model progresses at {_fmt(r)} mm/s, {_ratio(r, thesis):.3g} times the " \
               f"measured {thesis:.3g} mm/s (band {lo:.3g}-{hi:.3g})"
        ac = (f"with the AC solenoid off it is {_fmt(off['rate'])} mm/s" if off["status"] == "ok"
              else f"with the AC solenoid off the run ended {off['status']}")
        if law == "viscous":
            Fv = ACTUATOR_N_PER_V * REF["actuator"] / 135.0 * 1e3
            out.append(f"{side}, because the static force alone drives the rig through the viscous soil at "
                       f"F_static/soil_c = {Fv:.1f} mm/s (the model is within {abs(r / Fv - 1) * 100:.2g} % of it; "
                       f"{ac}): the impacts do not set the rate.")
        elif law == "coulomb":
            out.append(f"{side}, because the 1000 N friction holds the rig {100 * s:.4g} % of the time (slip onsets "
                       f"per relay period: {ref['moves_per_period']:.3g}, at the impacts' force peaks; "
                       f"{1e3 * E:.3g} mJ of relative kinetic energy per relay period; {ac}).")
        else:
            out.append(f"{side}, because under the assumed soil values (k_s 1e5 N/m, c_s 200 N s/m, P_max 60 N) "
                       f"the slider starts to yield {ref['moves_per_period']:.3g} times per relay period and moves "
                       f"{100 * (1 - s):.3g} % of the time, at {1e3 * E:.3g} mJ of impact energy per relay period "
                       f"({ac}).")
    return out


def _voltage_trends(m, size) -> list[str]:
    """The rate and impact energy over the AC voltage against Tables 5.2-5.4 at actuator 10 V."""
    t, out = m["tables52_54"], []
    volts = np.asarray(size["volts"], float)
    at10 = t["actuator_V"] == 10
    for law in LAWS:
        rv, Ev = m["volt"][law]["rate"], m["volt"][law]["energy"]
        ok = np.isfinite(rv)
        if ok.sum() < 2:
            continue
        spread = float(np.ptp(rv[ok]) / np.mean(np.abs(rv[ok])))
        monotone = bool(np.all(np.diff(rv[ok]) >= 0) or np.all(np.diff(rv[ok]) <= 0))
        trend = (f"stays at {_fmt(float(np.mean(rv[ok])))} mm/s (within {100 * spread:.2g} %)" if spread < 0.05 else
                 f"{'rises' if rv[ok][-1] > rv[ok][0] else 'falls'} {'monotonically' if monotone else 'non-monotonically'}"
                 f" from {_fmt(rv[ok][0])} to {_fmt(rv[ok][-1])} mm/s")
        off = m["reference"][law][0.0]
        out.append(f"{law}: over AC {volts[ok][0]:g}-{volts[ok][-1]:g} V RMS the rate {trend} "
                   f"(AC off: {_fmt(off['rate'])} mm/s), while the measurements at actuator "
                   f"10 V read {', '.join(f'{x:.3g}' for x in t['rate_mm_per_s'][at10])} mm/s at "
                   f"{', '.join(f'{x:g}' for x in t['ac_supply_V'][at10])} V; the impact energy per relay period "
                   f"goes from {_fmt(1e3 * Ev[ok][0])} to {_fmt(1e3 * Ev[ok][-1])} mJ, and is "
                   f"{_fmt(1e3 * off['energy'])} mJ with the AC solenoid off: the antiphase DC well supplies most "
                   f"of it.")
    return out


def _frequency_trends(m, size) -> list[str]:
    """Escapes and the rate's peak over the relay frequency against Table 5.5."""
    t55, out = m["table55"], []
    freqs = np.asarray(size["freqs"], float)
    from bifurc import Status
    for law in LAWS:
        f = m["freq"][law]
        gone = np.flatnonzero(f["status"] == Status.ESCAPED)
        if gone.size:
            out.append(f"{law}: at {', '.join(f'{w:g}' for w in freqs[gone])} Hz the run ends escaped (after "
                       f"{_fmt(float(np.nanmin(f['failure_time'][gone])))}-{_fmt(float(np.nanmax(f['failure_time'][gone])))} s):"
                       f" the bar is thrown beyond the model's domain (0.1 m behind the DC solenoid's centre or 2 cm "
                       f"into the stop), where no rate exists, while the rig measured "
                       f"{_fmt(float(np.min(np.interp(freqs[gone], t55['relay_Hz'], t55['rate_mm_per_s']))))}-"
                       f"{_fmt(float(np.max(np.interp(freqs[gone], t55['relay_Hz'], t55['rate_mm_per_s']))))} mm/s.")
    for law in LAWS:
        rf = m["freq"][law]["rate"]
        if np.isfinite(rf).sum() >= 2:
            peak = freqs[int(np.nanargmax(rf))]
            if not 5.2 <= peak <= 7.0:
                Ef = m["freq"][law]["energy"]
                out.append(f"{law}: the rate peaks at {peak:g} Hz, outside the measured peak 5.2-7.0 Hz (Table 5.5), "
                           f"where the impact energy per relay period is {_fmt(1e3 * Ef[int(np.nanargmax(rf))])} mJ "
                           f"(range {_fmt(1e3 * np.nanmin(Ef))}-{_fmt(1e3 * np.nanmax(Ef))} mJ over the sweep).")
    return out


def _static_force_trends(m, size) -> list[str]:
    """The rate's change over the static force against Tables 5.2-5.4."""
    t, out = m["tables52_54"], []
    acts = np.asarray(size["actuator"], float)
    for law in ("coulomb", "drift"):
        for ac in size["ac_levels"]:
            rs = m["static"][(law, ac)]["rate"]
            sel = t["ac_supply_V"] == ac
            th = np.interp([acts[0], acts[-1]], t["actuator_V"][sel], t["rate_mm_per_s"][sel])
            if not (np.isfinite(rs[[0, -1]]).all() and rs[0] > 0):
                continue
            F0, F1 = ACTUATOR_N_PER_V * acts[0], ACTUATOR_N_PER_V * acts[-1]
            why = (f"the static force alone exceeds P_max = 60 N above actuator {60 / ACTUATOR_N_PER_V:.3g} V, and "
                   f"then keeps the slider yielding" if law == "drift" and F1 > 60 else
                   "the static force stays far below the 1000 N friction limit, so only the impact peaks move the rig"
                   if law == "coulomb" else "")
            out.append(f"{law}, AC {ac} V: from F_static {F0:.3g} to {F1:.3g} N the rate changes x {rs[-1] / rs[0]:.3g} "
                       f"(measured x {th[1] / th[0]:.3g}){'; ' + why if why else ''}.")
    return out


def figures(m, size, out):
    """rates.png (against frequency, voltage, static force) and maps.png (what it would take)."""
    import matplotlib.pyplot as plt

    from bifurc.studykit import save_figure
    floor = 1e-4                       # [mm/s] zero rates drawn here on the log axes
    clip = lambda r: np.maximum(np.asarray(r, float), floor)  # noqa: E731
    colours = {"viscous": "C0", "coulomb": "C3", "drift": "C2"}
    fig, axes = plt.subplots(1, 3, figsize=(14, 4.2))
    t55 = m["table55"]
    ax = axes[0]
    ax.fill_between(t55["relay_Hz"], t55["rate_mm_per_s"] * BAND[0], t55["rate_mm_per_s"] * BAND[1], color="0.85",
                    label="Table 5.5 with the 60 % scatter band")
    ax.plot(t55["relay_Hz"], t55["rate_mm_per_s"], "k.", label="Table 5.5 (AC 90 V, actuator 10 V)")
    for law in LAWS:
        ax.plot(size["freqs"], clip(m["freq"][law]["rate"]), "-o", ms=3, color=colours[law], label=f"model, {law}")
    ax.set(xlabel="relay frequency [Hz]", ylabel="progression rate [mm/s]", yscale="log")
    t = m["tables52_54"]
    ax = axes[1]
    at10 = t["actuator_V"] == 10
    ax.fill_between(t["ac_supply_V"][at10], t["rate_mm_per_s"][at10] * BAND[0], t["rate_mm_per_s"][at10] * BAND[1],
                    color="0.85")
    ax.plot(t["ac_supply_V"][at10], t["rate_mm_per_s"][at10], "k.", label="Tables 5.2-5.4, actuator 10 V")
    for law in LAWS:
        ax.plot(size["volts"], clip(m["volt"][law]["rate"]), "-o", ms=3, color=colours[law])
    ax.set(xlabel="AC voltage [V RMS] (relay 6 Hz)", yscale="log")
    ax = axes[2]
    for k, ac in enumerate(size["ac_levels"]):
        sel = t["ac_supply_V"] == ac
        ax.plot(ACTUATOR_N_PER_V * t["actuator_V"][sel], t["rate_mm_per_s"][sel], "k" + "ovs"[k % 3], ms=4,
                mfc="none", label=f"Tables 5.2-5.4, AC {ac} V")
        for law in LAWS:
            ax.plot([ACTUATOR_N_PER_V * a for a in size["actuator"]], clip(m["static"][(law, ac)]["rate"]),
                    "-", color=colours[law], alpha=0.4 + 0.6 * (k + 1) / len(size["ac_levels"]))
    ax.set(xlabel=f"static force [N] ({ACTUATOR_N_PER_V} N per actuator volt, assumed)", yscale="log")
    for ax in axes:
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=7)
    fig.suptitle(f"Prototype progression: model (zero drawn at {floor:g} mm/s) against the thesis", fontsize=10)
    fig.tight_layout()
    save_figure(fig, out / "rates.png", overwrite=True, dpi=110)

    lo, hi = float(np.min(t["rate_mm_per_s"])), float(np.max(t["rate_mm_per_s"]))
    fig, axes = plt.subplots(2, 2, figsize=(11, 8.5))
    for col, law in enumerate(("coulomb", "drift")):
        name, grid = m["map_force"][law]
        ax = axes[0, col]
        _map(ax, size["map_force"], size["map_threshold"][law], grid, lo, hi, floor)
        ax.set(xscale="log", yscale="log", xlabel="F_static [N]", ylabel=f"{name} [N]",
               title=f"{law}: relay 6 Hz, AC 90 V RMS")
        ax = axes[1, col]
        _map(ax, size["map_freqs"], size["map_volts"], m["map_fv"][law], lo, hi, floor)
        ax.set(xlabel="relay frequency [Hz]", ylabel="AC voltage [V RMS]", title=f"{law}: F_static 31.1 N")
    fig.suptitle(f"log10 progression rate [mm/s]; white contours: the measured range {lo:.3g}-{hi:.3g} mm/s; "
                 f"blank cells: the run escaped or failed",
                 fontsize=10)
    fig.tight_layout()
    save_figure(fig, out / "maps.png", overwrite=True, dpi=110)


def _map(ax, x, y, rates, lo, hi, floor):
    z = np.log10(np.maximum(np.asarray(rates, float), floor))
    pcm = ax.pcolormesh(np.asarray(x, float), np.asarray(y, float), z, shading="nearest", cmap="viridis")
    ax.figure.colorbar(pcm, ax=ax)
    if z.shape[0] > 1 and z.shape[1] > 1:
        ax.contour(np.asarray(x, float), np.asarray(y, float), z, levels=[math.log10(lo), math.log10(hi)],
                   colors="w", linewidths=1.2)


def report(m, size, quick, seconds) -> str:
    t55 = m["table55"]
    lines = [f"# Prototype progression against the thesis (Tables 5.2-5.5){' -- quick form' if quick else ''}", "",
             "Scene `prototype` (dynamics-listing numbers, dc_scale 1.44, antiphase relay), DC-force law "
             "`listing` (listing C.9, the preset's), every soil law; nothing tuned. Sweeps on the batch engine: "
             f"{size['transient']} relay periods discarded, rates over the first {size['record']} of the window each "
             f"value is judged on (undecided values are extended, and a non-stationary first part discarded: "
             f"`transient_used`) (tol {TOL:g}); wall time {seconds:.0f} s.", "", provenance(NAME, quick), "",
             "## Assumptions", "",
             "- AC voltages are RMS: source amplitude V = sqrt(2) x RMS (docs/model.md section 4).",
             f"- Actuator volts to static force: F_static = {ACTUATOR_N_PER_V} N/V x actuator volts (31.1 N of "
             "listing C.14 at Table 5.5's 10 V); the thesis gives no mapping.",
             f"- Scatter band: x {BAND[0]:.2f} to x {BAND[1]:.2f} of a measured rate (Tables 5.4 and 5.5 at the "
             f"same settings: {SAME_SETTINGS[0]} and {SAME_SETTINGS[1]} mm/s).",
             "- Drift soil: k_s = 1e5 N/m, c_s = 200 N s/m, P_max = 60 N, all assumed (docs/model.md).", "",
             "## Rate against relay frequency (Table 5.5: AC 90 V, actuator 10 V)", "",
             "| relay [Hz] | thesis [mm/s] | " + " | ".join(f"{law} [mm/s]" for law in LAWS) + " |",
             "|---" * (2 + len(LAWS)) + "|"]
    for i, W in enumerate(size["freqs"]):
        th = float(np.interp(W, t55["relay_Hz"], t55["rate_mm_per_s"]))
        lines.append(f"| {W:g} | {th:.3g} | " + " | ".join(_cell(m["freq"][law], i) for law in LAWS) + " |")
    t = m["tables52_54"]
    lines += ["", "## Rate against AC voltage (relay 6 Hz, actuator 10 V)", "",
              "| AC [V RMS] | thesis [mm/s] | " + " | ".join(f"{law} [mm/s]" for law in LAWS) + " |",
              "|---" * (2 + len(LAWS)) + "|"]
    for i, v in enumerate(size["volts"]):
        sel = (t["ac_supply_V"] == v) & (t["actuator_V"] == 10)
        th = f"{float(t['rate_mm_per_s'][sel][0]):.3g}" if sel.any() else "-"
        lines.append(f"| {v:g} | {th} | " + " | ".join(_cell(m["volt"][law], i) for law in LAWS) + " |")
    lines += ["", "## Rate against static force (relay 6 Hz; Tables 5.2-5.4)", "",
              "| AC [V RMS] | actuator [V] | F_static [N] | thesis [mm/s] | " +
              " | ".join(f"{law} [mm/s]" for law in LAWS) + " |", "|---" * (4 + len(LAWS)) + "|"]
    for ac in size["ac_levels"]:
        for i, a in enumerate(size["actuator"]):
            sel = (t["ac_supply_V"] == ac) & (t["actuator_V"] == a)
            th = f"{float(t['rate_mm_per_s'][sel][0]):.3g}" if sel.any() else "-"
            lines.append(f"| {ac} | {a} | {ACTUATOR_N_PER_V * a:.3g} | {th} | " +
                         " | ".join(_cell(m["static"][(law, ac)], i) for law in LAWS) + " |")
    lines += ["", "## The DC-force law (relay 6 Hz, AC 90 V RMS, F_static 31.1 N)", "",
              "| soil | listing [mm/s] | fit [mm/s] | measured [mm/s] | AC off (listing) [mm/s] |", "|---|---|---|---|---|"]
    i6 = int(np.argmin(np.abs(np.asarray(size["freqs"]) - REF["relay_hz"])))
    for law in LAWS:
        off = m["reference"][law][0.0]
        lines.append(f"| {law} | {_cell(m['freq'][law], i6)} | {_cell(m['dc_laws'][(law, 'fit')], 0)} | "
                     f"{_cell(m['dc_laws'][(law, 'measured')], 0)} | "
                     f"{_fmt(off['rate']) if off['status'] == 'ok' else off['status']} |")
    lines += [""]
    for law in LAWS:
        base = float(m["freq"][law]["rate"][i6])
        said = []
        for dc_law in ("fit", "measured"):
            sw = m["dc_laws"][(law, dc_law)]
            cell = _cell(sw, 0)
            said.append(f"under `{dc_law}` {cell}" + (f" mm/s ({100 * (float(sw['rate'][0]) / base - 1):+.3g} %)"
                                                        if cell[0].isdigit() and base > 0 else ""))
        lines.append(f"- {law}: {_fmt(base)} mm/s under `listing`; " + ", ".join(said) + ".")
    from . import depth
    steady = {(law, f): float(m["freq"][law]["rate"][i]) for law in LAWS for i, f in enumerate(size["freqs"])}
    lines += [""] + depth.report_lines(m["depth"], size, t55, steady)
    from . import variants
    lines += variants.report_lines(m["variants"], m, size, t55, t)
    lines += ["## What it would take (maps.png)", "",
              "Progression-rate maps over (F_static, soil threshold) at 6 Hz and 90 V RMS, and over (relay "
              "frequency, AC voltage) at F_static 31.1 N, for the coulomb and drift laws; white contours mark "
              "the measured range. This is analysis, not tuning: no preset changes.", ""]
    for law in ("coulomb", "drift"):
        name, grid = m["map_force"][law]
        thr = np.asarray(size["map_threshold"][law], float)
        rows = []
        for i, F in enumerate(size["map_force"]):
            hit = thr[(grid[:, i] >= t["rate_mm_per_s"].min()) & (grid[:, i] <= t["rate_mm_per_s"].max())]
            if hit.size:
                rows.append(f"F_static {F:g} N: {name} {hit.min():g}-{hit.max():g} N")
        n_in = sum(1 for j in range(thr.size) for i in range(len(size["map_force"]))
                   if t["rate_mm_per_s"].min() <= grid[j, i] <= t["rate_mm_per_s"].max())
        lines.append(f"- {law}: {n_in} of {grid.size} grid points within the measured range" +
                     (f" ({'; '.join(rows)})" if rows else "") + ".")
    lines += ["", "## Disagreements, each with its measured cause", ""]
    lines += [f"- {s}" for s in disagreements(m, size)]
    lines += ["", "Figures: rates.png (model against the tables), maps.png (the maps), escape.png (an escaped frequency's "
              "time history, without and with the rear stop).", ""]
    return "\n".join(lines)


def run(out, quick=False, progress=True, overwrite=False) -> dict:
    """The study into folder ``out``: ``report.md``, ``rates.png``, ``maps.png``."""
    from bifurc.studykit import refuse_existing, write_text
    out = Path(out)
    for name in ("report.md", "rates.png", "maps.png", "escape.png"):
        refuse_existing(out / name, overwrite, hint="use --force")
    out.mkdir(parents=True, exist_ok=True)
    size = QUICK if quick else FULL
    clock = _time.perf_counter()
    m = measure(size, progress=progress)
    seconds = _time.perf_counter() - clock
    figures(m, size, out)
    from . import variants
    variants.figure(m["variants"], out)
    write_text(out / "report.md", report(m, size, quick, seconds), overwrite=True)
    return {"measured": m, "seconds": seconds}


def findings(results, quick) -> list:
    """The steady rate at the reference condition (6 Hz, AC 90 V RMS, actuator 10 V) per soil law (+-10 %,
    at least 0.05 mm/s) and the thesis' measure (0.2 m / t) and the 0.9 m runs (depth.findings)."""
    from bifurc.studykit import Finding

    from . import depth
    m = results["measured"]
    size = QUICK if quick else FULL
    i6 = int(np.argmin(np.abs(np.asarray(size["freqs"]) - REF["relay_hz"])))
    out = []
    for law in LAWS:
        r = float(m["freq"][law]["rate"][i6])
        out.append(Finding(f"steady rate, {law}, 6 Hz, thesis geometry", round(r, 4), round(max(0.1 * abs(r), 0.05), 4),
                           "mm s-1"))
    from . import variants
    thesis = [Finding(f"{f.name}, thesis geometry", f.value, f.tolerance, f.unit) for f in depth.findings(m["depth"])]
    return out + thesis + variants.findings(m["variants"], m, size)

