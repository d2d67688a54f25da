"""Pseudo-arclength continuation of periodic orbits against closed forms derived here.

The restitution oscillator x'' + 2 zeta w0 x' + w0^2 x = F cos(Omega t), x >= e, v -> -r v at
x = e.  Its 1:1 orbits (one impact per forcing period T) have a closed form: with x_p the
particular solution and P = exp(A T) the free flight's transition matrix, the flight from
(e, -r v) at the impact phase th must return to (e, v) one period later.  For a fixed th the
two conditions are linear in v and affine in e (and in F, x_p being proportional to F), so along
the family of 1:1 orbits e(th) and F(th) are explicit: the fold is an extremum of e(th) (or
F(th)), the period doubling the zero of det(P S + I) with the saltation matrix S of the impact.
"""
import math

import heyoka as hy
import numpy as np
import pytest
from scipy.linalg import expm
from scipy.optimize import brentq, minimize_scalar

import bifurc
import maps
from maps.hybrid import HybridSystem, State
from maps.parameters import Parameter, ParameterError

BASE = dict(w0=1.0, zeta=0.05, F=0.5, Omega=2.5, e=0.2, r=0.7)


def one_to_one_family(w0, zeta, F, Omega, r, e, free):
    """(value of ``free`` ('e' or 'F') along the 1:1 family as a function of the impact phase th,
    impact velocity, multipliers), the other parameters fixed."""
    T = 2 * math.pi / Omega
    Al = np.array([[0.0, 1.0], [-w0 * w0, -2 * zeta * w0]])
    D = (w0 * w0 - Omega * Omega) ** 2 + (2 * zeta * w0 * Omega) ** 2
    P = expm(Al * T)

    def G(th, e_, F_):
        a, b = F_ * (w0 * w0 - Omega * Omega) / D, F_ * 2 * zeta * w0 * Omega / D
        t = th / Omega
        x, u = a * math.cos(Omega * t) + b * math.sin(Omega * t), Omega * (-a * math.sin(Omega * t) + b * math.cos(Omega * t))
        v = ((P[0, 0] - 1) * (e_ - x) - P[0, 1] * u) / (P[0, 1] * r)
        return v - u - P[1, 0] * (e_ - x) - P[1, 1] * (-r * v - u), v

    def value(th):       # G is affine in the free parameter
        args = (lambda z: (z, F)) if free == "e" else (lambda z: (e, z))
        g0, g1 = G(th, *args(0.0))[0], G(th, *args(1.0))[0]
        return -g0 / (g1 - g0)

    def multipliers(th):
        z = value(th)
        e_, F_ = (z, F) if free == "e" else (e, z)
        v = G(th, e_, F_)[1]
        force = F_ * math.cos(th) - w0 * w0 * e_
        am, ap = force - 2 * zeta * w0 * v, force + 2 * zeta * w0 * r * v
        S = np.array([[-r, 0.0], [(ap + r * am) / v, -r]])
        return np.linalg.eigvals(P @ S), v
    return value, multipliers


def fold_of(value, th_grid, sign, multipliers=None):
    """The extremum of the family's parameter (sign +1: a maximum) over phases where the orbit is
    an impact toward the stop (v < 0) at a positive parameter value (with ``multipliers`` given)."""
    def admissible(t):
        return multipliers is None or (multipliers(t)[1] < 0 and value(t) > 0)
    vals = np.array([sign * value(t) if admissible(t) else -np.inf for t in th_grid])
    i = int(np.nanargmax(vals))
    res = minimize_scalar(lambda t: -sign * value(t), bounds=(th_grid[i - 1], th_grid[i + 1]), method="bounded",
                          options={"xatol": 1e-13})
    return value(res.x)


def period_doublings_of(value, multipliers, th_grid):
    f = [np.real(np.prod(multipliers(t)[0] + 1.0)) for t in th_grid]
    out = []
    for k in range(len(th_grid) - 1):
        if f[k] * f[k + 1] < 0:
            th = brentq(lambda t: np.real(np.prod(multipliers(t)[0] + 1.0)), th_grid[k], th_grid[k + 1], xtol=1e-15)
            if abs(multipliers(th)[1]) > 1e-6:          # not the grazing end of the family
                out.append((value(th), multipliers(th)[1]))
    return out


def specials(ds, kind):
    code = bifurc.storage.schema.SPECIAL_KINDS.index(kind)
    return [float(ds.special_value[i]) for i in range(ds.sizes["special"]) if int(ds.special_kind[i]) == code]


@pytest.mark.parametrize("zeta", [0.05, 0.0])
def test_fold_and_period_doubling_equal_the_closed_form(zeta):
    p = dict(BASE, zeta=zeta)
    value, mult = one_to_one_family(**{k: p[k] for k in ("w0", "zeta", "F", "Omega", "r", "e")}, free="e")
    th = np.linspace(0, 2 * math.pi, 4001)
    fold = fold_of(value, th, +1)
    pds = period_doublings_of(value, mult, th)
    pd = [e for e, v in pds if v < 0 and e < 0.2]          # an impact toward the stop, below e = 0.2
    assert len(pd) == 1
    up = bifurc.continue_orbit("impact-oscillator", "e", (0.2, 0.6), params=p, error=False)
    down = bifurc.continue_orbit("impact-oscillator", "e", (0.2, -0.2), params=p, error=False)
    folds, doublings = specials(up, "fold"), specials(down, "period_doubling")
    assert len(folds) == 1 and abs(folds[0] - fold) < 1e-8
    assert len(doublings) == 1 and abs(doublings[0] - pd[0]) < 1e-8
    # past the fold the branch is the unstable orbit: stable before it, unstable after
    i = int(up.special_point[0])
    assert bool(up.stable[i]) and not bool(up.stable[i + 1])
    assert float(up.special_multiplier_abs[0].max()) == pytest.approx(1.0, abs=1e-6)
    assert float(down.special_multiplier_arg[0, 0]) == pytest.approx(math.pi, abs=1e-6)
    assert float(down.special_tolerance[0]) < 1e-9


