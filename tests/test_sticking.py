"""Sticking on the stop: chattering ends in the stuck mode at the instants independent
calculations give, stick/unstick are logged events, and a runaway hits the event cap."""
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from maps.hybrid import EventCap
from maps.engines.scalar import HybridRun
from bifurc.verification.suite import CASES, case_scene, run_case


def _case(name):
    return next(c for c in CASES if c.name == name)


def _run(name, t_end=None, **kw):
    case = _case(name)
    sc, p = case_scene(case)
    run = HybridRun(sc.system, p, sc.initial_state(**case.x0), flags=case.flags or None, **kw)
    run.advance(t_end or case.t_end)
    return run, sc, p


def bouncing_ball(m, g, k, c, e, h, v_stick, t_end):
    """Closed-form Kelvin-Voigt bouncing ball: free flight is a parabola, contact a damped
    oscillation about x_s = e - m g / k.  Applies the model's stick rule: a contact beginning
    slower than ``v_stick``, or, in contact, the first instant the oscillation's speed amplitude
    sqrt(x'^2 + k/m (x - x_s)^2) falls to ``v_stick``.  Returns (contact onsets, stick time)."""
    w = math.sqrt(k / m)
    sig = c / (2 * m)
    wd = math.sqrt(w * w - sig * sig)
    s = m * g / k  # height of the stop above the static point
    t, v = math.sqrt(2 * (h - e) / g), -math.sqrt(2 * g * (h - e))
    onsets = []
    while t < t_end:
        onsets.append(t)
        if abs(v) < v_stick:
            return onsets, t
        A, B = s, (v + sig * s) / wd  # y = x - x_s = exp(-sig t) (A cos wd t + B sin wd t)
        y = lambda tau: math.exp(-sig * tau) * (A * math.cos(wd * tau) + B * math.sin(wd * tau))  # noqa: E731
        dy = lambda tau: math.exp(-sig * tau) * ((B * wd - sig * A) * math.cos(wd * tau)  # noqa: E731
                                                 - (A * wd + sig * B) * math.sin(wd * tau))
        rest = lambda tau: dy(tau) ** 2 + w * w * y(tau) ** 2 - v_stick ** 2  # noqa: E731
        phase = math.atan2(B * wd - sig * A, A * wd + sig * B) % math.pi
        ext = [(phase + n * math.pi) / wd for n in range(10_000)]  # y' = 0: minima (even n), maxima (odd n)
        released = None
        for n in range(0, len(ext), 2):
            if y(ext[n + 1]) > s:  # rises back above the stop: released
                released = brentq(lambda tau: y(tau) - s, ext[n], ext[n + 1], xtol=1e-16, rtol=1e-15)
                break
        end = released if released is not None else ext[-1]
        grid = np.linspace(0.0, end, int(end * wd / math.pi * 50) + 2)
        below = [i for i in range(1, grid.size) if rest(grid[i]) < 0]
        if below:  # the amplitude falls to v_stick inside this contact
            i = below[0]
            return onsets, t + brentq(rest, grid[i - 1], grid[i], xtol=1e-16, rtol=1e-15)
        if released is None:
            raise AssertionError("no release and no stick within 5000 oscillations")
        v_up = dy(released)
        t += released + 2 * v_up / g  # free flight back to the stop
        v = -v_up
    return onsets, math.nan


def test_zeno_cascade_sticks_when_the_closed_form_bouncing_ball_does():
    """ac-stop without current is a bouncing ball on a Kelvin-Voigt stop; the bounce sequence
    and the stick instant are known in closed form."""
    run, sc, p = _run("chatter-stick")
    onsets, t_stick = bouncing_ball(p["m"], p["g"], p["k"], p["c"], p["e"], 1e-3,
                                    sc.options.stick_speed, 1.0)
    got = [ev.t for ev in run.events if ev.name == "contact"]
    assert len(got) == len(onsets) == 36
    assert np.max(np.abs(np.array(got) - onsets)) < 1e-11  # measured 3.5e-13
    sticks = [ev for ev in run.events if ev.name == "stick"]
    assert len(sticks) == 1 and sticks[0].t == pytest.approx(t_stick, abs=1e-11)  # measured 8e-13
    # afterwards the bar rides the stop: x = e, v = 0 exactly, no further event or burnt step
    assert run.events[-1].name == "stick" and run.y[0] == p["e"] and run.y[1] == 0.0
    assert run.flags["stuck_bar"] == 1 and run.n_steps < 400


