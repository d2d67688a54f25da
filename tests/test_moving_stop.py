"""A moving stop: the bouncing ball on a sinusoidally vibrating table, against closed forms.

The table moves as s(t) = A sin(w t) (unaffected by the ball), gravity g, restitution e.  The
ball is declared twice:

- relative to the table: z = x - s(t), z'' = -g + A w^2 sin(w t); the stop z = 0 is fixed and
  the reset z' -> -e z' reads no time (only the vector field does);
- in absolute coordinates: x'' = -g; the guard x - s(t) = 0 moves (time-dependent guard) and
  the reset v+ = (1 + e) s'(t) - e v- reads the time of the impact (time-dependent reset), as
  heyoka expressions and as a Python ``reset(y, params, t)``.

Closed form of the period-1 orbit (one impact per table period T = 2 pi / w), derived here.
Between impacts the ball flies freely: after an impact at t_n with absolute take-off speed u_n,
x(t) = s(t_n) + u_n (t - t_n) - g (t - t_n)^2 / 2.  The next impact after a flight tau solves

    F(t_n, u_n, tau) = s(t_n) + u_n tau - g tau^2 / 2 - s(t_n + tau) = 0,

and the new take-off speed is u_{n+1} = (1 + e) s'(t_n + tau) - e (u_n - g tau).  Period 1:
tau = T and s(t_n + T) = s(t_n), so u T = g T^2 / 2, u = g T / 2, the speed before the impact
is u - g T = -g T / 2, and u = (1 + e) s'(t_i) + e g T / 2 gives the table's speed at impact

    s'(t_i) = A w cos(w t_i) = g T (1 - e) / (2 (1 + e))    (exists iff A w >= that),

the relative approach speed D = g T / 2 + s'(t_i) = g T / (1 + e).  Linearising the impact map
(t_n, u_n) -> (t_{n+1}, u_{n+1}) by implicit differentiation of F: F_t = s'(t_n) - s'(t_n + T) = 0,
F_u = T, F_tau = u - g T - s'(t_i) = -D, so d tau = (T / D) du and

    M = [[1, T / D], [(1 + e) s''_i, (1 + e) s''_i T / D - e + e g T / D]],

det M = e (g T / D - 1) = e^2 and trace M = 1 + e^2 + (1 + e)^2 s''_i / g, s''_i = -A w^2
sin(w t_i).  The stroboscopic map (sampled at t = k T) is conjugate to the impact map near the
orbit, so its multipliers are M's eigenvalues.  The stable orbit is the one with sin(w t_i) > 0
(trace < 1 + det); it period-doubles when trace = -(1 + det).

Lift-off: a ball resting on the table moves with it until the table's acceleration reaches -g
(-A w^2 sin(w t) = -g), the first time at arcsin(g / (A w^2)) / w after t = 0.
"""
import math

import heyoka as hy
import numpy as np
import pytest

import maps
from bifurc.orbits.periodic import find_periodic_orbit
from maps import Guard, HybridSystem, Parameter, State
from maps.impacts import impact_table

G, E, W = 9.81, 0.5, 2 * math.pi * 10.0
T = 2 * math.pi / W
A = 3.2e-3           # threshold 2.60 mm, period doubling 3.79 mm (closed form below)
P = dict(g=G, e=E, A=A, w=W)

PARAMETERS = [Parameter("g", "m s-2", "gravity", 0, math.inf),
              Parameter("e", "1", "coefficient of restitution", 0, 1),
              Parameter("A", "m", "table amplitude", 0, math.inf),
              Parameter("w", "rad s-1", "table angular frequency", 0, math.inf, low_open=True)]


