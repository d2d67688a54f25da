"""The whole bad-input corpus of the newcomer review (tests/data/bad_inputs.py): every command line
through ``python -m bifurc`` in a subprocess (two at a time), each ending (no hang) with its exit
code, exactly one ``bifurc: error:`` line and no traceback; every API row raising its typed,
one-line exception. The default run takes the rows of ``QUICK`` (one per kind of refusal, about
15 s); ``--runslow`` runs all 143 (review 3's 107 and review 4's 36; minutes on two loaded cores). Plus the guards that need more than a command line: a disk that fills
mid-run, a real read-only file system, the budget estimate against a normal job. No test here asserts a
wall time: benchmarks/wall_times.py prints each row's time against the 10 s limit and the run-time estimate
against a measured run."""
import contextlib
import fcntl
import json
import os
import shutil
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
import pytest

import bifurc
import maps
from bifurc.cli import main
from bifurc.storage.build import dataset
from bifurc.storage.files import write_netcdf

sys.path.insert(0, str(Path(__file__).parent))
from data.bad_inputs import API, API4, CLI, CLI4, CONT, MAP, QUICK, QUICK4, SIM, D  # noqa: E402


ROOT = Path(__file__).resolve().parents[1]
#: seconds after which a row is a hang: a refusal, or a row that computes (the slow rows: a small diagram, a census,
#: a branch, at load 8 beside other runs); no test asserts a wall time: benchmarks/wall_times.py times the rows
HANG, HANG_COMPUTING = 60, 900


def _mount_tmpfs(where: Path, options: str) -> bool:
    """Mount a small tmpfs at ``where`` (root only; False where the machine does not allow it)."""
    if os.geteuid() != 0 or not shutil.which("mount"):
        return False
    where.mkdir()
    r = subprocess.run(["mount", "-t", "tmpfs", "-o", options, "tmpfs", str(where)], capture_output=True)
    return r.returncode == 0


