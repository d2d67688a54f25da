"""Findings that cannot go stale: what a study states, checked again by re-running it.

A study module may define ``findings(results, quick) -> list[Finding]`` (``results``: what its ``run``
returned): the numbers and labels its report states.  :func:`bifurc.commands.study.run_study`
appends them to the study's ``report.md`` as a table (:func:`table`); the reports committed beside
each study (``studies/<name>/report.md`` for the full form, ``report-quick.md`` for the quick form)
hold that table, and ``bifurc study NAME --check [--quick]`` re-runs the form and compares what it
finds with what the committed report states (:func:`compare`).  A change that moves a finding fails
that check (and the slow test that runs it for every quick form) until the report is regenerated.
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass

__all__ = ["Finding", "HEADER", "table", "parse", "compare"]

#: the heading of the findings table in a report
HEADER = "## Findings (checked by `bifurc study NAME --check`)"


@dataclass(frozen=True)
class Finding:
    """One stated result: a number with its absolute tolerance and unit, or a text (label) that must
    match exactly (``tolerance`` ignored)."""

    name: str
    value: float | str
    tolerance: float = 0.0
    unit: str = ""

    def text(self) -> str:
        return self.value if isinstance(self.value, str) else f"{self.value:.6g}"


def table(findings, form: str, made_by: str = "") -> str:
    """The Markdown section stating ``findings`` of the ``form`` ("quick" or "full"); ``made_by``: the
    command that produced them (its commit and date are added)."""
    from datetime import datetime, timezone

    from maps.provenance import git_commit
    when = (f"Made by `{made_by}` at git {git_commit() or 'unknown'} on {datetime.now(timezone.utc):%Y-%m-%d %H:%M} "
            f"UTC. " if made_by else "")
    rows = [HEADER, "", f"{when}Form: {form}. A number holds within its tolerance (absolute); a text exactly.", "",
            "| finding | value | tolerance | unit |", "|---|---|---|---|"]
    for f in findings:
        if "|" in f.name or (isinstance(f.value, str) and "|" in f.value):
            raise ValueError(f"finding {f.name!r}: no '|' in names or texts (a table cell)")
        tol = "exact" if isinstance(f.value, str) else f"{f.tolerance:.6g}"
        rows.append(f"| {f.name} | {f.text()} | {tol} | {f.unit} |")
    return "\n".join(rows) + "\n"


def parse(text: str) -> tuple[str | None, dict]:
    """(form, {name: Finding}) of the findings table in a report's ``text`` ((None, {}) without one)."""
    if HEADER not in text:
        return None, {}
    part = text.split(HEADER, 1)[1]
    form = re.search(r"Form: (\w+)\.", part)
    out = {}
    for line in part.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) != 4 or cells[0] in ("finding", "---") or not line.startswith("|"):
            continue
        name, value, tol, unit = cells
        if tol == "exact":
            out[name] = Finding(name, value, 0.0, unit)
        else:
            out[name] = Finding(name, float(value), float(tol), unit)
    return (form.group(1) if form else None), out


def _holds(stated: Finding, found: Finding) -> bool:
    if isinstance(stated.value, str) or isinstance(found.value, str):
        return str(stated.value) == found.text()
    a, b = float(stated.value), float(found.value)
    if math.isnan(a) or math.isnan(b):
        return math.isnan(a) and math.isnan(b)
    return abs(a - b) <= stated.tolerance * (1 + 1e-12) + 1e-300


def compare(stated: dict, found) -> list[str]:
    """One line per stated finding that the re-run does not reproduce, or that it no longer reports;
    empty when every stated finding holds."""
    now = {f.name: f for f in found}
    bad = []
    for name, s in stated.items():
        f = now.get(name)
        if f is None:
            bad.append(f"{name}: stated {s.text()} {s.unit}, no longer reported")
        elif not _holds(s, f):
            tol = "" if isinstance(s.value, str) else f" +- {s.tolerance:.3g}"
            bad.append(f"{name}: stated {s.text()}{tol} {s.unit}, found {f.text()}".rstrip())
    return bad