def closed_form(g=G, e=E, A=A, w=W):
    """(impact time in [0, T), relative impact speed D > 0, absolute state (x, v) at t = 0 mod T,
    multipliers, threshold amplitude, period-doubling amplitude) of the stable period-1 orbit."""
    T = 2 * math.pi / w
    sd = g * T * (1 - e) / (2 * (1 + e))                    # table speed at impact
    threshold = sd / w
    assert A * w > sd
    ti = math.acos(sd / (A * w)) / w                        # sin(w ti) > 0: the stable one
    D = g * T / (1 + e)
    sdd = -A * w * w * math.sin(w * ti)
    M = np.array([[1.0, T / D], [(1 + e) * sdd, (1 + e) * sdd * T / D - e + e * g * T / D]])
    assert math.isclose(np.linalg.det(M), e * e, rel_tol=1e-12)
    assert math.isclose(np.trace(M), 1 + e * e + (1 + e) ** 2 * sdd / g, rel_tol=1e-12)
    mult = np.linalg.eigvals(M)
    # period doubling: trace = -(1 + e^2), i.e. A w^2 sin = 2 g (1 + e^2) / (1 + e)^2
    pd = math.hypot(sd, 2 * g * (1 + e * e) / (1 + e) ** 2 / w) / w
    u, fl = g * T / 2, T - ti                               # take-off speed, flight time to t = T
    x0 = A * math.sin(w * ti) + u * fl - g * fl * fl / 2
    v0 = u - g * fl
    return ti, D, np.array([x0, v0]), mult, threshold, pd


def relative_ball():
    def rhs(s):
        return [s.zd, -s.g + s.A * s.w ** 2 * hy.sin(s.w * s.t)]

    def guards(s):
        return [Guard("contact", s.z, -1, reset=[s.z, -s.e * s.zd], role="impact")]
    return HybridSystem("ball-relative", [State("z", "m", "height above the table"),
                                          State("zd", "m s-1", "velocity relative to the table")],
                        PARAMETERS, rhs, guards=guards)


def _cos(t):
    return hy.cos(t) if isinstance(t, hy.expression) else math.cos(t)


def absolute_ball(python_reset=False):
    def reset(y, p, t):                 # the table's speed at the impact instant
        y = y.copy()
        y[1] = (1 + p["e"]) * p["A"] * p["w"] * _cos(p["w"] * t) - p["e"] * y[1]
        return y

    def guards(s):
        table = s.A * hy.sin(s.w * s.t)
        r = reset if python_reset else [s.x, (1 + s.e) * s.A * s.w * hy.cos(s.w * s.t) - s.e * s.v]
        return [Guard("contact", s.x - table, -1, reset=r, role="impact")]
    return HybridSystem("ball-absolute" + ("-py" if python_reset else ""),
                        [State("x", "m", "height"), State("v", "m s-1", "velocity")], PARAMETERS,
                        lambda s: [s.v, -s.g], guards=guards)


def _to_relative(y, t):
    return np.array([y[0] - A * math.sin(W * t), y[1] - A * W * math.cos(W * t)])


CASES = {"relative": (relative_ball, lambda y: _to_relative(y, 0.0)),
         "absolute": (absolute_ball, lambda y: y),
         "absolute-python-reset": (lambda: absolute_ball(True), lambda y: y)}


def test_closed_form_parameters_are_in_the_stable_window():
    ti, D, y0, mult, threshold, pd = closed_form()
    assert threshold < A < pd and 0 < W * ti < math.pi / 2
    assert np.max(np.abs(mult)) < 1 and math.isclose(abs(mult[0]), E, rel_tol=1e-12)  # complex pair, |.| = e


