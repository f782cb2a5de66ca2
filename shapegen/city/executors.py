"""Where lots run: worker processes of this machine (the default) or a Dask cluster.

Both yield one record per lot as each finishes (:func:`shapegen.city.work.run_lot`), in the
order they finish.

Local processes. A small pool of our own rather than ``concurrent.futures``: a lot that is
stuck inside one long call (a QP solve) past its timeout is stopped by killing its worker, which
is then replaced, and a worker that dies (out of memory, a crash in a native library) costs one
row, not the batch; a standard pool breaks on either. Each worker is ``python -m
shapegen.city.worker`` (:mod:`shapegen.city.worker`), so it never re-imports the caller's
script, runs the numerical libraries on one thread (the lots are the parallelism) and is in a
session of its own, so Ctrl-C reaches only the parent, which stops the workers.

Dask. ``distributed.Client(address)`` on an existing scheduler; each lot is one task. A lot's
timeout is kept by the lot itself (it checks its time after every search step and every
derivation has a time limit), since a Dask task cannot be killed from outside.
"""

from __future__ import annotations

__all__ = ["DaskCluster", "LocalProcesses", "default_workers"]

import contextlib
import os
import time
from collections.abc import Iterable, Iterator

from shapegen.city.work import (
    CitySettings,
    LotTask,
    lot_seed,
    new_record,
    run_lot,
    timeout_message,
)
from shapegen.errors import ShapegenError

# A lot whose worker has not answered this long after its timeout is stopped from outside, s.
KILL_GRACE_S = 2.0
# The numerical libraries' thread counts in a worker.
_ONE_THREAD = {
    name: "1"
    for name in (
        "OMP_NUM_THREADS",
        "MKL_NUM_THREADS",
        "OPENBLAS_NUM_THREADS",
        "NUMEXPR_NUM_THREADS",
        "VECLIB_MAXIMUM_THREADS",
    )
}


