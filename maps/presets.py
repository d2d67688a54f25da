"""Parameter presets found in the thesis, each value with its provenance (docs/model.md, Presets)."""
from __future__ import annotations

_T = "thesis"
#: values shared by every preset: name -> (value, provenance)
COMMON = {
    "m": (0.155, "bar mass, listing C.1"),
    "m1": (0.155, "bar mass, section 4.7 / listing C.14"),
    "m2": (2.643, "rig mass, section 4.7 / listing C.14"),
    "g": (9.81, "listing C.1"),
    "e": (0.0, "clearance, listing C.1"),
    "f_mains": (50.0, "mains frequency, listing C.1"),
    "d_dc": (0.0625, "DC solenoid centre above the stop: xa = x - 0.0625, listing C.9 and docs/model.md section 1 "
                     "(from y = 0.108, l_c = 0.141, l_s = 0.05 m, eq 4.5)"),
    "d_ac": (0.0455, "eq 4.9 (xb = x + 0.0455)"),
    "L0": (0.48, "inductance fit, eq 4.13 / listing C.11"),
    "A": (0.048, "inductance fit, eq 4.13 / listing C.11"),
    "B": (0.039, "inductance fit, eq 4.13 / listing C.11"),
    "dc_scale": (1.0, "DC force Table 4.1 measured at 20 V DC"),
    "F_static": (31.1, "static force, section 4.7 / listing C.14 (C5)"),
    "soil_c": (135.0, "viscous soil coefficient Fs, listings C.4-C.6"),
    "soil_friction": (1000.0, "dry soil friction, listing C.14 (C7)"),
    "k_s": (1e5, "ASSUMPTION (the thesis gives no drift-soil values): element stiffness 1e5 N/m, a tenth of "
                 "the prototype's stop stiffness; F_static/k_s = 0.3 mm static deflection"),
    "c_s": (200.0, "ASSUMPTION (the thesis gives none): element damping 200 N s/m, damping ratio "
                   "c_s / (2 sqrt(k_s m2)) = 0.19 for the rig on the element"),
    "P_max": (60.0, "ASSUMPTION (the thesis gives none): slider threshold 60 N, about twice F_static = 31.1 N, "
                    "so that the static force alone holds the rig and only the impacts make it progress"),
    "c_air": (0.0, "free-flight damping: 0 = the thesis' model (no damping in flight); docs/model.md section 1b "
                   "estimates 0.01-0.5 N s/m for a steel bar in a guide tube (air drag, bearing friction)"),
    "e_rear": (0.0625 + 0.05, "ASSUMPTION (the housing's drawings, thesis Figs F.1-F.3, are not in the text): the "
                              "rear stop 50 mm beyond the DC solenoid's centre; documented range 0.0875-0.1625 m "
                              "(the coil's far face to the escape bound d_dc + 0.1 m)"),
    "tau_dc": (1.0 / 48.0, "DC coil L/R: R = (24 V)^2 / 12 W = 48 ohm (catalogue, Table 3.1), L = 1.0 H (Table 4.2: "
                           "0.55-1.46 H for the same solenoid model); documented range 0.011-0.030 s"),
    "soil_depth_scale": (0.9 / (4.3 / 0.65 - 1), "compaction (coulomb, drift): FITTED to the two numbers of thesis "
                         "Fig 5.22 (4.3 mm/s at the surface falling to 0.65 mm/s at 0.9 m) assuming the progression "
                         "rate inversely proportional to the resistance (an assumption): 1 + 0.9 m / L = 4.3 / 0.65"),
}

def _catalogue_fit() -> dict:
    """The catalogue law's coefficients as fitted by maps/data/fit_dc_catalogue.py (its committed output)."""
    import json
    from importlib import resources
    fit = json.loads(resources.files("maps").joinpath("data", "dc_catalogue_fit.json").read_text())
    src = (f"dc_law catalogue: maps/data/dc_catalogue_fit.json ({fit['produced_by']}, commit {fit['commit']}, "
           f"{fit['date']}): ")
    return {"F_dc_sat": (fit["F_dc_sat"], src + fit["anchors"]["F_dc_sat"]),
            "u_dc": (fit["u_dc"], src + fit["anchors"]["u_dc, s_dc"]),
            "s_dc": (fit["s_dc"], src + fit["anchors"]["u_dc, s_dc"])}


#: the DC-force cubic's coefficients of each law (``dc_law``; "measured" has none): name -> (value, provenance)
DC_LAW_COEFFICIENTS = {
    "listing": {
        "a1": (15.38, "dc_law listing: listing C.9 as printed (-15.38*xa)"),
        "a2": (1.652e-14, "dc_law listing: listing C.9 as printed (+1.652E-14*xa.^2)"),
        "a3": (1.473e5, "dc_law listing: listing C.9 as printed (-1.473E5*xa.^3; eq 4.6's cubic with its sign flipped)"),
    },
    "fit": {
        "a1": (15.38, "dc_law fit: eq 4.7 as printed (+15.38 x_a)"),
        "a2": (1.625e-14, "dc_law fit: eq 4.7 as printed (-1.625e-14 x_a^2; listing C.9 prints 1.652e-14)"),
        "a3": (1.473e5, "dc_law fit: eq 4.7 as printed (-1.473e5 x_a^3; eq 4.6: the least-squares odd cubic of Table 4.1)"),
    },
    "measured": {},
    "catalogue": _catalogue_fit(),
    "dynamics-script": {
        "a1": (15.38, "dc_law dynamics-script: listing C.14 as printed (Fspr: -15.38*(s))"),
        "a2": (1.652e-14, "dc_law dynamics-script: listing C.14 as printed (Fspr: +1.652e-14*(s)^2)"),
        "a3": (1.4735, "dc_law dynamics-script: listing C.14 as printed (Fspr: -1.4735*(s)^3; C.9's 1.473E5 is "
                       "1e5 larger)"),
        "d_dc": (0.0, "dc_law dynamics-script: listing C.14 writes Fspr on s, the bar relative to the stop, "
                      "without C.9's 0.0625 offset: the law is centred at the stop"),
    },
}