def test_without_the_stick_mode_the_cascade_is_an_event_cap_not_a_hang():
    case = _case("chatter-no-stick")
    res = run_case(case)
    assert res["verdict"] == "event-cap" and res["max_period_events"] == case.max_events_per_period + 1
    assert 0 < res["failure_time"] < 0.2  # within the first relay period (5 Hz)
    sc, p = case_scene(case)
    run = HybridRun(sc.system, p, sc.initial_state(**case.x0), max_events_per_period=30)
    with pytest.raises(EventCap, match="in one relay period"):
        run.advance(1.0)


def _circuit_alone(p, t0, y0, t_end, on):
    """Eq 4.16 with the bar held at x = e (v = dv/dt = 0): a linear ODE in (i, z) with the
    relay as ``on(t)``; the bar leaves when the (listing-sign) AC push 0.5 |L'| i^2 exceeds m g.
    Returns the first such instant."""
    xb = p["e"] + p["d_ac"]
    norm = p["A"] / (p["B"] * math.sqrt(math.pi / 2))
    gauss = math.exp(-2 * (xb / p["B"]) ** 2)
    L, dL = p["L0"] + norm * gauss, -4 * norm * xb / p["B"] ** 2 * gauss
    w = 2 * math.pi * p["f_mains"]

    def push(t, y):
        return 0.5 * abs(dL) * y[0] ** 2 - p["m"] * p["g"]
    push.terminal, push.direction = True, 1
    y = list(y0)
    for t_a, t_b, P in on(t0, t_end):
        rhs = lambda t, y, P=P: [y[1], (P * w * p["V"] * math.cos(w * t) - p["R"] * y[1] - y[0] / p["C"]) / L]  # noqa: E731
        sol = solve_ivp(rhs, (t_a, t_b), y, method="DOP853", rtol=1e-13, atol=1e-15, events=push)
        if sol.t_events[0].size:
            return sol.t_events[0][0]
        y = sol.y[:, -1]
    return math.nan


def test_time_on_the_stop_matches_the_circuit_alone():
    """Held on the stop from t = 0 with the AC always on, the bar leaves at the first root of
    the net force along the stuck trajectory."""
    case = _case("stuck-unstick")
    res = run_case(case)
    sc, p = case_scene(case)
    t_out = _circuit_alone(p, 0.0, [0.0, 0.0], 0.05, lambda a, b: [(a, b, 1.0)])
    assert res["unstick_time"] == pytest.approx(t_out, abs=1e-10)
    assert res["time_on_stop"] == pytest.approx(t_out, abs=1e-10)
    assert res["verdict"] == "ok"


