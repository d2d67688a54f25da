"""The prototype study's stated variants, the "escaped" frequencies, and the 1-DOF 4 Hz cells (issue 46 section 4).

- Variants (each a problem option or parameter on top of the scene): the housing as a rear stop (``rear_stop``,
  e_rear 0.1125 m, an assumption of the presets), the DC coil's L/R delay (``dc_delay``, tau_dc 1/48 s), both,
  and the DC well's rest at :data:`REST` above the stop (``dc_rest``, the dc-well study's rest height with the most
  cells in the thesis' regime: 3 mm, studies/dc_well/report.md, listing-25V and listing-25V-cair0.5), alone and
  with both elements.  Each runs the frequency sweep of Table 5.5 under the coulomb and drift soils; the rest
  height variants also the AC-voltage and static-force sweeps of Tables 5.2-5.4 (AC 90 V RMS).
- The escaped frequencies: every frequency where the thesis-geometry drift sweep escapes is re-run as one time
  history without and with the rear stop: when and where the bar leaves the model's domain (r = d_dc + 0.1 m
  behind the stop), how fast, and whether the DC gate was on; with the rear stop, how often the bar reaches the
  housing per relay period and the rate.
- The 4 Hz cells: thesis-1dof (preset thesis-text, the scene's default), dc_law `listing`, relay 4 Hz, a sweep of V
  over 100-160 V: the class in the bar's period and in the full state's.
"""
from __future__ import annotations

import math

import numpy as np

REST = 0.003          # [m] the dc-well study's rest height (see the module's docstring)
#: name -> (problem options, parameters)
VARIANTS = {
    "rear stop": ({"rear_stop": True}, {}),
    "coil delay": ({"dc_delay": True}, {}),
    "rear stop + coil delay": ({"rear_stop": True, "dc_delay": True}, {}),
    "rest 3 mm": ({}, {"dc_rest": REST}),
    "rest 3 mm + rear stop + coil delay": ({"rear_stop": True, "dc_delay": True}, {"dc_rest": REST}),
}
SOILS = ("coulomb", "drift")
REST_VARIANTS = ("rest 3 mm", "rest 3 mm + rear stop + coil delay")
V_4HZ = {"quick": tuple(range(100, 161, 10)), "full": tuple(range(100, 161, 2))}


def measure(size, sweep, v_amplitude, f_static, quick, say=print) -> dict:
    """Every variant's sweeps (``sweep``: the study's sweep function), the escape census and the 4 Hz cells."""
    import time as _time
    out = {"freq": {}, "volt": {}, "static": {}}
    for name, (opts, params) in VARIANTS.items():
        clock = _time.perf_counter()
        for soil in SOILS:
            out["freq"][(name, soil)] = sweep("relay_hz", _freqs(size), soil, size, options=opts, **params)
            if name in REST_VARIANTS:
                out["volt"][(name, soil)] = sweep("V", [math.sqrt(2.0) * v for v in size["volts"]], soil, size,
                                                  options=opts, relay_hz=6.0, **params)
                out["static"][(name, soil)] = sweep("F_static", [3.11 * a for a in size["actuator"]], soil, size,
                                                    options=opts, relay_hz=6.0, **params)
        say(f"variant {name}: sweeps in {_time.perf_counter() - clock:.1f} s", flush=True)
    out["cells_4hz"] = cells_4hz(V_4HZ["quick" if quick else "full"])
    return out


def _freqs(size) -> tuple:
    """The variants' relay frequencies: ``variant_freqs`` (the full form: 8 of the 25, the escaped ones among
    them, to fit its budget), else the form's own."""
    return tuple(size.get("variant_freqs", size["freqs"]))


