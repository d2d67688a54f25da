"""Bad inputs and bad files through the command line: one line on stderr, exit 2, no traceback.

Each case is refused before any long work (the whole test runs in seconds)."""
import socket

import numpy as np
import pytest
import xarray as xr

from bifurc.cli import main
from bifurc.storage.files import write_netcdf

DIAGRAM = ["diagram", "--preset", "matlab-listing", "--set", "V=90", "--from", "5", "--to", "9", "--n", "2",
           "--transient", "5", "--record", "4", "--no-lyapunov", "--quiet"]
SIMULATE = ["simulate", "--preset", "matlab-listing", "--t-end", "0.05", "--dt", "1e-3"]


def _closed_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]  # nothing listens once closed


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    d = tmp_path_factory.mktemp("bad")
    f = {k: d / k for k in ("diagram.nc", "sim.nc", "stab.nc", "corrupt.nc", "truncated.nc", "empty.nc",
                            "report.md", "full", "busy", "afile")}
    assert main([*DIAGRAM, "-o", str(f["diagram.nc"])]) == 0
    assert main([*SIMULATE, "-o", str(f["sim.nc"])]) == 0
    write_netcdf(xr.Dataset({"verdict": ("case", np.zeros(2, np.int8))}), f["stab.nc"])
    f["corrupt.nc"].write_bytes(np.random.default_rng(0).bytes(4096))
    data = f["diagram.nc"].read_bytes()
    f["truncated.nc"].write_bytes(data[: len(data) // 2])
    f["empty.nc"].write_bytes(b"")
    f["report.md"].write_text("keep me")
    f["afile"].write_text("a file, not a folder")
    for folder in ("full", "busy"):
        f[folder].mkdir()
    for name in ("notes.txt", "stability.nc", "stability.md", "accuracy.nc"):
        (f["full"] / name).write_text("keep me")
    return {k: str(v) for k, v in f.items()}


CASES = [  # (argv with {placeholders} from the files fixture, text the line must contain)
    (["report", "{corrupt.nc}"], "not a readable netCDF"),
    (["report", "{truncated.nc}"], "not a readable netCDF"),
    (["report", "{empty.nc}"], "not a readable netCDF"),
    (["report", "{sim.nc}", "--at", "5"], "--at: for a diagram dataset only; "),
    (["report", "{stab.nc}", "--period-of", "mechanical"], "holds a stability dataset"),
    (["report", "{full}/missing.nc"], "no dataset"),
    (["report", "{full}"], "folder"),
    (["report", "{diagram.nc}", "--at", "abc"], "--at"),
    (["report", "{diagram.nc}", "--at", "5,x"], "--at"),
    (["report", "{diagram.nc}", "-o", "{report.md}"], "--force"),
    (["report"], "dataset"),
    ([*DIAGRAM, "-o", "{full}/d1.nc", "--plot", "{full}/d.xyz"], ".xyz"),
    ([*DIAGRAM, "-o", "{full}/d2.nc", "--plot", "{full}/d"], "--plot"),
    ([*DIAGRAM, "-o", "{full}/d3.nc", "--tol", "-1"], "'tol'"),
    ([*DIAGRAM, "-o", "{full}/d4.nc", "--tol", "0"], "'tol'"),
    ([*DIAGRAM, "-o", "{full}/d5.nc", "--scheduler", "tcp://127.0.0.1:{port}"], "no Dask scheduler"),
    ([*DIAGRAM, "-o", "{full}/d6.nc", "--scheduler", "tcp://nohost"], "--scheduler"),
    ([*DIAGRAM, "-o", "{diagram.nc}"], "--force"),
    ([*DIAGRAM, "-o", "{full}/d7.nc", "--n", "0"], "--n"),
    ([*DIAGRAM, "-o", "{full}/d8.nc", "--mode", "sideways"], "--mode"),
    ([*DIAGRAM, "-o", "{full}/d9.nc", "--workers", "0"], "workers"),
    ([*DIAGRAM, "-o", "{full}/d10.nc", "--transient", "-1"], "transient"),
    ([*DIAGRAM, "-o", "{full}/d11.nc", "--record", "1"], "record"),
    ([*DIAGRAM, "-o", "{full}/d12.nc", "--from", "nan"], "--from nan"),
    ([*DIAGRAM, "-o", "{full}/d13.nc", "--batch-size", "100"], "batch_size"),
    ([*DIAGRAM, "-o", "{full}/d14.nc", "--max-transient", "1"], "max_transient"),
    ([*DIAGRAM, "-o", "{full}/d15.nc", "--param", "bogus"], "bogus"),
    ([*DIAGRAM, "-o", "{afile}/d.nc"], "afile"),
    ([*SIMULATE, "--plot", "{full}/s.xyz"], ".xyz"),
    ([*SIMULATE, "-o", "{sim.nc}"], "--force"),
    ([*SIMULATE, "--plot", "{full}/notes.txt"], ".txt"),
    ([*SIMULATE, "--dt", "-1"], "'dt'"),
    ([*SIMULATE, "--tol", "-1"], "'tol'"),
    (["simulate", "--periods", "0"], "'periods'"),
    (["simulate", "--x0", "x=1,v"], "--x0"),
    (["params", "--scene", "nope"], "nope"),
    (["params", "--preset", "nope"], "nope"),
    (["params", "--set", "V=-1"], "'V'"),
    (["study", "thesis-1dof-relay", "--quick", "-o", "{full}"], "--force"),
    (["study", "nope", "-o", "{busy}/s"], "nope"),
    (["accuracy", "--methods", "bogus", "-o", "{busy}/a"], "bogus"),
    (["accuracy", "--tols", "abc", "-o", "{busy}/a"], "--tols"),
    (["accuracy", "-o", "{full}"], "--force"),
    (["verify", "--quick", "-o", "{full}"], "--force"),
    (["verify", "--case", "nope", "-o", "{busy}/st"], "nope"),
]


@pytest.mark.parametrize("argv, named", CASES, ids=[" ".join(a[:1] + a[-2:]) for a, _ in CASES])
def test_refused_in_one_line(argv, named, files, capsys):
    fill = dict(files, port=_closed_port())
    for key, value in fill.items():
        argv = [a.replace("{" + key + "}", str(value)) for a in argv]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.startswith("bifurc: error:") and named in err, err
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1, err


def test_enough_cases_and_nothing_left_behind(files):
    assert len(CASES) >= 30
    from pathlib import Path
    full = Path(files["full"])
    # refused commands wrote nothing: no dataset, no figure, no .parts, no lock
    assert sorted(p.name for p in full.iterdir()) == ["accuracy.nc", "notes.txt", "stability.md", "stability.nc"]
    assert all(p.read_text() == "keep me" for p in full.iterdir())
    assert Path(files["report.md"]).read_text() == "keep me"
    assert not list(Path(files["busy"]).rglob("*"))
