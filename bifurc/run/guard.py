"""Checks before a grid computes: the planned work fits the machine (the API and the command line alike).

The budget is a cheap model, evaluated before any array of results exists:

- memory: the bytes of one value's results (the sweep schema's rows, :func:`bytes_per_value`)
  held about :data:`MEMORY_COPIES` times (results, dataset, file buffer), times the values;
- run time: (transient + record) periods per value at :data:`SECONDS_PER_PERIOD`, shared
  by the workers (the planned work); at most the budget times the tangent trajectories per value
  (every value extended to its budget: ``seconds_max``, stated in the refusal).

A job over the machine's available memory or over :data:`MAX_HOURS` is refused with its
estimate unless allowed (``Run(allow_large=True)``, ``--yes``).
"""
from __future__ import annotations

import os

from maps.parameters import ParameterError


#: seconds of computation per value per relay period: 7.3e-5 s measured on the 2-core development
#: machine (`bifurc diagram --scene thesis-1dof --preset matlab-listing --set V=90 --from 2 --to 10
#: --n 81 --workers 1`: values_seconds 2.56 s over 35,236 relay periods, commit 349e61d), rounded up
SECONDS_PER_PERIOD = 1e-4
#: the longest job run without --yes [h]
MAX_HOURS = 24.0
#: copies of a value's results held at once (ValueResult, the dataset, netCDF's write buffer)
MEMORY_COPIES = 3
#: impacts stored per recorded relay period (the sweep's impact dimension is 4 x record)
IMPACTS_PER_STEP = 4
#: bytes of a netCDF file beyond its values (HDF5 headers of ~50 variables): a 4-value diagram with
#: --record 10 is 180,879 bytes for 9 kB of values
FILE_OVERHEAD = 256_000
#: states sampled per stroboscopic point (the 2-DOF scenes have up to 6)
STATES = 6


def bytes_per_value(record: int) -> int:
    """Bytes of one value's results: each row of the sweep schema (``step``: record entries,
    ``impact``: IMPACTS_PER_STEP x record, texts 32 bytes) and the sampled states."""
    import numpy as np

    from ..storage.schema import SWEEP
    sizes = {"step": record, "impact": IMPACTS_PER_STEP * record}
    total = STATES * (record + 1) * 8
    for v in SWEEP:
        n = 1
        for d in v.dims[2:]:
            n *= sizes.get(d, 1)
        total += n * (32 if v.dtype is str else np.dtype(v.dtype).itemsize)
    return total


def available_memory() -> float:
    """Bytes the machine can give now (MemAvailable of /proc/meminfo; else the physical memory)."""
    from ..storage.files import proc_field
    kib = proc_field("/proc/meminfo", "MemAvailable")
    if kib is not None:
        return float(kib) * 1024
    try:
        return float(os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
    except (ValueError, OSError, AttributeError):
        return float("inf")


def estimate(n_values: int, transient: int, record: int, workers, budget: int | None = None,
             trajectories: int | None = None) -> dict:
    """{"values", "memory" [bytes], "file" [bytes], "seconds", "seconds_max"} of a grid of ``n_values``
    (seconds: the planned work; seconds_max: every value extended to ``budget`` relay periods with its
    ``trajectories`` - 1 tangent copies; None: the defaults)."""
    from ..labels.vocabulary import BUDGET, TRAJECTORIES
    per_value = bytes_per_value(max(int(record), 1))
    workers = max(1, int(workers or os.cpu_count() or 1))
    return {"values": n_values, "memory": n_values * (MEMORY_COPIES * per_value + 32),
            "file": n_values * per_value + FILE_OVERHEAD,
            "seconds": n_values * (max(transient, 0) + max(record, 0)) * SECONDS_PER_PERIOD / workers,
            "seconds_max": n_values * (budget or BUDGET) * (trajectories or TRAJECTORIES) * SECONDS_PER_PERIOD
            / workers}


def _duration(s: float) -> str:
    return f"{s / 86400:.3g} days" if s >= 86400 else f"{s / 3600:.3g} h" if s >= 3600 else f"{s:.3g} s"


def check_size(n_values: int, transient: int, record: int, workers, budget, allow: bool, what: str = "values",
               remedy: str = "reduce the values, transient or record, or pass allow_large=True to run it",
               trajectories: int | None = None) -> dict:
    """Refuse (one line) a job whose estimated memory exceeds the available memory or whose run time
    exceeds MAX_HOURS, unless ``allow``; returns the estimate (``trajectories``: the method's tangent
    trajectories per value, which the worst case multiplies)."""
    from ..storage.files import size_text
    est = estimate(n_values, transient, record, workers, budget, trajectories)
    free = available_memory()
    over = []
    if est["memory"] > free:
        over.append(f"about {size_text(est['memory'])} of memory, {size_text(free)} available")
    if est["seconds"] > MAX_HOURS * 3600:
        over.append(f"about {_duration(est['seconds'])} of computation (up to {_duration(est['seconds_max'])} if "
                    f"every {what[:-1]} runs to its budget; a time budget bounds it), over the {MAX_HOURS:g} h limit")
    if over and not allow:
        raise ParameterError(f"{n_values:,} {what} need {' and '.join(over)} (estimate); {remedy}")
    return est


