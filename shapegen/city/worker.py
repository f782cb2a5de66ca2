"""A local worker process: ``python -m shapegen.city.worker``, started by
:class:`shapegen.city.executors.LocalProcesses`.

It reads the run's settings and store, then batches of lots, from standard input; it runs each
batch and writes its files (:func:`shapegen.city.batches.run_batch`), then answers with the
batch's records (``{"records": [...]}``, or ``{"error": ...}`` when the store cannot be
written) on the original standard output; both ways a message is a pickle preceded by its length
(8 bytes, big-endian). As each lot starts it writes the lot's place in the batch and the time
(``time.monotonic``) into the memory map the parent shares with it (the file descriptor in its
first argument), so the parent can stop a lot past its timeout and knows which lot a dead
worker was on. Anything printed while a lot runs goes to standard error, so it cannot mix with
the answers. Ctrl-C is ignored: the parent decides what an interrupt stops.
"""

from __future__ import annotations

__all__ = ["PROGRESS", "read_message", "write_message"]

import os
import pickle
import signal
import struct
import sys
import time

_LENGTH_BYTES = 8
# The lot of its batch a worker is on (-1 before the first, the batch's length while writing its
# files) and since when, time.monotonic (the same clock in every process of the machine).
PROGRESS = struct.Struct("<qd")


def write_message(stream, message) -> None:
    data = pickle.dumps(message, protocol=pickle.HIGHEST_PROTOCOL)
    stream.write(len(data).to_bytes(_LENGTH_BYTES, "big") + data)
    stream.flush()


def read_message(stream):
    """The next message, or raise EOFError when the other end has gone."""
    head = _read(stream, _LENGTH_BYTES)
    return pickle.loads(_read(stream, int.from_bytes(head, "big")))


def _read(stream, size: int) -> bytes:
    chunks, left = [], size
    while left:
        chunk = stream.read(left)
        if not chunk:
            raise EOFError
        chunks.append(chunk)
        left -= len(chunk)
    return b"".join(chunks)


def main() -> None:
    import mmap

    signal.signal(signal.SIGINT, signal.SIG_IGN)
    answers = os.fdopen(os.dup(sys.stdout.fileno()), "wb")
    os.dup2(sys.stderr.fileno(), sys.stdout.fileno())  # stray prints go to stderr
    requests = sys.stdin.buffer
    board = mmap.mmap(int(sys.argv[1]), PROGRESS.size)
    from shapegen.city.batches import run_batch
    from shapegen.city.work import warm_up

    def started(index: int) -> None:
        PROGRESS.pack_into(board, 0, index, time.monotonic())

    try:
        settings, store = read_message(requests)
        warm_up(settings)
        while True:
            batch = read_message(requests)
            if batch is None:
                return
            try:
                answer = {"records": run_batch(settings, store, batch, started)}
            except OSError as exc:
                answer = {"error": f"cannot write there ({exc})"}
            except Exception as exc:  # noqa: BLE001 - the store's own errors (fsspec's)
                answer = {"error": f"cannot write there ({type(exc).__name__}: {exc})"}
            write_message(answers, answer)
    except (EOFError, BrokenPipeError):
        return


if __name__ == "__main__":
    main()
