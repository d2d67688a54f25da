"""Where the orbit does not persist past a grazing (issue 28, section 3): the impact oscillator
x'' + 2 zeta w0 x' + w0^2 x = F cos(Omega t), stop at x = e < 0 (impact when x falls to e, v -> -r v), with
w0 = 1, zeta = 0.05, Omega = 1.5, e = -0.5, r = 0.7, continued in F upward.

Closed forms derived here.  The non-impacting orbit is x_p(t) = A cos(Omega t - phi), A = F / D,
D = sqrt((w0^2 - Omega^2)^2 + (2 zeta w0 Omega)^2), tan phi = 2 zeta w0 Omega / (w0^2 - Omega^2); it grazes the
stop where A = |e|, F_g = |e| D, and penetrates it beyond (no non-impacting orbit for F > F_g).
The impacting 1:1 orbit with impact speed s at time t0: x = x_p + h, h' = L h (L the damped oscillator's
matrix), h(t0+) = (e - x_p(t0), r s - x_p'(t0)); returning to x = e with speed s after one period T = 2 pi / Omega
means (Phi - I) (e - x_p(t0), -x_p'(t0)) = -s (r Phi + I) (0, 1), Phi = exp(L T).  So
(e - x_p(t0), -x_p'(t0)) = s g with g = -(Phi - I)^-1 (r Phi + I) (0, 1), and
A^2 = (e - s g1)^2 + (s g2 / Omega)^2: F(s) = D sqrt((e - s g1)^2 + (s g2 / Omega)^2), dF/ds(0) = -D sign(e) g1.
Here dF/ds(0) < 0: the small impacting orbits exist only for F < F_g, on the SAME side as the non-impacting
orbit.  Past F_g neither exists near the grazing: the branch must not go on there; it can only turn back
onto the impacting orbit (a non-smooth fold), which it must say.
"""
import math

import numpy as np
import pytest
import scipy.linalg as sl

import bifurc
from bifurc.storage.schema import SPECIAL_KINDS

P = dict(w0=1.0, zeta=0.05, Omega=1.5, e=-0.5, r=0.7)
W, E, R = P["Omega"], P["e"], P["r"]
D = math.hypot(P["w0"] ** 2 - W ** 2, 2 * P["zeta"] * P["w0"] * W)
PHI = math.atan2(2 * P["zeta"] * P["w0"] * W, P["w0"] ** 2 - W ** 2)
F_GRAZE = abs(E) * D
T = 2 * math.pi / W
L = np.array([[0.0, 1.0], [-P["w0"] ** 2, -2 * P["zeta"] * P["w0"]]])
MONO = sl.expm(L * T)
G = -np.linalg.solve(MONO - np.eye(2), (R * MONO + np.eye(2)) @ [0.0, 1.0])


def impacting_strobe_state(F: float, phase: float) -> np.ndarray:
    """(x, v) at t = phase T of the impacting 1:1 orbit at F with the smallest impact speed s > 0."""
    A = F / D
    s = min(x for x in np.roots([G[0] ** 2 + (G[1] / W) ** 2, -2 * E * G[0], E * E - A * A]).real if x > 0)
    theta = math.atan2(s * G[1] / (W * A), (E - s * G[0]) / A)
    t0 = ((theta + PHI) / W) % T
    dt = (phase * T - t0) % T
    h = sl.expm(L * dt) @ [E - A * math.cos(W * t0 - PHI), R * s + A * W * math.sin(W * t0 - PHI)]
    t = t0 + dt
    return np.array([A * math.cos(W * t - PHI) + h[0], -A * W * math.sin(W * t - PHI) + h[1]])


@pytest.fixture(scope="module")
def ds():
    F0 = 0.9 * F_GRAZE
    A0 = F0 / D               # the non-impacting orbit's strobe state at t = 0, exact
    return bifurc.continue_orbit("impact-oscillator", "F", (F0, 1.2 * F_GRAZE), params=dict(P, F=F0),
                                 x0={"x": A0 * math.cos(PHI), "v": A0 * W * math.sin(PHI)}, transient=0)


def test_the_impacting_orbit_lies_on_the_non_impacting_side():
    assert -D * math.copysign(1.0, E) * G[0] < -0.5          # dF/ds at s = 0: -0.606


def test_no_piece_past_a_grazing_where_the_orbit_does_not_persist(ds):
    kinds = [SPECIAL_KINDS[int(k)] for k in ds.special_kind.values]
    assert kinds == ["grazing"]
    assert abs(float(ds.special_value[0]) - F_GRAZE) < 1e-8
    assert np.all(ds.F.values <= F_GRAZE + 1e-8)          # nothing invented beyond the grazing
    i = int(ds.special_point[0])
    ipp = ds.impacts_per_period.values
    assert np.all(ipp[:i + 1] == 0) and np.all(ipp[i + 1:] == 1) and ipp.size > i + 3
    note, why = str(ds.special_note.values[0]), ds.attrs["branch_stop_reasons"]
    assert "no small impacting orbit beyond the grazing" in note and "the branch turns there" in note
    assert f"no orbit persists past F = {float(ds.special_value[0]):.10g}: the branch turns back there" in why
    assert "continued from F = " in why and "toward decreasing F (1 impact per period)" in why


def test_the_branch_turns_back_onto_the_closed_form_impacting_orbit(ds):
    i = int(ds.special_point[0])
    for k in range(i + 1, ds.sizes["point"]):
        y = impacting_strobe_state(float(ds.F[k]), float(ds.section_phase[k]))
        np.testing.assert_allclose([float(ds.x[k, 0]), float(ds.v[k, 0])], y, rtol=0, atol=1e-9)
