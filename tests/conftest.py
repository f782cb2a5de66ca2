"""Test-suite settings.

Property-based tests (hypothesis) draw new random examples on every run, which is how they find
edge cases during development. Under CI (the ``CI`` environment variable set) they run
derandomized instead, so a clean clone passes or fails the same way every time; a failing example
found locally is then fixed in the test or the code, not left to chance.
"""

import os

from hypothesis import settings

settings.register_profile("ci", derandomize=True)
if os.environ.get("CI"):
    settings.load_profile("ci")
