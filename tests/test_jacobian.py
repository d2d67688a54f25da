"""Exact map Jacobians (variational equations with saltation) against independent truths:
the restitution oscillator's closed-form saltation and linear flow, and Richardson-extrapolated
central differences computed in long double at tol 1e-18 on thesis-1dof."""
import math

import numpy as np
import pytest
from scipy.linalg import expm

import maps
from bifurc.verification.suite import CASES, case_scene
from maps.engines.scalar import HybridRun

OSC = dict(w0=1.0, zeta=0.05, F=0.5, Omega=2.5, e=0.0, r=0.7)     # a stable 1:1 impacting orbit


@pytest.fixture(scope="module")
def osc_orbit():
    system = maps.forced_oscillator_with_stop()
    smap = maps.StroboscopicMap(system, OSC, tol=1e-14)
    o = smap.orbit({"x": 0.2, "v": 0.0}, 3, transient=200)
    return system, smap, o


def test_oscillator_det_is_restitution_squared_times_the_damping(osc_orbit):
    """Over one forcing period with m impacts: det J = r^(2m) exp(-2 zeta w0 T) (each impact's
    saltation has det r^2, the flow's Liouville factor is exp(trace A t))."""
    system, smap, o = osc_orbit
    T = 2 * math.pi / OSC["Omega"]
    for k in range(3):
        L = smap.linearize(o.state(k), 200 + k)
        m = L.signature.count("impact")
        assert m == 1 and L.rank == 2
        want = OSC["r"] ** (2 * m) * math.exp(-2 * OSC["zeta"] * OSC["w0"] * T)
        assert abs(np.linalg.det(L.J) / want - 1) < 1e-10       # measured 1e-15


def test_oscillator_jacobian_is_the_hand_composed_product(osc_orbit):
    """J = Phi(T - t_i) S Phi(t_i) with Phi the exact flow map of the linear part, expm(A t), and
    S = [[-r, 0], [(a+ + r a-)/v-, -r]] the saltation derived by hand (a: accelerations just
    before and after the impact, v-: the impact velocity)."""
    system, smap, o = osc_orbit
    w0, z, F, W, e, r = (OSC[k] for k in ("w0", "zeta", "F", "Omega", "e", "r"))
    A = np.array([[0.0, 1.0], [-w0 * w0, -2 * z * w0]])
    T = 2 * math.pi / W
    k = 201
    t0 = k * T
    run = HybridRun(system, OSC, o.points[1], t0=t0, tol=1e-14)
    run.advance(t0 + T)
    hits = [ev for ev in run.events if ev.name == "contact"]
    assert len(hits) == 1
    ti, vm = hits[0].t, hits[0].y_minus[1]
    force = F * math.cos(W * ti) - w0 * w0 * e
    a_minus = force - 2 * z * w0 * vm
    a_plus = force - 2 * z * w0 * (-r * vm)
    S = np.array([[-r, 0.0], [(a_plus + r * a_minus) / vm, -r]])
    want = expm(A * (t0 + T - ti)) @ S @ expm(A * (ti - t0))
    J = smap.linearize(o.state(1), k).J
    assert np.max(np.abs(J - want)) / np.max(np.abs(want)) < 1e-10     # measured 4e-15
    # the finite difference is only an oracle: it agrees to ~1e-8, and moves with its step
    fd = smap.jacobian(o.points[1], k, method="fd", eps=1e-6)
    assert np.max(np.abs(fd - want)) / np.max(np.abs(want)) < 1e-6


# ----- thesis-1dof, matlab-listing, 90 V, 9 Hz: a relay period with one contact at 0.6 m/s ----------
K = 8


@pytest.fixture(scope="module")
def thesis():
    sc = maps.get_scene("thesis-1dof").with_options(dc_law="listing")   # matlab-listing's law (C.9)
    p = sc.parameters(preset="matlab-listing", V=90.0, relay_hz=9.0)
    smap = maps.StroboscopicMap(sc, p, tol=1e-12)
    o = smap.orbit(sc.initial_state(), 12)
    assert o.impacts_per_step[K] == 1 and o.min_impact_speed_per_step[K] > 0.5   # not near grazing
    return sc, p, smap, o


