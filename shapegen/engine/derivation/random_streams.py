r"""CityEngine's random numbers: one stream per shape, as its runtime draws them.

Measured black-box against CityEngine's runtime (PyPRT 1.12, the rule packages of the shared
corpus; the numbers are in ``tests/data/cityengine_random.json`` and
docs/cga-compatibility.md):

- a stream is a linear congruential generator, ``x <- (4096 x + 150889) mod 714025``; a draw
  steps it and gives ``u = float32(x / 714024)``, so ``u`` lies in [0, 1] and can be 1.0;
- a derivation's start shape begins at ``uint32(seed) mod 714025``;
- a successor shape takes one step of its parent's stream; the successor's own stream begins
  at ``(4096 x + 339068) mod 714025``, ``x`` the parent's state before that step; a successor's
  arguments are evaluated (and draw) before that step;
- a shape an operation makes (a piece of a split, a component of comp...) is made the same
  way, and its stream begins one step further (as if its first draw had been taken);
- a split's sizes are drawn from the splitting shape's stream before its pieces are made;
- an attr's default is evaluated with a stream of its own, beginning at
  ``(uint32(seed) mod 714025 + k) mod 714025``, ``k`` fixed per attr. How CityEngine derives
  ``k`` from the attr is not known (no common hash of its name gives the measured values), so
  :func:`attr_stream` takes ``k`` from the attr's name by CRC-32: a stream of its own, the same
  for a name and a seed, but not CityEngine's numbers.

The functions take a state as a Python int or a numpy array of states (the city batch steps
the streams of many lots at once), so one definition serves both derivations.

>>> x = start(0)
>>> x, u = draw(x)
>>> x, round(u, 6)
(150889, 0.211322)
>>> child_stream(0)
339068
"""

from __future__ import annotations

__all__ = [
    "CHILD_INCREMENT",
    "INCREMENT",
    "MODULUS",
    "MULTIPLIER",
    "attr_stream",
    "child_stream",
    "choice",
    "draw",
    "draws",
    "start",
    "starts",
    "step",
    "threshold",
]

import struct
import zlib

import numpy as np

MODULUS = 714025
MULTIPLIER = 4096
INCREMENT = 150889
CHILD_INCREMENT = 339068
"""What a successor's stream begins at, from its parent's state: ``MULTIPLIER x + this``."""
_DIVISOR = float(MODULUS - 1)  # u = x / 714024 reaches 1.0 at the largest state
_FLOAT32 = struct.Struct("f")


def start(seed: int) -> int:
    """The state a derivation's start shape begins at: ``seed`` as an unsigned 32-bit
    number (CityEngine's ``seedian``), reduced."""
    return (int(seed) & 0xFFFFFFFF) % MODULUS


def step(x):
    """The next state of the stream (an int, or an int64 array of states)."""
    return (MULTIPLIER * x + INCREMENT) % MODULUS


def draw(x: int) -> tuple[int, float]:
    """Step the stream at state ``x``: ``(next state, u)`` with ``u`` in [0, 1], rounded to
    float32 as CityEngine's runtime rounds it."""
    x = (MULTIPLIER * x + INCREMENT) % MODULUS
    return x, _FLOAT32.unpack(_FLOAT32.pack(x / _DIVISOR))[0]


def draws(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """:func:`draw` of many streams at once: ``(next states, u)``, int64 and float64 arrays."""
    x = step(np.asarray(x, dtype=np.int64))
    return x, (x / _DIVISOR).astype(np.float32).astype(np.float64)


def child_stream(x, successor: bool = True):
    """The state a new shape's stream begins at, ``x`` its parent's state before the parent
    steps for it: a successor's (``A --> ... B``), or one step further a piece's, a shape an
    operation makes (a split's, a comp's, a setback's...)."""
    begin = (MULTIPLIER * x + CHILD_INCREMENT) % MODULUS
    return begin if successor else (MULTIPLIER * begin + INCREMENT) % MODULUS


def attr_stream(seed: int, name: str) -> int:
    """The state the stream of attr ``name``'s default begins at (see the module's doc: the
    offset per attr is shapegen's, CityEngine's is not known)."""
    return (start(seed) + zlib.crc32(name.encode("utf-8"))) % MODULUS


def choice(random, fractions) -> int:
    """The branch a stochastic choice takes (``fractions``: the branches' shares of 1, the
    ``else`` branch last and not listed): index ``len(fractions)`` is the ``else``.

    CityEngine draws once per branch tried, and takes branch ``i`` when the draw is below its
    share of what the branches before it left (``40%: A 50%: B else: C`` takes A when
    ``u1 < 0.4``, else B when ``u2 < 0.5 / 0.6``): measured on the attrs of a rule package,
    where one draw compared with the running sums does not fit. ``random`` gives the draws.
    """
    left = 1.0
    for index, fraction in enumerate(fractions):
        if random() < threshold(fraction, left):
            return index
        left -= fraction
    return len(fractions)


def threshold(fraction: float, left: float) -> float:
    """What a stochastic branch's draw must be below to take it: its ``fraction`` of what the
    branches before it ``left`` (:func:`choice`; the city batch applies it to many lots)."""
    return fraction / left if left > 0.0 else np.inf


def starts(seeds) -> np.ndarray:
    """:func:`start` of many seeds: an int64 array."""
    return np.array([start(seed) for seed in seeds], dtype=np.int64)
