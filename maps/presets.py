"""Parameter presets found in the thesis, each value with its provenance (docs/model.md, Presets)."""
from __future__ import annotations

import math

__all__ = ["PRESETS", "COMMON", "preset_values"]

_T = "thesis"
#: values shared by every preset: name -> (value, provenance)
COMMON = {
    "m": (0.155, "bar mass, listing C.1"),
    "m1": (0.155, "bar mass, section 4.7 / listing C.14"),
    "m2": (2.643, "rig mass, section 4.7 / listing C.14"),
    "g": (9.81, "listing C.1"),
    "e": (0.0, "clearance, listing C.1"),
    "f_mains": (50.0, "mains frequency, listing C.1"),
    "a1": (15.38, "DC force cubic fit, listing C.9"),
    "a2": (1.652e-14, "DC force cubic fit, listing C.9"),
    "a3": (1.473e5, "DC force cubic fit, listing C.9"),
    "d_dc": (0.0625, "eq 4.5 (xa = x - 0.0625)"),
    "d_ac": (0.0455, "eq 4.9 (xb = x + 0.0455)"),
    "L0": (0.48, "inductance fit, eq 4.13 / listing C.11"),
    "A": (0.048, "inductance fit, eq 4.13 / listing C.11"),
    "B": (0.039, "inductance fit, eq 4.13 / listing C.11"),
    "dc_scale": (1.0, "DC force table 4.1 measured at 20 V DC"),
    "F_static": (31.1, "static force, section 4.7 / listing C.14 (C5)"),
    "soil_c": (135.0, "viscous soil coefficient Fs, listings C.4-C.6"),
    "soil_friction": (1000.0, "dry soil friction, listing C.14 (C7)"),
}

PRESETS = {
    "thesis-text": {
        "R": (30.0, "sections 4.5-4.6"),
        "C": (3.0e-4, "sections 4.5-4.6"),
        "V": (25.0, "sections 4.5-4.6 (Fig 4.24: 25 V amplitude)"),
        "k": (1e5, "not given in the text; listing C.1 value"),
        "c": (10.0, "not given in the text; listing C.1 value"),
        "relay_hz": (5.0, "section 4.8 (Fig 4.27 d); the text sweeps 2-10 Hz"),
    },
    "matlab-listing": {
        "R": (25.0, "listing C.1"),
        "C": (2.8e-4, "listing C.1"),
        "V": (25.0, "never assigned in listing C.1; thesis-text value"),
        "k": (1e5, "listing C.1 (k1)"),
        "c": (10.0, "listing C.1 (c1)"),
        "relay_hz": (10.0, "listing C.1 (f)"),
    },
    "dynamics-listing": {
        "R": (300.0, "listing C.14 (C8)"),
        "C": (3.0e-4, "listing C.14 (C3)"),
        "V": (50 * 1.4142, "listing C.14 (1.4142*C9, C9 = 50 V)"),
        "k": (1e6, "listing C.14 (C6)"),
        "c": (500.0, "listing C.14 (C2)"),
        "relay_hz": (8.0, "listing C.14 (phi = 2 pi 8)"),
        "F_static": (31.1, "listing C.14 (C5)"),
        "soil_friction": (1000.0, "listing C.14 (C7)"),
    },
}


def preset_values(name: str) -> dict:
    """name -> (value, provenance) for every parameter of preset ``name``."""
    from .parameters import ParameterError
    if name not in PRESETS:
        raise ParameterError(f"unknown preset {name!r}; presets: {', '.join(PRESETS)}")
    out = dict(COMMON)
    out.update(PRESETS[name])
    return {k: (float(v), f"{name}: {src}") for k, (v, src) in out.items()}
