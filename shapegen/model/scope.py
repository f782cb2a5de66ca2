"""Scopes: the oriented boxes that CGA rules operate on."""

from __future__ import annotations

__all__ = ["Scope"]

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Scope:
    """An oriented box: ``origin`` (m, world), ``rotation`` (3x3, columns are the scope's x, y, z
    axes in world coordinates) and ``size`` (sx, sy, sz in metres, along those axes)."""

    origin: np.ndarray
    rotation: np.ndarray
    size: np.ndarray

    @classmethod
    def axis_aligned(cls, origin=(0.0, 0.0, 0.0), size=(1.0, 1.0, 1.0)) -> Scope:
        return cls(np.asarray(origin, float), np.eye(3), np.asarray(size, float))

    @classmethod
    def of_arrays(cls, origin: np.ndarray, rotation: np.ndarray, size: np.ndarray) -> Scope:
        """A scope of float arrays already of shapes (3,), (3, 3) and (3,), taken as they are
        (rows of a batch's stacked arrays): no conversion, for operations that make many."""
        scope = object.__new__(cls)
        object.__setattr__(scope, "origin", origin)
        object.__setattr__(scope, "rotation", rotation)
        object.__setattr__(scope, "size", size)
        return scope

    def __post_init__(self) -> None:
        object.__setattr__(self, "origin", np.asarray(self.origin, dtype=float).reshape(3))
        object.__setattr__(self, "rotation", np.asarray(self.rotation, dtype=float).reshape(3, 3))
        object.__setattr__(self, "size", np.asarray(self.size, dtype=float).reshape(3))

    @property
    def sx(self) -> float:
        return float(self.size[0])

    @property
    def sy(self) -> float:
        return float(self.size[1])

    @property
    def sz(self) -> float:
        return float(self.size[2])

    @property
    def size_text(self) -> str:
        """The sides for a message, ``"2 x 0 x 1 m"`` (cheap: no numpy array printing)."""
        return f"{self.sx:g} x {self.sy:g} x {self.sz:g} m"

    def to_world(self, local: np.ndarray) -> np.ndarray:
        """Scope coordinates (m, origin at the scope's corner) to world coordinates."""
        return self.origin + np.asarray(local, float) @ self.rotation.T

    def to_local(self, world: np.ndarray) -> np.ndarray:
        """World points to scope coordinates (m)."""
        return (np.asarray(world, float) - self.origin) @ self.rotation
