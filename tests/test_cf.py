"""CF: every units string is UDUNITS-valid (checked by cf-units), every file carries Conventions,
history (time, command line or API call, version, commit) and source, and every file kind passes
the IOOS compliance checker's cf:1.10 suite with no message at all (errors or warnings)."""
import cf_units
import numpy as np
import pytest
import xarray as xr

import bifurc
import maps
from bifurc.cli import main
from maps.provenance import git_commit

COMMANDS = {
    "simulate.nc": ["simulate", "--preset", "matlab-listing", "--set", "V=90", "--relay-hz", "9", "--t-end", "1",
                    "--dt", "1e-3", "-o", "{dir}/simulate.nc"],
    "diagram.nc": ["diagram", "--preset", "matlab-listing", "--set", "V=90", "--from", "5", "--to", "9", "--n", "3",
                   "--transient", "10", "--record", "6", "--quiet", "-o", "{dir}/diagram.nc"],
    "verify/stability.nc": ["verify", "--case", "stiff-k1e+05-c0", "-o", "{dir}/verify"],
    "orbit.nc": ["orbit", "--preset", "matlab-listing", "--set", "V=90", "--relay-hz", "8.5", "--tol", "1e-10",
                 "--no-error", "-o", "{dir}/orbit.nc"],
    "map.nc": ["map", "--preset", "matlab-listing", "--from", "5", "--to", "9", "--n", "2", "--from2", "80", "--to2",
               "90", "--n2", "2", "--transient", "10", "--record", "6", "--quiet", "-o", "{dir}/map.nc"],
    # a sweep and a branch in V beside the state v: names differing only by case (CF 2.3)
    "diagram_V.nc": ["diagram", "--preset", "matlab-listing", "--relay-hz", "9", "--param", "V", "--from", "80", "--to",
                     "90", "--n", "2", "--transient", "10", "--record", "6", "--quiet", "-o", "{dir}/diagram_V.nc"],
    "branch.nc": ["continue", "--preset", "matlab-listing", "--dc-law", "measured", "--relay-hz", "10", "--param", "V",
                  "--from", "90", "--to", "92", "-o", "{dir}/branch.nc"],
    "accuracy/accuracy.nc": ["accuracy", "--preset", "matlab-listing", "--set", "V=90", "--relay-hz", "9",
                             "--t-end", "0.2", "--methods", "heyoka,rk4-bisection", "--tols", "1e-8",
                             "--steps", "1e-3", "-o", "{dir}/accuracy"],
}


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    d = tmp_path_factory.mktemp("cf")
    out = {}
    for name, argv in COMMANDS.items():
        argv = [a.replace("{dir}", str(d)) for a in argv]
        assert main(argv) == 0, argv
        out[name] = (argv, bifurc.load(d / name))
    out["dir"] = d
    return out


def _files(written):
    return {name: v for name, v in written.items() if name != "dir"}


@pytest.mark.filterwarnings("ignore::DeprecationWarning")
def test_every_file_kind_passes_the_cf_1_10_compliance_checker(written):
    runner = pytest.importorskip("compliance_checker.runner")
    suite = runner.CheckSuite()
    suite.load_all_available_checkers()
    kinds = set()
    for name, (_, ds) in _files(written).items():
        kinds.add(ds.attrs["bifurc_kind"])
        results, errors = suite.run_all(suite.load_dataset(str(written["dir"] / name)), ["cf:1.10"], skip_checks=[])["cf:1.10"]
        assert not errors, (name, errors)
        assert not [(r.name, r.msgs) for r in results if r.msgs], name
        assert ds.attrs["title"], name
    assert kinds == {"diagram", "map", "history", "orbit", "branch", "accuracy", "stability"}


def test_a_parameter_beside_a_state_of_the_same_letter_is_stored_apart_and_loaded_back(written):
    for name in ("diagram_V.nc", "branch.nc"):
        loaded = written[name][1]
        assert {"V", "v"} <= set(loaded.variables) and "V_parameter" not in loaded.variables
        assert "bifurc_name" not in loaded["V"].attrs and loaded["V"].attrs["units"] == "V"
        with xr.open_dataset(written["dir"] / name) as raw:   # as another netCDF tool sees the file
            assert "V" not in raw.variables and raw["V_parameter"].attrs["bifurc_name"] == "V"
            np.testing.assert_array_equal(raw["V_parameter"].values, loaded["V"].values)
    assert written["diagram_V.nc"][1]["V"].values.tolist() == [80.0, 90.0]


def test_a_time_history_reads_as_float_seconds_in_plain_xarray(written):
    """Its elapsed time is a plain coordinate ``t`` in seconds: no epoch (xarray would decode dates) and not named
    ``time`` (CF checkers take that name for a CF time axis); the checker above passes it without exemption."""
    path = written["dir"] / "simulate.nc"
    with xr.open_dataset(path) as raw:   # as any user opens it: no decode_times=False
        assert "time" not in raw.variables and raw.t.dtype == np.float64 and raw.t.attrs["units"] == "s"
        assert "_FillValue" not in raw.t.encoding and "standard_name" not in raw.t.attrs
        t = raw.t.values
    np.testing.assert_allclose(t, np.arange(1001) * 1e-3, rtol=0, atol=1e-12)   # --t-end 1 --dt 1e-3
    loaded = written["simulate.nc"][1]
    np.testing.assert_array_equal(loaded.t.values, t)
    assert loaded.t.attrs["units"] == "s" and "elapsed" in loaded.t.attrs["comment"]


