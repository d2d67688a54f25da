"""The command line: same numbers as the API, clear errors, files written."""
import numpy as np
import pytest
import xarray as xr

import maps
from bifurc.cli import main


def test_scenes_lists_every_scene(capsys):
    assert main(["scenes"]) == 0
    out = capsys.readouterr().out
    for name in maps.scene_names():
        assert name in out
    assert len(out.strip().splitlines()) == len(maps.scene_names())


def test_simulate_writes_the_same_numbers_as_the_api(tmp_path):
    nc, png = tmp_path / "run.nc", tmp_path / "run.png"
    code = main(["simulate", "--scene", "thesis-1dof", "--relay-hz", "9", "--periods", "12",
                 "--preset", "matlab-listing", "--set", "V=90", "--set", "k=1e6", "--dt", "1e-3",
                 "-o", str(nc), "--plot", str(png)])
    assert code == 0
    ds = xr.open_dataset(nc)
    ref = maps.simulate("thesis-1dof", periods=12, preset="matlab-listing",
                        params={"V": 90, "k": 1e6, "relay_hz": 9}, dt=1e-3)
    assert ds.sizes["impact"] == ref.sizes["impact"] > 0
    np.testing.assert_allclose(ds.impact_time.values, ref.impact_time.values, rtol=0, atol=1e-12)
    np.testing.assert_allclose(ds.x.values, ref.x.values, rtol=0, atol=1e-12)
    assert ds.attrs["param_k"] == 1e6 and ds.attrs["param_V"] == 90
    for name, var in ds.variables.items():
        assert "units" in var.attrs, name
    assert png.stat().st_size > 20_000
    assert not list(tmp_path.glob(".*.tmp"))  # atomic write left no temporary file


@pytest.mark.parametrize("argv, named", [
    (["simulate", "--set", "mass=1"], "mass"),
    (["simulate", "--set", "m=-1"], "'m'"),
    (["simulate", "--set", "V=nan"], "'V'"),
    (["simulate", "--relay-hz", "0"], "relay_hz"),
    (["simulate", "--scene", "nope"], "nope"),
    (["simulate", "--set", "V"], "NAME=VALUE"),
    (["simulate", "--x0", "y=1"], "'y'"),
])
def test_bad_input_is_one_line_naming_the_parameter(argv, named, capsys):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.startswith("bifurc: error:") and named in err
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1