def test_relay_chattering_sticks_and_leaves_when_the_circuit_alone_says():
    """thesis-1dof without DC, listing-sign AC, stiff stop: each relay ON half lifts the bar,
    each OFF half it chatters down and sticks.  From every stick instant, the circuit alone
    (held bar, relay switching at n/(2 W)) gives the next unstick instant."""
    run, sc, p = _run("chatter-relay")
    W = p["relay_hz"]
    names = [ev.name for ev in run.events if ev.name in ("stick", "unstick")]
    assert names[:2] == ["stick", "unstick"] and len(names) >= 8
    i_idx = sc.system.state_names.index("i")

    def relay(a, b):  # (start, stop, P) pieces between relay switches n / (2 W)
        edges = [a] + [n / (2 * W) for n in range(math.floor(2 * W * a) + 1, math.ceil(2 * W * b))] + [b]
        return [(s, e, 1.0 if ((s + e) / 2 * W) % 1.0 < 0.5 else 0.0) for s, e in zip(edges[:-1], edges[1:])]

    checked = 0
    for k, ev in enumerate(run.events):
        if ev.name != "stick":
            continue
        nxt = next((e for e in run.events[k + 1:] if e.name == "unstick"), None)
        if nxt is None:
            continue
        t_out = _circuit_alone(p, ev.t, ev.y_plus[i_idx:i_idx + 2], nxt.t + 0.01, relay)
        assert nxt.t == pytest.approx(t_out, abs=1e-11), (ev.t, nxt.t, t_out)  # measured 3e-16
        checked += 1
    assert checked >= 4
    # the bar never leaves during an OFF half: only the AC pushes it up
    for ev in run.events:
        if ev.name == "unstick":
            assert (ev.t * W) % 1.0 < 0.5


def test_stick_and_unstick_are_logged_events_between_the_guard_records():
    run, sc, p = _run("chatter-relay", t_end=0.3)
    ev = run.events
    n_stick = 0
    for k, e in enumerate(ev):
        if e.name == "stick":
            n_stick += 1
            assert e.flags["stuck_bar"] == 1 and e.y_plus[0] == p["e"] and e.y_plus[1] == 0.0
            if ev[k - 1].t == e.t:      # a settle after a contact or switch: the transition that caused it
                assert ev[k - 1].flags["stuck_bar"] == 0 and ev[k - 1].name in ("contact", "P")
            else:                       # the stick guard: the contact oscillation died out, its speed
                # amplitude about the static point e + N/k fell to stick_speed (N: the net force, pressing)
                before = ev[k - 1].flags
                assert before["contact"] == 1 and before["stuck_bar"] == 0
                N = float(sc.system.evaluate(["N_bar"], e.y_minus, p, before, e.t)[0])
                amp = math.hypot(e.y_minus[1], math.sqrt(p["k"] / p["m"]) * (e.y_minus[0] - p["e"] - N / p["k"]))
                assert N < 0 and amp == pytest.approx(sc.options.stick_speed, rel=1e-6)  # measured 4e-9
        if e.name == "unstick":
            assert e.flags["stuck_bar"] == 0
    assert n_stick >= 2
    assert run.n_events == len(ev)


def test_pure_free_fall_escape_time():
    res = run_case(_case("free-fall-out"))
    sc, p = case_scene(_case("free-fall-out"))
    h = p["d_ac"] + 0.2  # escape 0.2 m beyond the AC centre, 0.0455 m below the start
    assert res["verdict"] == "escaped"
    assert res["failure_time"] == pytest.approx(math.sqrt(2 * h / p["g"]), abs=1e-12)


def test_two_dof_bar_rides_the_rig_and_leaves_at_the_analytic_instant():
    """thesis-2dof, no AC, weak DC, the static force reversed (pulling the rig onto the bar):
    held on the stop, bar and rig accelerate as one body, a(t) = (-F_static/M) exp(-soil_c t / M),
    and the bar leaves when the DC pull F_dc(e) exceeds m1 a(t) by the model's unstick_force."""
    case = _case("stuck-2dof")
    run, sc, p = _run("stuck-2dof")
    M = p["m1"] + p["m2"]
    xa = p["e"] - p["d_dc"]
    F_dc = p["dc_scale"] * (-p["a3"] * xa**3 + p["a2"] * xa**2 - p["a1"] * xa)
    eps = sc.options.unstick_force
    t_phys = M / p["soil_c"] * math.log(p["m1"] * -p["F_static"] / (M * F_dc))
    t_model = M / p["soil_c"] * math.log(p["m1"] * -p["F_static"] / (M * (F_dc - eps)))
    (ev,) = [e for e in run.events if e.name == "unstick"]
    assert ev.t == pytest.approx(t_model, abs=1e-15)  # measured 3.9e-18
    assert abs(t_phys - t_model) < 1e-10  # the regularisation's lag: eps / (dN/dt) = 1.4e-11 s
    x1, v1, x2, v2 = ev.y_minus[:4]
    assert x1 - x2 == p["e"] and v1 == v2  # rode the stop exactly
    assert v2 == pytest.approx(-p["F_static"] / p["soil_c"] * (1 - math.exp(-p["soil_c"] * ev.t / M)), rel=1e-12)
    assert case.flags == {"stuck_bar": 1.0}


