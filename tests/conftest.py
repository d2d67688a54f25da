import pytest


def pytest_addoption(parser):
    parser.addoption("--runslow", action="store_true", default=False, help="also run tests marked slow")


def pytest_collection_modifyitems(config, items):
    if config.getoption("--runslow"):
        return
    skip = pytest.mark.skip(reason="slow: run with --runslow")
    for item in items:
        if "slow" in item.keywords:
            item.add_marker(skip)


def completed_values(parts) -> int:
    """Values saved in a resume folder (one netCDF file per completed chunk)."""
    import xarray as xr
    n = 0
    for f in parts.glob("*.nc"):
        with xr.open_dataset(f) as ds:
            n += ds.sizes["value"]
    return n


def kill_when_parts(argv, parts, at_least=2, timeout=60, env=None) -> int:
    """Run ``argv`` in a child process, SIGKILL it once ``parts`` (a resume folder) holds
    ``at_least`` completed values (or after ``timeout`` s, or when it ends); returns the values then."""
    import os
    import signal
    import subprocess
    import time
    count = lambda: completed_values(parts)  # noqa: E731
    proc = subprocess.Popen(argv, env=env)
    try:
        deadline = time.monotonic() + timeout
        while count() < at_least and time.monotonic() < deadline and proc.poll() is None:
            time.sleep(0.01)
    finally:
        os.kill(proc.pid, signal.SIGKILL)
        proc.wait()
    return count()
