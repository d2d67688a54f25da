"""One machine-readable record per benchmark run, in benchmarks/results/ (the docs' benchmarks page and its
history plots are generated from them: ``python benchmarks/results_page.py``).

In a benchmark script::

    from record import Run
    run = Run("main job", command="bifurc diagram ...")      # notes the load, commit and time at the start
    ...                                                        # the measurement
    run.figure("main job end to end", 25.3, "s", target="30 s")
    run.write()                                                # benchmarks/results/<date>-<slug>.json

or after the fact, from the shell::

    python benchmarks/record.py --title "main job" --command "bifurc diagram ..." \\
        --figure "main job end to end=25.3 s" --load 0.6-1.1 --commit ed0af0c --date 2026-11-26 --time 05:26

A record holds: id, title, date and UTC time, the commit (and whether the tree was dirty), the commands, the
machine (cores, CPU, Python, heyoka), the load (1-minute load average at the start and the end, or as given),
the figures (name, value, unit; optional target, commit, note) and free notes.
"""
from __future__ import annotations

import argparse
import datetime as _dt
import json
import os
import platform
import re
import subprocess
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "benchmarks" / "results"


def _git(*args) -> str:
    try:
        return subprocess.run(["git", *args], cwd=ROOT, capture_output=True, text=True, timeout=10).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        return ""


def machine() -> dict:
    try:
        from importlib.metadata import version
        heyoka = version("heyoka")
    except Exception:   # noqa: BLE001 - a record is still worth writing without it
        heyoka = None
    cpu = platform.processor() or platform.machine()
    try:
        cpu = next(line.split(":", 1)[1].strip() for line in Path("/proc/cpuinfo").read_text().splitlines()
                   if line.startswith("model name"))
    except (OSError, StopIteration):
        pass
    return {"cores": os.cpu_count(), "cpu": cpu, "python": platform.python_version(), "heyoka": heyoka,
            "system": platform.system()}


def _load() -> float | None:
    try:
        return round(os.getloadavg()[0], 2)
    except OSError:
        return None


def slug(text: str) -> str:
    return re.sub(r"[^a-z0-9]+", "-", text.lower()).strip("-")[:70].rstrip("-")


class Run:
    """A benchmark run being measured: its start is noted now, its figures added, then written once."""

    def __init__(self, title: str, command: str | list[str], notes: str = ""):
        self.title, self.notes = title, notes
        self.commands = [command] if isinstance(command, str) else list(command)
        self.start = _dt.datetime.now(_dt.timezone.utc)
        self.load_start = _load()
        self.figures: list[dict] = []

    def figure(self, name: str, value: float, unit: str, **extra) -> None:
        self.figures.append(dict(name=name, value=value, unit=unit, **extra))

    def record(self, **override) -> dict:
        end = _dt.datetime.now(_dt.timezone.utc)
        commit = _git("rev-parse", "--short", "HEAD") or None
        rec = {
            "id": f"{self.start:%Y-%m-%d-%H%M}-{slug(self.title)}",
            "title": self.title,
            "date": f"{self.start:%Y-%m-%d}",
            "time_utc": f"{self.start:%H:%M}-{end:%H:%M}",
            "commits": [commit] if commit else [],
            "dirty": bool(_git("status", "--porcelain", "--untracked-files=no")),
            "commands": self.commands,
            "machine": machine(),
            "load": f"{self.load_start}-{_load()}",
            "figures": self.figures,
            "notes": self.notes,
        }
        rec.update(override)
        return rec

    def write(self, **override) -> Path:
        rec = self.record(**override)
        RESULTS.mkdir(parents=True, exist_ok=True)
        path = RESULTS / f"{rec['id']}.json"
        path.write_text(json.dumps(rec, indent=1, ensure_ascii=False) + "\n")
        return path


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python benchmarks/record.py", description="write one benchmark record")
    ap.add_argument("--title", required=True)
    ap.add_argument("--command", action="append", required=True)
    ap.add_argument("--figure", action="append", default=[], metavar="NAME=VALUE UNIT")
    ap.add_argument("--load", help="the load as measured (default: now)")
    ap.add_argument("--commit", help="the commit measured (default: HEAD)")
    ap.add_argument("--date", help="YYYY-MM-DD (default: today, UTC)")
    ap.add_argument("--time", help="HH:MM or HH:MM-HH:MM, UTC")
    ap.add_argument("--notes", default="")
    a = ap.parse_args(argv)
    run = Run(a.title, a.command, a.notes)
    for f in a.figure:
        name, _, rest = f.rpartition("=")
        value, _, unit = rest.strip().partition(" ")
        run.figure(name.strip(), float(value), unit.strip() or "1")
    override = {k: v for k, v in dict(load=a.load, date=a.date, time_utc=a.time).items() if v}
    if a.commit:                      # a past run: the tree's state then is not known from here
        override["commits"], override["dirty"] = [a.commit], None
    if a.date:
        override["id"] = f"{a.date}-{(a.time or '0000')[:5].replace(':', '')}-{slug(a.title)}"
    print(run.write(**override))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
