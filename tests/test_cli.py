"""The command line: the same numbers as the API, one-line errors, files written atomically."""
import matplotlib

matplotlib.use("Agg")
import matplotlib.image as mpimg  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
import xarray as xr  # noqa: E402

import bifurc  # noqa: E402
import maps  # noqa: E402
from bifurc import __version__, cli  # noqa: E402
from bifurc.cli import main  # noqa: E402
from bifurc.plots.history import plot_time_history  # noqa: E402
from bifurc.storage.files import write_netcdf  # noqa: E402

OPTS = dict(preset="matlab-listing", params={"V": 90.0, "k": 1e6, "relay_hz": 9.0}, dt=1e-3)
ARGV = ["--scene", "thesis-1dof", "--relay-hz", "9", "--preset", "matlab-listing",
        "--set", "V=90", "--set", "k=1e6", "--dt", "1e-3"]


@pytest.fixture(scope="module")
def reference():
    """maps.simulate with the options of ARGV: 12 relay periods at 9 Hz (first impacts ~0.85 s)."""
    return maps.simulate("thesis-1dof", periods=12, **OPTS)


def test_scenes_lists_every_scene_with_its_states(capsys):
    assert main(["scenes"]) == 0
    lines = capsys.readouterr().out.strip().splitlines()
    assert len(maps.scene_names()) == 7 and len(lines) == 7   # the six thesis scenes and the impact oscillator
    for name, line in zip(maps.scene_names(), lines):
        assert line.split()[0] == name
        assert "[" + ",".join(maps.get_scene(name).system.state_names) + "]" in line


def test_simulate_writes_the_same_numbers_as_the_api(tmp_path, reference, capsys):
    nc, png = tmp_path / "run.nc", tmp_path / "run.png"
    assert main(["simulate", *ARGV, "--periods", "12", "-o", str(nc), "--plot", str(png)]) == 0
    out = capsys.readouterr().out
    ds = bifurc.load(nc)   # t in s
    n = reference.sizes["impact"]
    assert n > 0 and ds.sizes["impact"] == n and f"{n} impacts" in out and "status ok" in out
    for name in ("impact_time", "impact_velocity", "impact_penetration", "impact_duration"):
        np.testing.assert_allclose(ds[name].values, reference[name].values, rtol=0, atol=1e-12,
                                   equal_nan=True, err_msg=name)
    np.testing.assert_array_equal(ds.t.values, reference.t.values)
    for name in maps.get_scene("thesis-1dof").system.state_names:
        scale = np.abs(reference[name].values).max()
        np.testing.assert_allclose(ds[name].values, reference[name].values, rtol=0, atol=1e-12 * scale,
                                   err_msg=name)
    np.testing.assert_array_equal(ds.relay.values, reference.relay.values)
    np.testing.assert_array_equal(ds.contact.values, reference.contact.values)
    assert ds.attrs["param_k"] == 1e6 and ds.attrs["param_V"] == 90 and ds.attrs["param_relay_hz"] == 9
    assert ds.attrs["param_V_source"] == "set by user"
    for name, var in ds.variables.items():
        assert var.attrs.get("units"), name
    assert not list(tmp_path.glob(".*.tmp"))  # the atomic write left no temporary file
    # the figure: several panels of real curves, not a blank canvas
    img = mpimg.imread(png)
    assert img.shape[0] > 600 and img.shape[1] > 900
    ink = (img[..., :3].min(axis=2) < 0.9).mean()
    assert 0.03 < ink < 0.6, ink


def test_t_end_is_the_same_run_as_periods(tmp_path, reference):
    nc = tmp_path / "t.nc"
    assert main(["simulate", *ARGV, "--t-end", repr(12 / 9), "-o", str(nc)]) == 0
    ds = xr.open_dataset(nc)
    np.testing.assert_allclose(ds.impact_time.values, reference.impact_time.values, rtol=0, atol=1e-12)
    np.testing.assert_allclose(ds.x.values, reference.x.values, rtol=0, atol=1e-12)


def test_time_history_figure_draws_the_dataset(reference):
    """Into a caller's Axes (returned): the displacement curve is x in mm, one marker per impact on the stop."""
    fig, ax = plt.subplots()
    assert plot_time_history(reference, ax=ax) is ax
    curve, stop_marks = ax.lines[0], ax.lines[-1]
    np.testing.assert_allclose(curve.get_ydata(), 1e3 * reference.x.values, rtol=1e-15)
    np.testing.assert_allclose(stop_marks.get_xdata(), reference.impact_time.values, rtol=0)
    assert "[mm]" in ax.get_ylabel()
    plt.close(fig)
    ax = plot_time_history(reference)  # own figure: displacement, current, relay; the first returned
    full = ax.figure
    assert ax is full.axes[0]
    labels = [a.get_ylabel() for a in full.axes]
    assert len(labels) == 3 and "[A]" in labels[1] and "V* = 90 V" in full._suptitle.get_text()
    plt.close(full)


def test_atomic_write_keeps_the_old_file_when_writing_fails(tmp_path, reference):
    path = tmp_path / "keep.nc"
    write_netcdf(reference, path, overwrite=True)
    before = path.read_bytes()
    bad = reference.copy()
    bad.attrs["not_storable"] = {"a": 1}  # netCDF refuses a dict attribute mid-write
    with pytest.raises(TypeError):
        write_netcdf(bad, path, overwrite=True)
    assert path.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["keep.nc"]


