"""The thesis' measured tables, shipped with the package (first line of each file: its source)."""
from __future__ import annotations

from importlib import resources

import numpy as np

TABLES = {
    "dc_force": "dc_force_table_4_1.csv",
    "inductance": "inductance_table_4_2.csv",
    "progression_vs_frequency": "progression_vs_frequency_table_5_5.csv",
    "progression_vs_static": "progression_vs_static_tables_5_2_to_5_4.csv",
}


def load_table(name: str) -> dict:
    """Columns of a measured table as float arrays, plus ``"source"`` (the thesis' caption)."""
    from .parameters import ParameterError
    if name not in TABLES:
        raise ParameterError(f"unknown table {name!r}; tables: {', '.join(TABLES)}")
    text = resources.files("maps").joinpath("data", TABLES[name]).read_text()
    lines = [ln for ln in text.splitlines() if ln.strip()]
    source = lines[0].lstrip("# ").strip()
    header = lines[1].split(",")
    rows = np.array([[float(v) for v in ln.split(",")] for ln in lines[2:]])
    out = {h: rows[:, j] for j, h in enumerate(header)}
    out["source"] = source
    return out
