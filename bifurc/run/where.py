"""Where an analysis runs: the :class:`Run` (workers, scheduler, output, progress, time budget)."""
from __future__ import annotations

from dataclasses import dataclass

from .settings import Settings, setting


@dataclass(frozen=True)
class Run(Settings):
    """Where and how an analysis runs; the same object for a diagram, a regime map and a census.

    With ``path`` every completed chunk of points is kept in ``<path>.parts/`` (one resume store, one manifest:
    the problem, the method's settings, the points and the code version): an interrupted run loses nothing and the
    same call resumes.  The result is written to ``path`` atomically and the parts are then removed.
    """

    workers: int | None = setting(None, "worker processes (default: every available core; a problem that does not "
                                  "pickle runs here)", low=1, high=1024, whole=True, optional=True, kind=int)
    scheduler: object = setting(None, "a Dask scheduler address tcp://host:port or a distributed.Client (then "
                                "workers is ignored)", optional=True, kind=str)
    path: object = setting(None, "netCDF file to write; completed points are kept in <path>.parts/ for resuming",
                           optional=True, cli="", kind=str)
    overwrite: bool = setting(False, "replace an existing output file", cli="")
    progress: bool = setting(True, "a progress bar (text, or a widget in Jupyter)", cli="")
    time_budget: float | None = setting(None, "wall-clock seconds for the whole job (default: no limit); once "
                                        "spent no point is extended further (the one setting whose result depends "
                                        "on the machine)", unit="s", low=1e-3, high=1e9, optional=True, kind=float)
    chunk_size: int | None = setting(None, "points per task (default: automatic); with path, an interruption loses "
                                     "at most the chunks in flight", low=1, high=1e9, whole=True, optional=True,
                                     cli="", kind=int)
    allow_large: bool = setting(False, "run a job estimated to need more memory than is available or more than a "
                                "day (refused otherwise, with its estimate)", cli="--yes")