@pytest.mark.parametrize("argv, named", [
    (["simulate", "--set", "mass=1"], "mass"),
    (["simulate", "--set", "m=-1"], "'m'"),
    (["simulate", "--set", "V=nan"], "'V'"),
    (["simulate", "--relay-hz", "0"], "relay_hz"),
    (["simulate", "--scene", "nope"], "nope"),
    (["simulate", "--set", "V"], "NAME=VALUE"),
    (["simulate", "--set", "V=ninety"], "'V'"),
    (["simulate", "--x0", "y=1"], "'y'"),
    (["simulate", "--x0", "x=abc"], "--x0"),
    (["simulate", "--tol", "abc"], "--tol"),
    (["simulate", "--periods", "1", "--t-end", "1"], "--t-end"),
    (["simulate", "--bogus"], "--bogus"),
    (["nope"], "nope"),
    (["diagram", "--from", "2", "--to", "3", "-o", "x.nc", "--batch-size", "0"], "batch_size"),
    (["diagram", "--from", "2", "--to", "3", "-o", "x.nc", "--record", "100", "--max-record", "50"], "max_record"),
])
def test_bad_input_is_one_line_naming_the_parameter(argv, named, capsys):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.startswith("bifurc: error:") and named in err, err
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1


def test_output_into_a_closed_pipe_ends_quietly(monkeypatch, capsys):
    """`bifurc params | head -1`: the reader closes the pipe; no BrokenPipeError traceback."""
    import os
    import sys
    read, write = os.pipe()
    os.close(read)
    with os.fdopen(write, "w") as pipe:
        monkeypatch.setattr(sys, "stdout", pipe)
        assert main(["params"]) == 141
    assert capsys.readouterr().err == ""


def test_version(capsys):
    assert main(["--version"]) == 0
    assert capsys.readouterr().out.strip() == f"bifurc {__version__}"


def test_missing_subcommand_module_is_skipped_but_a_broken_import_is_not(monkeypatch):
    real = cli.importlib.import_module

    def fake(name):
        if name == "bifurc.commands.report":
            raise ModuleNotFoundError(f"No module named {name!r}", name=name)
        if name == "bifurc.commands.diagram":
            raise ModuleNotFoundError("No module named 'somedep'", name="somedep")
        return real(name)

    monkeypatch.setattr(cli.importlib, "import_module", fake)
    monkeypatch.setattr(cli, "COMMANDS", ["scenes", "report"])
    assert "report" not in cli.build_parser()._subparsers._group_actions[0].choices
    monkeypatch.setattr(cli, "COMMANDS", ["scenes", "diagram"])
    with pytest.raises(ModuleNotFoundError, match="somedep"):
        cli.build_parser()


def test_every_command_a_help_text_names_exists():
    """G8: `--refine-from` once named a `bifurc branch` that does not exist (it is `bifurc continue`)."""
    import re
    sub = cli.build_parser()._subparsers._group_actions[0].choices
    named = {(name, m.group(1)) for name, sp in sub.items()
             for m in re.finditer(r"bifurc\s+([a-z][a-z-]*)", " ".join(sp.format_help().split()))}
    assert ("attractors", "continue") in named          # the --refine-from help names its source
    assert {w for _, w in named} <= set(sub), sorted((n, w) for n, w in named if w not in sub)


def test_the_census_command_has_the_api_s_defaults():
    """G7 (newcomer review 4): the API drew 100 starts and the command line 200. Every setting the command line
    builds from its defaults is the API's default object: the census method, the matcher, the sampler (200 starts,
    seed 0) and the diagram's method."""
    from bifurc.attractors.method import ByDistance, Census, sampler_of
    from bifurc.commands._options import settings_from_args
    args = cli.build_parser().parse_args(["attractors", "--from", "1", "--to", "1", "-o", "x.nc"])
    assert settings_from_args(Census, args) == Census() and settings_from_args(ByDistance, args) == ByDistance()
    assert sampler_of(None, {}) == bifurc.Box(n=args.starts, seed=args.seed) == bifurc.Box(n=200, seed=0)
    args = cli.build_parser().parse_args(["diagram", "--from", "1", "--to", "2", "-o", "x.nc"])
    assert settings_from_args(bifurc.Diagram, args) == bifurc.Diagram()


def test_no_option_is_another_s_plural():
    """G8: `--max-periods` (the budget) and `--max-period` (the longest period searched) differed by one letter;
    the budget is `--budget` now, in every verb."""
    sub = cli.build_parser()._subparsers._group_actions[0].choices
    pairs = [(name, o) for name, sp in sub.items() for act in sp._actions for o in act.option_strings
             if o.endswith("s") and o[:-1] in {s for a in sp._actions for s in a.option_strings}]
    assert not pairs, pairs
    census = " ".join(sub["attractors"].format_help().split())
    assert "--budget BUDGET" in census and "--max-period MAX_PERIOD" in census and "--max-periods" not in census


def test_a_renamed_option_of_0_1_is_told_its_new_name(tmp_path, capsys):
    """`--max-periods` (0.1) is `--budget` now: the one-line refusal says so, and runs nothing."""
    code = main(["attractors", "impact-oscillator", "--param", "Omega", "--from", "1", "--to", "1.2", "--n", "2",
                 "-o", str(tmp_path / "a.nc"), "--max-periods", "10"])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and "--max-periods is now --budget" in err[0], err
    assert not (tmp_path / "a.nc").exists()