def _ld_end(system, params, y, t0, t1):
    run = HybridRun(system, params, np.array(y, dtype=np.longdouble), t0=t0, tol=1e-18, fp_type=np.longdouble,
                    max_events=None)
    run.advance(t1)
    return np.array(run.ta.state, dtype=np.longdouble)


def _richardson(f, h):
    """Central differences at h and h/2, Richardson-extrapolated (error O(h^4))."""
    d1 = (f(h) - f(-h)) / (2 * h)
    d2 = (f(h / 2) - f(-h / 2)) / h
    return (4 * d2 - d1) / 3


def test_thesis_jacobian_against_long_double_differences(thesis):
    sc, p, smap, o = thesis
    y = o.points[K].astype(np.longdouble)
    t0, t1 = smap.sample_time(K), smap.sample_time(K + 1)
    cols = []
    for j in range(4):
        e = np.zeros(4, dtype=np.longdouble)
        e[j] = 1

        def f(h, e=e):
            return _ld_end(sc.system, p, y + h * e, t0, t1)
        cols.append(_richardson(f, np.longdouble(1e-5) * max(abs(y[j]), np.longdouble(1e-3))))
    oracle = np.array(cols, dtype=float).T
    L = smap.linearize(o.state(K), K)
    assert L.signature.count("impact") == 1 and L.rank == 4
    err = np.linalg.norm(L.J - oracle) / np.linalg.norm(oracle)
    assert err < 1e-8                                   # measured ~1e-10


def test_nine_periods_compose(thesis):
    sc, p, smap, o = thesis
    Js, state = [], o.state(K)
    for j in range(9):
        L = smap.linearize(state, K + j)
        Js.append(L.J)
        state = L.state
    prod = np.linalg.multi_dot(Js[::-1])
    J9 = smap.linearize(o.state(K), K, n=9).J
    assert np.linalg.norm(prod - J9) / np.linalg.norm(J9) < 1e-9


def test_parameter_derivative_against_long_double_differences(thesis):
    sc, p, smap, o = thesis
    y = o.points[K].astype(np.longdouble)
    t0, t1 = smap.sample_time(K), smap.sample_time(K + 1)
    oracle = {}
    for name, h in (("V", 1e-4), ("k", 1e-1)):
        def f(dh, name=name):
            return _ld_end(sc.system, dict(p, **{name: p[name] + float(dh)}), y, t0, t1)
        oracle[name] = np.array(_richardson(f, np.longdouble(h)), dtype=float)
    L = smap.linearize(o.state(K), K, params=("V", "k"))
    for j, name in enumerate(("V", "k")):
        err = np.linalg.norm(L.J_p[:, j] - oracle[name]) / np.linalg.norm(oracle[name])
        assert err < 1e-7, (name, err)


def test_relay_frequency_derivative_at_a_fixed_sample_index(thesis):
    """d P_k / dW at fixed k: the start k/W, the end (k+1)/W, both relay switches n/(2W) and the
    mains phase all move.  Oracle: the same map recomputed at W +- h in long double."""
    sc, p, smap, o = thesis
    y = o.points[K].astype(np.longdouble)

    def f(dh):
        W = 9.0 + float(dh)
        return _ld_end(sc.system, dict(p, relay_hz=W), y, K / W, (K + 1) / W)
    oracle = np.array(_richardson(f, np.longdouble(1e-6)), dtype=float)
    L = smap.linearize(o.state(K), K, params=("relay_hz",))
    assert np.linalg.norm(L.J_p[:, 0] - oracle) / np.linalg.norm(oracle) < 1e-7     # measured 3.5e-9


def test_a_stick_makes_the_step_rank_deficient_along_the_projected_directions():
    """chatter-relay: the bar sticks on the stop in the first relay period (x = e, v = 0 exactly).
    J has rank 2 of 4, the signature records the stick, and the map itself does not move along
    J's null directions (central differences of whole steps along them vanish)."""
    case = next(c for c in CASES if c.name == "chatter-relay")
    sc, p = case_scene(case)
    smap = maps.StroboscopicMap(sc.system, p, tol=1e-12)
    y0 = sc.system.state_vector(sc.initial_state(**case.x0))
    L = smap.linearize(y0, 0)
    assert "stick" in L.signature and L.rank == 2
    _, s, vt = np.linalg.svd(L.J)
    for null in vt[2:]:
        h = 1e-7
        d = (smap.step(y0 + h * null, 0) - smap.step(y0 - h * null, 0)) / (2 * h)
        assert np.max(np.abs(d)) < 1e-6 * s[0]
    moving = (smap.step(y0 + 1e-7 * vt[0], 0) - smap.step(y0 - 1e-7 * vt[0], 0)) / 2e-7
    assert np.max(np.abs(moving)) > 0.1 * s[0]