def test_prototype_stick_conserves_momentum_or_holds_the_rig():
    """In the prototype (dry-friction soil) the bar settles on the stop during an AC half and
    leaves when the antiphase DC comes on at the relay switch: at the stick the bar is put on the
    stop with the rig's velocity (rig held by friction) or the common momentum velocity."""
    run, sc, p = _run("prototype-stick")
    sticks = [k for k, e in enumerate(run.events) if e.name == "stick"]
    assert sticks
    for k in sticks:
        e = run.events[k]
        x1, v1, x2, v2 = e.y_plus[:4]
        assert x1 - x2 == p["e"] and v1 == v2
        if e.flags["stuck"] == 0:
            m1, m2 = p["m1"], p["m2"]
            assert m1 * v1 + m2 * v2 == pytest.approx(m1 * e.y_minus[1] + m2 * e.y_minus[3], abs=1e-15)
        nxt = next(u for u in run.events[k + 1:] if u.name == "unstick")
        assert nxt.t * p["relay_hz"] % 0.5 == pytest.approx(0.0, abs=1e-12)  # at a relay switch


def test_the_stick_guard_sticks_a_pressed_bar_and_declines_a_pulled_one():
    """The "stick" guard's transition at a state on its surface: pressed on the stop (N < 0,
    chatter-relay) the bar is put on it at rest, stuck, the projection named by the guard; pulled
    off it (N > 0: thesis-1dof's listing DC cubic, ~35 N at the stop) nothing happens and no event
    is logged."""
    from maps import transitions as tr
    for name, pressed in (("chatter-relay", True), (None, False)):
        if name:
            sc, p = case_scene(_case(name))
        else:
            import maps
            sc = maps.get_scene("thesis-1dof")
            p = sc.parameters(preset="matlab-listing", V=90.0)
        system = sc.system
        guard = next(g for g in system.guards if g.name == "stick")
        y = system.state_vector(sc.initial_state(x=p["e"] - 1e-9, v=-2e-5))
        flags = dict(tr.start_flags(system, 0.0, y, p, None), contact=1.0, stuck_bar=0.0)
        N = float(system.evaluate(["N_bar"], y, p, flags, 0.0)[0])
        out = tr.fire(system, guard, 0.0, y, flags, p)
        if pressed:
            assert N < 0 and out.changes == {"contact": 0.0, "stuck_bar": 1.0} and out.projection == "stick"
            assert out.y[0] == p["e"] and out.y[1] == 0.0 and np.array_equal(out.y[2:], y[2:])
            assert [r[0] for r in out.records] == ["stick"]
        else:
            assert N > 30 and out is tr.NOTHING


