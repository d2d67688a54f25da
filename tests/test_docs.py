"""The code in docs/hybrid-systems.md runs as printed and prints what the text says."""
import contextlib
import io
import math
import re
from pathlib import Path

import pytest

DOC = Path(__file__).resolve().parents[1] / "docs" / "hybrid-systems.md"


@pytest.fixture(scope="module")
def executed():
    blocks = re.findall(r"```python\n(.*?)```", DOC.read_text(), flags=re.S)
    ns, out = {}, io.StringIO()
    with contextlib.redirect_stdout(out):
        for code in blocks[:3]:          # the system, the stop above it, sticking (sweeps: test_sweep)
            exec(compile(code, str(DOC), "exec"), ns)
    return ns, out.getvalue()


def test_the_oscillator_snippet_prints_its_impacts(executed):
    ns, text = executed
    assert "6 impacts; first at t = 4.185486" in text


def test_the_stop_above_mirrors_the_stop_below(executed):
    """x -> -x, e -> -e, half a forcing period later: the same impact instants, the mirrored
    velocities, and the declared gap (e - x) is 0 at every impact and equals the first system's."""
    ns, text = executed
    system, above, params = ns["system"], ns["above"], ns["params"]
    run = __import__("maps").HybridRun(system, params, {"x": 0.0, "v": 0.0}, tol=1e-14)
    run.advance(50.0)
    below = [(ev.t, ev.y_minus[1]) for ev in run.events if ev.name == "contact"]
    hits = ns["hits"]
    assert len(hits) == len(below) == 6
    for (ta, va), (tb, vb) in zip(hits, below):
        assert abs(ta - tb) < 1e-9 and abs(va + vb) < 1e-9
    pa = dict(params, e=0.6)
    for ev in ns["run_above"].events:
        if ev.name == "hit":
            assert abs(above.gap(ev.y_minus, pa)[0]) < 1e-12
            assert above.gap(ev.y_minus, pa)[1] < 0          # approaching the stop
    assert above.gap([0.1, 0.0], pa)[0] == pytest.approx(0.5) and system.gap([0.1, 0.0], params)[0] == pytest.approx(0.7)


def test_the_sticky_snippet_leaves_at_the_closed_form_instants(executed):
    ns, text = executed
    got = [ev.t for ev in ns["run"].events if ev.name == "unstick"]
    want = [(2 * math.pi * k - math.acos(0.6)) / 0.8 for k in range(1, 6)]
    assert len(got) >= 3
    for t in got:
        assert min(abs(t - w) for w in want) < 1e-9


def test_the_doc_prints_what_it_says(executed):
    ns, text = executed
    assert "6 impacts; first at t = 4.185486 ; |gap| there < 1e-12: True" in text


def test_the_moving_stop_snippet_settles_on_the_period_1_orbit():
    """The vibrating-table example (a time-dependent guard and reset) prints the closed-form
    impact phase and relative speed of tests/test_moving_stop.py."""
    blocks = re.findall(r"```python\n(.*?)```", DOC.read_text(), flags=re.S)
    code = next(b for b in blocks if "ball-on-a-vibrating-table" in b)
    ns, out = {}, io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(compile(blocks[0], str(DOC), "exec"), ns)
        out.seek(0)
        out.truncate()
        exec(compile(code, str(DOC), "exec"), ns)
    assert "impact phase 0.098867 relative speed -0.654" in out.getvalue()
    T, p = ns["T"], ns["p"]
    ti = math.acos(p["g"] * T * (1 - p["e"]) / (2 * (1 + p["e"])) / (p["A"] * p["w"])) / p["w"]
    assert abs(ns["orbit"].impact_phase[-1] - ti / T) < 1e-8


def test_every_block_runs_in_order_and_the_problem_block_says_what_it_shows():
    """Every python block of the guide, in one namespace as a reader would paste them (the sweeps
    run quickly: 17 and 3 values)."""
    blocks = re.findall(r"```python\n(.*?)```", DOC.read_text(), flags=re.S)
    ns = {}
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
        for code in blocks:
            exec(compile(code, str(DOC), "exec"), ns)
    p = ns["p"]
    assert p.strobe_period() == pytest.approx(2 * math.pi / 0.8, rel=1e-15) and p.forcing_q() == 1
    assert ns["thesis"].options.dc_law == "listing" and ns["p2"].values["Omega"] == 0.85
    assert list(ns["d"].Omega.values) == pytest.approx([0.7, 0.8, 0.9])
