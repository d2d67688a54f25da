"""The README and the documentation pages are programs: every Python block runs as printed (in the default
run with the smaller grids of its `# quick: A -> B; C -> D` comment, as written under --runslow, there also as
a script under a main guard), the bifurc commands of their shell blocks (indented, or `$ ` lines of a
console block) run under --runslow, and every notebook in notebooks/ executes in its quick form without an
error or a stderr output."""
import os
import re
import subprocess
import sys
import textwrap
from pathlib import Path

import matplotlib
import pytest

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
#: folders of docs/ that the docs build writes (docs/conf.py): not sources
GENERATED = ("_build", "api", "studies", "notebooks")
DOCS = [ROOT / "README.md"] + sorted(p for p in (ROOT / "docs").rglob("*.md")
                                     if p.relative_to(ROOT / "docs").parts[0] not in GENERATED)
NOTEBOOKS = sorted((ROOT / "notebooks").glob("*.ipynb"))
ENV = dict(os.environ, PYTHONPATH=os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")]), MPLBACKEND="Agg")


def _id(path) -> str:
    return str(path.relative_to(ROOT))


def python_blocks(path, quick: bool) -> list[str]:
    """The file's ```python blocks in order, their `# quick:` substitutions applied when ``quick``."""
    out = []
    for code in re.findall(r"```python\n(.*?)```", path.read_text(), flags=re.S):
        rules = re.findall(r"^# quick: (.*)\n", code, flags=re.M)
        code = re.sub(r"^# quick: .*\n", "", code, flags=re.M)
        for rule in (r for line in rules for r in line.split(";")) if quick else ():
            old, new = (part.strip() for part in rule.split("->"))
            assert old in code, f"{path.name}: `# quick: {rule}` matches nothing in its block"
            code = code.replace(old, new)
        out.append(code)
    return out


def shell_commands(path) -> list[str]:
    """The bifurc commands of the file's indented (shell) blocks and of the `$ ` lines of its console blocks
    (a trailing backslash continues a line)."""
    text = path.read_text()
    lines = re.findall(r"^    (\S.*)$", text, flags=re.M)
    for block in re.findall(r"```console\n(.*?)```", text, flags=re.S):
        lines += [line[2:] for line in re.sub(r"\\\n\s*", " ", block).splitlines() if line.startswith("$ ")]
    return [line.split(".venv/bin/")[-1] for line in lines if re.match(r"(\S+ )*?(\.venv/bin/)?bifurc ", line)
            and ("bifurc " in line.split("&&")[-1])]


def doc_commands() -> list[str]:
    """Every page's commands, each once, less those that need a machine the tests do not have (a cluster)."""
    seen = []
    for path in DOCS:
        for c in shell_commands(path):
            if c not in seen and "tcp://host" not in c:
                seen.append(c)
    return seen


def _run_blocks(path, quick, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    ns = {"__name__": "__main__"}
    for k, code in enumerate(python_blocks(path, quick)):
        try:
            exec(compile(code, f"{path.name} block {k + 1}", "exec"), ns)
        finally:
            plt.close("all")
    return ns


def _orbit_17_12(ns):                   # 8.5 Hz: period 17, 12 impacts, stable
    o = ns["o"]
    assert int(o.period) == 17 and int(o.impacts_per_period) == 12 and int(o.stable) == 1


def _main_job(ns):
    _orbit_17_12(ns)                     # here from the sweep's stored point
    assert ns["p"].options.dc_law == "listing" and ns["p"].forcing_q() == 9


def _branches(ns):
    assert abs(float(ns["ds"].special_value[0]) - (-0.039370255693)) < 1e-8   # the closed form the page cites
    kinds, at = ns["fr"].special_kind.values, ns["fr"].special_value.values
    assert any(abs(float(a) - 2.66319) < 1e-5 for a, k in zip(at, kinds) if k == 1)   # its period doubling
    assert list(ns["gz"].impacts_per_period.values[[0, -1]]) == [0, 1]         # 0 up to the grazing, 1 after it


def _quick_start(ns):
    _orbit_17_12(ns)
    assert "period-17" in str(ns["d"].bifurc.class_at(8.5)["text"])


def _census(ns):
    fractions = ns["atlas"].basin_fraction.sum("attractor").values
    assert abs(fractions - 1).max() < 1e-12                                     # the fractions sum to 1


def _lorenz84(ns):                     # at a = 5 Attractors.jl's tutorial shows a limit cycle beside a chaotic attractor
    df = ns["table"]
    assert sorted(df["description"]) == ["chaotic attractor", "limit cycle"]
    assert abs(df["basin_fraction"].sum() - 1) < 1e-12
    chaos = df[df["description"] == "chaotic attractor"].iloc[0]
    assert chaos["lyapunov_low"] > 0 and chaos["lifetime_verdict"] == "attractor"


#: what the values a page's blocks comment on must be (the page's path: its check)
CHECKS = {"README.md": _quick_start, "docs/tutorials/main-job.md": _main_job,
          "docs/tutorials/frequency-response.md": _branches, "docs/tutorials/census.md": _census,
          "docs/howto/autonomous-flows.md": _lorenz84}


def test_the_checked_pages_exist():
    assert all((ROOT / page).is_file() for page in CHECKS)


@pytest.mark.parametrize("path", DOCS, ids=[_id(p) for p in DOCS])
def test_every_python_block_runs_in_its_quick_form(path, tmp_path, monkeypatch):
    ns = _run_blocks(path, True, tmp_path, monkeypatch)
    CHECKS.get(_id(path), lambda ns: None)(ns)   # the lookups the blocks print comment on


@pytest.mark.slow
@pytest.mark.parametrize("path", DOCS, ids=[_id(p) for p in DOCS])
def test_every_python_block_runs_as_written_in_a_script(path, tmp_path):
    """As a user's script: the blocks in order under `if __name__ == "__main__":` (sweeps on worker processes)."""
    body = "\n".join(python_blocks(path, False))
    script = tmp_path / "readme_script.py"
    script.write_text('if __name__ == "__main__":\n' + textwrap.indent(body, "    ") + "\n    pass\n")
    r = subprocess.run([sys.executable, str(script)], cwd=tmp_path, env=ENV, capture_output=True, text=True,
                       timeout=1800)
    assert r.returncode == 0, r.stderr[-3000:]


@pytest.mark.slow
@pytest.mark.parametrize("command", doc_commands())
def test_every_documented_command_runs(command, tmp_path):
    import shlex
    argv = shlex.split(command)
    if argv[1] in ("report",) and not (tmp_path / argv[2]).exists():   # reads the main job's output
        subprocess.run([sys.executable, "-m", *shlex.split(shell_commands(ROOT / "README.md")[0])], cwd=tmp_path,
                       env=ENV, capture_output=True, timeout=600)
    r = subprocess.run([sys.executable, "-m", *argv], cwd=tmp_path, env=ENV, capture_output=True, text=True,
                       timeout=1800)
    assert r.returncode == 0, r.stderr[-3000:]


def test_a_script_without_a_main_guard_gets_one_error_naming_it(tmp_path):
    """F2: the README's sweep pasted into a script ended in BrokenProcessPool, its workers re-running it."""
    script = tmp_path / "snippet.py"
    script.write_text("import numpy as np, bifurc\nprint('top level')\n"
                      "bifurc.sweep('thesis-1dof', 'relay_hz', np.linspace(2, 10, 41), preset='matlab-listing', "
                      "transient=5, record=4, workers=2, progress=False)\n")
    r = subprocess.run([sys.executable, str(script)], cwd=tmp_path, env=ENV, capture_output=True, text=True,
                       timeout=300)
    last = r.stderr.strip().splitlines()[-1]
    assert r.returncode == 1 and last == (
        f"bifurc.run.executor.MainGuardError: worker processes could not start: they re-import {script}, which "
        'starts a sweep at its top level; put the script\'s code under `if __name__ == "__main__":`, or pass workers=1')
    assert "BrokenProcessPool" not in r.stderr and "freeze_support" not in r.stderr


def test_the_readme_lists_every_shell_command_it_runs():
    commands = shell_commands(ROOT / "README.md")
    assert commands[0].startswith("bifurc diagram --scene thesis-1dof") and len(commands) >= 4
    assert "bifurc study --quick" not in " ".join(doc_commands())            # a study needs its name
    assert any(c.startswith("bifurc continue --scene impact-oscillator --set w0=1") for c in doc_commands())


def test_the_readme_is_short_and_keeps_its_two_commands_at_the_top():
    text = (ROOT / "README.md").read_text()
    lines = text.splitlines()
    assert len(lines) <= 200
    first = [line for line in lines if line.startswith("    ")][:2]
    assert first[0].startswith("    python3 -m venv .venv && .venv/bin/pip install -q -e . && .venv/bin/bifurc diagram")
    assert first[1] == "    python3 -m venv .venv && .venv/bin/pip install -q -e \".[test,dask,explore]\" && .venv/bin/python -m pytest -q"
    for link in re.findall(r"\]\(((?:docs/|CHANGELOG)[^)#]+)", text):      # its links into the docs resolve
        assert (ROOT / link).is_file(), link


def test_the_readme_states_each_study_s_cost_as_study_help_does():
    from bifurc.commands.study import DURATIONS, durations_table, studies
    assert set(DURATIONS) == set(studies())
    assert durations_table() in (ROOT / "README.md").read_text()
    from bifurc.cli import build_parser
    sub = build_parser()._subparsers._group_actions[0].choices["study"]
    text = sub.format_help()
    for name, (quick, full, _) in DURATIONS.items():
        assert f"{name}" in text and f"quick {quick}; full {full}" in " ".join(text.split())


@pytest.mark.parametrize("path", NOTEBOOKS, ids=[p.name for p in NOTEBOOKS])
def test_every_notebook_executes_quickly_without_errors_or_stderr(path, tmp_path):
    """With Jupyter's inline backend (a user's notebook has no MPLBACKEND=Agg); outputs in tmp_path."""
    import nbclient
    import nbformat
    nb = nbformat.read(path, as_version=4)
    env = dict(ENV, BIFURC_NOTEBOOK_OUT=str(tmp_path), MPLBACKEND="module://matplotlib_inline.backend_inline")
    env.pop("BIFURC_NOTEBOOK_FULL", None)
    before = dict(os.environ)
    os.environ.clear()
    os.environ.update(env)
    try:
        nbclient.NotebookClient(nb, timeout=600, kernel_name="python3",
                                resources={"metadata": {"path": str(path.parent)}}).execute()
    finally:
        os.environ.clear()
        os.environ.update(before)
    outputs = [o for c in nb.cells if c.cell_type == "code" for o in c.get("outputs", [])]
    assert not [o for o in outputs if o.output_type == "error"]
    assert not [o.get("text", "")[:200] for o in outputs if o.get("name") == "stderr"]
    for cell in nb.cells:  # each figure once (a returned Figure would show twice)
        if cell.cell_type == "code":
            assert sum("image/png" in o.get("data", {}) for o in cell.get("outputs", [])) <= 1, cell.source
    assert sum("image/png" in o.get("data", {}) for o in outputs) >= 1
    if path.name == "orbits.ipynb":                 # a frequency response, a branch through a grazing
        text = "".join(o.get("text", "") for o in outputs)
        assert "period_doubling  Omega = 2.6631899" in text and "grazing          F = 0.1843908891" in text
        assert "Nordmark" in text and sum("image/png" in o.get("data", {}) for o in outputs) == 2
    if path.name == "explore_thesis_1dof.ipynb":     # the diagram, the table, the classes, the time history
        text = "".join(o.get("text", "") for o in outputs)
        assert "toolkit" in text and " 6 " in text and "in the last 10 relay periods" in text
        assert sum("image/png" in o.get("data", {}) for o in outputs) >= 2 and (tmp_path / "matlab-listing-90V.nc").exists()
        assert any("relay_hz" in o.get("data", {}).get("text/html", "") for o in outputs)   # ds.bifurc.table()
        assert "sys.path" not in nb.cells[1].source     # the public API is importable as is