# ----- the impact map: the next impact's state and time, with the section's moving hitting time ---------
def _free_flight(y0, t0, osc=OSC):
    """The oscillator's free flight in closed form: y(t) = y_p(t) + expm(A (t - t0)) (y0 - y_p(t0)),
    y_p the steady forced response X cos(W t) + Y sin(W t)."""
    w0, z, F, W = (osc[k] for k in ("w0", "zeta", "F", "Omega"))
    A = np.array([[0.0, 1.0], [-w0 * w0, -2 * z * w0]])
    X, Y = np.linalg.solve([[w0 * w0 - W * W, 2 * z * w0 * W], [-2 * z * w0 * W, w0 * w0 - W * W]], [F, 0.0])

    def yp(t):
        return np.array([X * math.cos(W * t) + Y * math.sin(W * t), W * (Y * math.cos(W * t) - X * math.sin(W * t))])
    return A, (lambda t: yp(t) + expm(A * (t - t0)) @ (np.asarray(y0, float) - yp(t0)))


def _hand_impact(y0, t0, osc=OSC):
    """(t1, y after the impact, J, dt1/dy0, S) of the next impact, derived by hand: the first root of
    x(t) = e of the closed-form flight (brentq), J = R (I - f- g^T / (g . f-)) expm(A (t1 - t0)) with
    g = (1, 0), R = diag(1, -r), f- = (v-, F cos(W t1) - 2 zeta w0 v- - w0^2 e); S = R + (f+ - R f-) g^T / (g . f-)
    the saltation matrix (states compared at the same time)."""
    from scipy.optimize import brentq
    w0, z, F, W, e, r = (osc[k] for k in ("w0", "zeta", "F", "Omega", "e", "r"))
    A, y = _free_flight(y0, t0, osc)
    grid = t0 + np.linspace(1e-9, 4 * math.pi / W, 4001)
    gap = np.array([y(t)[0] - e for t in grid])
    i = int(np.argmax(gap[1:] < 0)) + 1                 # the first crossing downward
    t1 = brentq(lambda t: y(t)[0] - e, grid[i - 1], grid[i], xtol=1e-15, rtol=1e-15)
    v = y(t1)[1]
    f = np.array([v, F * math.cos(W * t1) - 2 * z * w0 * v - w0 * w0 * e])
    g = np.array([1.0, 0.0])
    Phi = expm(A * (t1 - t0))
    R = np.diag([1.0, -r])
    J = R @ (np.eye(2) - np.outer(f, g) / (g @ f)) @ Phi
    f_plus = np.array([-r * v, F * math.cos(W * t1) + 2 * z * w0 * r * v - w0 * w0 * e])
    S = R + np.outer(f_plus - R @ f, g) / (g @ f)
    return t1, np.array([e, -r * v]), J, -(g @ Phi) / (g @ f), S


def test_impact_map_jacobian_is_the_hand_derived_projection(osc_orbit):
    """From a state in free flight, then from the impact's own state on the section: impact time,
    state after the reset, J and dt/dy0 against the closed form, to 1e-9 (the finite difference only
    as an oracle, to 1e-6)."""
    system, smap, o = osc_orbit
    imap = maps.ImpactMap(system, OSC, tol=1e-14)
    T = 2 * math.pi / OSC["Omega"]
    state, t0 = o.points[1], 201 * T
    for hop in range(2):
        t1, y1, J, dt, _ = _hand_impact(state, t0)
        L = imap.linearize(state, t0)
        assert L.signature[-1] == "impact" and abs(L.t - t1) < 1e-10
        assert np.max(np.abs(L.state.y - y1)) < 1e-10
        assert np.max(np.abs(L.J - J)) / np.max(np.abs(J)) < 1e-9          # measured 3e-14, 2e-13
        assert np.max(np.abs(L.dt_dy - dt)) / np.max(np.abs(dt)) < 1e-9
        assert np.max(np.abs(L.J[0])) < 1e-12 and np.max(np.abs(L.J[1])) > 0.04   # x = e after: the section
        fd = imap.jacobian(state, t0, method="fd", eps=1e-7)
        assert np.max(np.abs(fd - J)) / np.max(np.abs(J)) < 1e-6          # measured 9e-9
        state, t0 = y1, t1                                # the impact map proper: impact to impact