def test_branch_switching_at_the_period_doubling_gives_the_simulated_period_2_orbit():
    ds = bifurc.continue_orbit("impact-oscillator", "e", (0.2, -0.2), branch_switch=True, error=False,
                               max_points=60)
    doubled = ds.where(ds.branch_id == 1, drop=True)
    assert doubled.sizes["point"] >= 5 and set(doubled.period.values.astype(int)) == {2}
    for i in range(ds.sizes["special"]):      # every located point lies on its own branch's stretch
        on = ds.e.values[ds.branch_id.values == int(ds.special_branch[i])]
        if np.isfinite(float(ds.special_tolerance[i])):
            assert on.min() - 1e-3 <= float(ds.special_value[i]) <= on.max() + 1e-3     # a fold: just past
    stable = doubled.where((doubled.stable == 1) & (doubled.multiplier_abs.max("multiplier") < 0.9), drop=True)
    j = stable.sizes["point"] // 2
    e = float(stable.e[j])
    params = dict(BASE, e=e)
    system = maps.forced_oscillator_with_stop()
    smap = maps.StroboscopicMap(system, params, tol=1e-13)
    node = maps.HybridState(np.array([float(stable.x[j, 0]), float(stable.v[j, 0])]), {"stuck": 0.0})
    t0 = (int(stable.section_k0[j]) + float(stable.section_phase[j])) * smap.period     # node 0's time
    on_branch = smap.orbit(node, 2, t0=t0)
    assert on_branch.impact_velocity.size == 2 and abs(on_branch.impact_velocity[0] - on_branch.impact_velocity[1]) > 1e-3
    # started 1e-3 off the orbit, the simulation must settle onto it (another attractor coexists)
    simulated = smap.orbit({"x": float(stable.x[j, 0]) + 1e-3, "v": float(stable.v[j, 0]) - 1e-3}, 2,
                           transient=3000, t0=t0)
    np.testing.assert_allclose(np.sort(simulated.impact_velocity), np.sort(on_branch.impact_velocity), rtol=0,
                               atol=1e-9)


def test_grazing_of_the_non_impacting_orbit_and_the_hysteresis_fold():
    """Omega = 1.5, e = -0.05: the non-impacting orbit x_p (amplitude F / sqrt(D)) grazes at
    F_g = -e sqrt(D); the impacting 1:1 family folds at F_fold < F_g (both coexist between)."""
    p = dict(BASE, Omega=1.5, e=-0.05)
    D = (1 - 1.5 ** 2) ** 2 + (2 * 0.05 * 1.5) ** 2
    F_graze = 0.05 * math.sqrt(D)
    quiet = bifurc.continue_orbit("impact-oscillator", "F", (0.02, 0.3), params=p, x0={"x": 0.0}, error=False,
                                  max_points=600)
    grazes = specials(quiet, "grazing")
    assert len(grazes) == 1 and abs(grazes[0] - F_graze) < 1e-8
    g = int(quiet.special_point.values[0])
    assert int(quiet.impacts_per_period[:g + 1].max()) == 0
    assert abs(float(quiet.special_test_value[0])) < 1e-10
    value, mult = one_to_one_family(**{k: p[k] for k in ("w0", "zeta", "F", "Omega", "r", "e")}, free="F")
    F_fold = fold_of(value, np.linspace(0, 2 * math.pi, 4001), -1, mult)
    assert F_fold < F_graze
    # past the grazing the branch turns back (Nordmark's K < 0: the small impacting orbit lies on the
    # non-impacting side), along the unstable impacting orbits to their fold, then up the stable ones
    assert "no small impacting orbit beyond the grazing" in str(quiet.special_note.values[0])
    assert np.all(quiet.impacts_per_period[g + 1:] == 1) and float(quiet.F[g + 1]) < F_graze
    assert abs(specials(quiet, "fold")[0] - F_fold) < 1e-8 and float(quiet.F[-1]) >= 0.3
    loud = bifurc.continue_orbit("impact-oscillator", "F", (0.3, 0.0), params=dict(p, F=0.3), error=False)
    folds = specials(loud, "fold")
    assert len(folds) == 1 and abs(folds[0] - F_fold) < 1e-8
    # past the fold the unstable impacting orbit returns toward the grazing, its impact slowing to 0 until
    # the corrector stalls; the grazing is located there by the augmented system (from the orbit less that
    # impact), and the branch goes on along the non-impacting orbits
    assert "grazing" in loud.attrs["branch_stop_reasons"]
    g = specials(loud, "grazing")
    assert abs(g[0] - F_graze) < 1e-8 and "impacting side" in str(loud.special_note.values[1])
    i = int(loud.special_point.values[1])
    assert abs(float(loud.F[i]) - F_graze) < 1e-5 and int(loud.impacts_per_period[i]) == 1
    assert np.all(loud.impacts_per_period[i + 1:] == 0) and float(loud.F[-1]) < 0.01


