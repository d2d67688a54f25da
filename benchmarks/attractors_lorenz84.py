"""Attractors.jl's global continuation example on our census (issue 47, section 3); not run in CI.

    python benchmarks/attractors_lorenz84.py                  # 66 values x 1000 starts, every core
    python benchmarks/attractors_lorenz84.py --starts 100     # a smaller form

The modified Lorenz-84 flow (x' = y - x, y' = -x z + b |z|, z' = x y - a, b = 0.1) as declared in
docs/howto/autonomous-flows.md (its first Python block, imported from a module written from it, so that the
worker processes import the same scene), over a = 4.7:0.02:6 (66 values) with Attractors.jl's box [-15, 15] x
[-20, 20] x [-20, 20], 100 cells a side and 1000 starts per value: the census end to end (compilation included),
what it finds per value (fixed points, limit cycles, chaotic attractors, their fractions), written to
benchmarks/reports/attractors-lorenz84/README.md beside Attractors.jl's account of the same system, and a record in
benchmarks/results/.
"""
from __future__ import annotations

import argparse
import importlib
import re
import resource
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(HERE))
from record import Run  # noqa: E402

PAGE = ROOT / "docs" / "howto" / "autonomous-flows.md"
REPORT = HERE / "reports" / "attractors-lorenz84" / "README.md"

#: Attractors.jl's account of the same system and range (its tutorial, docs/src/tutorial.jl, over a = 4.5:0.02:6 with
#: the box [-10, 10] x [-15, 15]^2 in that version; bfkit_comparison.jl runs 4.7:0.02:6 with the box used here, "about
#: 15 seconds"), in our words: the maximum Lyapunov exponents it plots show a limit cycle first, then bistability of a
#: chaotic attractor and a limit cycle, then a limit cycle alone, then a second bistable regime of chaos and a limit
#: cycle; at a = 5 the two coexist (its basins_fractions example)
ANCHOR = ("limit cycle alone; then a chaotic attractor beside the limit cycle; then the limit cycle alone again; then "
          "a second regime of a chaotic attractor beside a limit cycle; at a = 5 a limit cycle and a chaotic "
          "attractor coexist")


def scene_module():
    """The docs page's first Python block as a module (its LORENZ scene importable by worker processes)."""
    code = re.findall(r"```python\n(.*?)```", PAGE.read_text(), flags=re.S)[0]
    folder = Path(tempfile.mkdtemp(prefix="lorenz84-"))
    (folder / "lorenz84_scene.py").write_text(code)
    sys.path.insert(0, str(folder))
    return importlib.import_module("lorenz84_scene")


def kinds(ds, i) -> dict:
    """{fixed point | limit cycle | chaotic attractor | ...: [(label, fraction)]} at value ``i``, and the outcomes."""
    from attractors import words        # benchmarks/attractors.py: ds.bifurc.table()'s description
    out: dict = {}
    text = words(ds)
    for j, label in enumerate(ds.attractor_label.values):
        f = float(ds.basin_fraction.values[i, j])
        if f > 0 or (str(label).startswith("A") and ds.present.values[i, j]):
            what = text[i, j] if str(label).startswith("A") else f"outcome {label}"
            out.setdefault(what, []).append((str(label), f))
    return out


def report(ds, seconds, cmd, commit, date, workers, load) -> str:
    a = ds["a"].values
    lines = ["# Attractors.jl's modified Lorenz-84 example on the census", "",
             f"Command `{cmd}`, commit {commit}, {date}, {workers} worker processes on the shared 2-core machine "
             f"(load {load}). Written by `benchmarks/attractors_lorenz84.py`; the scene is the one of "
             "`docs/howto/autonomous-flows.md` (sample_step 0.5).", "",
             f"**{a.size} values x {ds.sizes['start']} starts: {seconds:.1f} s end to end** (fresh starts "
             f"{float(ds.attrs['fresh_seconds']):.1f} s, seeding and matching {float(ds.attrs['seeding_seconds']):.1f} s, "
             f"linking {float(ds.attrs['linking_seconds']):.1f} s); {float(ds.attrs['periods_per_start_mean']):.0f} "
             f"samples per start on average. Attractors.jl states about 15 s for its 66 x 1000.", "",
             f"Attractors.jl's account of the same system and range: {ANCHOR}.", "",
             "| a | fixed points | limit cycles | chaotic attractors | other outcomes |", "|---|---|---|---|---|"]
    for i, v in enumerate(a):
        k = kinds(ds, i)

        def cell(name):
            got = [f"{lab} {f:.3f}" for key, items in k.items() if key.startswith(name) for lab, f in items]
            return ", ".join(got) or "-"
        other = ", ".join(f"{key.replace('outcome ', '')} {f:.3f}" for key, items in k.items()
                          if key.startswith("outcome") for _, f in items) or "-"
        lines.append(f"| {v:.2f} | {cell('fixed point')} | {cell('limit cycle')} | {cell('chaotic')} | {other} |")
    return "\n".join(lines) + "\n"


def kept_sections() -> str:
    """The report's written sections (from its first "## " heading on), kept when the run rewrites its table."""
    old = REPORT.read_text() if REPORT.exists() else ""
    at = old.find("\n## ")
    return "" if at < 0 else old[at:]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--starts", type=int, default=1000)
    ap.add_argument("--workers", type=int, default=None)
    ap.add_argument("--no-record", action="store_true")
    a = ap.parse_args(argv)
    cmd = "python benchmarks/attractors_lorenz84.py" + (f" --starts {a.starts}" if a.starts != 1000 else "") + \
        (f" --workers {a.workers}" if a.workers else "")
    run = Run(f"modified Lorenz-84 census, 66 values x {a.starts} starts", cmd)
    t = time.perf_counter()
    mod = scene_module()
    import bifurc
    values = np.round(np.arange(4.7, 6.0 + 1e-9, 0.02), 10)
    ds = bifurc.attractors(mod.LORENZ, "a", values, bifurc.Census(cells=100, locate=768),
                           starts=bifurc.Box(n=a.starts, seed=1), progress=True, workers=a.workers)
    seconds = time.perf_counter() - t
    kids = resource.getrusage(resource.RUSAGE_CHILDREN)
    ds.to_netcdf(Path(tempfile.gettempdir()) / f"lorenz84-{a.starts}.nc")
    rec = run.record()
    text = report(ds, seconds, cmd, ",".join(rec["commits"]) + (" (dirty)" if rec["dirty"] else ""), rec["date"] + " "
                  + rec["time_utc"] + " UTC", ds.attrs["workers"], rec["load"])
    print(text)
    if not a.no_record:
        run.figure(f"modified Lorenz-84 census 66 x {a.starts} end to end", round(seconds, 1), "s", target="<= 15 s")
        run.figure("samples per start, mean", round(float(ds.attrs["periods_per_start_mean"]), 1), "samples")
        run.figure("fresh starts' census", round(float(ds.attrs["fresh_seconds"]), 1), "s")
        run.figure("worker processes' CPU", round(kids.ru_utime + kids.ru_stime, 1), "s")
        # the record first: written after the report, it saw the report itself as a dirty tree
        print(run.write(notes=f"{ds.attrs['workers']} worker processes; report {REPORT.relative_to(ROOT)}"))
        REPORT.parent.mkdir(parents=True, exist_ok=True)
        REPORT.write_text(text + kept_sections())
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
