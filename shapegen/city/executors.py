"""Where batches of lots run: worker processes of this machine (the default), a Dask cluster, or
this process (for an output in ``memory://``, which no other process sees).

Every executor takes the lots in batches (:class:`Batcher`), and the worker that runs a batch
writes the batch's files itself (:func:`shapegen.city.batches.run_batch`); what comes back to
the parent is each batch's records without their buildings, in the order the batches finish.

Batch size. Unless it is given, the first batches are of 4 lots; after each batch the size is
set so that a batch is about :data:`BATCH_SECONDS` of a worker's time (at most
:data:`MAX_BATCH` lots), and never more than a quarter of one worker's share of the lots left,
so the last batches are small and every worker stays busy to the end.

Local processes. A small pool of our own rather than ``concurrent.futures``: a lot stuck inside
one long call (a QP solve) past its timeout is stopped by killing its worker, which is then
replaced, and a worker that dies (out of memory, a crash in a native library) costs one row; a
standard pool breaks on either. Each worker tells, through a small shared memory map, which lot
of its batch it is on and since when, so the parent knows which lot overran or was running
when its worker died: that lot is a row (``timeout``, or ``error``: the worker died), which the
parent writes, and the batch's other lots are run again in a new batch (the lots it had done
were not written yet). Each worker is ``python -m shapegen.city.worker``, so it never
re-imports the caller's script, runs the numerical libraries on one thread (the lots are the
parallelism) and is in a session of its own, so Ctrl-C reaches only the parent, which stops
the workers.

Dask. ``distributed.Client(address)`` on an existing scheduler; each batch is one task. A lot's
timeout is kept by the lot itself (it checks its time after every search step and every
derivation has a time limit), since a Dask task cannot be killed from outside. A batch that the
cluster loses (a worker gone after Dask's own retries) is a row per lot: ``error``, the cluster
lost it; they are not run again in this run (a rerun does them).
"""

from __future__ import annotations

__all__ = ["Batcher", "DaskCluster", "InProcess", "LocalProcesses", "default_workers"]

import contextlib
import math
import os
import time
from collections import deque
from collections.abc import Iterator, Sequence

from shapegen.city.batches import batch_key, run_batch, write_batch
from shapegen.city.work import CitySettings, LotTask, lot_seed, new_record, timeout_message
from shapegen.errors import InputFormatError, ShapegenError
from shapegen.threads import ONE_THREAD

# A lot whose worker has not answered this long after its timeout is stopped from outside, s.
KILL_GRACE_S = 2.0
# A batch's share of a worker's time, s, when the batch size is not given.
BATCH_SECONDS = 0.5
MAX_BATCH = 1000
FIRST_BATCH = 4