def test_impact_map_jacobian_against_long_double_differences(thesis):
    """thesis-1dof, 9 Hz: from the strobe sample before a contact at 0.6 m/s to the contact onset
    (the compliant contact: no reset), against Richardson central differences of the onset state
    computed in long double at tol 1e-18."""
    sc, p, smap, o = thesis
    imap = maps.ImpactMap(sc, p, tol=1e-12)
    y = o.points[K].astype(np.longdouble)
    t0 = smap.sample_time(K)

    def onset(yy):
        run = HybridRun(sc.system, p, np.array(yy, dtype=np.longdouble), t0=t0, tol=1e-18, fp_type=np.longdouble,
                        max_events=None)
        run.advance(t0 + 2 * smap.period, stop_roles=("impact",))
        assert run.stopped_by == "contact"
        return np.array(run.ta.state, dtype=np.longdouble)
    cols = []
    for j in range(4):
        e = np.zeros(4, dtype=np.longdouble)
        e[j] = 1
        cols.append(_richardson(lambda h, e=e: onset(y + h * e), np.longdouble(1e-5) * max(abs(y[j]), np.longdouble(1e-3))))
    oracle = np.array(cols, dtype=float).T
    L = imap.linearize(o.state(K), t0)
    assert L.signature.count("impact") == 1 and smap.sample_time(K) < L.t < smap.sample_time(K + 1)
    err = np.linalg.norm(L.J - oracle) / np.linalg.norm(oracle)
    assert err < 1e-8                                   # measured 3e-12


# ----- the largest Lyapunov exponent from one tangent vector integrated with the flow (batch engine) -----
OSC_REAL = dict(OSC, Omega=1.2, r=0.5)      # a stable 1:1 orbit with real multipliers -0.797, -0.186


def test_tangent_exponent_is_the_log_of_the_hand_composed_multiplier():
    """On the 1:1 orbit the one-period Jacobian is expm(A (T - t1)) S expm(A t1) (closed-form flight,
    hand-derived saltation S).  The tangent vector integrated with the flow on the batch engine
    (saltation applied to it at the impact) stretches, once aligned, by its largest |multiplier|
    every period (to 1e-8), and its total stretch over the record is |J^N u0| / |u0| (to 1e-10)."""
    system = maps.forced_oscillator_with_stop()
    smap = maps.StroboscopicMap(system, OSC_REAL, tol=1e-14)
    T = 2 * math.pi / OSC_REAL["Omega"]
    o = smap.orbits([{}], {"x": 0.2, "v": 0.0}, 40, transient=300, tangent=True, method="batch")[0]
    assert o.status == "ok" and set(o.impacts_per_step) == {1}
    t0 = 300 * T
    t1, y1, _, _, S = _hand_impact(o.points[0], t0, OSC_REAL)
    A, _ = _free_flight(o.points[0], t0, OSC_REAL)
    J = expm(A * (t0 + T - t1)) @ S @ expm(A * (t1 - t0))
    lam = np.linalg.eigvals(J)
    assert np.all(np.isreal(lam)) and abs(lam[0]) != abs(lam[1])
    stretch = o.tangent_stretch()
    assert abs(stretch[-1] - math.log(np.max(np.abs(lam)))) < 1e-8
    u0 = maps.tangent.start_direction(2)
    total = math.log(np.linalg.norm(np.linalg.matrix_power(J, 40) @ u0))
    assert abs(np.sum(stretch) - total) < 1e-10 * max(1.0, abs(total))