def _negatively_damped_oscillator():
    def rhs(s):
        return [s.v, s.F * hy.cos(s.Omega * s.t) - 2 * s.zeta * s.w0 * s.v - s.w0 * s.w0 * s.x]
    system = HybridSystem("linear-oscillator", states=[State("x", "m", "position"), State("v", "m s-1", "velocity")],
                          parameters=[Parameter("w0", "rad s-1", "natural angular frequency", 0, 10, low_open=True),
                                      Parameter("zeta", "1", "damping ratio (negative: energy input)", -1, 1),
                                      Parameter("F", "m s-2", "forcing amplitude", 0, 10),
                                      Parameter("Omega", "rad s-1", "forcing frequency", 0, 10, low_open=True)],
                          rhs=rhs, strobe_period=lambda p: 2 * math.pi / p["Omega"])
    return system


def test_neimark_sacker_where_the_damping_changes_sign():
    """The forced linear oscillator's periodic response has multipliers exp((-zeta w0 +- i w0
    sqrt(1 - zeta^2)) T): a complex pair whose modulus exp(-zeta w0 T) crosses 1 at zeta = 0."""
    params = dict(w0=1.0, zeta=0.05, F=0.5, Omega=2.5)
    D = (1 - 2.5 ** 2) ** 2 + (2 * 0.05 * 2.5) ** 2
    a, b = 0.5 * (1 - 2.5 ** 2) / D, 0.5 * 2 * 0.05 * 2.5 / D
    ds = bifurc.continue_orbit(_negatively_damped_oscillator(), "zeta", (0.05, -0.05), params=params,
                               start=np.array([a, 2.5 * b]), k0=0, error=False)
    ns = specials(ds, "neimark_sacker")
    assert len(ns) == 1 and abs(ns[0]) < 1e-8
    T = 2 * math.pi / 2.5
    i = int(ds.special_point[0])
    assert float(ds.multiplier_abs[0, 0]) == pytest.approx(math.exp(-0.05 * T), rel=1e-9)
    assert bool(ds.stable[i]) and not bool(ds.stable[i + 1])


def test_two_parameter_neimark_sacker_curve_is_the_closed_form():
    """The Neimark-Sacker point of the negatively damped oscillator continued in (zeta, Omega): the pair
    exp((-zeta w0 +- i w0 sqrt(1 - zeta^2)) T) is on the unit circle exactly where zeta = 0, for every Omega."""
    params = dict(w0=1.0, zeta=0.05, F=0.5, Omega=2.5)
    D = (1 - 2.5 ** 2) ** 2 + (2 * 0.05 * 2.5) ** 2
    a, b = 0.5 * (1 - 2.5 ** 2) / D, 0.5 * 2 * 0.05 * 2.5 / D
    ds = bifurc.continue_orbit(_negatively_damped_oscillator(), "zeta", (0.05, -0.05), params=params,
                               start=np.array([a, 2.5 * b]), k0=0, error=False, param2="Omega", span2=(2.5, 2.0))
    assert [bifurc.storage.schema.SPECIAL_KINDS[int(k)] for k in ds.curve_kind.values] == ["neimark_sacker"]
    assert ds.curve_Omega.size >= 10 and float(ds.curve_Omega.min()) < 2.01      # measured: 18 points to 1.984
    assert float(np.max(np.abs(ds.curve_zeta.values))) < 1e-6                    # measured: 1.1e-12


def test_refusals_are_one_line_naming_the_parameter():
    with pytest.raises(ParameterError, match="relay_hz cannot be continued") as err:
        bifurc.continue_orbit("thesis-1dof", "relay_hz", (5, 6), preset="matlab-listing")
    assert "\n" not in str(err.value)
    with pytest.raises(ParameterError, match="unknown parameter .nope."):
        bifurc.continue_orbit("impact-oscillator", "nope", (0, 1))
    with pytest.raises(ParameterError, match="span"):
        bifurc.continue_orbit("impact-oscillator", "e", (0.2, 0.2))
    with pytest.raises(ParameterError, match="r"):
        bifurc.continue_orbit("impact-oscillator", "r", (0.7, 1.5))


def test_the_branch_dataset_round_trips_through_netcdf(tmp_path):
    import xarray as xr
    ds = bifurc.continue_orbit("impact-oscillator", "e", (0.2, -0.06), max_points=30)
    path = tmp_path / "branch.nc"
    bifurc.storage.files.write_netcdf(ds, path)
    back = xr.open_dataset(path).load()
    for name in ds.data_vars:
        assert name in back
        if ds[name].dtype.kind == "f":
            np.testing.assert_array_equal(back[name].values, ds[name].values)
        else:
            assert (back[name].values == ds[name].values).all()
        assert back[name].attrs.get("units") is not None and back[name].attrs.get("long_name")
    assert back.e.attrs["units"] == "m"
    assert back.attrs["Conventions"].startswith("CF")
    assert float(back.special_multiplier_error[0]) < 1e-8        # re-solved at tol/100


