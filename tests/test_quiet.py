"""G9 (newcomer review 4): heyoka's benign event-detection warnings and tqdm's IProgress warning do not reach
the user. heyoka logs to stdout through its own logger; importing maps.hybrid sets it to "error" unless
BIFURC_HEYOKA_LOG says otherwise."""
import os
import subprocess
import sys
from pathlib import Path

import pytest

import bifurc

ROOT = Path(__file__).resolve().parents[1]
#: heyoka set to its loudest level, then (or not) maps imported, then an integrator built and run: heyoka logs
#: its Taylor decomposition at trace level on stdout
SCRIPT = """import sys
import heyoka as hy
hy.set_logger_level_trace()
if sys.argv[1] == "maps":
    import maps.hybrid  # noqa: F401
x, y = hy.make_vars("x", "y")
hy.taylor_adaptive([(x, y), (y, -x)], [0.0, 1.0]).propagate_until(1.0)
"""


def _heyoka_lines(*argv, **env):
    r = subprocess.run([sys.executable, "-c", SCRIPT, *argv], capture_output=True, text=True, timeout=300,
                       env=dict(os.environ, PYTHONPATH=str(ROOT), **env))
    assert r.returncode == 0, r.stderr
    return [ln for ln in (r.stdout + r.stderr).splitlines() if "[heyoka" in ln]


def test_heyoka_logs_below_error_are_silenced_once_maps_is_imported():
    assert _heyoka_lines("none")                    # the machinery would print (a check that can fail)
    assert _heyoka_lines("maps") == []
    assert _heyoka_lines("maps", BIFURC_HEYOKA_LOG="trace")     # the user's way to see them


def test_the_census_bar_is_text_without_ipywidgets(monkeypatch):
    """tqdm.auto in Jupyter without ipywidgets warns "IProgress not found": the census takes the text bar."""
    import tqdm.auto
    monkeypatch.setitem(sys.modules, "ipywidgets", None)           # not installed
    monkeypatch.setattr(tqdm.auto, "tqdm", lambda *a, **k: pytest.fail("tqdm.auto without ipywidgets"))
    from bifurc.run.progress import tqdm_class
    import tqdm as plain
    assert tqdm_class() is plain.tqdm
    ds = bifurc.attractors("impact-oscillator", "Omega", [1.3], params=dict(F=0.3, e=-1.0, r=0.8), n_starts=2,
                           seed=1, progress=True, link=False)
    assert ds.sizes["start"] == 2