def test_tangent_exponent_agrees_with_the_companion_along_the_same_record():
    """thesis-1dof, 90 V, 200 recorded periods with contacts: the tangent vector integrated with the
    record (batch engine) against Benettin's companion run along the very same record.  At the
    chaotic 4.1 and 4.7 Hz the exponents agree within their 95 % intervals (both reported); at every
    value the per-period stretches agree to a median 5e-3 (the companion's own noise: its 1e-8
    separation carries the 1e-10 integration error; without the saltation of the tangent vector at
    contacts the median difference is 0.014-0.30, measured)."""
    from bifurc.labels.classify import state_scale
    from bifurc.labels.lyapunov import exponent_interval
    sc = maps.get_scene("thesis-1dof").with_options(dc_law="listing")
    smap = maps.StroboscopicMap(sc, sc.parameters(preset="matlab-listing", V=90.0), tol=1e-10)
    over = [{"relay_hz": f} for f in (4.1, 4.7, 8.6)]
    orbits = smap.orbits(over, sc.initial_state(), 200, transient=300, tangent=True)
    for o, ov in zip(orbits, over):
        assert o.status == "ok" and o.impacts_per_step.sum() > 50
        scale = state_scale(o.points, 1e-9)
        tangent = o.tangent_stretch(scale)
        companion = smap.stretch([o.points], [ov], k0=[300], scales=[scale])[0]
        assert np.median(np.abs(tangent - companion)) < 5e-3               # measured 1.6e-3 - 2.6e-3
        (lt, lo_t, hi_t), (lc, lo_c, hi_c) = exponent_interval(tangent), exponent_interval(companion)
        print(f"{ov['relay_hz']} Hz: tangent {lt:.4f} [{lo_t:.4f}, {hi_t:.4f}], companion {lc:.4f} [{lo_c:.4f}, {hi_c:.4f}]")
        if ov["relay_hz"] < 5:                                              # the chaotic values
            assert lo_t > 0.05 and lo_c > 0.05                             # measured 0.09-0.15
            assert abs(lt - lc) <= math.hypot(hi_t - lt, hi_c - lc)        # measured 0.001-0.005 against 0.14-0.16


def test_sweep_stores_the_exponent_method_and_both_methods_agree():
    """The product path (sweep) with either method at chaotic 4.7 Hz: the method is stored, and the
    two exponents (over records that part by chaos-amplified round-off) agree within their spread."""
    from bifurc.labels.classify import ClassCode
    from bifurc.sweeps.sweep import sweep
    kw = dict(preset="matlab-listing", params={"V": 90}, grazing=False, error_sample=0, progress=False, workers=1)
    ds = {m: sweep("thesis-1dof", "relay_hz", np.array([4.7]), lyapunov_method=m, **kw).isel(branch=0, relay_hz=0)
          for m in ("tangent", "companion")}
    t, c = ds["tangent"], ds["companion"]
    assert t.attrs["lyapunov_method"].startswith("tangent") and c.attrs["lyapunov_method"].startswith("companion")
    half = [float(d.lyapunov_high - d.lyapunov) for d in (t, c)]
    assert 0 < max(half) < 0.2
    assert abs(float(t.lyapunov) - float(c.lyapunov)) <= math.hypot(*half)
    assert ClassCode(int(t.class_code)) == ClassCode(int(c.class_code)) == ClassCode.CHAOTIC
    with pytest.raises(maps.ParameterError, match="lyapunov_method"):
        sweep("thesis-1dof", "relay_hz", np.array([4.7]), lyapunov_method="qr", **kw)


def _kelvin_voigt_case():
    """thesis-1dof (listing law, 90 V, 5 Hz): (system, params, Derivatives, the vector field as a
    cfunc, guards by name)."""
    import heyoka as hy
    from maps.variational import Derivatives
    sc = maps.get_scene("thesis-1dof").with_options(dc_law="listing")
    system = sc.system
    return (system, sc.parameters(preset="matlab-listing", V=90.0, relay_hz=5.0), Derivatives(system),
            hy.cfunc(list(system.rhs), vars=system.sym.state_vars), {g.name: g for g in system.guards})


def _kelvin_voigt_crossings(system, p, rhs, t):
    """(guard name, contact flag before, v, flags before, y, f+ - f-) at contact onset and release."""
    for name, before, v in (("contact", 0.0, -0.37), ("release", 1.0, 0.52)):
        flags = dict(system.initial_flags(0.0, p), contact=before)
        y = np.array([p["e"], v, 1.3, -20.0])
        f = {c: rhs(y, pars=np.array(system.par_vector(p, dict(flags, contact=c)))[:rhs.nparams], time=t)
             for c in (0.0, 1.0)}
        yield name, before, v, flags, y, f[1.0 - before] - f[before]


