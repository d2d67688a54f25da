"""Evaluate a job over many parameter values: serial, a process pool, or a Dask cluster.

The job is a picklable callable ``job(value)``, optionally with ``job.run_many(values)``
(several values at once, e.g. heyoka's batch mode) and ``job.warm()`` (compile once per
process).  :func:`map_values` evaluates it over a grid in chunks of contiguous values:

- ``workers=1`` and no ``scheduler``: a plain loop in this process;
- ``workers=N``: a :class:`WorkerPool` (processes whose initializer warms the job once each),
  opened for the call, or ``pool=`` one already open that stays open for other tasks
  (:meth:`WorkerPool.submit`, :func:`submit_all`: e.g. a sweep's grazing bisections);
- ``scheduler="tcp://host:port"`` or a ``dask.distributed.Client``: chunks go to the Dask
  workers, each warmed up front with ``client.run``.

Results come back per chunk to ``on_chunk(start, results)`` (stream them to disk) and,
unless ``collect=False``, as one list in grid order.
"""
from __future__ import annotations

import math
import os
import time as _time
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait

import numpy as np

from maps.parameters import ParameterError

#: a worker process pays its start and one compilation (~1-2 s) before it helps: below this many
#: values per worker the default stays in this process
MIN_VALUES_PER_WORKER = 16


def available_cores() -> int:
    """Cores this process may run on (its CPU affinity where the OS reports it)."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


def default_workers(n_values: int, per_worker: int = MIN_VALUES_PER_WORKER) -> int:
    """Every available core, but at least ``per_worker`` values per worker (1: this process); a task declares its
    own grain (a diagram value: MIN_VALUES_PER_WORKER; a census value, far longer: fewer)."""
    return max(1, min(available_cores(), n_values // per_worker))


#: exit code of a worker process that found itself re-running a script without a main guard
GUARD_EXIT = 86


class MainGuardError(RuntimeError):
    """Worker processes could not start: the script that started them has no main guard."""


def _warm(job):
    """Process initializer: Ctrl-C is the parent's to handle (it stops the workers, see
    :meth:`WorkerPool.terminate`); compile the job's integrator once in this process."""
    import signal
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    if job is not None and hasattr(job, "warm"):
        job.warm()
    return os.getpid()


def _refuse_unguarded_script() -> None:
    """In a worker process that is re-running the script which started it (a script without
    ``if __name__ == "__main__":``, re-imported as ``__mp_main__`` by the spawn start method), exit at
    once with :data:`GUARD_EXIT` instead of starting workers of its own; the parent then raises
    :class:`MainGuardError`."""
    import sys
    if "__mp_main__" not in sys.modules:
        return
    frame = sys._getframe(1)
    while frame is not None:
        if frame.f_globals.get("__name__") == "__mp_main__" and frame.f_code.co_name == "<module>":
            raise SystemExit(GUARD_EXIT)
        frame = frame.f_back


def _guard_message() -> str:
    import sys
    script = getattr(sys.modules.get("__main__"), "__file__", None) or "the script"
    return (f"worker processes could not start: they re-import {script}, which starts a sweep at its top level; "
            'put the script\'s code under `if __name__ == "__main__":`, or pass workers=1')


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


class WorkerPool:
    """``workers`` processes, each warmed once with ``job`` (``job.warm()``), kept open for many
    tasks: chunks of values (:meth:`map_values`) and any picklable call (:meth:`submit`).
    A context manager; closing waits for the tasks in flight.

    ``mp_context``: start method ("spawn" is safe with heyoka's threads); with it, processes
    start at the first task.
    """

    def __init__(self, job, workers: int, mp_context: str = "spawn"):
        import multiprocessing as mp
        if workers < 1:
            raise ParameterError(f"workers = {workers}: need at least 1")
        _refuse_unguarded_script()
        self.job, self.workers, self._seen = job, int(workers), {}
        self._pool = ProcessPoolExecutor(max_workers=self.workers, mp_context=mp.get_context(mp_context),
                                         initializer=_warm, initargs=(job,))

    def __enter__(self):
        return self

    def __exit__(self, exc_type, *exc):
        if exc_type is not None and issubclass(exc_type, KeyboardInterrupt):
            self.terminate()
        else:
            self.close()

    def close(self) -> None:
        self._pool.shutdown(wait=True)

    def terminate(self) -> None:
        """Stop at once (Ctrl-C, a kernel interrupt): cancel the tasks not started and end the worker
        processes with the chunks they are running (their results are lost; finished ones were kept)."""
        procs = list(self._processes().values())
        self._pool.shutdown(wait=False, cancel_futures=True)
        for proc in procs:
            proc.terminate()
        for proc in procs:
            proc.join(1)
        # the executor's manager thread closes its wake-up pipe as it ends; until it has, the interpreter's exit hook
        # (concurrent.futures.process._python_exit) may write into the pipe while it closes and print "Exception
        # ignored ... Bad file descriptor" under the one-line interrupt message (CPython 3.11: a check-then-send race)
        manager = getattr(self._pool, "_executor_manager_thread", None)
        if manager is not None:
            manager.join(1)

    def _processes(self) -> dict:
        """The pool's worker processes now, {pid: Process} (the executor's private table; empty if it has none)."""
        return getattr(self._pool, "_processes", None) or {}

    def submit(self, fn, *args) -> Future:
        """Run ``fn(*args)`` on a worker (``fn`` and ``args`` picklable); returns its Future."""
        return self._pool.submit(fn, *args)

    def map_values(self, values, chunk_size: int | None = None, on_chunk=None, collect: bool = True):
        """:func:`map_values` of this pool's job on its workers."""
        return map_values(self.job, values, chunk_size=chunk_size, on_chunk=on_chunk, collect=collect, pool=self)

    def _run_chunks(self, values, ranges, take):
        """Every ``(start, stop)`` range of ``values`` through the job, at most 2 chunks per worker in
        flight (bounded memory); ``take(start, results)`` as each completes."""
        pending, running = ranges[::-1], {}
        while pending or running:
            while pending and len(running) < 2 * self.workers:
                a, b = pending.pop()
                running[self.submit(_run_chunk, self.job, values[a:b])] = a
                self._seen.update(self._processes())      # their exit codes, if the pool breaks
            finished = _first_done(running)
            for fut in finished:
                take(running.pop(fut), self._result(fut))

    def _result(self, fut):
        """A chunk's results; a pool broken by workers that re-ran an unguarded script: :class:`MainGuardError`."""
        from concurrent.futures.process import BrokenProcessPool
        try:
            return fut.result()
        except BrokenProcessPool:
            self._seen.update(self._processes())
            for proc in self._seen.values():
                proc.join(EXIT_WAIT)
            if GUARD_EXIT in [proc.exitcode for proc in self._seen.values()]:
                raise MainGuardError(_guard_message()) from None
            raise


