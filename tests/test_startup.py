"""`bifurc --help` and `bifurc --version` start fast: the command line imports neither heyoka nor
numpy nor xarray until a command runs (lazy package exports, the law names in maps.laws)."""
import os
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
ENV = dict(os.environ, PYTHONPATH=str(ROOT))
#: the start-up budget of `bifurc --help` / `--version` [s], best of 3 (issue 29)
BUDGET = 0.3
#: on a machine where the bare interpreter is slow, the budget is this margin over `python -c pass` [s]
MARGIN = 0.2


def _best_of_3(argv) -> float:
    best = float("inf")
    for _ in range(3):
        t0 = time.perf_counter()
        r = subprocess.run(argv, env=ENV, capture_output=True, text=True, timeout=60)
        best = min(best, time.perf_counter() - t0)
        assert r.returncode == 0, r.stderr
    return best


def test_help_and_version_start_within_the_budget():
    bare = _best_of_3([sys.executable, "-c", "pass"])
    limit = max(BUDGET, bare + MARGIN)   # a slow CI machine: the margin over the bare interpreter
    for flag in ("--help", "--version"):
        best = _best_of_3([sys.executable, "-m", "bifurc", flag])
        assert best < limit, f"bifurc {flag}: {best:.3f} s best of 3 (python -c pass {bare:.3f} s)"


def test_the_parser_is_built_without_the_integrator_and_keeps_the_choices():
    code = ("import sys, io, contextlib\nfrom bifurc.cli import main\nout = io.StringIO()\n"
            "with contextlib.redirect_stdout(out):\n    main(['diagram', '--help'])\n"
            "heavy = [m for m in ('heyoka', 'numpy', 'xarray', 'matplotlib', 'scipy') if m in sys.modules]\n"
            "assert not heavy, heavy\nprint(out.getvalue())")
    r = subprocess.run([sys.executable, "-c", code], env=ENV, capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr
    text = " ".join(r.stdout.split())
    assert "--dc-law {listing,fit,measured,catalogue,dynamics-script}" in text and "--soil {viscous,coulomb,drift}" in text


def test_the_light_law_tables_are_the_models():
    import maps.laws
    import maps.model
    assert maps.model.DC_LAWS is maps.laws.DC_LAWS and maps.model.SOIL_LAWS is maps.laws.SOIL_LAWS
    import maps
    assert maps.SOIL_LAWS is maps.laws.SOIL_LAWS
    assert callable(maps.simulate) and callable(maps.problem)   # the functions, not their submodules