@pytest.mark.parametrize("units", ["s since 1970-01-01 00:00:00", "s"])
def test_a_history_written_before_0_2_loads_with_its_time_in_seconds_as_t(tmp_path, units):
    """Files before 0.2 named the elapsed time ``time``: with a nominal epoch ("s since 1970-01-01"), then in plain
    seconds; both load as ``t`` in seconds."""
    old = xr.Dataset({"x": ("time", [0.0, 1e-3, 2e-3], {"units": "m"})}, coords={"time": ("time", [0.0, 0.5, 1.0], {
        "units": units, "calendar": "proleptic_gregorian", "standard_name": "time",
        "comment": "elapsed time from the start of the integration"})}, attrs={"scene": "thesis-1dof"})
    old.to_netcdf(tmp_path / "old.nc")
    from bifurc.storage.load import kind_of, read
    ds = read(tmp_path / "old.nc")
    t = ds.t
    assert "time" not in ds.variables and ds.x.dims == ("t",) and kind_of(ds) == "history"
    assert t.values.tolist() == [0.0, 0.5, 1.0] and t.attrs["units"] == "s"
    assert "standard_name" not in t.attrs and "calendar" not in t.attrs


def unit_strings(ds):
    """(where, units) for every variable's units and every ``*_units`` attribute."""
    found = [(name, v.attrs["units"]) for name, v in ds.variables.items() if "units" in v.attrs]
    found += [(k, v) for k, v in ds.attrs.items() if k.endswith("_units")]
    return found


def assert_udunits(pairs):
    assert pairs
    for where, units in pairs:
        try:
            cf_units.Unit(units)
        except ValueError:
            pytest.fail(f"{where}: units {units!r} are not UDUNITS-valid")


def test_every_units_string_in_every_file_is_udunits_valid(written):
    for name, (_, ds) in _files(written).items():
        assert_udunits(unit_strings(ds))
    diagram = written["diagram.nc"][1]
    for name in ("period", "lyapunov", "forcing_period", "transient_used"):
        assert diagram[name].attrs["units"] == "1" and "relay period" in diagram[name].attrs["long_name"]


def test_the_checker_would_catch_a_bad_unit():
    with pytest.raises(ValueError):
        cf_units.Unit("relay periods")


def test_parameter_state_and_schema_units_are_udunits_valid():
    from bifurc.storage.schema import GRAZING, HISTORY, ORBIT, ORBIT_SCALARS, SWEEP, SWEEP_COORDS
    assert_udunits([(p.name, p.unit) for p in maps.PARAMETERS.values()])
    for name in maps.scene_names():
        assert_udunits([(s.name, s.unit) for s in maps.get_scene(name).system.states])
    rows = SWEEP + SWEEP_COORDS + HISTORY + ORBIT + ORBIT_SCALARS + [v for v in GRAZING if v.units != "<param>"]
    assert_udunits([(v.name, v.units) for v in rows])


def test_every_file_carries_conventions_history_and_source(written):
    commit = git_commit()
    for name, (argv, ds) in _files(written).items():
        a = ds.attrs
        assert a["Conventions"] == "CF-1.10", name
        assert "bifurc " + " ".join(argv[:2]) in a["history"], (name, a["history"])  # the command line
        assert f"bifurc {bifurc.__version__}" in a["history"] and a["history"][:4].isdigit()
        if commit:
            assert f"git {commit}" in a["history"]
        assert a["source"].startswith(f"bifurc {bifurc.__version__}"), name


def test_api_datasets_record_the_call():
    h = maps.simulate("thesis-1dof", t_end=0.01, preset="matlab-listing", params={"V": 90})
    assert "maps.simulate('thesis-1dof', t_end=0.01, preset='matlab-listing', params={'V': 90})" in h.attrs["history"]
    d = bifurc.sweep("thesis-1dof", "relay_hz", np.array([5.0, 6.0]), transient=3, record=3, lyapunov=False,
                     grazing=False, error_sample=0, progress=False)
    assert "bifurc.sweep('thesis-1dof', 'relay_hz', [5.0, 6.0], transient=3" in d.attrs["history"]
    assert d.attrs["Conventions"] == h.attrs["Conventions"] == "CF-1.10" and "source" in d.attrs


def test_bifurc_report_reads_every_file_kind(written, capsys):
    """`bifurc report` on each kind: exit 0 and a report naming the kind, with the sizes the commands asked for."""
    expect = {"simulate.nc": ("# Time history report (history)", "- 1001 samples"),       # --t-end 1 --dt 1e-3
              "diagram.nc": ("# Classification report (diagram)", "3 values of `relay_hz` from 5 to 9"),
              "map.nc": ("# Regime map report (map)", "2 values of `relay_hz` x 2 values of `V`"),
              "branch.nc": ("# Branch report (branch)", "continuation in V"),
              "orbit.nc": ("# Periodic orbit report (orbit)", "- period "),
              "accuracy/accuracy.nc": ("# Work-precision report (accuracy)", "| heyoka | 1e-08 |"),
              "verify/stability.nc": ("# Stability suite report (stability)", "1 cases")}
    for name, (title, words) in expect.items():
        assert main(["report", str(written["dir"] / name)]) == 0, name
        out = capsys.readouterr().out
        assert out.startswith(title) and words in out, (name, out[:300])
