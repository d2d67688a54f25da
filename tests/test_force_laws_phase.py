"""`bifurc params --plot` (the force laws of Figs 4.5, 4.6, 4.10-4.12, 4.26) and `ds.bifurc.phase()`: the
plotted data against formulas typed here from the thesis and against closed-form motion."""
import math

import matplotlib
import numpy as np
import pytest

import maps
from bifurc.cli import main
from bifurc.plots.laws import law_curves
from maps.problem import problem
from maps.thesis_data import load_table

matplotlib.use("Agg")


@pytest.fixture(scope="module")
def curves():
    return law_curves("thesis-1dof", "matlab-listing", t_end=0.05)


def test_dc_curves_are_the_laws_typed_from_the_thesis(curves):
    xa = curves["xa"]
    # listing C.9 as printed: -15.38 xa + 1.652e-14 xa^2 - 1.473e5 xa^3 (dc_scale 1 in matlab-listing)
    listing = -15.38 * xa + 1.652e-14 * xa ** 2 - 1.473e5 * xa ** 3
    assert curves["F_dc"]["listing"] == pytest.approx(listing, abs=1e-9)
    # catalogue: -F_sat/2 [tanh((xa - u)/(2 s)) + tanh((xa + u)/(2 s))] with the law's own values
    v = dict(problem("thesis-1dof", "matlab-listing", None, dc_law="catalogue").values)
    F, u, s = v["F_dc_sat"], v["u_dc"], v["s_dc"]
    cat = -0.5 * F * (np.tanh((xa - u) / (2 * s)) + np.tanh((xa + u) / (2 * s))) * v["dc_scale"]
    assert curves["F_dc"]["catalogue"] == pytest.approx(cat, abs=1e-12)
    # measured: through Table 4.1's points (a pull toward the centre: +T at xa = -|x|), zero beyond 29 mm
    t41 = load_table("dc_force")
    got = np.interp(-t41["x_a_m"][::-1], xa, curves["F_dc"]["measured"])[::-1]
    inside = t41["x_a_m"] < 0.0285
    assert got[inside] == pytest.approx(t41["force_N"][inside], abs=0.02)    # the grid's 0.2 mm spacing
    assert np.all(curves["F_dc"]["measured"][np.abs(xa) > 0.0295] == 0.0)


def test_inductance_curves_are_eq_4_13(curves):
    xb = curves["xb"]
    L0, A, B = 0.48, 0.048, 0.039                       # eq 4.13 / listing C.11
    L = L0 + A / B * math.sqrt(2 / math.pi) * np.exp(-2 * (xb / B) ** 2)
    dL = A / B * math.sqrt(2 / math.pi) * np.exp(-2 * (xb / B) ** 2) * (-4 * xb / B ** 2)
    assert curves["L"] == pytest.approx(L, abs=2e-4)               # integrated from the model's dL/dx
    assert curves["dL"] == pytest.approx(dL, abs=2e-3 * np.max(np.abs(dL)))
    ddL = np.gradient(dL, xb)
    assert curves["ddL"][5:-5] == pytest.approx(ddL[5:-5], abs=0.02 * np.max(np.abs(ddL)))
    assert np.isfinite(curves["F_ac"]).all() and curves["t"][-1] == pytest.approx(0.05)


def test_params_plot_writes_the_figure_and_refuses_to_overwrite(tmp_path, capsys):
    out = tmp_path / "laws.png"
    assert main(["params", "--scene", "thesis-1dof", "--preset", "matlab-listing", "--plot", str(out)]) == 0
    assert out.stat().st_size > 20_000 and "wrote" in capsys.readouterr().out
    assert main(["params", "--scene", "thesis-1dof", "--plot", str(out)]) == 2
    assert "bifurc: error:" in capsys.readouterr().err
    assert main(["params", "--scene", "impact-oscillator", "--plot", str(tmp_path / "none.png")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "has no solenoid force law" in err[0] and not (tmp_path / "none.png").exists()


def test_phase_portrait_of_a_free_oscillator_is_its_ellipse():
    """impact-oscillator with no damping, forcing or stop in reach: x = 0.5 cos t, v = -0.5 sin t (w0 = 1)."""
    ds = maps.simulate("impact-oscillator", t_end=7.0, dt=0.01, params={"zeta": 0.0, "F": 0.0, "e": -10.0},
                       x0={"x": 0.5, "v": 0.0})
    ax = ds.bifurc.phase(t_from=1.0)
    pos, vel = ax.lines[0].get_data()
    sel = ds.sel(t=slice(1.0, None))
    assert np.array_equal(pos, 1e3 * sel.x.values) and np.array_equal(vel, sel.v.values)
    assert (pos / 1e3) ** 2 + vel ** 2 == pytest.approx(0.25, abs=1e-9)    # the closed-form ellipse
    with pytest.raises(maps.ParameterError, match="positions: x"):
        ds.bifurc.phase(x="q")


def test_phase_portrait_of_a_2dof_run_draws_the_relative_motion(tmp_path):
    ds = maps.simulate("thesis-2dof", periods=3, params={"V": 90.0})
    ax = ds.bifurc.phase(x="r", path=tmp_path / "phase.png")
    pos, vel = ax.lines[0].get_data()
    assert np.allclose(pos, 1e3 * (ds.x1 - ds.x2).values) and np.allclose(vel, (ds.v1 - ds.v2).values)
    assert (tmp_path / "phase.png").stat().st_size > 10_000
