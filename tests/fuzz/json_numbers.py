"""The numbers of a JSON document that the command line wrote (a model, a report), for the checks
that every number it writes is finite: the numbers fuzzer's (test_fuzz_numbers.py) and those of
its reproducers through the command line (tests/cli/test_cli_numbers.py)."""

from __future__ import annotations

from collections.abc import Iterator


def json_numbers(value) -> Iterator[int | float]:
    """Every number in ``value`` (decoded JSON: dicts, lists, scalars), depth first; booleans are
    not numbers."""
    if isinstance(value, dict):
        for item in value.values():
            yield from json_numbers(item)
    elif isinstance(value, list):
        for item in value:
            yield from json_numbers(item)
    elif isinstance(value, int | float) and not isinstance(value, bool):
        yield value