def test_compiled_tangent_jump_is_the_hand_derived_kelvin_voigt_saltation():
    """thesis-1dof's compliant stop (force -(k (x - e) + c v) while in contact): at onset (x = e,
    moving down) the guard g = x - e has grad (1, 0, 0, 0) and rate v, so one tangent vector jumps by
    u+ = u + (f+ - f-) u_x / v, where the vector field jumps by -c v / m in dv/dt (and in dz/dt
    through the circuit's coupling to the acceleration); at release the jump is reversed.  The
    compiled rule the batch engine applies at every recorded event (Derivatives.tangent_jump) against
    that form, with f+- evaluated from the model's vector field in the two modes."""
    system, p, der, rhs, guards = _kelvin_voigt_case()
    rng = np.random.default_rng(3)
    t = 0.013
    for name, before, v, flags, y, jump in _kelvin_voigt_crossings(system, p, rhs, t):
        u = rng.standard_normal(4)
        assert jump[0] == 0.0 and jump[1] == pytest.approx((before - (1.0 - before)) * p["c"] * v / p["m"], rel=1e-13)
        pars = np.array(system.par_vector(p, flags))
        got = der.tangent_jump(guards[name], {"contact": 1.0 - before})(np.concatenate([y, u]), pars, t)
        np.testing.assert_allclose(got, u + jump * u[0] / v, rtol=1e-13, atol=1e-13 * np.abs(jump).max())


def test_compiled_matrix_jump_is_the_hand_derived_saltation_with_the_event_time_row():
    """The scalar engine's state-Jacobian path (Derivatives.matrix_jump: every column of Y in one
    flat call) against closed forms.  thesis-1dof's compliant stop as above: Y+ = Y + (f+ - f-)
    Y[0] / v and dt_e/dy0 = -Y[0] / v.  The restitution oscillator (reset v -> -r v at x = e):
    R = diag(1, -r), f- = (v, a-), f+ = (-r v, a+), so Y+ = R Y + (f+ - R f-) Y[0] / v =
    R Y + (-(1 + r) v, a+ + r a-) Y[0] / v, with a-+ = F cos(Omega t) - w0^2 e - 2 zeta w0 v-+
    (v- = v, v+ = -r v); dt_e/dy0 = -Y[0] / v in both."""
    from maps.variational import Derivatives
    system, p, der, rhs, guards = _kelvin_voigt_case()
    rng = np.random.default_rng(5)
    t = 0.013
    for name, before, v, flags, y, jump in _kelvin_voigt_crossings(system, p, rhs, t):
        Y = rng.standard_normal((4, 4))
        got, dt, rate = der.matrix_jump(guards[name], {"contact": 1.0 - before})(np.concatenate([y, Y.ravel()]),
                                                                                 system.par_vector(p, flags), t)
        assert rate == pytest.approx(v, rel=1e-14)          # the crossing rate d(gap)/dt = v
        np.testing.assert_allclose(got, Y + np.outer(jump, Y[0] / v), rtol=1e-13, atol=1e-13 * np.abs(jump).max())
        np.testing.assert_allclose(dt, -Y[0] / v, rtol=1e-14)
    osc = maps.forced_oscillator_with_stop()
    q = osc.validate(dict(w0=1.0, zeta=0.05, F=0.5, Omega=0.8, e=-0.6, r=0.7))
    contact = next(g for g in osc.guards if g.name == "contact")
    t, v = 2.1, -0.9
    a = q["F"] * math.cos(q["Omega"] * t) - q["w0"] ** 2 * q["e"] - 2 * q["zeta"] * q["w0"] * v
    a_plus = q["F"] * math.cos(q["Omega"] * t) - q["w0"] ** 2 * q["e"] + 2 * q["zeta"] * q["w0"] * q["r"] * v
    Y = rng.standard_normal((2, 2))
    R = np.diag([1.0, -q["r"]])
    got, dt, rate = Derivatives(osc).matrix_jump(contact, {})(np.concatenate([[q["e"], v], Y.ravel()]),
                                                         osc.par_vector(q, {"stuck": 0.0}), t)
    expect = R @ Y + np.outer([-q["r"] * v - v, a_plus + q["r"] * a], Y[0] / v)
    np.testing.assert_allclose(got, expect, rtol=1e-13, atol=1e-15)
    np.testing.assert_allclose(dt, -Y[0] / v, rtol=1e-14)
    assert abs(rate) == pytest.approx(abs(v), rel=1e-14)     # |d(x - e)/dt| = |v|