@pytest.mark.parametrize("case", list(CASES))
def test_period_1_orbit_on_a_vibrating_table(case):
    make, coords = CASES[case]
    ti, D, y0_abs, mult, _, _ = closed_form()
    smap = maps.StroboscopicMap(make(), P, period=T, tol=1e-15)
    y0 = coords(y0_abs)
    orbit = find_periodic_orbit(smap, y0 * (1 + 1e-3), 1, tol=1e-13)
    node = orbit.nodes[0].y
    print(f"{case}: node error {np.max(np.abs(node - y0)):.2e}")
    assert np.max(np.abs(node - y0)) < 1e-9
    # the impact log: phase and the relative approach speed at the impact instant
    o = smap.orbit(orbit.nodes[0], 1)
    assert o.impacts_per_step.tolist() == [1]
    phase_err = abs(o.impact_time[0] - ti)
    speed_err = abs(o.impact_velocity[0] + D)
    print(f"{case}: impact time error {phase_err:.2e} s, relative impact speed error {speed_err:.2e} m/s")
    assert phase_err < 1e-9 and abs(o.impact_phase[0] - ti / T) < 1e-9
    assert speed_err < 1e-9
    run = maps.HybridRun(smap.system, P, node, tol=1e-15)
    run.advance(T)
    table = impact_table(run)
    assert abs(table["t"][0] - ti) < 1e-9 and abs(table["velocity"][0] + D) < 1e-9
    assert table["penetration"][0] < 1e-9
    # multipliers: exact Jacobian (saltation with the guard's and reset's time derivatives)
    J = smap.linearize(orbit.nodes[0]).J
    got = np.sort_complex(np.linalg.eigvals(J))
    want = np.sort_complex(mult)
    mult_err = np.max(np.abs(got - want))
    print(f"{case}: multipliers {got}, closed form {want}, error {mult_err:.2e}")
    assert mult_err < 1e-6
    assert np.max(np.abs(np.sort_complex(orbit.multipliers) - want)) < 1e-6
    # and against finite differences of the map
    J_fd = smap.jacobian(orbit.nodes[0].y, method="fd", eps=1e-7)
    fd_err = np.max(np.abs(J - J_fd)) / np.max(np.abs(J))
    print(f"{case}: |J - J_fd| / |J| = {fd_err:.2e}")
    assert fd_err < 1e-5


def test_the_two_declarations_agree():
    ti, D, y0_abs, _, _, _ = closed_form()
    rel = maps.StroboscopicMap(relative_ball(), P, period=T, tol=1e-15)
    ab = maps.StroboscopicMap(absolute_ball(), P, period=T, tol=1e-15)
    y = y0_abs + np.array([2e-4, -3e-2])          # off the orbit: a transient of several impacts
    o_abs = ab.orbit(y, 6)
    o_rel = rel.orbit(_to_relative(y, 0.0), 6)
    assert o_abs.impact_time.size == o_rel.impact_time.size >= 5
    assert np.max(np.abs(o_abs.impact_time - o_rel.impact_time)) < 1e-9
    assert np.max(np.abs(o_abs.impact_velocity - o_rel.impact_velocity)) < 1e-9
    for k in range(7):
        assert np.max(np.abs(_to_relative(o_abs.points[k], k * T) - o_rel.points[k])) < 1e-9
    J_abs, J_rel = ab.jacobian(y), rel.jacobian(_to_relative(y, 0.0))
    # z = x - s(t), z' = v - s'(t): at the sample times a translation, so J is the same matrix
    assert np.max(np.abs(J_abs - J_rel)) < 1e-7 * np.max(np.abs(J_abs))


def test_a_reset_without_time_is_still_called_with_two_arguments():
    calls = []

    def restitute(y, p):
        calls.append(1)
        y = y.copy()
        y[1] = -p["e"] * y[1]
        return y

    def guards(s):
        return [Guard("contact", s.z, -1, reset=restitute, role="impact")]
    sys2 = HybridSystem("ball-relative-py2", [State("z", "m", "h"), State("zd", "m s-1", "v")], PARAMETERS,
                        lambda s: [s.zd, -s.g + s.A * s.w ** 2 * hy.sin(s.w * s.t)], guards=guards,
                        gap=lambda y, p: (y[0], y[1]))
    ti, D, y0_abs, mult, _, _ = closed_form()
    smap = maps.StroboscopicMap(sys2, P, period=T, tol=1e-15)
    o = smap.orbit(_to_relative(y0_abs, 0.0), 1)
    assert calls and abs(o.impact_time[0] - ti) < 1e-9 and abs(o.impact_velocity[0] + D) < 1e-9
    assert sys2.gap([0.1, 0.2], P) == (0.1, 0.2) == sys2.gap([0.1, 0.2], P, 1.0)


