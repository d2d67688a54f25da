"""Evaluate a job over many parameter values: serial, a process pool, or a Dask cluster.

The job is a picklable callable ``job(value)``, optionally with ``job.run_many(values)``
(several values at once, e.g. heyoka's batch mode) and ``job.warm()`` (compile once per
process).  :func:`map_values` evaluates it over a grid in chunks of contiguous values:

- ``workers=1`` and no ``scheduler``: a plain loop in this process;
- ``workers=N``: a ``ProcessPoolExecutor`` whose initializer warms the job once per worker;
- ``scheduler="tcp://host:port"`` or a ``dask.distributed.Client``: chunks go to the Dask
  workers, each warmed up front with ``client.run``.

Results come back per chunk to ``on_chunk(start, results)`` (stream them to disk) and,
unless ``collect=False``, as one list in grid order.
"""
from __future__ import annotations

import math
import os
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait

import numpy as np

from maps.parameters import ParameterError

__all__ = ["map_values", "chunks_of", "guided_chunks", "available_cores", "default_workers", "MIN_VALUES_PER_WORKER"]

#: a worker process pays its start and one compilation (~1-2 s) before it helps: below this many
#: values per worker the default stays in this process
MIN_VALUES_PER_WORKER = 16


def available_cores() -> int:
    """Cores this process may run on (its CPU affinity where the OS reports it)."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


def default_workers(n_values: int) -> int:
    """Every available core, but at least MIN_VALUES_PER_WORKER values per worker (1: this process)."""
    return max(1, min(available_cores(), n_values // MIN_VALUES_PER_WORKER))


def _warm(job):
    """Process initializer: compile the job's integrator once in this process."""
    if job is not None and hasattr(job, "warm"):
        job.warm()
    return os.getpid()


def _run_chunk(job, values):
    if hasattr(job, "run_many"):
        return job.run_many(values)
    return [job(v) for v in values]


def chunks_of(n: int, size: int):
    """``(start, stop)`` index ranges covering ``range(n)`` in pieces of ``size``."""
    return [(i, min(n, i + size)) for i in range(0, n, size)]


def _default_chunk(n, workers, multiple=1):
    size = max(1, min(64, math.ceil(n / (8 * max(1, workers)))))
    return math.ceil(size / multiple) * multiple


def guided_chunks(n: int, workers: int, multiple: int = 1, largest: int = 64):
    """``(start, stop)`` ranges covering ``range(n)`` that shrink toward the end (guided
    self-scheduling): each is about the remainder / (4 workers), at most ``largest`` and at least
    ``multiple`` (the batch lanes) values, so that the last chunks finish together instead of one
    worker running a long last chunk while the others wait."""
    out, start = [], 0
    while start < n:
        size = min(largest, math.ceil((n - start) / (4 * max(1, workers))))
        size = max(multiple, math.ceil(size / multiple) * multiple)
        out.append((start, min(n, start + size)))
        start += size
    return out


def map_values(job, values, workers: int = 1, scheduler=None, chunk_size: int | None = None,
               on_chunk=None, collect: bool = True, mp_context: str = "spawn"):
    """Evaluate ``job(value)`` for every value; returns the results in grid order.

    ``scheduler``: a Dask scheduler address or ``dask.distributed.Client`` (then ``workers``
    is ignored).  ``on_chunk(start, results)`` is called as each chunk completes (any order).
    ``mp_context``: start method of the process pool ("spawn" is safe with heyoka's threads).
    """
    values = np.asarray(values, dtype=float).ravel()
    n = values.size
    if workers < 1:
        raise ParameterError(f"workers = {workers}: need at least 1")
    out = [None] * n if collect else None

    def take(start, results):
        if on_chunk is not None:
            on_chunk(start, results)
        if collect:
            out[start:start + len(results)] = results

    if scheduler is not None:
        _map_dask(job, values, scheduler, chunk_size, take)
    elif workers == 1:
        size = chunk_size or max(1, n)
        for a, b in chunks_of(n, size):
            take(a, _run_chunk(job, values[a:b]))
    else:
        import multiprocessing as mp
        ranges = chunks_of(n, chunk_size) if chunk_size else guided_chunks(n, workers, getattr(job, "batch_size", 1))
        with ProcessPoolExecutor(max_workers=workers, mp_context=mp.get_context(mp_context),
                                 initializer=_warm, initargs=(job,)) as pool:
            pending = ranges[::-1]
            running = {}
            while pending or running:      # at most 2 chunks per worker in flight: bounded memory
                while pending and len(running) < 2 * workers:
                    a, b = pending.pop()
                    running[pool.submit(_run_chunk, job, values[a:b])] = a
                finished, _ = wait(running, return_when=FIRST_COMPLETED)
                for fut in finished:
                    take(running.pop(fut), fut.result())
    return out


def _map_dask(job, values, scheduler, chunk_size, take):
    from dask.distributed import Client, as_completed as dask_completed
    own = not isinstance(scheduler, Client)
    client = Client(scheduler) if own else scheduler
    try:
        n_workers = max(1, len(client.scheduler_info().get("workers", {})))
        client.run(_warm, job)                         # compile once per worker, up front
        size = chunk_size or _default_chunk(values.size, n_workers, getattr(job, "batch_size", 1))
        starts = [a for a, _ in chunks_of(values.size, size)]
        futures = client.map(_run_chunk, [job] * len(starts),
                             [values[a:b] for a, b in chunks_of(values.size, size)], pure=False)
        index = {f.key: a for f, a in zip(futures, starts)}
        for fut in dask_completed(futures):
            take(index[fut.key], fut.result())
            fut.release()
    finally:
        if own:
            client.close()
