"""Ctrl-C latency of the command line (issue 48's "stops within a second"; a benchmark, not a test: a loaded
machine may delay any process, and no test asserts a wall time).

    python benchmarks/interrupt.py [--repeat 5] [--no-record]

Runs the tests' interrupted diagram (tests/test_interrupt.py's grid: thesis-1dof, `matlab-listing`, 90 V,
800 values of relay_hz in 2-10 Hz, 100 + 30 relay periods, budget 1000, 2 workers) as a terminal's foreground
command, sends SIGINT to its process group once the first chunk is kept, and times the signal to the process'
end; ``--repeat`` runs, each figure their median and largest, against the 1 s target.
"""
from __future__ import annotations

import argparse
import os
import signal
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
GRID = ["--scene", "thesis-1dof", "--preset", "matlab-listing", "--set", "V=90", "--from", "2", "--to", "10",
        "--n", "800", "--transient", "100", "--record", "30", "--budget", "1000", "--quiet", "--workers", "2"]


def _as_in_a_terminal():
    signal.signal(signal.SIGINT, signal.SIG_DFL)       # a terminal's foreground command: SIGINT at its default


def one(folder: Path) -> float:
    """Seconds from a Ctrl-C (SIGINT to the group) after the first kept chunk to the command's end."""
    out = folder / "d.nc"
    parts = Path(str(out) + ".parts")
    proc = subprocess.Popen([sys.executable, "-m", "bifurc", "diagram", *GRID, "-o", str(out)],
                            env=dict(os.environ, PYTHONPATH=str(ROOT)), stderr=subprocess.PIPE, text=True,
                            start_new_session=True, preexec_fn=_as_in_a_terminal)
    while proc.poll() is None and not (parts.is_dir() and any(parts.glob("*.nc"))):
        time.sleep(0.02)
    sent = time.monotonic()
    os.killpg(proc.pid, signal.SIGINT)
    proc.communicate(timeout=60)
    if proc.returncode != 130:
        raise SystemExit(f"the command ended with {proc.returncode}, not 130 (interrupted)")
    return time.monotonic() - sent


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--no-record", action="store_true")
    a = ap.parse_args(argv)
    sys.path.insert(0, str(Path(__file__).parent))
    from record import Run
    run = Run("Ctrl-C latency of bifurc diagram", command=f"python benchmarks/interrupt.py --repeat {a.repeat}")
    seconds = []
    for k in range(a.repeat):
        with tempfile.TemporaryDirectory() as d:
            seconds.append(one(Path(d)))
        print(f"run {k + 1}: {seconds[-1]:.2f} s", flush=True)
    med, worst = statistics.median(seconds), max(seconds)
    print(f"Ctrl-C to exit: median {med:.2f} s, largest {worst:.2f} s (target 1 s)")
    run.figure("Ctrl-C to exit, median", round(med, 3), "s", target="1 s")
    run.figure("Ctrl-C to exit, largest", round(worst, 3), "s", target="1 s")
    if not a.no_record:
        print(run.write())
    return 0


if __name__ == "__main__":
    sys.exit(main())