def escapes(freqs, periods, v_amplitude, f_static) -> list:
    """One time history per frequency (drift soil, thesis geometry, then with the rear stop): a dict of the
    escape (time [s] and relay periods, r [m], dr/dt [m/s], DC gate on?) and the rear stop's run (status, r max,
    upward crossings of e_rear per relay period, rate [mm/s])."""
    import maps
    out = []
    for f in freqs:
        p = {"relay_hz": float(f), "V": v_amplitude, "F_static": f_static}
        pb = maps.problem("prototype", soil="drift", params=p)
        h = maps.simulate(pb, periods=periods, dt=5e-4)
        row = {"relay_hz": float(f), "status": h.attrs["status"]}
        edge = pb.values["d_dc"] + 0.1
        if h.attrs["status"] != "ok":
            s = dict(zip([v.name for v in pb.system.states], np.asarray(h.attrs["failure_state"], float)))
            t = float(h.attrs["failure_time"])
            r = h.x1.values - h.x2.values
            row.update(t=t, periods=t * f, r=s["x1"] - s["x2"], dr=s["v1"] - s["v2"], edge=edge,
                       gate_dc=bool(h.relay.values[-1] == 0),      # antiphase: P = 1 AC on, DC gated by 1 - P
                       r_max_before=float(np.nanmax(r)), impacts=int(np.isfinite(h.impact_time.values).sum()))
        pr = maps.problem("prototype", soil="drift", params=p, rear_stop=True)
        hr = maps.simulate(pr, periods=periods, dt=5e-4)
        e_rear = pr.values["e_rear"]
        rr = hr.x1.values - hr.x2.values
        up = int(np.sum((rr[:-1] < e_rear) & (rr[1:] >= e_rear)))
        ti = hr.impact_time.values
        late = int(np.sum(np.isfinite(ti) & (ti >= 0.5 * periods / f)))
        row["rear"] = {"status": hr.attrs["status"], "r_max": float(np.nanmax(rr)), "e_rear": float(e_rear),
                       "r_min_late": float(np.nanmin(rr[hr.t.values >= 0.5 * periods / f])),
                       "stop_per_period": late / (0.5 * periods),
                       "hits_per_period": up / periods, "rate": 1e3 * float(hr.progression_rate),
                       "time": hr.t.values, "r": rr}
        row["history"] = {"time": h.t.values, "r": h.x1.values - h.x2.values}
        out.append(row)
    return out


def cells_4hz(volts) -> list:
    """thesis-1dof, listing, 4 Hz: [(V, mechanical class text, full-state class text)] (bifurc.sweep)."""
    import bifurc
    import maps
    from bifurc import class_at
    from bifurc.studykit import in_convention
    pb = maps.problem("thesis-1dof", dc_law="listing", params={"relay_hz": 4.0})
    ds = bifurc.sweep(pb, "V", np.asarray(volts, float), bifurc.Diagram(lyapunov=False, grazing=False, error_sample=0),
                      run=bifurc.Run(workers=1, progress=False))
    dm = in_convention(ds, "mechanical")
    out = []
    for v in ds.V.values:
        c = class_at(dm, float(v))
        out.append({"V": float(v), "text": c["text"], "full": class_at(ds, float(v))["text"],
                    "p1_one": c["label"] == "periodic" and c["period"] == 1 and c["impacts"] == 1})
    return out


