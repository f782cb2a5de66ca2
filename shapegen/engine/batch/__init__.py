"""Derivation in batches: many shapes at one rule derived together, as arrays.

:mod:`~shapegen.engine.batch.lots` derives a city's lots together with the grammar's compiled
rules at the width of the batch (each body's and operation's batch form, from
:mod:`shapegen.engine.operations.registry`: their footprints packed as arrays, one operation on
all of them, conditions and stochastic choices as masks), with each lot's random numbers drawn
from its own stream, exactly as one lot at a time. A lot the batch
cannot derive (a rule or a footprint outside what it implements) is left to the one-shape-at-a-
time derivation, and counted.
"""

from __future__ import annotations

__all__ = ["LotBatch", "derive_lots"]

from shapegen.engine.batch.lots import LotBatch, derive_lots
