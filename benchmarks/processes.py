"""Running shapegen as a user runs it, for the benchmarks that time whole processes.

A user's Python keeps the compiled bytecode of the modules it imported (``__pycache__``) and
reuses it from the second run on. A shell with ``PYTHONDONTWRITEBYTECODE`` set (some
containers and CI images set it) makes every process compile every module again: ~0.25 s of a
one-line build's 0.32 s of CPU. The children of these benchmarks run without it, after one
run that writes the bytecode, so their figures are a user's second run, not a compiler's.
"""

from __future__ import annotations

__all__ = ["user_environment"]

import os


def user_environment() -> dict[str, str]:
    """This process's environment as a user's shell has it: bytecode written and reused."""
    return {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