def default_workers() -> int:
    """The cores this process may use."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # not on Linux
        return max(1, os.cpu_count() or 1)


class Batcher:
    """Hands out the lots left in batches (see the module doc), ``size`` lots each if given."""

    def __init__(self, tasks: Sequence[LotTask], workers: int, size: int | None = None):
        self.pending = deque(tasks)
        self.workers = max(1, workers)
        self.size = size
        self.per_lot: float | None = None  # a lot's seconds in its worker, smoothed

    def __bool__(self) -> bool:
        return bool(self.pending)

    def next(self) -> list[LotTask]:
        if self.size is not None:
            count = self.size
        elif self.per_lot is None:
            count = FIRST_BATCH
        else:
            fill = round(BATCH_SECONDS / max(self.per_lot, 1e-5))
            share = math.ceil(len(self.pending) / (4 * self.workers))
            count = max(1, min(fill, share, MAX_BATCH))
        return [self.pending.popleft() for _ in range(min(count, len(self.pending)))]

    def observe(self, records: list[dict]) -> None:
        seconds = [r["seconds"] for r in records if isinstance(r.get("seconds"), int | float)]
        if seconds:
            mean = sum(seconds) / len(seconds)
            self.per_lot = mean if self.per_lot is None else 0.5 * (self.per_lot + mean)

    def again(self, tasks: Sequence[LotTask]) -> None:
        """Put ``tasks`` back at the front (a batch whose worker was stopped)."""
        self.pending.extendleft(reversed(list(tasks)))


class InProcess:
    """Run the batches in this process, one after the other."""

    def describe(self) -> str:
        return "this process"

    def run(self, settings, store, batcher: Batcher) -> Iterator[list[dict]]:
        while batcher:
            records = _written(store, lambda batch: run_batch(settings, store, batch), batcher)
            batcher.observe(records)
            yield records


class _Worker:
    """One ``python -m shapegen.city.worker`` process, its batch (None when idle) and the map
    where it says which lot of the batch it is on, and since when."""

    def __init__(self, settings: CitySettings, store):
        import mmap
        import subprocess
        import sys
        import tempfile

        from shapegen.city.worker import PROGRESS, write_message

        self.board = tempfile.TemporaryFile()
        self.board.truncate(PROGRESS.size)
        self.view = mmap.mmap(self.board.fileno(), PROGRESS.size)
        env = {**os.environ, **ONE_THREAD}
        fd = self.board.fileno()
        self.process = subprocess.Popen(
            [sys.executable, "-m", "shapegen.city.worker", str(fd)],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            env=env,
            pass_fds=(fd,),
            start_new_session=True,  # Ctrl-C reaches the parent only; it stops the workers
        )
        write_message(self.process.stdin, (settings, store))
        self.batch: list[LotTask] | None = None

    def give(self, batch: list[LotTask]) -> None:
        from shapegen.city.worker import PROGRESS, write_message

        PROGRESS.pack_into(self.view, 0, -1, time.monotonic())
        self.batch = batch
        write_message(self.process.stdin, batch)

    def where(self) -> tuple[int, float]:
        """The lot of its batch it is on (``len(batch)``: writing its files) and since when
        (``time.monotonic``)."""
        from shapegen.city.worker import PROGRESS

        return PROGRESS.unpack_from(self.view, 0)

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
        with contextlib.suppress(OSError, ValueError, BufferError):
            self.view.close()
        self.board.close()


class LocalProcesses:
    """Run batches on ``workers`` processes of this machine (default: one per core)."""

    def __init__(self, workers: int | None = None):
        self.workers = default_workers() if workers is None else int(workers)
        if self.workers < 1:
            raise ValueError(f"workers must be at least 1, got {workers}")

    def describe(self) -> str:
        return f"{self.workers} local process{'es' if self.workers != 1 else ''}"

    def run(self, settings: CitySettings, store, batcher: Batcher) -> Iterator[list[dict]]:
        from multiprocessing.connection import wait

        if not batcher:
            return
        count = min(self.workers, len(batcher.pending))  # no more workers than lots
        workers = [_Worker(settings, store) for _ in range(count)]
        deaths = 0  # of workers before their first lot, since the last answer
        try:
            for worker in workers:
                if batcher:
                    worker.give(batcher.next())
            while any(worker.batch is not None for worker in workers):
                busy = {w.process.stdout: w for w in workers if w.batch is not None}
                for stream in wait(list(busy), timeout=self._wait(busy.values(), settings)):
                    worker = busy[stream]
                    try:
                        answer = worker.answer()
                    except (EOFError, OSError):
                        records = self._lost(worker, settings, store, batcher, died=True)
                        deaths += not records  # before its first lot
                        if deaths > 2 * len(workers):
                            raise ShapegenError(
                                "shapegen's worker processes stop as they start (see the"
                                " messages above)"
                            ) from None
                        worker = self._replace(workers, worker, settings, store)
                    else:
                        deaths = 0
                        if "error" in answer:
                            raise InputFormatError(f"{store.location}: {answer['error']}")
                        records = answer["records"]
                        batcher.observe(records)
                        worker.batch = None
                    if batcher:  # before the parent looks at the records: no worker waits
                        worker.give(batcher.next())
                    if records:
                        yield records
                for worker in list(workers):
                    if worker.batch is not None and self._overdue(worker, settings):
                        records = self._lost(worker, settings, store, batcher, died=False)
                        worker = self._replace(workers, worker, settings, store)
                        if batcher:
                            worker.give(batcher.next())
                        yield records
        finally:
            for worker in workers:
                worker.stop(kill=worker.batch is not None)

    @staticmethod
    def _replace(workers: list, worker: _Worker, settings, store) -> _Worker:
        worker.stop(kill=True)
        fresh = _Worker(settings, store)
        workers[workers.index(worker)] = fresh
        return fresh

    @staticmethod
    def _wait(busy, settings: CitySettings) -> float | None:
        if settings.timeout is None:
            return None
        now = time.monotonic()
        ends = []
        for worker in busy:
            index, since = worker.where()
            if 0 <= index < len(worker.batch):
                ends.append(since + settings.timeout + KILL_GRACE_S - now)
        return max(0.05, min(ends, default=settings.timeout))

    @staticmethod
    def _overdue(worker: _Worker, settings: CitySettings) -> bool:
        if settings.timeout is None:
            return False
        index, since = worker.where()
        on_a_lot = 0 <= index < len(worker.batch)
        return on_a_lot and time.monotonic() - since > settings.timeout + KILL_GRACE_S

    @staticmethod
    def _lost(worker: _Worker, settings, store, batcher: Batcher, *, died: bool) -> list[dict]:
        """The row of the lot its worker was on when it died or overran (written here), the
        batch's other lots put back to run again. A worker that died before its first lot puts
        the whole batch back; one that died writing the batch's files makes every lot of it a
        row (running them again would end the same way)."""
        index, since = worker.where()
        batch, seconds = worker.batch, time.monotonic() - since
        worker.batch = None
        if index < 0:
            batcher.again(batch)
            return []
        code = None
        if died:
            try:
                code = worker.process.wait(5)
            except Exception:  # noqa: BLE001 - still running after closing its output
                code = None
        how = f"signal {-code}" if code is not None and code < 0 else f"exit status {code}"
        blamed = batch[index : index + 1] if index < len(batch) else batch
        records = []
        for task in blamed:
            record = _empty_record(task, settings)
            if died:
                record["error"] = f"its worker process died ({how}; out of memory?)"
            else:
                record.update(status="timeout", error=timeout_message(settings.timeout))
            record["seconds"] = seconds
            records.append(record)
        write_batch(store, batch_key(blamed), records)
        batcher.again(batch[:index] + batch[index + 1 :] if index < len(batch) else [])
        return records


class DaskCluster:
    """Run batches on a Dask cluster: a scheduler ``address``, a ``distributed.Client``, or
    ``local:N`` (a new ``LocalCluster`` of N one-thread processes, closed at the end).

    Every worker needs shapegen (the same version) installed, and must reach the output: a
    folder they all see (a shared file system) or an object store URL.
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
        if str(self.scheduler).startswith("local:"):
            return _local_cluster(str(self.scheduler))
        try:
            return Client(self.scheduler, timeout="10s")
        except (OSError, TimeoutError) as exc:
            from shapegen.errors import OptionError

            raise OptionError(
                f"--scheduler {self.scheduler}: cannot reach a Dask scheduler ({exc})"
            ) from None

    def run(self, settings: CitySettings, store, batcher: Batcher) -> Iterator[list[dict]]:
        from distributed import as_completed

        if not batcher:
            return
        with self._client() as client:
            workers = max(1, len(client.scheduler_info().get("workers", {})))
            batcher.workers = workers
            shared = client.scatter(settings, broadcast=True)
            futures: dict = {}

            def submit():
                batch = batcher.next()
                key = f"shapegen-city-{batch_key(batch)}-{len(futures)}"
                future = client.submit(run_batch, shared, store, batch, pure=False, key=key)
                futures[future] = batch
                return future

            running = as_completed([submit() for _ in range(2 * workers) if batcher])
            try:
                for future in running:
                    batch = futures[future]
                    try:
                        records = future.result()
                        batcher.observe(records)
                    except Exception as exc:  # noqa: BLE001 - a lost batch is rows
                        text = " ".join(str(exc).split()) or type(exc).__name__
                        records = [_empty_record(task, settings) for task in batch]
                        for record in records:
                            record["error"] = f"the cluster lost it: {type(exc).__name__}: {text}"
                        write_batch(store, batch_key(batch), records)
                    if batcher:
                        running.add(submit())
                    yield records
            finally:
                client.cancel(list(futures))


@contextlib.contextmanager
def _local_cluster(spec: str):
    """A Dask ``LocalCluster`` of N one-thread worker processes (``local:N``), and its client."""
    from distributed import Client, LocalCluster

    from shapegen.errors import OptionError

    count = spec.partition(":")[2]
    if not count.isdigit() or int(count) < 1:
        raise OptionError(f"--scheduler {spec}: local:N needs a whole number N >= 1")
    with LocalCluster(
        n_workers=int(count),
        threads_per_worker=1,
        processes=True,
        dashboard_address=None,
        env=ONE_THREAD,
    ) as cluster, Client(cluster) as client:  # fmt: skip
        yield client


def _written(store, run, batcher: Batcher) -> list[dict]:
    batch = batcher.next()
    try:
        return run(batch)
    except OSError as exc:
        raise InputFormatError(f"{store.location}: cannot write there ({exc})") from None


def _empty_record(task: LotTask, settings: CitySettings) -> dict:
    record = new_record(task.id, lot_seed(task.id, settings.seed))
    record["input"] = task.input
    return record
