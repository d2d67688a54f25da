"""One-off: the dated sections of the old benchmarks/README.md log (at b962ece) as one JSON record each.

    python benchmarks/results/convert_log.py OLD_README.md

Each section becomes ``benchmarks/results/<date>-<slug>.json`` with what its heading and text state: the
date and UTC time window, heyoka's version, the machine and its load (as written), the commands and
commits it names, its bold figures (``highlights``), the figures curated here (``figures``: name, value,
unit, and the commit and target where the text gives them) and the section's text itself, unchanged
(``text``), so that nothing the log said is lost. Kept for the record of how the records were made.
"""
from __future__ import annotations

import json
import re
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent

QW = "census 21 values x 200 starts, end to end (attractors.py --quick)"
QR = "census against a bare ensemble of the same starts (attractors.py --quick)"

#: the figures read from each section's text by hand (section heading's start: figures); units in UDUNITS
#: where there is one, "1" for ratios and counts
CURATED = {
    "The main job after the copies' decorrelation": [
        dict(name="main job end to end", value=25.3, unit="s", commit="ed0af0c", target="30 s"),
        dict(name="main job values decided", value=73, unit="1", commit="ed0af0c", of=81),
        dict(name="anytime overhead against a fixed record, 1000 values", value=0.97, unit="1", commit="c5a9b3d",
             target="1.3"),
    ],
    "The sensitivity study's full form": [
        dict(name="sensitivity full form wall", value=3964, unit="s", target="7200 s"),
    ],
    "Attractor census, issue 31: torus evidence, and unstable orbits noted": [
        dict(name=QW, value=74.9, unit="s", commit="f2a2b4e", when="2026-11-27 08:47", load="nothing else running", target="30 s"),
        dict(name=QR, value=2.09, unit="1", commit="f2a2b4e", when="2026-11-27 08:47", target="1.3"),
        dict(name=QW, value=73.6, unit="s", commit="9b40f85", when="2026-11-27 05:52", load="nothing else running", target="30 s"),
        dict(name=QR, value=2.19, unit="1", commit="9b40f85", when="2026-11-27 05:52", target="1.3"),
    ],
    "Attractor census, issue 31: records that decide": [
        dict(name=QW, value=80.9, unit="s", commit="f537126", when="2026-11-27 03:30", load="3.1-4.4", target="30 s"),
        dict(name=QR, value=2.33, unit="1", commit="f537126", when="2026-11-27 03:30", target="1.3"),
    ],
    "Attractor census, issue 31: the benchmarks had run another model": [
        dict(name=QW, value=62.1, unit="s", commit="758d0e1", when="2026-11-26 17:37", load="small diagnostics beside it", target="30 s"),
        dict(name=QR, value=2.08, unit="1", commit="758d0e1", when="2026-11-26 17:37", target="1.3"),
        dict(name=QW, value=75.4, unit="s", commit="aa3197b", when="2026-11-27 00:47", load="idle", target="30 s"),
        dict(name=QR, value=2.24, unit="1", commit="aa3197b", when="2026-11-27 00:47", target="1.3"),
        dict(name=QW, value=77.9, unit="s", commit="72d3c3c", when="2026-11-26 21:20", load="idle", target="30 s"),
        dict(name=QR, value=2.28, unit="1", commit="72d3c3c", when="2026-11-26 21:20", target="1.3"),
        dict(name=QW, value=81.8, unit="s", commit="3d2caf6", when="2026-11-26 18:02", load="idle", target="30 s"),
        dict(name=QR, value=2.19, unit="1", commit="3d2caf6", when="2026-11-26 18:02", target="1.3"),
        dict(name=QW, value=87.5, unit="s", commit="96a856b", when="2026-11-26 15:09", target="30 s"),
    ],
    "Attractor census, issue 31: neutral motion": [
        dict(name=QW, value=107.2, unit="s", commit="54bc35f", when="2026-11-26 13:14", load="0.4-1.7", target="30 s",
             note="before 96a856b the census benchmarks ran the thesis-text preset, another model"),
    ],
    "Attractor census, issue 31: the merged census measured idle": [
        dict(name=QW, value=110.6, unit="s", when="2026-11-26 10:43", load="0.1-1.6", target="30 s",
             note="before 96a856b the census benchmarks ran the thesis-text preset, another model"),
    ],
    "Equal timing for every method": [
        dict(name="one trajectory against the best scipy method", value=164, unit="1", target="150",
             note="heyoka-transient, seven runs 164-172x; the default run 149.9-156x"),
        dict(name="90 V diagram against a bare batch ensemble", value=1.16, unit="1", target="1.2"),
        dict(name="default diagram 1000 values wall", value=14.39, unit="s", target="20 s", note="best of two rounds"),
        dict(name="map step with exact Jacobian against a plain step", value=4.88, unit="1", target="5",
             note="4.88-4.92 over four runs"),
    ],
    "Idle re-measurements after the stick guard": [
        dict(name="90 V diagram against a bare batch ensemble", value=1.17, unit="1", target="1.2",
             note="two runs, 1.17 and 1.16"),
        dict(name="100 x 100 regime map wall", value=168.9, unit="s", target="180 s"),
        dict(name="2-DOF progression against a bare ensemble, drift soil", value=1.10, unit="1", target="1.3"),
        dict(name="default diagram 1000 values wall", value=16.51, unit="s", target="20 s",
             note="/usr/bin/time bifurc diagram, CLI defaults"),
        dict(name="5000-value sweep peak memory", value=939, unit="MiB", target="1024 MiB"),
        dict(name="one trajectory against the best scipy method", value=110, unit="1", target="150"),
    ],
    "Latest figures (2026-11-23": [
        dict(name="default diagram 1000 values wall", value=25.5, unit="s", target="20 s", note="25.5-27.1 s"),
        dict(name="90 V diagram against a bare batch ensemble", value=1.56, unit="1", target="1.2"),
        dict(name="one trajectory against the best scipy method", value=187, unit="1", target="150"),
        dict(name="5000-value sweep peak memory", value=956, unit="MiB", target="1024 MiB"),
        dict(name="map step with exact Jacobian against a plain step", value=4.99, unit="1", target="5",
             note="4.6-5.6 over four runs"),
    ],
}


