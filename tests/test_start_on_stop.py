"""Starting exactly on the stop must not loop (heyoka needs an explicit event cooldown)."""
import time

import numpy as np

import maps
from maps.hybrid import HybridRun


def test_dc_only_bar_starting_on_the_stop_runs_without_looping():
    """From rest on the stop the DC force (~37 N) throws the bar up; the cubic potential is
    symmetric, so it comes back to the stop at almost zero speed: a near-graze every cycle."""
    scene = maps.get_scene("dc-only")
    p = scene.parameters()
    run = HybridRun(scene.system, p, {"x": 0.0, "v": 0.0}, tol=1e-15, max_events=200)
    clock = time.perf_counter()
    run.advance(1.0)
    assert time.perf_counter() - clock < 5.0
    contacts = [ev for ev in run.events if ev.name == "contact"]
    turns = [ev for ev in run.events if ev.name == "lowest" and ev.t > 0]
    # a near-graze every oscillation (~0.12 s): a turning point within 1 nm of the stop, or a
    # contact slower than 1 mm/s (which one is decided by rounding at the exact graze)
    assert 5 <= len(contacts) + len(turns) <= 20
    assert all(abs(ev.y_minus[0]) < 1e-9 for ev in turns)
    assert all(abs(ev.y_minus[1]) < 1e-3 for ev in contacts)

    def energy(y):  # free flight: kinetic + cubic potential (the weight offset cancels m g)
        xa = y[0] - p["d_dc"]
        return 0.5 * p["m"] * y[1] ** 2 + p["a3"] * xa**4 / 4 - p["a2"] * xa**3 / 3 + p["a1"] * xa**2 / 2
    frees = [ev for ev in run.events if ev.name == "lowest"] + [ev for ev in contacts]
    E0 = energy(np.array([0.0, 0.0]))
    for ev in frees:
        assert abs(energy(ev.y_minus) - E0) / E0 < 1e-6  # the grazing contacts take almost nothing


def test_oscillator_starting_on_the_stop_moving_away_or_pressed_on():
    system = maps.forced_oscillator_with_stop()
    p = dict(w0=1.0, zeta=0.05, F=0.5, Omega=0.8, e=0.0, r=0.7)
    for v0 in (0.3, 0.0):
        run = HybridRun(system, p, {"x": 0.0, "v": v0}, tol=1e-14, max_events=500)
        clock = time.perf_counter()
        run.advance(30.0)
        assert time.perf_counter() - clock < 5.0
        assert run.y[0] >= -1e-12  # never below the rigid stop
        assert len(run.events) < 500