def report_lines(v, m, size, t55, t52) -> list:
    """The report's sections on the variants, the escapes and the 4 Hz cells."""
    from bifurc import Status
    freqs, main = _freqs(size), list(np.round(size["freqs"], 6))

    def cell(sw, i):
        st = int(sw["status"][i])
        return f"{sw['rate'][i]:.3g}" if st == Status.OK else Status(st).name.lower()

    names = ["thesis geometry"] + list(VARIANTS)
    def get(name, soil):     # the thesis geometry's sweep read at the variants' frequencies
        if name != "thesis geometry":
            return v["freq"][(name, soil)]
        idx = [main.index(round(f, 6)) for f in freqs]
        return {k: np.asarray(a)[idx] for k, a in m["freq"][soil].items()}
    lines = ["## Variants: the rear stop, the coil delay and the dc-well rest height", "",
             "Each variant on top of the scene (dc_law listing, AC 90 V RMS, F_static 31.1 N): `rear stop`: the housing "
             "at e_rear = 0.1125 m (an assumption); `coil delay`: the DC coil's tau_dc = 1/48 s; `rest 3 mm`: the DC "
             f"well's rest {1e3 * REST:g} mm above the stop (`dc_rest`, the dc-well study's rest height with the most "
             "cells in the thesis' regime), the thesis' geometry having it at d_dc = 62.5 mm.  Rates in mm/s; "
             f"`escaped`: the bar left the model's domain.  Relay frequencies: {', '.join(f'{f:g}' for f in freqs)} Hz"
             + (" (8 of the full sweep's 25, the escaped ones among them: the variants' sweeps at all 25 exceed the "
                "full form's budget on the shared machine)" if len(freqs) < len(main) else "") + ".", ""]
    for soil in SOILS:
        lines += [f"### Rate against relay frequency, {soil} soil (Table 5.5: AC 90 V RMS, actuator 10 V)", "",
                  "| relay [Hz] | thesis | " + " | ".join(names) + " |", "|---" * (2 + len(names)) + "|"]
        for i, W in enumerate(freqs):
            th = float(np.interp(W, t55["relay_Hz"], t55["rate_mm_per_s"]))
            lines.append(f"| {W:g} | {th:.3g} | " + " | ".join(cell(get(n, soil), i) for n in names) + " |")
        lines.append("")
    lines += ["### Rate against AC voltage and static force under the dc-well rest height (relay 6 Hz)", "",
              "| soil | variant | sweep | value | thesis [mm/s] | model [mm/s] |", "|---|---|---|---|---|---|"]
    for soil in SOILS:
        for name in REST_VARIANTS:
            for i, a in enumerate(size["volts"]):
                sel = (t52["ac_supply_V"] == a) & (t52["actuator_V"] == 10)
                th = f"{float(t52['rate_mm_per_s'][sel][0]):.3g}" if sel.any() else "-"
                lines.append(f"| {soil} | {name} | AC [V RMS], actuator 10 V | {a:g} | {th} | "
                             f"{cell(v['volt'][(name, soil)], i)} |")
            for i, a in enumerate(size["actuator"]):
                sel = (t52["ac_supply_V"] == 90) & (t52["actuator_V"] == a)
                th = f"{float(t52['rate_mm_per_s'][sel][0]):.3g}" if sel.any() else "-"
                lines.append(f"| {soil} | {name} | actuator [V], AC 90 V RMS | {a:g} | {th} | "
                             f"{cell(v['static'][(name, soil)], i)} |")
    lines += ["", "## The escaped frequencies: what the bar does there", ""]
    esc = v.get("escapes", [])
    if not esc:
        lines += ["No frequency of the drift sweep escapes under the thesis geometry.", ""]
    else:
        lines += ["Each escaped frequency of the drift sweep (thesis geometry) re-run as one time history "
                  f"({v['escape_periods']} relay periods, drift soil), then with the rear stop (escape.png: r = x1 - x2 "
                  "against time at the first of them).", "",
                  "| relay [Hz] | leaves the domain at [s] | [relay periods] | r there [mm] | dr/dt [m/s] | DC gate | "
                  "impacts before | with the rear stop: status | r max [mm] | housing reached per relay period | "
                  "stop impacts per relay period (second half) | r min, second half [mm] | rate [mm/s] |",
                  "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
        for e in esc:
            rr = e["rear"]
            if e["status"] == "ok":
                head = f"| {e['relay_hz']:g} | stays (ok over this run) | | | | | "
            else:
                head = (f"| {e['relay_hz']:g} | {e['t']:.3f} | {e['periods']:.2f} | {1e3 * e['r']:.1f} | {e['dr']:+.2f} | "
                        f"{'on' if e['gate_dc'] else 'off'} | {e['impacts']} | ")
            lines.append(head + f"{rr['status']} | {1e3 * rr['r_max']:.1f} | {rr['hits_per_period']:.2f} | "
                                f"{rr['stop_per_period']:.2f} | {1e3 * rr['r_min_late']:.1f} | {rr['rate']:.3g} |")
        lines += ["", escape_sentence(esc), ""]
    lines += ["## The 4 Hz mechanical period-1 cells (thesis-1dof, dc_law listing)", "",
              "thesis-1dof (preset thesis-text), dc_law `listing` (d_dc 62.5 mm), relay 4 Hz, V swept (bifurc.sweep, "
              "300 transient + 100 recorded relay periods, extended while undecided, no Lyapunov exponents): the class in "
              "the bar's period (mechanical) and in the full state's.", "",
              "| V [V] | mechanical | full state |", "|---|---|---|"]
    lines += [f"| {c['V']:g} | {'**' + c['text'] + '**' if c['p1_one'] else c['text']} | {c['full']} |"
              for c in v["cells_4hz"]]
    hit = [c["V"] for c in v["cells_4hz"] if c["p1_one"]]
    lines += ["", f"Mechanical period-1 with one impact per relay period at {len(hit)} of {len(v['cells_4hz'])} "
              f"voltages: {', '.join(f'{x:g}' for x in hit) or 'none'} V.", ""]
    return lines


def escape_sentence(esc) -> str:
    gone = [e for e in esc if e["status"] != "ok"]
    if not gone:
        return ""
    first = max(e["periods"] for e in gone)
    held = [e for e in esc if e["rear"]["status"] == "ok"]
    off = sum(not e["gate_dc"] for e in gone)
    return (f"Where it escapes, the bar leaves within the first {math.ceil(first)} relay period(s), after "
            f"{min(e['impacts'] for e in gone)}-{max(e['impacts'] for e in gone)} contacts with the stop, moving away "
            f"from it at {min(e['dr'] for e in gone):.2f}-{max(e['dr'] for e in gone):.2f} m/s through r = "
            f"{1e3 * gone[0]['edge']:.1f} mm, with the DC gate off at {off} of {len(gone)} (nothing pulls it back "
            "while the AC half of the relay period lasts): the switch-on transient throws it beyond the model's domain "
            "before any steady motion forms, so no rate exists there.  With the rear stop (the housing) the run "
            f"completes at {len(held)} of {len(esc)} of these frequencies, the bar reaching the housing "
            f"{min(e['rear']['hits_per_period'] for e in esc):.2f}-{max(e['rear']['hits_per_period'] for e in esc):.2f} "
            "times per relay period and the stop "
            f"{min(e['rear']['stop_per_period'] for e in esc):.2f}-{max(e['rear']['stop_per_period'] for e in esc):.2f} "
            "times (second half of the run): where the second is 0 the bar swings between the well and the housing "
            "without striking the stop.")


def figure(v, out):
    """escape.png: r against time at the first escaped frequency, without and with the rear stop."""
    esc = v.get("escapes", [])
    if not esc:
        return
    import matplotlib.pyplot as plt

    from bifurc.studykit import save_figure
    e = esc[0]
    fig, ax = plt.subplots(figsize=(8, 3.6))
    ax.plot(e["rear"]["time"], 1e3 * e["rear"]["r"], color="C0", lw=0.8, label="with the rear stop (e_rear 112.5 mm)")
    ax.plot(e["history"]["time"], 1e3 * e["history"]["r"], color="C3", lw=1.2, label="thesis geometry (no rear stop)")
    if "edge" in e:
        ax.axhline(1e3 * e["edge"], color="k", ls=":", lw=0.8, label="the model's domain (d_dc + 0.1 m)")
    ax.axhline(1e3 * e["rear"]["e_rear"], color="C0", ls="--", lw=0.8)
    ax.set(xlabel="time [s]", ylabel="r = x1 - x2 [mm]", title=f"prototype, drift soil, {e['relay_hz']:g} Hz, AC 90 V RMS",
           xlim=(0, min(2.0, float(e["rear"]["time"][-1]))))
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    save_figure(fig, out / "escape.png", overwrite=True, dpi=110)


def findings(v, m, size) -> list:
    """Per variant the drift and coulomb rates at 6 Hz (+-10 %, at least 0.05 mm/s), the escape census (exact
    counts) and the 4 Hz cells (exact)."""
    from bifurc.studykit import Finding
    i6 = int(np.argmin(np.abs(np.asarray(_freqs(size)) - 6.0)))
    out = []
    for (name, soil), sw in v["freq"].items():
        r = float(sw["rate"][i6])
        out.append(Finding(f"steady rate, {soil}, 6 Hz, variant {name}", round(r, 4) if math.isfinite(r) else math.nan,
                           round(max(0.1 * abs(r), 0.05), 4) if math.isfinite(r) else 0.0, "mm s-1"))
    esc = v.get("escapes", [])
    out.append(Finding("escaped frequencies (drift, thesis geometry)", len(esc), 0, "frequencies"))
    out.append(Finding("of them completed with the rear stop", sum(e["rear"]["status"] == "ok" for e in esc), 0,
                       "frequencies"))
    hit = [c["V"] for c in v["cells_4hz"] if c["p1_one"]]
    out.append(Finding("4 Hz, listing: voltages with mechanical P1, 1 impact",
                       ", ".join(f"{x:g}" for x in hit) or "none"))
    return out