@pytest.mark.parametrize("scene", ["thesis-1dof", "thesis-2dof"])
def test_the_settle_gate_never_skips_a_settle_that_acts(scene):
    """The model's ``settle_if`` (stuck, or in contact below stick_speed) lets the engines skip the
    settle rule after a fast contact.  It must never be False where the rule itself acts: the rule,
    called on states around every threshold (gap rates across stick_speed, pressed and pulled bars,
    each mode), is the independent truth."""
    import maps
    from maps.hybrid import settle_may_act
    sc = maps.get_scene(scene)
    system = sc.system
    assert callable(system.settle_if)
    p = sc.parameters(preset="matlab-listing") if scene == "thesis-1dof" else sc.parameters()
    speed = system.options.stick_speed
    rng = np.random.default_rng(3)
    acted = skipped = stuck_by_speed = 0
    y0 = system.state_vector(sc.initial_state())
    for _ in range(3000):
        flags = dict(system.initial_flags(0.0, p), contact=float(rng.integers(2)), stuck_bar=float(rng.integers(2)))
        y = y0.copy()
        y[0] = p["e"] + (y[2] if system.options.dof == 2 else 0.0) + rng.choice([0.0, rng.normal(0, 2e-6)])
        rate = rng.choice([-1, 1]) * speed * rng.choice([0.0, 0.6, 0.9, 0.999, 1.001, 2.0, 1e3])
        y[1] = rate + (y[3] if system.options.dof == 2 else 0.0)
        y[len(y0) // 2 if system.options.dof == 1 else 4] = rng.normal(0, 2.0)      # a current: the DC/AC force
        acts = bool(system.settle(0.0, y.copy(), dict(flags), p))
        gate = settle_may_act(system, flags, y, p)
        assert gate or not acts, (flags, y)
        acted += acts
        skipped += not gate
        stuck_by_speed += acts and flags["stuck_bar"] == 0 and abs(rate) > 0.5 * speed
    assert acted > 20 and skipped > 50        # both sides of the gate were exercised
    assert stuck_by_speed > 10                # sticks at gap rates within a factor 2 of stick_speed


def test_a_stuck_state_off_the_stop_starts_on_it_as_its_exact_jacobian_assumes():
    """thesis-1dof (`matlab-listing`, `measured`, 10 Hz) at 110.85 V: the bar at rest on the stop stays stuck
    through the relay period.  Started stuck 7 um inside the stop at 0.2 mm/s (a state no run reaches: sticking
    puts the bar at x = e, v = 0), a map step starts it at x = e, v = 0, so the step is the same as from the stop:
    its derivative by central differences in x and v is 0, as the exact Jacobian (perturbations projected onto the
    stuck set) says; the step from the off-stop state equals the step from the stop to round-off (on the scalar and
    the batch engine); and Newton from
    the off-stop guess converges to the state at rest on the stop, not to a stuck bar left where the guess put it
    (the stick-onset passage at 110.799 V had "converged" so: x = -7.09 um, v = 0.21 mm/s)."""
    import maps
    from maps.hybrid import HybridState
    from maps.poincare import StroboscopicMap
    from bifurc.orbits.periodic import find_periodic_orbit
    pb = maps.problem("thesis-1dof", preset="matlab-listing", params={"relay_hz": 10.0, "V": 110.85}, dc_law="measured")
    smap = StroboscopicMap(pb, tol=1e-12)
    e = smap.params["e"]
    rest = smap.step(HybridState(np.array([e, 0.0, -0.1133, 13.58]), None), 0)
    for _ in range(30):
        rest = smap.step(rest, 0)
    assert rest.flags["stuck_bar"] == 1.0 and rest.y[0] == e and rest.y[1] == 0.0
    off = HybridState(rest.y + np.array([-7.09e-6, 2.1e-4, 0.0, 0.0]), dict(rest.flags))
    assert np.allclose(smap.step(off, 0).y, smap.step(rest, 0).y, rtol=1e-12, atol=1e-15)
    batch = smap.orbits([{}], [off], 1, batch_size=4, events=False)[0].final      # the batch engine likewise
    assert np.allclose(batch.y, smap.step(rest, 0).y, rtol=1e-9, atol=1e-12)
    J = smap.linearize(rest, 0).J
    for j, h in ((0, 1e-7), (1, 1e-5)):
        plus = smap.step(HybridState(rest.y + h * np.eye(4)[j], dict(rest.flags)), 0).y
        minus = smap.step(HybridState(rest.y - h * np.eye(4)[j], dict(rest.flags)), 0).y
        assert np.allclose((plus - minus) / (2 * h), J[:, j], atol=1e-6), j
    po = find_periodic_orbit(smap, off, 1, k0=0, tol=1e-10)
    assert po.nodes[0].y[0] == e and po.nodes[0].y[1] == 0.0 and po.impacts_per_period == 0
