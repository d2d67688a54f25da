"""The census over two parameters: a list of parameter points on the one grid driver, resumed from the one store.

Truths: each point's fresh starts are followed independently, so a point's basin fractions (fresh starts only) are
those of a census at that point alone; the dataset of a run interrupted and resumed on two workers is the one of a
run in one go; the grid's points are followed in a snake (each step changes one parameter).
"""
import numpy as np
import pytest
import xarray as xr

import bifurc
import maps
from bifurc.attractors.atlas import follow_order, grid_points

OSC = dict(w0=1.0, zeta=0.05, F=0.3, Omega=1.3, e=-1.0, r=0.8)
BOX = {"x": (-1.0, 2.0), "v": (-2.0, 2.0)}
KW = dict(params=OSC, box=BOX, n_starts=12, seed=5, progress=False)
OMEGA, R = [1.25, 1.35], [0.7, 0.8, 0.9]


def _sorted_fractions(ds, **at):
    f = ds.basin_fraction.sel(**at).values
    return np.sort(f[f > 0])


@pytest.fixture(scope="module")
def grid_census():
    return bifurc.attractors("impact-oscillator", None, grid_points("Omega", OMEGA, "r", R), workers=1, **KW)


def test_a_grid_census_has_both_dimensions_and_each_point_equals_its_own_census(grid_census):
    ds = grid_census
    assert ds.basin_fraction.dims == ("Omega", "r", "attractor")
    np.testing.assert_array_equal(ds.Omega.values, OMEGA)
    np.testing.assert_array_equal(ds.r.values, R)
    assert ds.attrs["swept_parameter2"] == "r"
    np.testing.assert_allclose(ds.basin_fraction.sum("attractor").values, 1.0, rtol=0, atol=1e-12)
    for om in OMEGA:
        for r in R:
            alone = bifurc.attractors("impact-oscillator", "Omega", [om], workers=1,
                                      **dict(KW, params=dict(OSC, r=r)))
            np.testing.assert_array_equal(_sorted_fractions(ds, Omega=om, r=r), _sorted_fractions(alone, Omega=om))


def test_a_grid_census_interrupted_and_resumed_on_two_workers_equals_one_go(tmp_path, monkeypatch):
    from bifurc.run.parts import Parts
    points = grid_points("Omega", OMEGA, "r", R)
    whole = bifurc.attractors("impact-oscillator", None, points, workers=2, **KW)
    path = tmp_path / "grid.nc"
    save = Parts.save

    def save_then_stop(self, branch, indices, results):
        save(self, branch, indices, results)
        if len(list(self.dir.glob("census-*.nc"))) >= 2:
            raise KeyboardInterrupt
    monkeypatch.setattr(Parts, "save", save_then_stop)
    with pytest.raises(KeyboardInterrupt):
        bifurc.attractors("impact-oscillator", None, points, workers=1, path=path, **KW)
    assert not path.exists() and len(list((tmp_path / "grid.nc.parts").glob("census-*.nc"))) == 2
    monkeypatch.setattr(Parts, "save", save)
    again = bifurc.attractors("impact-oscillator", None, points, run=bifurc.Run(workers=2, path=path, progress=False),
                              params=OSC, box=BOX, n_starts=12, seed=5)
    assert again.attrs["values_resumed"] == 2 and again.attrs["workers"] == 2
    xr.testing.assert_equal(whole, again)
    xr.testing.assert_equal(whole, xr.load_dataset(path))


def test_the_grid_is_followed_in_a_snake_and_a_curve_as_given():
    pts = grid_points("a", [0, 1, 2], "b", [0, 1])
    order = follow_order(("a", "b"), pts)
    steps = [sum(pts[i][k] != pts[j][k] for k in "ab") for i, j in zip(order, order[1:])]
    assert sorted(order) == list(range(6)) and steps == [1] * 5
    curve = [{"a": 0.0, "b": 1.0}, {"a": 2.0, "b": 0.0}, {"a": 1.0, "b": 1.0}]
    assert follow_order(("a", "b"), curve) == [0, 1, 2]


def test_points_with_different_names_and_an_unknown_option_are_one_line_each():
    with pytest.raises(maps.ParameterError, match="every point names the same parameters"):
        bifurc.attractors("impact-oscillator", None, [{"Omega": 1.3}, {"r": 0.8}], **KW)
    with pytest.raises(maps.ParameterError, match="unknown option 'cels'.*valid:.*cells"):
        bifurc.attractors("impact-oscillator", "Omega", [1.3], cels=10, **KW)
    with pytest.raises(maps.ParameterError, match="'max_periods' is now budget"):
        bifurc.attractors("impact-oscillator", "Omega", [1.3], max_periods=10, **KW)
    with pytest.raises(maps.ParameterError, match="seed.* = -1 is outside"):
        bifurc.attractors("impact-oscillator", "Omega", [1.3], **dict(KW, seed=-1))


def test_the_figure_of_a_grid_census_shows_the_largest_basin_of_each_cell_and_each_fraction_map(grid_census):
    """``ds.bifurc.plot()`` of a two-parameter census: the first panel colours each cell by the attractor whose
    basin fraction is largest there (the colour index of each cell against the argmax computed here), one panel per
    attractor with a basin."""
    ds = grid_census
    fig = ds.bifurc.plot()
    frac = ds.basin_fraction.transpose("Omega", "r", "attractor").values
    present = [j for j in range(frac.shape[2]) if frac[..., j].max() > 0]
    assert len(fig.axes) - sum(a.get_label() == "<colorbar>" for a in fig.axes) == 1 + len(present)
    shown = fig.axes[0].collections[0].get_array().reshape(len(OMEGA), len(R))
    np.testing.assert_array_equal(shown, [[present.index(j) for j in row] for row in frac.argmax(axis=2)])