def slug(text: str) -> str:
    return re.sub(r"[^a-z0-9]+", "-", text.lower()).strip("-")[:70].rstrip("-")


def parse(title: str, body: str) -> dict:
    paren = re.search(r"\(([^()]*(?:\([^()]*\)[^()]*)*)\)\s*$", title)
    meta = paren.group(1) if paren else ""
    date = re.search(r"20\d\d-\d\d-\d\d(?:/\d\d)?", meta or title)
    times = re.search(r"\d\d:\d\d(?:-\d\d:\d\d)?(?: UTC)?", meta)
    heyoka = re.search(r"heyoka ([\d.]+)", meta)
    load = re.search(r"load ([\d.]+(?:-[\d.]+)?)", meta)
    cores = re.search(r"(\d) (?:idle |shared )?cores", meta)
    commands = []
    for c in re.findall(r"`((?:python |bifurc |pytest )[^`]+)`", body) + re.findall(r"^    ((?:python|bifurc) .+)$", body, re.M):
        c = c.strip()
        if c not in commands:
            commands.append(c)
    commits = []
    for c in re.findall(r"\b(?:at|commit|git|before|after)\s+`?([0-9a-f]{7,10})\b", body + " " + title):
        if c not in commits:
            commits.append(c)
    return {
        "title": title.split(" (")[0] if paren else title,
        "heading": title,
        "date": date.group(0) if date else None,
        "time_utc": times.group(0).replace(" UTC", "") if times else None,
        "commits": commits,
        "commands": commands,
        "machine": {"cores": int(cores.group(1)) if cores else 2, "heyoka": heyoka.group(1) if heyoka else None,
                    "as_logged": meta},
        "load": load.group(1) if load else ("idle" if re.search(r"idle|no other agent", meta) else None),
        "highlights": [h.strip() for h in re.findall(r"\*\*([^*]+)\*\*", body)],
        "figures": [],
        "source": "benchmarks/README.md at b962ece (the dated log, converted by benchmarks/results/convert_log.py)",
        "text": body.strip() + "\n",
    }


def main(path) -> None:
    text = Path(path).read_text()
    sections = re.split(r"^## ", text, flags=re.M)[1:]
    seen = set()
    for k, sec in enumerate(sections):
        title, _, body = sec.partition("\n")
        rec = parse(title.strip(), body)
        for key, figures in CURATED.items():
            if rec["heading"].startswith(key):
                rec["figures"] = figures
        name = f"{(rec['date'] or 'undated')[:10]}-{slug(rec['title'])}"
        while name in seen:
            name += "-2"
        seen.add(name)
        rec["id"] = name
        rec["log_order"] = k + 1          # 1 = the newest section of the log
        (HERE / f"{name}.json").write_text(json.dumps(rec, indent=1, ensure_ascii=False) + "\n")
        print(name, rec["date"], rec["load"], len(rec["commands"]), len(rec["commits"]))


if __name__ == "__main__":
    main(sys.argv[1])
