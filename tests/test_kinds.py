"""Every dataset kind the toolkit writes records it (attrs["bifurc_kind"]), keeps it through netCDF,
and has a report (and a figure, except the stability suite) through ds.bifurc; older files without
the attribute are recognised by their variables (a branch is never an orbit) and read with the
current variable names."""
import warnings

import matplotlib
import matplotlib.pyplot as plt
import numpy as np
import pytest

import bifurc
import maps
from bifurc.storage.files import BadFileError, write_netcdf
from bifurc.storage.load import RENAMED, kind_of

DIAGRAM = dict(preset="matlab-listing", params={"V": 90}, transient=10, record=6, progress=False, workers=1)


def _diagram():
    return bifurc.sweep("thesis-1dof", "relay_hz", np.array([5.0, 7.0, 9.0]), error_sample=1, **DIAGRAM)


def _map():
    return bifurc.regime_map("thesis-1dof", "relay_hz", [5.0, 7.0], "V", [80.0, 90.0], error_sample=0,
                             **{k: v for k, v in DIAGRAM.items() if k != "params"})


def _orbit():   # the default start (x0 = 0 at rest) lands on a degenerate first guess: a short transient first
    return bifurc.periodic_orbit("impact-oscillator", x0={"x": 0.0}, transient=20)


def _accuracy():
    from bifurc.verification.accuracy import work_precision
    return work_precision("thesis-1dof", 0.2, ladders={"heyoka": [1e-6, 1e-9], "rk4-bisection": [3e-4]}, repeats=1,
                          preset="matlab-listing", params={"V": 90.0, "relay_hz": 9.0})


def _stability():
    from bifurc.verification.suite import run_suite
    return run_suite(quick=True, names=["stiff-k1e+05-c0"], progress=False)


BUILD = {"diagram": _diagram, "map": _map, "history": lambda: maps.simulate("impact-oscillator", periods=3),
         "orbit": _orbit, "branch": lambda: bifurc.continue_orbit("impact-oscillator", "e", (0.2, 0.1), max_points=10),
         "accuracy": _accuracy, "stability": _stability,
         "attractors": lambda: bifurc.attractors("impact-oscillator", "Omega", [1.3], n_starts=4, progress=False,
                                                 params=dict(F=0.3, e=-1.0, r=0.8, Omega=1.3), link=False)}


@pytest.fixture(scope="module")
def datasets():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return {kind: build() for kind, build in BUILD.items()}


@pytest.mark.parametrize("kind", list(BUILD))
def test_every_kind_records_itself_and_keeps_it_through_netcdf(datasets, kind, tmp_path):
    ds = datasets[kind]
    assert ds.attrs["bifurc_kind"] == kind and ds.bifurc.kind == kind == kind_of(ds)
    path = write_netcdf(ds, tmp_path / f"{kind}.nc")
    back = bifurc.load(path, kind=kind)
    assert back.attrs["bifurc_kind"] == kind and back.bifurc.kind == kind
    other = "orbit" if kind != "orbit" else "branch"
    with pytest.raises(BadFileError, match=f"holds an? {kind} dataset"):
        bifurc.load(path, kind=other)


@pytest.mark.parametrize("kind", list(BUILD))
def test_every_kind_has_a_markdown_report_naming_it(datasets, kind):
    text = datasets[kind].bifurc.report()
    assert text.startswith("# ") and f"({kind})" in text.splitlines()[0] and len(text.splitlines()) > 2
    assert text._repr_markdown_() == str(text)


@pytest.mark.parametrize("kind", [k for k in BUILD if k != "stability"])
def test_every_kind_but_the_suite_has_a_figure(datasets, kind):
    out = datasets[kind].bifurc.plot()
    axes = [out] if isinstance(out, matplotlib.axes.Axes) else list(np.ravel(out))
    assert all(isinstance(a, matplotlib.axes.Axes) for a in axes)
    assert any(a.lines or a.collections or a.patches or a.images for a in axes)
    plt.close(axes[0].figure)
    fig, ax = plt.subplots()
    if kind in ("orbit", "branch", "history", "accuracy"):       # ax= draws there and returns it
        assert datasets[kind].bifurc.plot(ax=ax) is ax and ax.lines
    plt.close("all")


