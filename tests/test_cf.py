"""CF: every units string is UDUNITS-valid (checked by cf-units), every file carries Conventions,
history (time, command line or API call, version, commit) and source."""
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
        out[name] = (argv, xr.load_dataset(d / name))
    return out


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
    for name, (_, ds) in written.items():
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
    for name, (argv, ds) in written.items():
        a = ds.attrs
        assert a["Conventions"] == "CF-1.10", name
        assert "bifurc " + " ".join(argv[:2]) in a["history"], (name, a["history"])  # the command line
        assert f"bifurc {bifurc.__version__}" in a["history"] and a["history"][:4].isdigit()
        if commit:
            assert f"git {commit}" in a["history"]
        assert a["source"].startswith(f"bifurc {bifurc.__version__}"), name


def test_api_datasets_record_the_call():
    h = maps.simulate("thesis-1dof", t_end=0.01, preset="matlab-listing", params={"V": 90})
    assert "maps.simulate('thesis-1dof', t_end=0.01, params={'V': 90}, preset='matlab-listing')" in h.attrs["history"]
    d = bifurc.sweep("thesis-1dof", "relay_hz", np.array([5.0, 6.0]), transient=3, record=3, lyapunov=False,
                     grazing=False, error_sample=0, progress=False)
    assert "bifurc.sweep('thesis-1dof', 'relay_hz', [5.0, 6.0], transient=3" in d.attrs["history"]
    assert d.attrs["Conventions"] == h.attrs["Conventions"] == "CF-1.10" and "source" in d.attrs
