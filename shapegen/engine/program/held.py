"""What a derivation holds while it runs, so that no shape pays for it again.

Within :func:`derivation_held`: each asset name is looked up and each asset file read once
(:func:`~shapegen.engine.project.asset_files.assets_held`), and the cyclic garbage collector is
paused. A derivation makes some 100 000 objects that live until it ends (shapes, scopes,
arrays), few of them in cycles, and the collector's passes over them cost a few percent of a
building's derivation; its state is restored however the derivation ends (a collector paused
by the caller stays paused).
"""

from __future__ import annotations

__all__ = ["derivation_held"]

import contextlib
import gc

from shapegen.engine.project.asset_files import assets_held


@contextlib.contextmanager
def derivation_held():
    """Within: assets found and read once, the cyclic garbage collector paused."""
    was_enabled = gc.isenabled()
    gc.disable()
    try:
        with assets_held():
            yield
    finally:
        if was_enabled:
            gc.enable()
