"""Each test module names its bundled rule file in ``GRAMMAR``; it is loaded once per module."""

import pytest

import shapegen


@pytest.fixture(scope="module")
def grammar(request):
    return shapegen.load_grammar(request.module.GRAMMAR)
