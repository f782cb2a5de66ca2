"""Every example in a module's docstrings runs: each module of the package is a test case here, so
an example that stops holding fails like any other test (examples that need a browser, a server or
files outside the package say ``# doctest: +SKIP``)."""

from __future__ import annotations

import doctest
import importlib
import pkgutil

import pytest

import shapegen


def _has_examples(name: str) -> bool:
    module = importlib.import_module(name)
    return any(test.examples for test in doctest.DocTestFinder().find(module))


MODULES = sorted(
    info.name
    for info in pkgutil.walk_packages(shapegen.__path__, prefix="shapegen.")
    if not info.name.endswith("__main__") and _has_examples(info.name)
)


def test_the_examples_are_found():
    assert len(MODULES) >= 15, MODULES  # a finder that found nothing would pass every case below


@pytest.mark.parametrize("name", MODULES)
def test_the_docstring_examples_hold(name):
    result = doctest.testmod(importlib.import_module(name), optionflags=doctest.ELLIPSIS)
    assert result.failed == 0, f"{result.failed} of {result.attempted} examples of {name} failed"
