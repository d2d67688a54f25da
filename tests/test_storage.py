"""The sweep Dataset on disk: netCDF round trip, CF attributes, NaN only where flagged."""
import math

import netCDF4
import numpy as np
import pytest
import xarray as xr

import maps
from bifurc.storage import files, load as storage
from bifurc.labels.classify import CLASS_LABELS
from bifurc.sweeps.sweep import sweep

OSC = dict(w0=1.0, zeta=0.02, F=0.1, Omega=0.7, e=-1.0, r=0.8)


@pytest.fixture(scope="module")
def escaping_sweep():
    """k = 1 N/m without DC force: the bar falls through the stop (escaped); k = 1e5: impacts."""
    return sweep("thesis-1dof", "k", np.array([1.0, 1e5]), preset="matlab-listing",
                 params={"V": 90.0, "relay_hz": 5.0, "dc_scale": 0.0}, transient=5, record=6,
                 error_sample=1, progress=False, budget=11)   # no extension: the k = 1e5 value stays in its window


@pytest.fixture(scope="module")
def grazing_sweep():
    """Follow mode over the oscillator's grazing: branch and grazing dimensions both filled."""
    W = OSC["Omega"]
    F_graze = abs(OSC["e"]) * math.hypot(1 - W**2, 2 * OSC["zeta"] * W)
    return sweep(maps.forced_oscillator_with_stop(), "F", np.array([0.9, 1.1]) * F_graze, mode="follow",
                 params=OSC, transient=200, record=10, tol=1e-12, lyapunov=False, error_sample=0,
                 grazing_xtol=1e-4, progress=False)


def _round_trip(ds, tmp_path, name):
    path = tmp_path / name
    files.write_netcdf(ds, path)
    return storage.read(path), path


@pytest.mark.parametrize("which", ["escaping_sweep", "grazing_sweep"])
def test_netcdf_round_trip_keeps_values_dtypes_and_attributes(which, request, tmp_path):
    ds = request.getfixturevalue(which)
    back, _ = _round_trip(ds, tmp_path, f"{which}.nc")
    back = back.drop_encoding() if hasattr(back, "drop_encoding") else back
    xr.testing.assert_identical(back, ds)  # values (NaN, inf included), coordinates, attrs
    for name, var in ds.variables.items():
        assert back[name].dtype == var.dtype, name
        assert back[name].attrs.keys() == var.attrs.keys(), name
        if var.dtype.kind == "f":
            np.testing.assert_array_equal(np.isnan(back[name].values), np.isnan(var.values))
            np.testing.assert_array_equal(np.isinf(back[name].values), np.isinf(var.values))
    for key, value in ds.attrs.items():
        np.testing.assert_array_equal(back.attrs[key], value, err_msg=key)
    assert ds.sizes["grazing"] >= (1 if which == "grazing_sweep" else 0)


def test_every_variable_is_cf_described_and_flags_decode(escaping_sweep, tmp_path):
    ds = escaping_sweep
    _, path = _round_trip(ds, tmp_path, "cf.nc")
    with netCDF4.Dataset(path) as nc:  # any netCDF tool sees the same description
        for name, var in nc.variables.items():
            attrs = var.ncattrs()
            assert "units" in attrs and "long_name" in attrs, name
            if "flag_values" in attrs:
                assert len(var.flag_values) == len(var.flag_meanings.split()), name
        assert nc.variables["class_code"].dtype == np.int8
        assert nc.getncattr("swept_parameter") == "k" and nc.getncattr("Conventions").startswith("CF")
    meanings = ds.class_code.attrs["flag_meanings"].split()
    assert [m.replace("_", "-") for m in meanings] == list(CLASS_LABELS)
    for key in ("scene", "mode", "tol", "transient_periods", "recorded_periods", "heyoka_version",
                "numpy_version", "xarray_version", "sweep_seconds", "compile_seconds", "param_V",
                "param_V_units", "param_V_source", "swept_parameter_units"):
        assert key in ds.attrs, key
    assert ds.attrs["param_V_source"] == "set by user" and ds.attrs["swept_parameter_units"] == "N m-1"


def test_missing_values_are_flagged_never_silent(escaping_sweep):
    """The escaped value has NaN samples after its escape, and its status and class say so;
    the completed value has no NaN in any recorded quantity."""
    ds = escaping_sweep.isel(branch=0)
    esc, ok = ds.isel(k=0), ds.isel(k=1)
    assert int(esc.status) == 1 and CLASS_LABELS[int(esc.class_code)] == "escaped"
    assert math.isfinite(float(esc.failure_time)) and int(esc.n_impacts) == 0
    assert np.isnan(esc.x.values[1:]).all() and np.isfinite(esc.x.values[0])
    assert np.isnan(float(esc.min_clearance)) and np.isnan(float(esc.min_impact_speed))
    assert int(ok.status) == 0 and int(ok.n_impacts) > 0
    for name in ("x", "v", "i", "z", "min_clearance_per_step", "min_clearance", "min_impact_speed", "run_seconds"):
        assert np.isfinite(ok[name].values).all(), name
    n = int(ok.n_impacts)
    assert np.isfinite(ok.impact_time.values[:n]).all() and np.isnan(ok.impact_time.values[n:]).all()
    assert ok.impacts_per_step.values.sum() == n


def test_time_history_attributes_follow_the_schema_table():
    """maps.simulate writes its own attributes (maps never imports bifurc); they must agree with
    the history rows of bifurc.storage.schema, which its to_dataset will later draw from."""
    from bifurc.storage.schema import HISTORY
    rows = {v.name: v for v in HISTORY}
    for scene in ("thesis-1dof", "thesis-2dof"):
        ds = maps.simulate(scene, periods=2, preset="matlab-listing", params={"V": 90, "relay_hz": 9})
        states = set(maps.get_scene(scene).system.state_names)
        for name, var in ds.variables.items():
            if name in states:
                continue
            row = rows[name]          # every other variable has a row
            assert var.dims == row.dims, name
            assert var.attrs["units"] == row.units and var.attrs["long_name"] == row.long_name, name
            if "flag_meanings" in var.attrs:
                assert var.attrs["flag_meanings"] == dict(row.extra)["flag_meanings"], name
                np.testing.assert_array_equal(var.attrs["flag_values"], dict(row.extra)["flag_values"])
    assert {"rig_stuck", "progression", "relay", "contact", "impact_time"} <= set(rows)


def test_param_attributes_have_one_writer():
    """The sweep's param_* attributes are schema.param_attrs of its parameter table, swept one excluded."""
    from bifurc.storage.schema import param_attrs
    table = {"V": (90.0, "set by user"), "k": (1e5, "preset matlab-listing")}
    system = maps.get_scene("thesis-1dof").system
    assert param_attrs(table, system, skip=("k",)) == {"param_V": 90.0, "param_V_units": "V",
                                                       "param_V_source": "set by user"}


def test_text_variables_keep_their_whole_text():
    """class_reason is stored whole (a fixed-width array sized by its first entry cut it to one letter)."""
    import numpy as np
    from bifurc.sweeps.sweep import sweep
    ds = sweep("thesis-1dof", "relay_hz", np.array([5.0, 9.0]), preset="matlab-listing", params={"V": 90},
               transient=20, record=30, grazing=False, error_sample=0, progress=False)
    reasons = [str(r) for r in ds.class_reason.values.ravel()]
    assert any(len(r) > 20 for r in reasons) or all(r == "" for r in reasons)
    for code, r in zip(ds.class_code.values.ravel(), reasons):
        assert (int(code) == 4) == (r != "") and (r == "" or len(r) > 20)
