"""Work-precision study: errors fall with the tolerance, the reference is trustworthy."""
import numpy as np
import pytest
import xarray as xr

from bifurc.verification.accuracy import reference_solution, work_precision
from bifurc.verification.baselines import solve_rk4_bisection, solve_scipy

SETUP = dict(preset="matlab-listing", params={"V": 90.0, "relay_hz": 9.0})
T_END = 1.0     # two contacts (0.85 s and 0.97 s)


@pytest.fixture(scope="module")
def study():
    ladders = {"heyoka": [1e-6, 1e-9, 1e-12, 1e-15], "heyoka-transient": [1e-9, 1e-15], "scipy-DOP853": [1e-6, 1e-9],
               "rk4-bisection": [3e-4, 1e-4]}
    return work_precision("thesis-1dof", T_END, ladders=ladders, repeats=1, **SETUP)


def _method(ds, name):
    return ds.where(ds["method"] == name, drop=True)


def test_reference_bound_and_impacts(study):
    # the long-double reference moves by less than 1e-14 when its tolerance is loosened 100x
    assert study.attrs["reference_error_bound"] < 1e-14
    assert study.attrs["reference_n_impacts"] == 2
    assert (study["n_impacts"].values == 2).all()


@pytest.mark.parametrize("method", ["heyoka", "heyoka-transient"])
def test_tight_double_run_agrees_with_reference(study, method):
    """Both toolkit runs (with and without the stops at turning points) against long double."""
    h = _method(study, method)
    tight = h.where(h["tol"] == 1e-15, drop=True)
    # double round-off over ~500 steps bounds the agreement; the reference is 100x better
    assert float(tight["final_state_error"].item()) < 1e-12
    assert float(tight["impact_time_error"].item()) < 1e-13


@pytest.mark.parametrize("method", ["heyoka", "scipy-DOP853", "rk4-bisection"])
def test_error_decreases_with_tolerance(study, method):
    sel = _method(study, method).sortby("tol", ascending=False)
    err = sel["final_state_error"].values
    assert np.all(np.diff(err) < 0), err
    terr = sel["impact_time_error"].values
    assert np.all(np.diff(terr) < 0), terr


def test_errors_normalised_by_tolerance(study):
    h = _method(study, "heyoka")
    loose = h.where(h["tol"] >= 1e-12, drop=True)
    assert np.all(loose["final_state_error"].values / loose["tol"].values < 20)
    d = _method(study, "scipy-DOP853")
    assert np.all(d["final_state_error"].values / d["tol"].values < 200)
    rk = _method(study, "rk4-bisection").sortby("tol")
    e_fine, e_coarse = rk["final_state_error"].values
    # RK4 is fourth order: 3x smaller step gives ~81x smaller error; demand at least 3rd order
    assert e_coarse / e_fine > 3 ** 3


def test_baselines_agree_with_each_other_independently():
    """The numpy RHS (written separately from the heyoka model) and two integrators agree."""
    import maps
    sc = maps.get_scene("thesis-1dof")
    p = sc.parameters(**{k: v for k, v in SETUP["params"].items()}, preset=SETUP["preset"])
    y0 = sc.system.state_vector(sc.initial_state())
    a = solve_scipy(p, y0, T_END, "DOP853", 1e-12)
    b = solve_rk4_bisection(p, y0, T_END, h=5e-5)
    ref = reference_solution("thesis-1dof", T_END, **SETUP)
    yref = np.array(ref["y"], dtype=float)
    assert np.max(np.abs(a.y - yref) / np.maximum(1, abs(yref))) < 1e-10
    assert np.max(np.abs(b.y - yref) / np.maximum(1, abs(yref))) < 1e-7
    assert a.n_impacts == b.n_impacts == ref["impact_times"].size


def test_command_writes_csv_netcdf_and_figure(tmp_path, capsys):
    from bifurc.commands.accuracy import main
    rc = main(["--preset", "matlab-listing", "--set", "V=90", "--set", "relay_hz=9", "--t-end", "0.3",
               "--methods", "heyoka,scipy-DOP853", "--tols", "1e-6,1e-9", "-o", str(tmp_path)])
    assert rc == 0
    ds = xr.open_dataset(tmp_path / "accuracy.nc")
    assert ds["run_seconds"].attrs["units"] == "s" and "long_name" in ds["final_state_error"].attrs
    assert ds.sizes["run"] == 4
    assert (tmp_path / "accuracy.csv").read_text().count("\n") == 5
    assert (tmp_path / "accuracy.png").stat().st_size > 10_000


def test_command_bad_input_is_one_line_error(tmp_path, capsys):
    from bifurc.commands.accuracy import main
    assert main(["--set", "V=-5", "-o", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("bifurc: error:") and "'V'" in err and err.count("\n") == 1
    # an option the scipy/RK4 baselines do not implement is refused before any run, naming it
    for args, named in ((["--dc-law", "measured"], "dc_law='measured'"), (["--set", "c_air=0.1"], "air_damping=True")):
        assert main(args + ["-o", str(tmp_path / "x")]) == 2
        err = capsys.readouterr().err
        assert err.startswith("bifurc: error:") and named in err and err.count("\n") == 1


@pytest.mark.slow
def test_longdouble_reference_matches_real128():
    ld = reference_solution("thesis-1dof", T_END, precision="longdouble", **SETUP)
    q = reference_solution("thesis-1dof", T_END, precision="real128", **SETUP)
    diff = np.abs(np.asarray(ld["y"], np.longdouble) - np.asarray(q["y"], np.longdouble))
    assert float(np.max(diff / np.maximum(1, np.abs(np.asarray(q["y"], np.longdouble))))) < 1e-15
