"""Run one fuzz input in a forked child under a CPU-time and memory cap, and say how it ended.

The child runs ``target(data)``; it ends ``clean`` (no error, or a ShapegenError: the project's
own one-line error), ``crash`` (any other exception: its traceback comes back), ``killed``
(past the CPU cap or out of memory) or ``hung`` (no answer within the wall-clock guard, which is
far above the CPU cap, even on a loaded machine, and only there so that a blocked child cannot
stall the suite). The
child's CPU seconds and peak resident memory come back with every outcome.

:func:`run_campaign` is every fuzzer's loop: its inputs one by one in such children, the
failures and the figures (refused in one line, slowest, largest, wall clock);
:func:`print_figures` shows them and :func:`fuzz_seed` draws a campaign's seed.
"""

from __future__ import annotations

import json
import os
import random
import resource
import select
import signal
import sys
import time
import traceback
from collections.abc import Callable, Iterable
from dataclasses import dataclass

from shapegen.threads import one_thread_unless_chosen

# A child's CPU cap counts every thread: the numerical libraries on one, as the command runs them
# (here too when a campaign runs as a script, outside the tests' conftest).
one_thread_unless_chosen()

CPU_SECONDS = 10
MEMORY_BYTES = 2 * 2**30
WALL_SECONDS = 600  # a busy child on a machine loaded 10 times over gets a tenth of a core


@dataclass(frozen=True)
class Outcome:
    kind: str  # "clean", "crash", "killed" or "hung"
    detail: str
    cpu_seconds: float
    peak_bytes: int


def _virtual_size() -> int:
    with open("/proc/self/status") as status:
        for line in status:
            if line.startswith("VmSize:"):
                return int(line.split()[1]) * 1024
    return 0


def run_limited(
    target: Callable[[object], None],
    data: object,
    *,
    cpu_seconds: int = CPU_SECONDS,
    memory_bytes: int = MEMORY_BYTES,
) -> Outcome:
    """``target(data)`` in a forked child; see the module docstring."""
    from shapegen.errors import ShapegenError

    read_end, write_end = os.pipe()
    # The child inherits the parent's mappings (numpy, scipy...): the address-space cap is
    # what it starts with plus the memory allowance. Peak RSS is checked against the allowance.
    address_space = _virtual_size() + memory_bytes
    pid = os.fork()
    if pid == 0:  # the child
        os.close(read_end)
        try:
            resource.setrlimit(resource.RLIMIT_CPU, (cpu_seconds, cpu_seconds + 1))
            resource.setrlimit(resource.RLIMIT_AS, (address_space, address_space))
            devnull = os.open(os.devnull, os.O_WRONLY)
            os.dup2(devnull, 1)  # print() of a rule
            try:
                target(data)
                message = {"kind": "clean", "detail": ""}
            except ShapegenError as exc:
                lines = str(exc).splitlines()
                message = {"kind": "clean", "detail": lines[0] if lines else ""}
            except MemoryError:
                message = {"kind": "killed", "detail": "MemoryError"}
            except BaseException:  # noqa: BLE001 (everything else is what the fuzz looks for)
                message = {"kind": "crash", "detail": traceback.format_exc()[-4000:]}
            os.write(write_end, json.dumps(message).encode())
        finally:
            os._exit(0)
    os.close(write_end)
    chunks = []
    deadline = time.monotonic() + WALL_SECONDS
    hung = False
    while True:
        remaining = deadline - time.monotonic()
        if remaining <= 0:
            hung = True
            os.kill(pid, signal.SIGKILL)
            break
        ready, _, _ = select.select([read_end], [], [], remaining)
        if ready:
            chunk = os.read(read_end, 65536)
            if not chunk:
                break
            chunks.append(chunk)
    os.close(read_end)
    _, status, usage = os.wait4(pid, 0)
    cpu = usage.ru_utime + usage.ru_stime
    peak = usage.ru_maxrss * 1024
    if hung:
        return Outcome("hung", f"no answer in {WALL_SECONDS} s", cpu, peak)
    if os.WIFSIGNALED(status):
        name = signal.Signals(os.WTERMSIG(status)).name
        return Outcome("killed", f"signal {name}", cpu, peak)
    try:
        message = json.loads(b"".join(chunks).decode())
    except ValueError:
        return Outcome("killed", "the child ended without an answer", cpu, peak)
    kind = message["kind"]
    if kind == "clean" and (cpu > cpu_seconds or peak > memory_bytes):
        kind = "killed"
        message["detail"] = f"over the cap: {cpu:.1f} s CPU, {peak / 2**20:.0f} MiB"
    return Outcome(kind, message["detail"], cpu, peak)


def run_campaign(
    inputs: Iterable[tuple[str, Callable[[object], None], object]],
    *,
    cpu_seconds: int = CPU_SECONDS,
    memory_bytes: int = MEMORY_BYTES,
    progress: bool = False,
    every: int = 200,
) -> dict:
    """Run each ``(label, target, data)`` of ``inputs`` with :func:`run_limited`; the figures:
    ``inputs``, ``refused`` (ended in the project's one-line error), ``failures`` (one line
    each, labelled), ``slowest_cpu_s`` and ``peak_mib`` (each with the label of its input)
    and ``wall_s``. With ``progress``, failures and a count every ``every`` inputs go to
    stderr as they come."""
    failures: list[str] = []
    refused = count = 0
    slowest, peak = (0.0, ""), (0, "")
    began = time.monotonic()
    for label, target, data in inputs:
        outcome = run_limited(target, data, cpu_seconds=cpu_seconds, memory_bytes=memory_bytes)
        count += 1
        if outcome.kind != "clean":
            failures.append(f"{label}: {outcome.kind}: {outcome.detail}")
            if progress:
                print(failures[-1], file=sys.stderr, flush=True)
        elif outcome.detail:
            refused += 1
        slowest = max(slowest, (outcome.cpu_seconds, label))
        peak = max(peak, (outcome.peak_bytes, label))
        if progress and count % every == 0:
            print(f"{count} inputs, {len(failures)} failures", file=sys.stderr, flush=True)
    return {
        "inputs": count,
        "refused": refused,
        "failures": failures,
        "slowest_cpu_s": slowest,
        "peak_mib": (peak[0] / 2**20, peak[1]),
        "wall_s": time.monotonic() - began,
    }


def print_figures(figures: dict, shown: int | None = None) -> None:
    """The figures of :func:`run_campaign`, one a line, the failures indented below."""
    for key, value in figures.items():
        if key == "failures":
            print(f"failures: {len(value)}")
            for line in value[:shown]:
                print("   ", line.replace("\n", "\n    "))
        else:
            print(f"{key}: {value}")


def fuzz_seed() -> int:
    """A campaign's seed: ``SHAPEGEN_FUZZ_SEED`` when set (to replay one), else a fresh one."""
    given = os.environ.get("SHAPEGEN_FUZZ_SEED")
    return int(given) if given else random.SystemRandom().randrange(10**6)