def test_the_suite_has_no_figure_and_says_which_kinds_do(datasets):
    with pytest.raises(maps.ParameterError, match="no figure for a stability dataset.*orbit, branch"):
        datasets["stability"].bifurc.plot()


def test_orbit_figure_marks_impacts_and_multipliers_and_saves(datasets, tmp_path):
    ds = datasets["orbit"]
    fig, pair = plt.subplots(1, 2)
    assert bifurc.plot_orbit(ds, ax=tuple(pair)) is pair[0]
    assert any(line.get_marker() == "x" for line in pair[0].lines) == bool(int(ds.impacts_per_period))
    assert len(pair[1].lines[1].get_xdata()) == ds.sizes["multiplier"]      # circle, then the multipliers
    plt.close(fig)
    bifurc.plot_orbit(ds, path=tmp_path / "orbit.png")
    assert (tmp_path / "orbit.png").stat().st_size > 1000


def test_a_branch_file_without_the_attribute_is_a_branch_not_an_orbit(datasets, tmp_path):
    """Files written before bifurc_kind: a continue_orbit result (point x node x multiplier) was read as
    an orbit, accepted by load(kind="orbit"), and ds.bifurc.plot() raised "no figure for a orbit dataset"."""
    old = datasets["branch"].copy()
    del old.attrs["bifurc_kind"]
    path = write_netcdf(old, tmp_path / "old-branch.nc")
    with pytest.raises(BadFileError, match="holds a branch dataset"):
        bifurc.load(path, kind="orbit")
    ds = bifurc.load(path, kind="branch")
    assert ds.bifurc.kind == "branch" and "(branch)" in ds.bifurc.report()
    ax = ds.bifurc.plot()
    assert ax.lines
    plt.close(ax.figure)
    orbit = datasets["orbit"].copy()
    del orbit.attrs["bifurc_kind"]
    assert kind_of(orbit) == "orbit"


def test_simulate_is_still_accepted_for_a_time_history(datasets, tmp_path):
    old = datasets["history"].copy()
    del old.attrs["bifurc_kind"]
    path = write_netcdf(old, tmp_path / "old-history.nc")
    ds = bifurc.load(path, kind="simulate")
    assert ds.bifurc.kind == "history"
    with pytest.raises(maps.ParameterError, match="needs a diagram dataset.*this is a history dataset"):
        ds.bifurc.table()


def test_old_variable_names_are_read_as_the_new_ones(datasets, tmp_path):
    new = datasets["diagram"]
    old = new.rename({v: k for k, v in RENAMED.items() if v in new.variables})
    assert "min_gap" in old and "impact_t" in old and "min_clearance" not in old
    del old.attrs["bifurc_kind"]
    ds = bifurc.load(write_netcdf(old, tmp_path / "old.nc"), kind="diagram")
    for name in ("min_clearance", "min_flight_clearance", "min_clearance_per_step", "impact_time"):
        np.testing.assert_array_equal(ds[name].values, new[name].values)
    assert "min_gap" not in ds and "impact_t" not in ds
    assert "min_clearance" in ds.bifurc.table() and "Orbits flagged grazing" in ds.bifurc.report()
    np.testing.assert_array_equal(ds.grazing_flag.values, new.grazing_flag.values)


def test_datasets_are_built_by_one_builder_that_refuses_an_unknown_kind():
    from bifurc.storage.build import KINDS, dataset
    assert set(KINDS) == set(BUILD)
    with pytest.raises(ValueError, match="allowed: diagram"):
        dataset("simulate")
    with pytest.raises(ValueError, match="allowed"):
        bifurc.load(__file__, kind="nope")
