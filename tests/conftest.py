"""Test-suite settings, and the fixtures that tests in every folder share.

Property-based tests (hypothesis) draw new random examples on every run, which is how they find
edge cases during development. Under CI (the ``CI`` environment variable set) they run
derandomized instead, so a clean clone passes or fails the same way every time; a failing example
found locally is then fixed in the test or the code, not left to chance.
"""

import os

from shapegen.threads import one_thread_unless_chosen

# The tests run the numerical libraries as the command line does (before numpy loads).
one_thread_unless_chosen()

import pytest  # noqa: E402
from hypothesis import settings  # noqa: E402

settings.register_profile("ci", derandomize=True)
if os.environ.get("CI"):
    settings.load_profile("ci")


@pytest.fixture
def package_cache(tmp_path, monkeypatch):
    """Rule packages unpack into the test's own folder (``tmp_path / "cache"``), never into the
    user's cache, so that a test sees only what it unpacked itself."""
    cache = tmp_path / "cache"
    monkeypatch.setenv("SHAPEGEN_CACHE", str(cache))
    return cache
