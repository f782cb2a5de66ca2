"""The stable-range scanning process: ``python -m shapegen.editor.scan_worker PAUSE``.

:class:`~shapegen.editor.stability.StabilityScanner` starts it and speaks to it in JSON lines.
In, on standard input: ``{"job": {...}}`` (a :class:`~shapegen.editor.stability.ScanJob`; a
newer one abandons the older), ``{"idle": true|false}`` (whether the editor is free: a scan
waits for it before each evaluation), ``{"stop": true}``. Out, on standard output:
``[generation, attr, result]`` per partial or final result. Anything else the process prints
goes to standard error. It runs at lower priority (``nice`` +10), ignores Ctrl-C (the editor
ends it) and is stopped by the editor (``SIGSTOP``) while a change is computed.
"""

from __future__ import annotations

import json
import os
import signal
import sys
import threading

from shapegen.editor.stability import PAUSE_S, ScanJob, Stale, scan
from shapegen.model.lot import Lot


class Inbox:
    """What the editor has said: the newest job, whether it is idle, whether to stop."""

    def __init__(self):
        self.changed = threading.Condition()
        self.job: ScanJob | None = None
        self.generation = 0
        self.idle = threading.Event()
        self.idle.set()
        self.stopped = False

    def read(self, stream) -> None:
        for line in stream:
            try:
                message = json.loads(line)
            except ValueError:
                continue
            with self.changed:
                if "job" in message:
                    fields = dict(message["job"])
                    fields["ranges"] = {k: tuple(v) for k, v in fields["ranges"].items()}
                    fields["current"] = {k: tuple(v) for k, v in fields["current"].items()}
                    lot = fields.get("lot")  # a Lot's fields, or None
                    fields["lot"] = Lot(**lot) if lot else None
                    self.job = ScanJob(**fields)
                    self.generation = self.job.generation
                elif "idle" in message:
                    (self.idle.set if message["idle"] else self.idle.clear)()
                elif message.get("stop"):
                    break
                self.changed.notify_all()
        with self.changed:
            self.stopped = True
            self.idle.set()
            self.changed.notify_all()

    def next_job(self, pause: float) -> ScanJob | None:
        """The newest job once no newer one has come for ``pause`` seconds; None to stop."""
        with self.changed:
            while True:
                while self.job is None and not self.stopped:
                    self.changed.wait()
                if self.stopped:
                    return None
                job = self.job
                self.changed.wait(timeout=pause)
                if self.stopped:
                    return None
                if self.job is job:
                    self.job = None
                    return job

    def stale(self, job: ScanJob) -> bool:
        return self.stopped or self.generation != job.generation

    def wait_idle(self, job: ScanJob) -> None:
        while not self.idle.wait(0.5):
            if self.stale(job):
                raise Stale


def main(argv: list[str] | None = None) -> None:
    argv = sys.argv[1:] if argv is None else argv
    pause = float(argv[0]) if argv else PAUSE_S
    protocol = os.fdopen(os.dup(1), "w", encoding="utf-8", buffering=1)
    os.dup2(2, 1)  # nothing else may write to the protocol's stream
    sys.stdout = sys.stderr
    try:
        os.nice(10)
    except OSError:
        pass
    # Ctrl-C in the terminal reaches the whole process group: the editor ends this process
    # (its standard input closes), so the interrupt is not for it
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    from shapegen.engine.grammar_api import load_grammar, parse_grammar
    from shapegen.structures import make_structure

    inbox = Inbox()
    threading.Thread(target=inbox.read, args=(sys.stdin,), daemon=True).start()
    lock = threading.Lock()

    def emit(generation: int, name: str, result: dict) -> None:
        with lock:
            protocol.write(json.dumps([generation, name, result]) + "\n")

    parsed: dict[str, object] = {}
    cache: dict[tuple, dict] = {}
    while (job := inbox.next_job(pause)) is not None:
        try:
            source = (job.path, job.text)
            if source not in parsed:
                parsed.clear()
                # from its file, whose folder and project resolve a .cga file's imports and
                # assets; the text alone only when there is no file
                parsed[source] = (
                    load_grammar(job.path) if job.path else parse_grammar(job.text, job.name)
                )
            grammar = parsed[source]
            structure = make_structure(grammar.structure)
            scan(
                job,
                grammar,
                structure,
                cache,
                emit,
                stale=lambda job=job: inbox.stale(job),
                wait_idle=lambda job=job: inbox.wait_idle(job),
            )
        except Stale:
            continue
        except Exception as exc:  # one bad job must not end the shading of the next designs
            sys.stderr.write(f"shapegen edit: the stable-range scan failed: {exc}\n")


if __name__ == "__main__":
    main()