def test_continue_command_writes_the_branch_and_its_figure(tmp_path, capsys):
    from bifurc.cli import main
    out, fig = tmp_path / "branch.nc", tmp_path / "branch.png"
    code = main(["continue", "--scene", "impact-oscillator", "--param", "e", "--from", "0.2", "--to", "-0.06",
                 "--max-points", "40", "-o", str(out), "--plot", str(fig)])
    text = capsys.readouterr()
    assert code == 0 and out.exists() and fig.stat().st_size > 10_000
    assert "period_doubling at e = -0.03937025569" in text.out
    assert "main point: e =" in text.err                      # the progress line
    assert main(["continue", "--scene", "impact-oscillator", "--param", "e", "--from", "0.2", "--to", "0",
                 "-o", str(out)]) == 2                         # nothing overwritten without --force
    assert "--force" in capsys.readouterr().err
    assert main(["continue", "--scene", "thesis-1dof", "--param", "relay_hz", "--from", "5", "--to", "6"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "relay_hz cannot be continued" in err


def test_stable_intervals_of_a_branch():
    """The study's reading of a branch: runs of consecutive stable points with one (period, impacts),
    each end at the located bifurcation that bounds it where there is one."""
    import xarray as xr

    from studies.thesis_orbits import stable_intervals
    ds = xr.Dataset({"V": ("point", [1.0, 2.0, 3.0, 4.0, 5.0, 6.0]), "stable": ("point", [1, 1, 0, 1, 1, 1]),
                     "period": ("point", [1, 1, 1, 1, 1, 2]), "impacts_per_period": ("point", [1, 1, 1, 2, 2, 4])})
    assert stable_intervals(ds) == [(1.0, 2.0, 1, 1), (4.0, 5.0, 1, 2), (6.0, 6.0, 2, 4)]
    # located ends: the special point nearest to the run's end between it and the next point (a
    # fold may lie beyond both: the branch turns there); a bracket-only one (NaN tolerance), one
    # outside the bracket, one farther away: not ends
    kinds = bifurc.storage.schema.SPECIAL_KINDS
    sp = [("period_doubling", 2.4, 1e-9, 1), ("period_doubling", 2.8, 1e-9, 1), ("period_doubling", 9.0, 1e-9, 1),
          ("fold", 3.7, 1e-9, 2), ("impact_lost", 6.0, math.nan, 5)]
    ds = ds.assign(special_kind=("special", [kinds.index(k) for k, *_ in sp]),
                   special_value=("special", [v for _, v, _, _ in sp]),
                   special_tolerance=("special", [t for *_, t, _ in sp]),
                   special_point=("special", [i for *_, i in sp]))
    assert stable_intervals(ds, located=True) == [(1.0, 2.4, 1, 1, None, "period_doubling"),
                                                  (3.7, 5.0, 1, 2, "fold", None), (6.0, 6.0, 2, 4, None, None)]
    # two branches in one dataset: a run never spans them, nor takes the other's special points;
    # one recorded at a branch's last point lies beyond it (the located grazing that ended it)
    two = ds.assign(branch_id=("point", [0, 0, 0, 1, 1, 1]), stable=("point", [1, 1, 1, 1, 1, 1]),
                    impacts_per_period=("point", [1, 1, 1, 1, 1, 1]), period=("point", [1] * 6),
                    special_kind=("special", [kinds.index("grazing")]), special_value=("special", [3.2]),
                    special_tolerance=("special", [1e-9]), special_point=("special", [2]))
    assert stable_intervals(two, located=True) == [(1.0, 3.2, 1, 1, None, "grazing"), (4.0, 6.0, 1, 1, None, None)]
    # a branch through a period doubling, back at a fold and through it again: one stable run whose
    # ends both lie at the period doubling and whose V reaches down to the fold inside it
    turn = xr.Dataset({"V": ("point", [3.0, 2.0, 1.2, 1.5, 2.5, 3.5]), "stable": ("point", [0, 1, 1, 1, 1, 0]),
                       "period": ("point", [1] * 6), "impacts_per_period": ("point", [1] * 6),
                       "special_kind": ("special", [kinds.index(k) for k in ("period_doubling", "fold", "period_doubling")]),
                       "special_value": ("special", [2.6, 1.1, 2.6]), "special_tolerance": ("special", [1e-9] * 3),
                       "special_point": ("special", [0, 2, 4])})
    assert stable_intervals(turn, located=True) == [(1.1, 2.6, 1, 1, "fold", "period_doubling")]
    # a stable run that ends at a fold: the fold lies beyond its last point and the next one
    edge = turn.assign(stable=("point", [0, 0, 1, 0, 0, 0]), special_point=("special", [0, 1, 4]))
    assert stable_intervals(edge, located=True) == [(1.1, 1.2, 1, 1, "fold", None)]
    assert stable_intervals(turn) == [(1.2, 2.5, 1, 1)]


@pytest.mark.slow
def test_quick_thesis_orbits_study_writes_its_report(tmp_path):
    """`bifurc study thesis-orbits --quick`: under the measured law at 10 Hz the 6-impact period-1
    orbit from 90 V loses stability by period doubling near 98.36 V and folds near 84.59 V."""
    from bifurc.cli import main
    assert main(["study", "thesis-orbits", "--quick", "-o", str(tmp_path)]) == 0
    text = (tmp_path / "report.md").read_text()
    assert "## DC law `measured`, relay 10 Hz" in text and "## Where the thesis model hammers periodically" in text
    assert "period_doubling at V = 98.36" in text and "fold at V = 84.59" in text
    assert (tmp_path / "orbits_measured_10Hz.png").stat().st_size > 20_000
    assert main(["study", "thesis-orbits", "--quick", "-o", str(tmp_path)]) == 2     # not empty: refused


def test_two_parameter_fold_period_doubling_and_grazing_curves_equal_the_closed_form():
    """The fold of the 1:1 family in (e, r): at each r on the curve, the extremum of e(th) of the
    closed form; its period doubling in (e, r): the zero of det(P S + I) along the family; the
    grazing of the non-impacting orbit in (F, zeta): F = -e sqrt(D(zeta))."""
    ds = bifurc.continue_orbit("impact-oscillator", "e", (0.2, 0.6), param2="r", span2=(0.7, 0.9), error=False)
    kinds = [bifurc.storage.schema.SPECIAL_KINDS[int(k)] for k in ds.curve_kind.values]
    assert kinds == ["fold"]
    e, r = ds.curve_e.values, ds.curve_r.values
    assert e.size >= 10 and r.max() > 0.85
    th = np.linspace(0, 2 * math.pi, 4001)
    for i in (1, e.size // 2, e.size - 2):
        p = dict(BASE, r=float(r[i]))
        value, _ = one_to_one_family(**{k: p[k] for k in ("w0", "zeta", "F", "Omega", "r", "e")}, free="e")
        assert abs(e[i] - fold_of(value, th, +1)) < 1e-7
    pd = bifurc.continue_orbit("impact-oscillator", "e", (0.2, -0.2), param2="r", span2=(0.7, 0.8), error=False)
    # the period doubling is continued first; with numpy 2.4 / heyoka 7.13 the branch also locates the grazing of
    # the 1:1 orbit at e = -0.0951 (its slowest impact 4e-7) and continues it: checked here only for its kind
    kinds = [bifurc.storage.schema.SPECIAL_KINDS[int(k)] for k in pd.curve_kind.values]
    assert kinds[0] == "period_doubling" and set(kinds[1:]) <= {"grazing"}
    on = pd.curve_id.values == 0
    e, r = pd.curve_e.values[on], pd.curve_r.values[on]
    assert e.size >= 8 and r.max() > 0.79
    for i in (1, e.size // 2, e.size - 2):
        p = dict(BASE, r=float(r[i]))
        value, mult = one_to_one_family(**{k: p[k] for k in ("w0", "zeta", "F", "Omega", "r", "e")}, free="e")
        closed = [ee for ee, v in period_doublings_of(value, mult, th) if v < 0 and ee < 0.2]
        assert len(closed) == 1 and abs(e[i] - closed[0]) < 1e-7
    # no false codimension-two points: the 1:1 fold is the extremum of a sinusoid in the impact phase (never
    # degenerate: no cusp), and det(P S) = r^2 exp(-2 zeta w0 T) > 0 forbids +1 and -1 together (no fold-flip)
    codim2 = ds.attrs["curve_codim2"] + pd.attrs["curve_codim2"]
    assert "cusp" not in codim2 and "fold_flip" not in codim2
    p = dict(BASE, Omega=1.5, e=-0.05)
    g = bifurc.continue_orbit("impact-oscillator", "F", (0.02, 0.3), params=p, x0={"x": 0.0}, error=False,
                              param2="zeta", span2=(0.05, 0.3))
    # the branch passes the grazing and turns back to the impacting orbits' fold: both are continued
    assert [bifurc.storage.schema.SPECIAL_KINDS[int(k)] for k in g.curve_kind.values] == ["grazing", "fold"]
    on = g.curve_id.values == 0
    F, zeta = g.curve_F.values[on], g.curve_zeta.values[on]
    assert F.size >= 10 and zeta.max() > 0.25
    for i in (1, F.size // 2, F.size - 2):
        D = (1 - 1.5 ** 2) ** 2 + (2 * zeta[i] * 1.5) ** 2
        assert abs(F[i] - 0.05 * math.sqrt(D)) < 1e-7


def test_continue_command_with_a_second_parameter_writes_the_curves(tmp_path, capsys):
    import xarray as xr

    from bifurc.cli import main
    out, fig = tmp_path / "b.nc", tmp_path / "curves.png"
    assert main(["continue", "--scene", "impact-oscillator", "--param", "e", "--from", "0.2", "--to", "0.6",
                 "--param2", "r", "--from2", "0.7", "--to2", "0.8", "--no-error", "-o", str(out),
                 "--plot2", str(fig)]) == 0
    assert "curve 0 (fold" in capsys.readouterr().out and fig.stat().st_size > 10_000
    back = xr.open_dataset(out).load()
    assert back.curve_r.attrs["units"] == "1" and back.curve_e.attrs["units"] == "m"
    assert float(back.curve_r.max()) >= 0.8 and back.attrs["curve_parameters"] == "e r"
    assert main(["continue", "--scene", "impact-oscillator", "--param", "e", "--from", "0.2", "--to", "0.6",
                 "--param2", "r"]) == 2
    assert "--param2 needs --from2 and --to2" in capsys.readouterr().err


def test_an_impact_born_on_the_unstable_branch_is_a_grazing_located_by_the_augmented_system():
    """From e = 0.15 up through the fold, the unstable 1:1 orbit comes back down until its free
    flight touches the stop (a second impact is born).  Closed form: along the family, the flight's
    lowest point x_min(th) = e(th), x_min minimised over the exact linear flight."""
    p = dict(BASE)
    w0, z, F, Om, r = p["w0"], p["zeta"], p["F"], p["Omega"], p["r"]
    T = 2 * math.pi / Om
    Al = np.array([[0.0, 1.0], [-w0 * w0, -2 * z * w0]])
    D = (w0 * w0 - Om * Om) ** 2 + (2 * z * w0 * Om) ** 2
    a, b = F * (w0 * w0 - Om * Om) / D, F * 2 * z * w0 * Om / D

    def xp(t):
        return np.array([a * math.cos(Om * t) + b * math.sin(Om * t), Om * (-a * math.sin(Om * t) + b * math.cos(Om * t))])
    value, mult = one_to_one_family(w0, z, F, Om, r, 0.0, free="e")

    def clearance(th):
        e, v, ti = value(th), mult(th)[1], th / Om
        y0 = np.array([e, -r * v]) - xp(ti)
        x = lambda s: (expm(Al * s) @ y0 + xp(ti + s))[0]           # noqa: E731
        grid = np.linspace(0.05 * T, 0.95 * T, 61)
        k = int(np.argmin([x(s) for s in grid]))
        s = minimize_scalar(x, bounds=(grid[max(k - 1, 0)], grid[min(k + 1, 60)]), method="bounded",
                            options={"xatol": 1e-12}).x
        return x(s) - e
    ds = bifurc.continue_orbit("impact-oscillator", "e", (0.15, 0.6), error=False)
    grazes = specials(ds, "grazing")
    kinds = [bifurc.storage.schema.SPECIAL_KINDS[int(k)] for k in ds.special_kind.values]
    assert kinds[:2] == ["fold", "grazing"]         # the fold, then the grazing (then the 1:2 branch past it)
    i = int(ds.special_point.values[1])             # the unstable orbit just before the grazing
    assert int(ds.impacts_per_period[i]) == 1 and int(ds.impacts_per_period[i + 1]) == 2
    ths = np.linspace(0, 2 * math.pi, 401)
    near = [t for t in ths if mult(t)[1] < 0 and abs(value(t) - float(ds.e[i])) < 0.01
            and np.max(np.abs(mult(t)[0])) > 1]
    lo, hi = min(near) - 0.01, max(near) + 0.01
    assert clearance(lo) * clearance(hi) < 0
    th_g = brentq(clearance, lo, hi, xtol=1e-14)
    assert abs(grazes[0] - value(th_g)) < 1e-8


def test_a_thesis_grazing_is_located_at_the_integrations_noise_floor():
    """thesis-1dof (listing law, 5 Hz): the stable period-6 orbit with 7 impacts through V = 165 V
    (a state of the thesis-orbits study's sweep) is followed up in V until a free flight touches
    the stop.  The augmented Newton's residual there hovers at 1-3e-11 against a tol of 1e-11 (the
    integration's round-off), and the grazing was once reported as not located, with NaN
    multipliers.  Now it is located, and where the branch's own minimum flight clearance (from the
    plain runs' records of its last points) extrapolates linearly to zero: measured 1.3e-10 V apart."""
    from maps.hybrid import HybridState
    y = np.array([0.11657860100686679, -1.781064610968027, 0.0542832187049277, 5.6271235218329645])
    flags = {"P": 1.0, "contact": 0.0, "stuck_bar": 0.0, "escaped": 0.0}
    ds = bifurc.continue_orbit("thesis-1dof", "V", (165.0, 300.0), preset="matlab-listing", dc_law="listing",
                               params={"relay_hz": 5.0}, max_points=100, start=(HybridState(y, flags), 400),
                               period=6, error=False)
    code = bifurc.storage.schema.SPECIAL_KINDS.index("grazing")
    g = [k for k in range(ds.sizes["special"]) if int(ds.special_kind[k]) == code]
    assert len(g) == 1
    g = g[0]
    V_g, tol_g = float(ds.special_value.values[g]), float(ds.special_tolerance.values[g])
    assert 0 < tol_g < 1e-7
    assert np.all(np.isfinite(ds.special_multiplier_abs.values[g]))
    i = int(ds.special_point.values[g])
    V, c = ds.V.values, ds.min_flight_clearance.values
    assert 0 < c[i] < c[i - 1] < c[i - 2] < 1e-9       # the last points' flights come ever closer
    V_zero = V[i] - c[i] * (V[i] - V[i - 1]) / (c[i] - c[i - 1])
    assert abs(V_zero - V_g) < 1e-8


def test_a_branch_that_runs_into_sticking_says_so():
    """thesis-1dof, `measured` law, 10 Hz: the stable period-1 orbit with 3 impacts through 110 V
    (a state of the thesis-orbits study), followed up in V.  Its contact oscillation dies out ever
    closer to the end of the period, until the stick guard acts inside it: the map's signature
    gains a "stick" and its Jacobian loses rank, the corrector diverges there (it once stopped with
    "parameter 'V' = -2145.62 V is outside its allowed range").  The branch now stops with the
    reason, and a stick-onset special point.  Checked with plain map steps from the last point: no
    stick at its own V, a stick 2e-5 V beyond."""
    from maps.hybrid import HybridState
    y = np.array([-1.4455816835552885e-05, 0.0008837720418095785, -0.11244184337532166, 13.466893868895696])
    sc = maps.get_scene("thesis-1dof").with_options(dc_law="measured")
    flags = dict(sc.system.initial_flags(0.0, sc.parameters(preset="matlab-listing", relay_hz=10.0)), contact=1.0)
    ds = bifurc.continue_orbit("thesis-1dof", "V", (110.0, 300.0), preset="matlab-listing", dc_law="measured",
                               params={"relay_hz": 10.0}, max_points=100, start=(HybridState(y, flags), 400),
                               period=1, error=False)
    assert "sticking sets in" in ds.attrs["branch_stop_reasons"]
    code = bifurc.storage.schema.SPECIAL_KINDS.index("stick_onset")
    assert int(ds.special_kind.values[0]) == code
    last = int(ds.special_point.values[0])      # the last point before the stick; the branch goes on past it
    assert ds.sizes["point"] > last + 1 and ds.signature.values[last + 1] != ds.signature.values[last]
    V_last = float(ds.V.values[last])
    node = HybridState(np.array([float(ds[v].values[last, 0]) for v in ("x", "v", "i", "z")]),
                       {k[5:]: float(ds[k].values[last, 0]) for k in ds.data_vars if k.startswith("flag_")})
    roles = []
    for V in (V_last, V_last + 2e-5):
        smap = maps.StroboscopicMap(sc, sc.parameters(preset="matlab-listing", relay_hz=10.0, V=V), tol=1e-12)
        roles.append(smap.linearize(node, int(ds.section_k0.values[last])).signature)
    assert "stick" not in roles[0] and "stick" in roles[1]


def test_a_corrector_that_lands_on_another_branch_is_refused():
    """thesis-1dof, `measured` law, 10 Hz: the one-impact period-1 orbit a simulation reaches at
    96.63 V (benchmarks/continuation.py), followed up in V.  Near 101.61992 V the steps shrink to
    the smallest, and there Newton once converged on an orbit at rest at 243.9 V: compared with it,
    the branch was said to stop where "an impact is lost".  A correction that moves farther than its
    step is now refused, so the stop reads what the map does just past the last point.  Checked
    independently: the last point's impact is not slowing (8.5 mm/s: no impact is being lost), and
    plain map steps from its node show no stick at its own V and a stick 1e-5 V beyond."""
    from maps.hybrid import HybridState
    ds = bifurc.continue_orbit("thesis-1dof", "V", (96.63, 300.0), preset="matlab-listing", dc_law="measured",
                               params={"relay_hz": 10.0}, max_points=100, error=False)
    reason = ds.attrs["branch_stop_reasons"]
    assert "impact is lost" not in reason and "sticking sets in" in reason
    code = bifurc.storage.schema.SPECIAL_KINDS.index("stick_onset")
    assert int(ds.special_kind.values[0]) == code
    last = int(ds.special_point.values[0])      # the last point before the stick; the branch goes on past it
    assert ds.sizes["point"] > last + 1 and ds.signature.values[last + 1] != ds.signature.values[last]
    V_last = float(ds.V.values[last])
    assert abs(V_last - 101.61992) < 1e-4
    assert "predicted point" in str(ds.special_note.values[0])
    sc = maps.get_scene("thesis-1dof").with_options(dc_law="measured")
    node = HybridState(np.array([float(ds[v].values[last, 0]) for v in ("x", "v", "i", "z")]),
                       {k[5:]: float(ds[k].values[last, 0]) for k in ds.data_vars if k.startswith("flag_")})
    out = []
    for V in (V_last, V_last + 1e-5):
        smap = maps.StroboscopicMap(sc, sc.parameters(preset="matlab-listing", relay_hz=10.0, V=V), tol=1e-12)
        out.append(smap.linearize(node, int(ds.section_k0.values[last])))
    assert "stick" not in out[0].signature and "stick" in out[1].signature
    impacts = [ev.y_minus[1] for ev in out[0].events if ev.name == "contact"]
    assert len(impacts) == 1 and impacts[0] < -5e-3


def test_a_fold_that_newton_cannot_locate_at_a_period_doubling_birth_says_so():
    """Where a period-2m branch is born at a period doubling of a period-m orbit, the branch turns in
    the parameter (a fold: p - p_pd ~ a^2 in the amplitude a of the half-period difference) and meets
    the doubled period-m orbit there (a branch point, singular for Newton).  In the thesis-orbits
    study five such folds were bracketed with NaN multipliers and nothing else.  A bracket whose
    ends nearly repeat after m periods now says what it is.  Half-period mismatch by hand: nodes
    y_j and y_{j+m} differ by d in one component of size 1 (mismatch d), not at all elsewhere."""
    from types import SimpleNamespace

    from bifurc.orbits.continuation import BranchPoint, NoConvergence
    from bifurc.orbits.special_points import detect, half_period_mismatch

    def point(p, d, dp_ds, n=4):
        nodes = [maps.HybridState(np.array([1.0 + (d if j >= n // 2 else 0.0), 0.5 * (j % max(1, n // 2)) - 3.0]), {})
                 for j in range(n)]
        return BranchPoint(p, nodes, np.full(2, np.nan), [()] * n, [], np.zeros(3), np.array([0.0, 0.6, dp_ds]),
                           0, 0.0, [[]] * n)

    a, b = point(2.1, 0.01, 0.8), point(2.0, 0.003, -0.8)
    assert half_period_mismatch(a) == pytest.approx(0.01 / 1.01, rel=1e-12)
    assert half_period_mismatch(b) == pytest.approx(0.003 / 1.003, rel=1e-12)
    assert math.isnan(half_period_mismatch(point(2.0, 0.01, 0.8, n=3)))

    def fail(*args, **kw):
        raise NoConvergence("singular bordered Jacobian")
    class Section(SimpleNamespace):         # a map's sampling section, a value as maps.StroboscopicMap.at gives
        def at(self, params=None, *, phase=None):
            return Section(phase=self.phase if phase is None else phase)

    problem = SimpleNamespace(smap=Section(phase=0.0), k0=0, correct=fail)
    sp = detect(problem, a, b, "fold")
    assert sp.kind == "fold" and sp.point is None
    assert "born at a period doubling of a period-2 orbit" in sp.note and "0.0099" in sp.note
    # p = p* + c r^2 through both points (r the mismatch): p* = 2.1 - 0.1 r_a^2 / (r_a^2 - r_b^2)
    ra, rb = 0.01 / 1.01, 0.003 / 1.003
    birth = 2.1 - 0.1 * ra ** 2 / (ra ** 2 - rb ** 2)
    assert 1.98 < birth < 2.0 and sp.p == pytest.approx(birth, rel=1e-14)
    assert sp.tolerance == pytest.approx(2.0 - birth, rel=1e-12)
    far = detect(problem, point(2.0, 0.5, 0.8), point(2.1, 0.4, -0.8), "fold")     # far from repeating
    assert "location failed" in far.note and "period doubling" not in far.note
    assert far.p == pytest.approx(2.05) and far.tolerance == pytest.approx(0.1)      # the bracket


def test_an_impact_lost_is_extrapolated_where_its_speed_vanishes():
    """thesis-1dof (listing law, 5 Hz): the stable period-3 orbit with 3 impacts, followed down in V
    from 100.2076 V (a point of the thesis-orbits study's branch), loses its slowest impact near
    100.11027 V: its speed goes to zero like sqrt(V - V_lost) (a grazing from the impacting side).
    The branch's stop extrapolates the speed squared from its last two points.  Independently,
    Newton at fixed V 1, 2 and 4 uV above that value gives orbits whose slowest impact has v^2
    proportional to the distance; their linear fit vanishes within 1e-8 V of the extrapolated value,
    and 1 uV below it Newton's orbit has no slow impact left."""
    from maps.hybrid import HybridState
    y = np.array([0.1136715832167957, -1.9978129924308143, 0.033629308140196705, 3.358177157251365])
    flags = {"P": 1.0, "contact": 0.0, "stuck_bar": 0.0, "escaped": 0.0}
    ds = bifurc.continue_orbit("thesis-1dof", "V", (100.20762077889577, 25.0), preset="matlab-listing",
                               dc_law="listing", params={"relay_hz": 5.0}, max_points=60,
                               start=(HybridState(y, flags), 400), period=3, error=False)
    assert "an impact is lost" in ds.attrs["branch_stop_reasons"]
    assert bifurc.storage.schema.SPECIAL_KINDS[int(ds.special_kind.values[0])] == "impact_lost"
    V_lost, tol = float(ds.special_value[0]), float(ds.special_tolerance[0])
    assert 0 < tol < 1e-5 and abs(V_lost - 100.11027) < 1e-4
    sc = maps.get_scene("thesis-1dof").with_options(dc_law="listing")
    last = int(ds.special_point.values[0])     # the last point before the loss (the branch goes on past it)
    assert int(ds.impacts_per_period[last + 1]) < int(ds.impacts_per_period[last])
    k0 = int(ds.section_k0.values[last])
    node = HybridState(np.array([float(ds[v].values[last, 0]) for v in ("x", "v", "i", "z")]), flags)

    def slowest(dV):
        smap = maps.StroboscopicMap(sc, sc.parameters(preset="matlab-listing", relay_hz=5.0, V=V_lost + dV), tol=1e-12)
        orbit = bifurc.find_periodic_orbit(smap, node, 3, k0=k0)
        return min(abs(ev.y_minus[1]) for k in range(3) for ev in smap.linearize(orbit.nodes[k], k0 + k).events
                   if ev.name == "contact")
    dV = np.array([1e-6, 2e-6, 4e-6])
    v2 = np.array([slowest(d) ** 2 for d in dV])
    slope, intercept = np.polyfit(dV, v2, 1)
    assert np.max(np.abs(v2 - (slope * dV + intercept))) < 1e-3 * v2.max()      # linear in V
    assert abs(-intercept / slope) < 1e-8
    assert slowest(-1e-6) > 0.05


def test_a_corrector_node_takes_the_flags_its_state_implies():
    """A node moved deep into the stop keeps its previous point's DC region flags (region 5): the node is given
    the region containing its xa and contact; its step then ends in Escaped (beyond the model's domain, 20 mm
    into the stop) instead of integrating region 5's cubic far outside its region (one heyoka step for minutes)."""
    from bifurc.orbits.continuation import ContinuationProblem
    from maps.hybrid import Escaped, HybridState
    from maps.model import STOP_ESCAPE, _region_flags, measured_dc_regions
    from maps.poincare import StroboscopicMap
    pb = maps.problem("thesis-1dof", "matlab-listing", {"relay_hz": 10.0, "V": 155.0}, dc_law="measured")
    smap = StroboscopicMap(pb, tol=1e-10)
    cp = ContinuationProblem(smap, "V", 4, 36, scale=np.ones(4), p_scale=7.5, p_ref=155.0)
    y = np.array([-0.02863546412288712, 1.7867193968824058, -0.10546384861207692, 24.07249126862597])
    stale = dict(P=1.0, contact=0.0, stuck_bar=0.0, escaped=0.0, **_region_flags(5))
    fixed = cp.consistent(HybridState(y, stale))
    xa = y[0] - smap.params["d_dc"]
    lows = [r[0] for r in measured_dc_regions()]
    region = max(k for k, lo in enumerate(lows) if lo <= xa)
    assert xa < -0.029 and region == 0 and fixed.flags["dc_region"] == float(region)
    assert fixed.flags["dc_lo"] <= xa <= fixed.flags["dc_hi"]
    assert fixed.flags["contact"] == 1.0          # inside the stop (e = 0)
    assert y[0] - smap.params["e"] < -STOP_ESCAPE  # beyond the model's domain: the step escapes
    with pytest.raises(Escaped):
        smap.linearize(fixed, 36, params=("V",))
    same = cp.consistent(fixed)
    assert same is fixed                          # consistent flags: the node as it is