def test_a_gap_given_with_time():
    def gap(y, p, t):          # absolute coordinates: the clearance above the moving table
        return y[0] - p["A"] * math.sin(p["w"] * t), y[1] - p["A"] * p["w"] * math.cos(p["w"] * t)
    base = absolute_ball()
    sys3 = HybridSystem("ball-absolute-gap", base.states, PARAMETERS, lambda s: [s.v, -s.g],
                        guards=base.guards, gap=gap)
    ti, D, y0_abs, _, _, _ = closed_form()
    o = maps.StroboscopicMap(sys3, P, period=T, tol=1e-15).orbit(y0_abs, 1)
    assert abs(o.impact_time[0] - ti) < 1e-9 and abs(o.impact_velocity[0] + D) < 1e-9
    assert sys3.gap([0.1, 0.2], P) == (0.1, 0.2 - A * W)          # t defaults to 0


def test_lift_off_from_rest_on_the_table():
    """A ball at rest on the table (mode ``stuck``: it moves with the table) lifts off when the
    table's acceleration -A w^2 sin(w t) reaches -g, at arcsin(g / (A w^2)) / w."""
    def rhs(s):
        free = 1 - s.stuck
        a_table = -s.A * s.w ** 2 * hy.sin(s.w * s.t)
        return [s.v, free * (-s.g) + s.stuck * a_table]

    def guards(s):
        table = s.A * hy.sin(s.w * s.t)
        return [Guard("contact", s.x - table, -1, when={"stuck": 0},
                      reset=[s.x, (1 + s.e) * s.A * s.w * hy.cos(s.w * s.t) - s.e * s.v], role="impact"),
                Guard("unstick", s.g - s.A * s.w ** 2 * hy.sin(s.w * s.t), -1, when={"stuck": 1},
                      then={"stuck": 0}, role="unstick")]
    system = HybridSystem("ball-absolute-stuck", [State("x", "m", "height"), State("v", "m s-1", "velocity")],
                          PARAMETERS, rhs, flags={"stuck": 0.0}, guards=guards)
    run = maps.HybridRun(system, P, [0.0, A * W], flags={"stuck": 1.0}, tol=1e-15)
    run.advance(0.5 * T, stop_roles=("unstick",))
    want = math.asin(G / (A * W * W)) / W
    (ev,) = [ev for ev in run.events if ev.name == "unstick"]
    err = abs(ev.t - want)
    print(f"lift-off at {ev.t:.15f} s, closed form {want:.15f} s, error {err:.2e} s")
    assert err < 1e-9
    # it lifted off on the table, moving with it
    assert abs(ev.y_minus[0] - A * math.sin(W * want)) < 1e-9 and abs(ev.y_minus[1] - A * W * math.cos(W * want)) < 1e-9


@pytest.mark.parametrize("python_reset", [False, True])
def test_impact_map_jacobian_through_a_moving_stop(python_reset):
    """ImpactMap.linearize (the flow projected on the moving section, then the time-dependent
    reset) against central differences of ImpactMap.step, from the period-1 orbit's sample."""
    _, _, y0, _, _, _ = closed_form()
    imap = maps.ImpactMap(absolute_ball(python_reset), P, period=T, tol=1e-15)
    J = imap.jacobian(y0)
    J_fd = imap.jacobian(y0, method="fd", eps=1e-7)
    err = np.max(np.abs(J - J_fd)) / np.max(np.abs(J))
    print(f"impact map: |J - J_fd| / |J| = {err:.2e}")
    assert err < 1e-6