def _read_only_folder(d: Path) -> str:
    """A folder no one may write into: a read-only tmpfs (root), a chmod 555 folder (other users), or
    /sys, which refuses root too."""
    if _mount_tmpfs(d / "ro", "ro,size=64k"):
        return str(d / "ro")
    if os.geteuid() != 0:
        (d / "ro").mkdir(exist_ok=True)
        (d / "ro").chmod(0o555)
        return str(d / "ro")
    return "/sys"


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    d = tmp_path_factory.mktemp("corpus")
    for argv in ([*D, "-o", f"{d}/diagram.nc"], [*SIM, "-o", f"{d}/run.nc"], [*MAP, "-o", f"{d}/map.nc"],
                 [*CONT, "-o", f"{d}/branch.nc"]):
        assert main(argv) == 0, argv
    write_netcdf(dataset("stability", attrs={"title": "t"}).assign(verdict=("case", np.zeros(2, np.int8))),
                 d / "stability.nc")
    write_netcdf(dataset("accuracy", attrs={"title": "t"}).assign(tol=("run", [1e-8])), d / "accuracy.nc")
    (d / "random.nc").write_bytes(np.random.default_rng(0).bytes(4096))
    data = (d / "diagram.nc").read_bytes()
    (d / "truncated.nc").write_bytes(data[: len(data) // 2])
    (d / "empty.nc").write_bytes(b"")
    (d / "text.nc").write_text("not netCDF\n")
    (d / "exists.nc").write_text("keep me")
    (d / "adir").mkdir()
    (d / "nonempty").mkdir()
    (d / "nonempty" / "notes.txt").write_text("keep me")
    (d / "corrupt.nc.parts").mkdir()
    (d / "corrupt.nc.parts" / "manifest.json").write_text("{bad json")
    (d / "other.nc.parts").mkdir()
    (d / "other.nc.parts" / "manifest.json").write_text(json.dumps(
        {"format": "bifurc sweep parts", "version": 8, "arguments": {"params": {"V": 80.0}}}))
    lock = os.open(d / "busy.nc.lock", os.O_RDWR | os.O_CREAT)
    fcntl.flock(lock, fcntl.LOCK_EX)         # another run holds busy.nc (X11)
    full = d / "full"
    out = {"d": str(d), "ro": _read_only_folder(d), "full": str(full) if _mount_tmpfs(full, "size=64k") else None}
    with socket_port() as port:
        out["port"] = str(port)
    yield out
    os.close(lock)
    for m in (d / "ro", full):
        if m.is_mount():
            subprocess.run(["umount", str(m)], capture_output=True)


@contextlib.contextmanager
def socket_port():
    import socket
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    yield port       # closed: nothing listens there


def _run(argv, hang=HANG):
    """(exit code, stdout, stderr) of one command line; (None, "", "timeout") for a hang."""
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    try:
        r = subprocess.run([sys.executable, "-m", "bifurc", *argv], env=env, capture_output=True, text=True,
                           timeout=hang)
        return r.returncode, r.stdout, r.stderr
    except subprocess.TimeoutExpired:
        return None, "", "timeout"


@pytest.fixture(scope="module")
def results(files, request):
    """Every selected CLI row run once, two at a time: {id: (code, stdout, stderr)}."""
    slow = request.config.getoption("--runslow")
    rows = {r[0]: [a.format(**files) for a in r[1]] for r in CLI + CLI4
            if (slow or r[0] in QUICK | QUICK4) and not ("{full}" in " ".join(r[1]) and files["full"] is None)}
    hangs = [HANG_COMPUTING if "slow" in r[4:] else HANG for r in CLI + CLI4 if r[0] in rows]
    with ThreadPoolExecutor(max_workers=2) as pool:
        done = dict(zip(rows, pool.map(_run, rows.values(), hangs)))
    return done


def _marks(row):
    return [] if row[0] in QUICK | QUICK4 else [pytest.mark.slow]


@pytest.mark.parametrize("row", [pytest.param(r, id=r[0], marks=_marks(r)) for r in CLI + CLI4])
def test_cli_row(row, results, files):
    rid, argv, code, stream = row[:4]
    if "{full}" in " ".join(argv) and files["full"] is None:
        pytest.skip("no small tmpfs can be mounted here; the disk-full path is tested in-process below")
    got, out, err = results[rid]
    assert got == code, (rid, got, err)
    assert "Traceback" not in err and "Traceback" not in out, (rid, err)
    lines = err.strip().splitlines()
    if stream is None:
        assert not lines, (rid, err)
    elif stream == "progress":
        assert lines, (rid, err)
    else:
        assert len(lines) == 1 and lines[0].startswith(f"bifurc: {stream}:"), (rid, err)


def test_nothing_is_left_behind_by_the_refusals(results, files):
    d = Path(files["d"])
    assert (d / "exists.nc").read_text() == "keep me" and (d / "nonempty" / "notes.txt").read_text() == "keep me"
    assert (d / "corrupt.nc.parts" / "manifest.json").read_text() == "{bad json"   # nothing lost
    assert not (d / "adir.parts").exists() and not list((d / "adir").iterdir())
    assert not (d / "o.nc").exists() and not (d / "c90dir").exists() and not (d / "m.nc").exists()


def test_the_corpus_holds_every_row_of_both_reviews():
    """Review 3's 111 command lines but the four that need a signal or a second run (X08, X12, X13, X15:
    tests/test_sweep.py, tests/test_interrupt.py) and all its 60 API calls; review 4's 36 command lines and
    24 API calls (NA01-NA25 without NA24, a typo in the review). Each id once."""
    cli = [r[0] for r in CLI + CLI4]
    api = [r[0] for r in API + API4]
    assert len(cli) == len(set(cli)) and len(api) == len(set(api))
    review3 = {f"C{i:02d}" for i in range(1, 97)} | {f"X{i:02d}" for i in range(1, 16)}
    assert set(cli) == review3 - {"X08", "X12", "X13", "X15"} | {f"N{i:02d}" for i in range(1, 37)}
    assert set(api) == {f"A{i:02d}" for i in range(1, 61)} | {f"NA{i:02d}" for i in range(1, 26)} - {"NA24"}
    assert (len(cli), len(api)) == (107 + 36, 60 + 24)


@pytest.fixture(scope="module")
def api_scope(files):
    d = files["d"]
    return {"bifurc": bifurc, "maps": maps, "np": np, "folder": d, "ro": files["ro"],
            "d": bifurc.load(f"{d}/diagram.nc"), "h": bifurc.load(f"{d}/run.nc"), "m": bifurc.load(f"{d}/map.nc")}


@pytest.mark.parametrize("row", [pytest.param(r, id=r[0]) for r in API + API4])
def test_api_row(row, api_scope):
    rid, code, expected = row[:3]
    if expected is None:           # a call the review found right to run (A07, A40, A57)
        assert eval(code, dict(api_scope)) is not None, rid  # noqa: S307 - the corpus is this repository's own data
        return
    with pytest.raises(Exception) as info:
        eval(code, dict(api_scope))  # noqa: S307 - the corpus is this repository's own data
    names = [c.__name__ for c in type(info.value).__mro__]
    assert expected in names, (rid, type(info.value).__name__, str(info.value))
    text = str(info.value).strip()
    assert text and "\n" not in text and "Traceback" not in text, (rid, text)


def test_a_disk_filling_mid_run_is_one_line_and_keeps_the_parts(tmp_path, monkeypatch, capsys):
    """The second part of a sweep fails to write (netCDF's "HDF error" on a full disk): one line naming
    the full disk, exit 2, the first part kept for the rerun."""
    import xarray as xr

    import bifurc.storage.files as files_mod
    real, calls = xr.Dataset.to_netcdf, {"n": 0}

    def failing(self, path, *a, **kw):
        calls["n"] += 1
        if calls["n"] == 2:
            raise RuntimeError("NetCDF: HDF error")
        return real(self, path, *a, **kw)
    monkeypatch.setattr(xr.Dataset, "to_netcdf", failing)
    real_usage = shutil.disk_usage     # full once the failing write has happened (not at the check before)
    monkeypatch.setattr(files_mod.shutil, "disk_usage", lambda p: shutil._ntuple_diskusage(10**6, 10**6 - 10, 10)
                        if calls["n"] >= 2 else real_usage(p))
    out = tmp_path / "x.nc"
    code = main(["diagram", "--preset", "matlab-listing", "--set", "V=90", "--from", "2", "--to", "10", "--n", "8",
                 "--transient", "5", "--record", "4", "--no-lyapunov", "--quiet", "--workers", "1",
                 "--batch-size", "1", "-o", str(out)])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and "no space left on device" in err, err
    assert err.startswith(f"bifurc: error: cannot write {tmp_path}/x.nc.parts/"), err
    assert len(list((tmp_path / "x.nc.parts").glob("*.nc"))) == 1 and not out.exists()


def test_the_free_space_check_refuses_before_computing(tmp_path, monkeypatch, capsys):
    import bifurc.storage.files as files_mod
    monkeypatch.setattr(files_mod.shutil, "disk_usage", lambda p: shutil._ntuple_diskusage(10**9, 10**9 - 1000, 1000))
    import bifurc.sweeps.sweep as sweep_mod
    monkeypatch.setattr(sweep_mod, "sweep", lambda *a, **k: pytest.fail("computed before refusing"))
    assert main([*D, "-o", str(tmp_path / "x.nc")]) == 2
    err = capsys.readouterr().err
    assert "its file system has 0.001 MB free" in err, err
    assert not list(tmp_path.iterdir())


def test_a_normal_job_is_within_the_budget_and_the_estimated_file_is_an_upper_bound(tmp_path):
    """The README's main job: not refused; its estimated memory bounds the written file from above. (The
    estimated run time against a measured one is a wall time: benchmarks/wall_times.py prints that ratio.)"""
    import argparse

    from bifurc.commands._guards import check_budget
    from bifurc.run.guard import estimate
    args = argparse.Namespace(transient=300, record=100, workers=1, yes=False)
    est = check_budget(args, 81)
    assert est["memory"] < 50e6 and est["seconds"] < 60
    bifurc.sweep("thesis-1dof", "relay_hz", np.linspace(2, 10, 9), preset="matlab-listing", params={"V": 90},
                 transient=300, record=100, progress=False, workers=1, path=tmp_path / "m.nc")
    assert (tmp_path / "m.nc").stat().st_size < estimate(9, 300, 100, 1)["file"]


def test_yes_runs_what_the_budget_refuses(monkeypatch, tmp_path, capsys):
    import bifurc.run.guard as guards
    monkeypatch.setattr(guards, "available_memory", lambda: 1000.0)   # a machine with 1 kB free
    argv = [*D, "--n", "1", "--from", "5", "--to", "5", "-o", str(tmp_path / "y.nc")]
    assert main(argv) == 2 and "pass --yes" in capsys.readouterr().err
    assert main([*argv, "--yes"]) == 0 and (tmp_path / "y.nc").exists()



def test_the_worst_case_counts_the_method_s_tangent_trajectories(monkeypatch):
    """Every value extended to its budget runs budget periods on each of its K tangent trajectories (its own and
    K - 1 copies): 1000 values x 6000 periods x K at the guard's 1e-4 s per period on one worker is 600 K s, so a
    Diagram with 8 trajectories is refused quoting 4800 s (1.33 h), twice the 2400 s of one with 4 (the guard used to
    count the default 4 whatever the method said)."""
    import re

    import bifurc.run.guard as guards
    from maps.parameters import ParameterError
    monkeypatch.setattr(guards, "MAX_HOURS", 1e-6)        # every job over the limit: the refusal quotes the estimate
    quoted = {}
    for k in (4, 8):
        with pytest.raises(ParameterError) as err:
            bifurc.sweep("thesis-1dof", "relay_hz", np.linspace(2, 10, 1000),
                         bifurc.Diagram(budget=6000, trajectories=k), run=bifurc.Run(workers=1, progress=False))
        found = re.search(r"up to ([0-9.e+]+) (s|h|days)", str(err.value))
        assert found, str(err.value)
        number, unit = found.groups()
        quoted[k] = float(number) * {"s": 1.0, "h": 3600.0, "days": 86400.0}[unit]
    assert quoted[4] == pytest.approx(1000 * 6000 * 4 * 1e-4, rel=1e-2)
    assert quoted[8] == pytest.approx(1000 * 6000 * 8 * 1e-4, rel=1e-2)