#: each preset's DC-force law (docs/model.md sections 1 and 4), with the reason
PRESET_DC_LAW = {
    "thesis-text": ("fit", "the text's law, eqs 4.6-4.7"),
    "matlab-listing": ("listing", "what the thesis' simulations ran, listing C.9"),
    "dynamics-listing": ("listing", "listing C.9; C.14's own cubic (on s, without the 0.0625 offset, a3 1e5 "
                                    "smaller) is a different model, not implemented"),
}

#: docs/model.md section 4's notes on each preset, stated in its provenance (dataset attribute
#: ``preset_notes``)
PRESET_NOTES = {
    "thesis-text": "sections 4.2-4.3 simulate at 15 V DC: dc_scale = (15/20)^2 = 0.5625 under the linear-magnetics "
                   "assumption (1.0 reproduces the 20 V Table 4.1); k and c are not given in the text (listing "
                   "C.1 values)",
    "matlab-listing": "Table C.1 numbers; V is never assigned in the listing (25 V: the text's value); the listings "
                      "start on the stop at rest with i = 0.1 A (C.1), tf = 3 s; the toolkit's default start (1 mm "
                      "above the stop, circuit at rest) is a choice",
    "dynamics-listing": "C.14's numbers only (its algebra differs: cubic on s without the 0.0625 offset, a3 1e5 "
                        "smaller, inductance at s, sign(x)*1000 soil without sticking); the prototype takes R, C "
                        "and V from C.14, the source written as 1.4142 x RMS: Chapter 5's 40-110 V read as RMS",
}

PRESETS = {
    "thesis-text": {
        "R": (30.0, "sections 4.5-4.6"),
        "C": (3.0e-4, "sections 4.5-4.6"),
        "V": (25.0, "sections 4.5-4.6 (Fig 4.24: 25 V amplitude)"),
        "k": (1e5, "not given in the text; listing C.1 value"),
        "c": (10.0, "not given in the text; listing C.1 value"),
        "relay_hz": (5.0, "section 4.8 (Fig 4.27 d); the text sweeps 2-10 Hz"),
        "dc_scale": (1.0, "Table 4.1 at 20 V DC; sections 4.2-4.3 simulate at 15 V DC, which is "
                          "dc_scale = (15/20)^2 = 0.5625 if the magnetic circuit is linear (an assumption)"),
    },
    "matlab-listing": {
        "R": (25.0, "listing C.1"),
        "C": (2.8e-4, "listing C.1"),
        "V": (25.0, "never assigned in listing C.1; thesis-text value (the listings start on the stop at "
                    "rest with i = 0.1 A, tf = 3 s)"),
        "k": (1e5, "listing C.1 (k1)"),
        "c": (10.0, "listing C.1 (c1)"),
        "relay_hz": (10.0, "listing C.1 (f)"),
    },
    "dynamics-listing": {
        "R": (300.0, "listing C.14 (C8)"),
        "C": (3.0e-4, "listing C.14 (C3)"),
        "V": (50 * 1.4142, "listing C.14 (1.4142*C9, C9 = 50 V: 1.4142 x an RMS value); C.14's numbers only, "
                           "not its algebra"),
        "k": (1e6, "listing C.14 (C6)"),
        "c": (500.0, "listing C.14 (C2)"),
        "relay_hz": (8.0, "listing C.14 (phi = 2 pi 8)"),
        "F_static": (31.1, "listing C.14 (C5)"),
        "soil_friction": (1000.0, "listing C.14 (C7)"),
    },
}


def preset_dc_law(name: str) -> str:
    """The DC-force law preset ``name`` uses by default ("listing", "fit" or "measured")."""
    from .parameters import ParameterError
    if name not in PRESETS:
        raise ParameterError(f"unknown preset {name!r}; presets: {', '.join(PRESETS)}")
    return PRESET_DC_LAW[name][0]


def preset_values(name: str, dc_law: str | None = None) -> dict:
    """name -> (value, provenance) for every parameter of preset ``name``; the DC cubic's
    coefficients are those of ``dc_law`` (default: the preset's own law)."""
    from .parameters import ParameterError
    law = preset_dc_law(name) if dc_law is None else dc_law     # raises for an unknown preset
    if name not in PRESETS:
        raise ParameterError(f"unknown preset {name!r}; presets: {', '.join(PRESETS)}")
    if law not in DC_LAW_COEFFICIENTS:
        raise ParameterError(f"option 'dc_law' = {law!r}; allowed: {', '.join(DC_LAW_COEFFICIENTS)}")
    out = dict(COMMON)
    out.update(DC_LAW_COEFFICIENTS[law])
    out.update(PRESETS[name])
    return {k: (float(v), f"{name}: {src}") for k, (v, src) in out.items()}


def preset_attrs(table: dict) -> dict:
    """Dataset attributes naming the preset behind a provenance table ({name: (value, source)}),
    its DC-force law and docs/model.md section 4's notes on it (empty when no preset is named)."""
    counts: dict = {}
    for _, src in table.values():
        head = str(src).split(":")[0]
        if head in PRESETS:
            counts[head] = counts.get(head, 0) + 1
    if not counts:
        return {}
    name = max(counts, key=counts.get)
    law, why = PRESET_DC_LAW[name]
    return {"preset": name, "preset_dc_law": f"{law}: {why}", "preset_notes": PRESET_NOTES[name]}
