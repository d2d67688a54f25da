"""Output files: nothing overwritten silently, one writer at a time, resume, umask, compression."""
import os
import stat
import subprocess
import sys
from pathlib import Path

import netCDF4
import numpy as np
import pytest
import xarray as xr

import bifurc
import maps
from bifurc.cli import main
from bifurc.storage.files import OutputBusy, output_guard, output_lock, write_netcdf

ARGS = dict(preset="matlab-listing", params={"V": 90}, transient=10, record=6, lyapunov=False, grazing=False,
            error_sample=0, progress=False, batch_size=1)
VALUES = np.array([5.0, 7.0, 9.0])
DIAGRAM = ["diagram", "--preset", "matlab-listing", "--set", "V=90", "--from", "5", "--to", "9", "--n", "3",
           "--transient", "10", "--record", "6", "--no-lyapunov", "--quiet"]


def test_api_and_cli_refuse_an_existing_output_and_replace_it_when_told(tmp_path, capsys):
    path = tmp_path / "d.nc"
    path.write_text("not mine to replace")
    with pytest.raises(FileExistsError, match="overwrite=True"):
        bifurc.sweep("thesis-1dof", "relay_hz", VALUES, path=path, **ARGS)
    assert main([*DIAGRAM, "-o", str(path)]) == 2
    assert "--force" in capsys.readouterr().err
    assert path.read_text() == "not mine to replace" and not (tmp_path / "d.nc.parts").exists()
    ds = bifurc.sweep("thesis-1dof", "relay_hz", VALUES, path=path, overwrite=True, **ARGS)
    assert bifurc.load(path).class_code.shape == ds.class_code.shape == (1, 3)
    png = tmp_path / "d.png"
    png.write_text("x")
    with pytest.raises(FileExistsError):
        bifurc.plot_diagram(ds, png)
    bifurc.plot_diagram(ds, png, overwrite=True)
    assert png.stat().st_size > 10_000
    with pytest.raises(FileExistsError):
        write_netcdf(ds, path)
    assert main([*DIAGRAM, "-o", str(path), "--force"]) == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["d.nc", "d.png"]  # no lock, parts or temporary left


def test_a_refused_argument_leaves_no_parts_that_block_the_corrected_command(tmp_path, capsys):
    out = tmp_path / "d.nc"
    assert main([*DIAGRAM, "-o", str(out), "--tol", "-1"]) == 2
    assert not (tmp_path / "d.nc.parts").exists()
    assert main([*DIAGRAM, "-o", str(out), "--tol", "1e-9"]) == 0
    assert out.exists()


def test_a_failure_after_the_parts_folder_is_made_removes_it_only_if_nothing_was_completed(tmp_path):
    def work(path, completed, overwrite=False):
        with output_guard(path, overwrite):
            parts = tmp_path / (path.name + ".parts")
            parts.mkdir()
            (parts / "manifest.json").write_text("{}")
            if completed:
                (parts / "independent-000000.nc").write_bytes(b"done")
            raise maps.ParameterError("refused")

    with pytest.raises(maps.ParameterError):
        work(tmp_path / "a.nc", False)
    assert not (tmp_path / "a.nc.parts").exists()
    with pytest.raises(maps.ParameterError):
        work(tmp_path / "b.nc", True)
    assert (tmp_path / "b.nc.parts" / "independent-000000.nc").exists()  # completed work is kept


def test_a_second_writer_of_the_same_output_is_refused_at_once(tmp_path, capsys):
    out = tmp_path / "d.nc"
    with output_lock(out):
        assert (tmp_path / "d.nc.lock").exists()
        with pytest.raises(OutputBusy, match="another run"):
            bifurc.sweep("thesis-1dof", "relay_hz", VALUES, path=out, **ARGS)
        assert main([*DIAGRAM, "-o", str(out)]) == 2
        err = capsys.readouterr().err
        assert "being written by another run" in err and len(err.strip().splitlines()) == 1
        with output_lock(tmp_path / "other.nc"):  # another output is free
            pass
    assert not (tmp_path / "d.nc.lock").exists() and not out.exists()
    with output_lock(out):  # released: taken again
        pass
    (tmp_path / "d.nc.lock").write_text("")  # left by a run killed with SIGKILL: its flock died with it
    assert main([*DIAGRAM, "-o", str(out)]) == 0 and out.exists() and not (tmp_path / "d.nc.lock").exists()


def test_another_process_holding_the_lock_is_refused_in_one_line(tmp_path, capsys):
    """Across processes (fcntl.flock): the holder runs in a child process until its stdin closes."""
    out = tmp_path / "d.nc"
    code = ("import sys; from bifurc.storage.files import output_lock\n"
            f"with output_lock({str(out)!r}):\n    print('held', flush=True); sys.stdin.read()\n")
    env = dict(os.environ, PYTHONPATH=str(Path(__file__).resolve().parents[1]))
    holder = subprocess.Popen([sys.executable, "-c", code], stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True,
                              env=env)
    try:
        assert holder.stdout.readline().strip() == "held"
        assert main([*DIAGRAM, "-o", str(out)]) == 2
        err = capsys.readouterr().err
        assert "being written by another run" in err and len(err.strip().splitlines()) == 1
    finally:
        holder.communicate("", timeout=60)
    assert holder.returncode == 0 and not out.exists()
    assert main([*DIAGRAM, "-o", str(out)]) == 0 and out.exists()


@pytest.mark.parametrize("umask, mode", [(0o022, 0o644), (0o077, 0o600), (0o002, 0o664)])
def test_files_get_the_mode_of_the_users_umask(tmp_path, umask, mode):
    ds = xr.Dataset({"a": ("n", np.arange(3.0), {"units": "m"})})
    old = os.umask(umask)
    try:
        write_netcdf(ds, tmp_path / "a.nc")
        bifurc.storage.files.write_text(tmp_path / "a.md", "text")
    finally:
        os.umask(old)
    assert stat.S_IMODE((tmp_path / "a.nc").stat().st_mode) == mode
    assert stat.S_IMODE((tmp_path / "a.md").stat().st_mode) == mode


def test_netcdf_files_are_zlib_compressed_and_read_back_unchanged(tmp_path):
    t = np.linspace(0, 1, 20_000)
    ds = xr.Dataset({"x": ("time", np.round(np.sin(40 * t), 3), {"units": "m"}),
                     "flag": ("time", (t > 0.5).astype(np.int8), {"units": "1"})},
                    coords={"time": ("time", t, {"units": "s"})})
    write_netcdf(ds, tmp_path / "z.nc")
    ds.to_netcdf(tmp_path / "plain.nc")
    with netCDF4.Dataset(tmp_path / "z.nc") as nc:
        for name in ("x", "flag", "time"):
            assert nc.variables[name].filters()["zlib"], name
    assert (tmp_path / "z.nc").stat().st_size < 0.5 * (tmp_path / "plain.nc").stat().st_size
    back = xr.load_dataset(tmp_path / "z.nc")
    for name in ("x", "flag", "time"):
        np.testing.assert_array_equal(back[name].values, ds[name].values)
        assert back[name].dtype == ds[name].dtype
