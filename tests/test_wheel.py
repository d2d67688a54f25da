"""The wheel holds everything `bifurc study` needs: built from this tree, installed into a fresh
environment that sees the dependencies (heyoka, numpy, xarray, ...) but not the project's
editable install, and run from a folder outside the repository."""
import os
import re
import site
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
#: the fastest quick form (about 5 s on 2 shared cores, measured against the other four)
QUICK_STUDY = "prototype-progression"


def _run(cmd, **kw):
    r = subprocess.run([str(c) for c in cmd], capture_output=True, text=True, timeout=600, **kw)
    assert r.returncode == 0, f"{cmd}\n{r.stdout}\n{r.stderr}"
    return r


@pytest.fixture(scope="module")
def installed(tmp_path_factory):
    """(environment's bin folder, a work folder outside the repository, the environment's variables)."""
    tmp = tmp_path_factory.mktemp("wheel")
    _run([sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation", "-q", "-w", tmp / "dist", ROOT])
    wheel, = (tmp / "dist").glob("bifurc-*.whl")
    # the dependencies without the project: every site-packages entry but bifurc's own (its
    # dist-info and the editable finder, which would map bifurc, maps and studies to this tree)
    deps = tmp / "deps"
    deps.mkdir()
    for sp in map(Path, site.getsitepackages()):
        for entry in sp.iterdir():
            own = entry.name.startswith(("__editable__", "bifurc-", "bifurc.", "maps", "studies"))
            if not own and entry.suffix != ".pth" and not (deps / entry.name).exists():
                (deps / entry.name).symlink_to(entry)
    env_dir = tmp / "env"
    _run([sys._base_executable, "-m", "venv", "--without-pip", env_dir])
    purelib = _run([env_dir / "bin" / "python", "-c", "import sysconfig; print(sysconfig.get_path('purelib'))"])
    Path(purelib.stdout.strip(), "deps.pth").write_text(f"{deps}\n")
    _run([sys.executable, "-m", "pip", "--python", env_dir / "bin" / "python", "install", "--no-deps", "--no-index",
          "-q", wheel])
    work = tmp / "work"
    work.mkdir()
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VIRTUAL_ENV")}
    env["MPLBACKEND"] = "Agg"
    where = _run([env_dir / "bin" / "python", "-c", "import bifurc, maps, studies; print(bifurc.__file__); "
                  "print(maps.__file__); print(studies.__file__)"], cwd=work, env=env)
    for path in where.stdout.split():
        assert Path(path).is_relative_to(env_dir), path   # the wheel's copy, not this tree
    return env_dir / "bin", work, env


def test_installed_wheel_lists_every_study_of_pyproject(installed):
    bindir, work, env = installed
    declared = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["entry-points"]["bifurc.studies"]
    r = _run([bindir / "bifurc", "study", "--help"], cwd=work, env=env)
    listed = re.search(r"^studies: (.*)$", r.stdout, re.M).group(1).split(", ")
    assert sorted(listed) == sorted(declared) and len(declared) == 9
    for name, module in declared.items():   # every entry point resolves to a module with run()
        _run([bindir / "python", "-c", f"import {module} as m; assert callable(m.run), {name!r}"], cwd=work, env=env)


def test_installed_wheel_runs_a_quick_study_outside_the_repository(installed):
    bindir, work, env = installed
    out = work / "out"
    r = _run([bindir / "bifurc", "study", QUICK_STUDY, "--quick", "-o", out], cwd=work, env=env)
    assert r.stdout.strip().endswith("report.md and its figures")
    assert (out / "report.md").read_text().startswith("#")


def test_every_package_of_the_tree_is_in_the_wheel_list():
    """pyproject lists packages by hand: a new subpackage left out would be missing from the wheel
    (as maps.engines was until this test's first run)."""
    listed = set(tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]["packages"])
    found = {".".join(p.parent.relative_to(ROOT).parts) for top in ("maps", "bifurc", "studies")
             for p in (ROOT / top).rglob("__init__.py")}
    assert found <= listed, sorted(found - listed)
