"""A census' full attractor records (issue 47 section 4) against independent truths.

1. The impact oscillator of tests/test_attractors.py at Omega = 1.3 (w0 = 1, zeta = 0.05, r = 0.8, e = -1): its
   non-impacting orbit is the linear forced response, whose monodromy is exp(A T) whatever the forcing (A the
   free oscillator's matrix, T = 2 pi / Omega): the multipliers exp(lambda T), lambda = -zeta w0 +- i w0 sqrt(1 -
   zeta^2), a complex pair.  Its impacting 1:1 orbit has the monodromy exp(A (T - tau)) S exp(A tau), with tau the
   impact's phase (found here from the closed-form flight) and S the Newtonian impact's saltation matrix
   [[-r, 0], [(a+ + r a-) / u, -r]] (u < 0 the impact speed, a-+ the accelerations before and after it), derived
   below; its determinant r^2 exp(-2 zeta w0 T) is a check of its own (Liouville plus det S = r^2).
2. The logistic map as a kicked flow (tests/test_attractors.py): at r = 2.9 the fixed point (r - 1) / r has the
   multiplier 2 - r = -0.9 (argument pi) and the decaying coordinate y' = -y the multiplier exp(-1) over the 1 s
   period; at r = 4 the map is chaotic with exponent ln 2 (conjugate to the tent map) and persists: its lifetime
   verdict is "attractor".
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.linalg import expm
from scipy.optimize import brentq

import bifurc
from bifurc.labels.codes import OUTCOMES
from bifurc.labels.codes import ClassCode
from test_attractors import BOX, KICKED, OSC, _free, _impacting, _non_impacting


@pytest.fixture(scope="module")
def census():
    return bifurc.attractors("impact-oscillator", "Omega", [OSC["Omega"]], params=OSC, box=BOX, n_starts=30,
                             seed=3, progress=False, link=False)


def _orbit_column(ds, impacts: int) -> int:
    cols = [j for j in range(ds.sizes["attractor"] - len(OUTCOMES)) if ds.present.values[0, j]
            and int(ds.impacts_per_period.values[0, j]) == impacts]
    assert len(cols) == 1
    return cols[0]


def _multipliers(ds, i, j) -> np.ndarray:
    a, g = ds.multiplier_abs.values[i, j], ds.multiplier_arg.values[i, j]
    ok = np.isfinite(a)
    return a[ok] * np.exp(1j * g[ok])


def _free_matrix(p, s: float) -> np.ndarray:
    """exp(A s) of the free oscillator x'' + 2 zeta w0 x' + w0^2 x = 0: the flow's Jacobian over s, any forcing."""
    return expm(np.array([[0.0, 1.0], [-p["w0"] ** 2, -2 * p["zeta"] * p["w0"]]]) * s)


def _impacting_monodromy(p) -> np.ndarray:
    """The 1:1 impacting orbit's monodromy from its strobe state at t = 0 (the closed-form orbit): the first impact
    at tau in (0, T) (the flight's first crossing of x = e), then exp(A (T - tau)) S exp(A tau)."""
    T, e, r = 2 * math.pi / p["Omega"], p["e"], p["r"]
    x0, v0 = _impacting(p)
    ts = np.linspace(0.0, T, 4001)
    x = _free(p, 0.0, x0, v0, ts)[0] - e
    k = int(np.argmax((x[:-1] > 0) & (x[1:] <= 0)))
    tau = brentq(lambda t: _free(p, 0.0, x0, v0, t)[0] - e, ts[k], ts[k + 1], xtol=1e-15)
    u = _free(p, 0.0, x0, v0, tau)[1]
    assert u < 0

    def accel(v):
        return p["F"] * math.cos(p["Omega"] * tau) - 2 * p["zeta"] * p["w0"] * v - p["w0"] ** 2 * e
    S = np.array([[-r, 0.0], [(accel(-r * u) + r * accel(u)) / u, -r]])
    return _free_matrix(p, T - tau) @ S @ _free_matrix(p, tau)


def _same_multipliers(got, want, tol):
    got = np.asarray(got)[np.lexsort((np.angle(got), -np.abs(got)))]
    want = np.asarray(want)[np.lexsort((np.angle(want), -np.abs(want)))]
    assert got.shape == want.shape
    assert np.max(np.abs(got - want)) <= tol, (got, want)


def test_the_non_impacting_orbit_stores_its_complex_pair_exp_lambda_t(census):
    ds, p = census, OSC
    j = _orbit_column(ds, 0)
    T = 2 * math.pi / p["Omega"]
    lam = -p["zeta"] * p["w0"] + 1j * p["w0"] * math.sqrt(1 - p["zeta"] ** 2)
    want = np.exp(np.array([lam, lam.conjugate()]) * T)
    assert abs(want[0].imag) > 0.5 * abs(want[0])              # a genuine complex pair, not near the real axis
    _same_multipliers(_multipliers(ds, 0, j), want, 1e-8)
    assert np.allclose(ds.multiplier_abs.values[0, j], math.exp(-p["zeta"] * p["w0"] * T), rtol=1e-8, atol=0)
    arg = np.angle(want[0])
    assert sorted(ds.multiplier_arg.values[0, j]) == pytest.approx(sorted([arg, -arg]), abs=1e-8)
    assert float(ds.max_multiplier.values[0, j]) == pytest.approx(float(ds.multiplier_abs.values[0, j, 0]), rel=1e-12)
    assert np.allclose([ds.x.values[0, j, 0], ds.v.values[0, j, 0]], _non_impacting(p), atol=1e-8)


def test_the_impacting_orbit_stores_the_saltation_monodromys_multipliers(census):
    ds, p = census, OSC
    j = _orbit_column(ds, 1)
    M = _impacting_monodromy(p)
    T = 2 * math.pi / p["Omega"]
    assert np.linalg.det(M) == pytest.approx(p["r"] ** 2 * math.exp(-2 * p["zeta"] * p["w0"] * T), rel=1e-9)
    mu = _multipliers(ds, 0, j)
    _same_multipliers(mu, np.linalg.eigvals(M), 1e-7)
    assert np.prod(mu).real == pytest.approx(p["r"] ** 2 * math.exp(-2 * p["zeta"] * p["w0"] * T), rel=1e-7)
    assert int(ds.period.values[0, j]) == 1 and int(ds.period_mechanical.values[0, j]) == 1


def test_the_table_lists_every_record(census):
    df = census.bifurc.table()
    rows = df[df["attractor"].str.startswith("A")]
    assert len(rows) == 2 and set(rows["description"]) >= {"period-1, 1 impact (1:1)"}
    for k in ("multiplier_abs_1", "multiplier_arg_2", "x_at_section", "v_at_section", "period_mechanical",
              "impacts_per_period", "lyapunov_low", "lifetime_verdict", "basin_fraction"):
        assert k in df.columns, k
    assert df.attrs["units"]["multiplier_arg_1"] == "rad" and df.attrs["units"]["x_at_section"] == "m"
    assert rows["basin_fraction"].sum() == pytest.approx(1.0, abs=1e-12)
    j = _orbit_column(census, 0)
    row = rows[rows["attractor"] == f"A{j}"].iloc[0]
    assert row["multiplier_abs_1"] == pytest.approx(math.exp(-OSC["zeta"] * 2 * math.pi / OSC["Omega"]), rel=1e-8)


def test_a_negative_multiplier_has_argument_pi_and_a_chaotic_set_its_verdict():
    ds = bifurc.attractors(KICKED, "r", [2.9, 4.0], n_starts=20, seed=1, progress=False, workers=1, link=False)
    j = [k for k in range(ds.sizes["attractor"] - len(OUTCOMES)) if ds.present.values[0, k]][0]
    assert int(ds.period.values[0, j]) == 1
    _same_multipliers(_multipliers(ds, 0, j), [2.0 - 2.9 + 0j, math.exp(-1.0) + 0j], 1e-8)
    assert abs(float(ds.multiplier_arg.values[0, j, 0])) == pytest.approx(math.pi, abs=1e-12)
    assert int(ds.lifetime_verdict.values[0, j]) == 0                         # periodic: no verdict
    chaos = [k for k in range(ds.sizes["attractor"] - len(OUTCOMES)) if ds.present.values[1, k]]
    assert len(chaos) == 1
    k = chaos[0]
    assert int(ds.class_code.values[1, k]) == int(ClassCode.CHAOTIC)
    assert float(ds.lyapunov_low.values[1, k]) <= math.log(2.0) <= float(ds.lyapunov_high.values[1, k])
    meanings = ds.lifetime_verdict.attrs["flag_meanings"].split()
    assert meanings[int(ds.lifetime_verdict.values[1, k])] == "attractor"
    assert float(ds.lifetime_low.values[1, k]) > 4000                         # the census' horizon (Settings.persist)
    assert np.all(np.isnan(ds.multiplier_abs.values[1, k]))
    df = ds.bifurc.table()
    assert list(df.loc[df["r"] == 4.0, "lifetime_verdict"]) == ["attractor"]


def _rectified():
    """q' = -q + cos(pi t) (a drive of period 2 s, as a relay flipping the current), x' = v, v' = -x - v + q^2 (the
    mechanics see q^2, of period 1 s), sampled every 1 s: the orbit repeats after 2 samples, its mechanical states
    (x, v) after 1."""
    import heyoka as hy
    from maps import HybridSystem, Parameter, State
    return HybridSystem("rectified-drive", states=[State("x", "m", "position"), State("v", "m s-1", "velocity"),
                                                   State("q", "C", "charge")],
                        parameters=[Parameter("g", "1", "drive gain", 0, 10)],
                        rhs=lambda s: [s.v, -s.x - s.v + s.g * s.q * s.q, -s.q + hy.cos(math.pi * s.t)],
                        strobe_period=lambda p: 1.0, forcing=lambda p: [0.5], mechanical=("x", "v"))


def test_the_mechanical_period_is_that_of_the_mechanical_states_and_the_multipliers_those_of_the_linear_parts():
    """Closed forms: q = Re(exp(i pi t) / (1 + i pi)) of period 2, so q^2 = |Q|^2 / 2 (1 + Re(Q^2 / |Q|^2 exp(2 i pi t)))
    of period 1, and x = |Q|^2 / 2 + Re(|Q|^2 / 2 (Q^2/|Q|^2) exp(2 i pi t) / (1 - 4 pi^2 + 2 i pi)) (g = 1).  The
    variational system is triangular (x, v do not act on q): the monodromy over the 2-sample orbit has the
    multipliers exp(-2) (q) and exp(2 lambda), lambda = (-1 +- i sqrt 3) / 2 (x, v): a complex pair of modulus exp(-1),
    arguments +-sqrt 3."""
    import maps
    sc = maps.Scene("rectified-drive", "tests/test_census_records.py", None, preset=None,
                    overrides={"g": (1.0, "tests/test_census_records.py")}, x0={"x": 0.0, "v": 0.0, "q": 0.0},
                    builder=_rectified, box={"x": (-0.5, 0.5), "v": (-0.5, 0.5), "q": (-1.0, 1.0)})
    ds = bifurc.attractors(sc, "g", [1.0], n_starts=4, seed=1, progress=False, workers=1, link=False)
    (j,) = [k for k in range(ds.sizes["attractor"] - len(OUTCOMES)) if ds.present.values[0, k]]
    assert int(ds.period.values[0, j]) == 2 and int(ds.period_mechanical.values[0, j]) == 1
    Q = 1.0 / (1.0 + 1j * math.pi)
    A2 = abs(Q) ** 2 / 2

    def exact(t):
        X = A2 * (Q ** 2 / abs(Q) ** 2) / (1 - 4 * math.pi ** 2 + 2j * math.pi)
        e = np.exp(2j * math.pi * t)
        return np.array([A2 + (X * e).real, (2j * math.pi * X * e).real, (Q * np.exp(1j * math.pi * t)).real])
    k0 = int(ds.attractor_k0.values[0, j])
    for node in range(2):
        got = [float(ds[s].values[0, j, node]) for s in ("x", "v", "q")]
        assert np.allclose(got, exact(k0 + node), atol=1e-8, rtol=0), (node, got, exact(k0 + node))
    lam = (-1 + 1j * math.sqrt(3)) / 2
    _same_multipliers(_multipliers(ds, 0, j), [math.exp(-2.0), np.exp(2 * lam), np.exp(2 * lam.conjugate())], 1e-8)
    df = ds.bifurc.table()
    assert list(df["period_mechanical"]) == [1] and df.attrs["units"]["q_at_section"] == "C"