#: seconds to wait for each worker of a broken pool to exit before reading its exit code (only a broken pool
#: waits): the full test run on 2 cores once ended the main-guard test in a bare BrokenProcessPool where runs of
#: that test alone give the main-guard error; a worker still exiting after the 1 s waited then is one possible
#: cause (not established), and the pool's processes are read again there in case one was missed
EXIT_WAIT = 10.0

#: seconds a wait for workers blocks before the main thread looks at signals again
TICK = 0.2


def _first_done(futures) -> set:
    """The finished ones of ``futures``, once at least one is: waited for in slices of :data:`TICK` seconds.  A
    Ctrl-C the kernel hands to one of the pool's threads is run by the main thread only when it wakes, and a wait
    without a timeout does not wake (the diagram command ignored Ctrl-C until a chunk finished, 10 s and more on a
    loaded machine)."""
    while True:
        finished, _ = wait(futures, timeout=TICK, return_when=FIRST_COMPLETED)
        if finished:
            return finished


def result_of(fut):
    """``fut.result()``, waited for as :func:`_first_done` waits (so that Ctrl-C stops the wait)."""
    _first_done([fut])
    return fut.result()


def timed(fn, *args):
    """``(fn(*args), seconds it took)``: a task that reports its own run time from any process."""
    clock = _time.perf_counter()
    out = fn(*args)
    return out, _time.perf_counter() - clock


def submit_all(tasks, pool: WorkerPool | None = None) -> list:
    """Start ``tasks`` [(cost, fn, args), ...] in decreasing ``cost`` (the longest first, so the last to
    start are short): on ``pool``'s workers, or without a pool here and now, one after the other.
    Returns a Future per task, in the order of ``tasks`` (an exception is raised by its ``result()``)."""
    futures = [None] * len(tasks)
    for k in sorted(range(len(tasks)), key=lambda k: -tasks[k][0]):
        _, fn, args = tasks[k]
        if pool is not None:
            futures[k] = pool.submit(fn, *args)
            continue
        futures[k] = Future()
        try:
            futures[k].set_result(fn(*args))
        except Exception as exc:  # noqa: BLE001 - handed to the caller by result(), as from a worker
            futures[k].set_exception(exc)
    return futures


def map_values(job, values, workers: int = 1, scheduler=None, chunk_size: int | None = None,
               on_chunk=None, collect: bool = True, mp_context: str = "spawn", pool: WorkerPool | None = None):
    """Evaluate ``job(value)`` for every value; returns the results in grid order.

    ``scheduler``: a Dask scheduler address or ``dask.distributed.Client`` (then ``workers``
    is ignored).  ``pool``: an open :class:`WorkerPool` warmed with this ``job`` (its job runs,
    ``workers`` and ``mp_context`` are its own; it stays open).  ``on_chunk(start, results)`` is called as each
    chunk completes (any order).  ``mp_context``: start method of a process pool opened for this call
    ("spawn" is safe with heyoka's threads).
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
    elif pool is not None:
        pool._run_chunks(values, _ranges(job, n, pool.workers, chunk_size), take)
    elif workers == 1:
        size = chunk_size or max(1, n)
        for a, b in chunks_of(n, size):
            take(a, _run_chunk(job, values[a:b]))
    else:
        with WorkerPool(job, workers, mp_context) as own:
            own._run_chunks(values, _ranges(job, n, workers, chunk_size), take)
    return out


def _ranges(job, n, workers, chunk_size):
    """Chunks of a process pool: ``chunk_size`` values each, else guided (shrinking toward the end)."""
    return chunks_of(n, chunk_size) if chunk_size else guided_chunks(n, workers, getattr(job, "batch_size", 1))


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
