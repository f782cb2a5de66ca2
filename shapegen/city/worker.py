"""A local worker process: ``python -m shapegen.city.worker``, started by
:class:`shapegen.city.executors.LocalProcesses`.

It reads the run's settings, then lots, from standard input and answers each lot with its record
on the original standard output; both ways a message is a pickle preceded by its length (8
bytes, big-endian). Anything printed while a lot runs goes to standard error, so it cannot mix
with the answers. Ctrl-C is ignored: the parent decides what an interrupt stops.
"""

from __future__ import annotations

__all__ = ["read_message", "write_message"]

import os
import pickle
import signal
import sys

_LENGTH_BYTES = 8


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
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    answers = os.fdopen(os.dup(sys.stdout.fileno()), "wb")
    os.dup2(sys.stderr.fileno(), sys.stdout.fileno())  # stray prints go to stderr
    requests = sys.stdin.buffer
    from shapegen.city.work import run_lot

    try:
        settings = read_message(requests)
        while True:
            task = read_message(requests)
            if task is None:
                return
            write_message(answers, run_lot(settings, task))
    except (EOFError, BrokenPipeError):
        return


if __name__ == "__main__":
    main()