def default_workers() -> int:
    """The cores this process may use."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # not on Linux
        return max(1, os.cpu_count() or 1)


class _Worker:
    """One ``python -m shapegen.city.worker`` process and the lot it has (None when idle)."""

    def __init__(self, settings: CitySettings):
        import subprocess
        import sys

        from shapegen.city.worker import write_message

        env = {**os.environ, **_ONE_THREAD}
        self.process = subprocess.Popen(
            [sys.executable, "-m", "shapegen.city.worker"],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            env=env,
            start_new_session=True,  # Ctrl-C reaches the parent only; it stops the workers
        )
        write_message(self.process.stdin, settings)
        self.task: LotTask | None = None
        self.started = 0.0

    def give(self, task: LotTask) -> None:
        from shapegen.city.worker import write_message

        self.task, self.started = task, time.perf_counter()
        write_message(self.process.stdin, task)

    def answer(self) -> dict:
        from shapegen.city.worker import read_message

        return read_message(self.process.stdout)

    def stop(self, *, kill: bool = False) -> None:
        from shapegen.city.worker import write_message

        if not kill and self.process.poll() is None:
            with contextlib.suppress(OSError, ValueError):
                write_message(self.process.stdin, None)
        for stream in (self.process.stdin, self.process.stdout):
            with contextlib.suppress(OSError, ValueError):
                stream.close()
        try:
            self.process.wait(0 if kill else 5)
        except Exception:  # noqa: BLE001 - still running: stop it
            pass
        if self.process.poll() is None:
            self.process.kill()
            self.process.wait()


class LocalProcesses:
    """Run lots on ``workers`` processes of this machine (default: one per core)."""

    def __init__(self, workers: int | None = None):
        self.workers = default_workers() if workers is None else int(workers)
        if self.workers < 1:
            raise ValueError(f"workers must be at least 1, got {workers}")

    def describe(self) -> str:
        return f"{self.workers} local process{'es' if self.workers != 1 else ''}"

    def run(self, settings: CitySettings, tasks: Iterable[LotTask]) -> Iterator[dict]:
        from multiprocessing.connection import wait

        pending = list(tasks)
        pending.reverse()  # pop() from the end keeps the input order
        if not pending:
            return
        workers = [_Worker(settings) for _ in range(min(self.workers, len(pending)))]
        answered = 0
        deaths = 0
        try:
            for worker in workers:
                worker.give(pending.pop())
            while any(worker.task is not None for worker in workers):
                busy = {w.process.stdout: w for w in workers if w.task is not None}
                for stream in wait(list(busy), timeout=self._wait(busy.values(), settings)):
                    worker = busy[stream]
                    try:
                        record = worker.answer()
                        answered += 1
                    except (EOFError, OSError):
                        deaths += 1
                        if answered == 0 and deaths > len(workers):
                            raise ShapegenError(
                                "shapegen's worker processes stop as they start (see the"
                                " messages above)"
                            ) from None
                        record = self._lost(worker, settings)
                        worker = self._replace(workers, worker, settings)
                    worker.task = None
                    if pending:  # before the record is written, so the worker never waits
                        worker.give(pending.pop())
                    yield record
                for worker in list(workers):
                    if worker.task is not None and self._overdue(worker, settings):
                        task, seconds = worker.task, time.perf_counter() - worker.started
                        worker = self._replace(workers, worker, settings)
                        if pending:
                            worker.give(pending.pop())
                        yield _timeout_record(task, settings, seconds)
        finally:
            for worker in workers:
                worker.stop(kill=worker.task is not None)

    @staticmethod
    def _replace(workers: list, worker: _Worker, settings: CitySettings) -> _Worker:
        worker.stop(kill=True)
        fresh = _Worker(settings)
        workers[workers.index(worker)] = fresh
        return fresh

    @staticmethod
    def _wait(busy, settings: CitySettings) -> float | None:
        if settings.timeout is None:
            return None
        now = time.perf_counter()
        ends = [w.started + settings.timeout + KILL_GRACE_S - now for w in busy]
        return max(0.05, min(ends))

    @staticmethod
    def _overdue(worker: _Worker, settings: CitySettings) -> bool:
        if settings.timeout is None:
            return False
        return time.perf_counter() - worker.started > settings.timeout + KILL_GRACE_S

    @staticmethod
    def _lost(worker: _Worker, settings: CitySettings) -> dict:
        try:
            code = worker.process.wait(5)
        except Exception:  # noqa: BLE001 - still running after closing its output
            code = None
        how = f"signal {-code}" if code is not None and code < 0 else f"exit status {code}"
        record = _empty_record(worker.task, settings)
        record["error"] = f"its worker process died ({how}; out of memory?)"
        record["seconds"] = time.perf_counter() - worker.started
        return record


class DaskCluster:
    """Run lots on an existing Dask cluster: a scheduler ``address`` or a ``distributed.Client``.

    Every worker needs shapegen (the same version) installed.
    """

    def __init__(self, scheduler):
        self.scheduler = scheduler

    def describe(self) -> str:
        address = getattr(self.scheduler, "scheduler", None)
        address = getattr(address, "address", None) or self.scheduler
        return f"the Dask cluster at {address}"

    def _client(self):
        try:
            from distributed import Client
        except ImportError:
            from shapegen.errors import OptionError

            raise OptionError(
                "--scheduler needs dask.distributed: pip install 'shapegen[city]'"
            ) from None
        if isinstance(self.scheduler, Client):
            return contextlib.nullcontext(self.scheduler)
        try:
            return Client(self.scheduler, timeout="10s")
        except (OSError, TimeoutError) as exc:
            from shapegen.errors import OptionError

            raise OptionError(
                f"--scheduler {self.scheduler}: cannot reach a Dask scheduler ({exc})"
            ) from None

    def run(self, settings: CitySettings, tasks: Iterable[LotTask]) -> Iterator[dict]:
        from distributed import as_completed

        tasks = list(tasks)
        if not tasks:
            return
        with self._client() as client:
            shared = client.scatter(settings, broadcast=True)
            futures = {
                client.submit(run_lot, shared, task, pure=False, key=f"shapegen-lot-{k}"): task
                for k, task in enumerate(tasks)
            }
            try:
                for future in as_completed(futures):
                    task = futures[future]
                    try:
                        record = future.result()
                    except Exception as exc:  # noqa: BLE001 - a lost task is a row
                        record = _empty_record(task, settings)
                        text = " ".join(str(exc).split()) or type(exc).__name__
                        record["error"] = f"the cluster lost it: {type(exc).__name__}: {text}"
                    yield record
            finally:
                client.cancel(list(futures))


def _empty_record(task: LotTask, settings: CitySettings) -> dict:
    return new_record(task.id, lot_seed(task.id, settings.seed))


def _timeout_record(task: LotTask, settings: CitySettings, seconds: float) -> dict:
    record = _empty_record(task, settings)
    record.update(status="timeout", error=timeout_message(settings.timeout), seconds=seconds)
    return record
