"""Scopes: the oriented boxes that CGA rules operate on."""

from __future__ import annotations

__all__ = ["Scope"]

import numpy as np

_EYE = (1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0)


def _frozen(values, shape) -> np.ndarray:
    """A read-only array of ``values``: a scope's numbers are shared by the shapes made from it,
    so an in-place change would move them all (it fails instead)."""
    array = np.array(values, dtype=float).reshape(shape)
    array.flags.writeable = False
    return array


class Scope:
    """An oriented box: ``origin`` (m, world), ``rotation`` (3x3, columns are the scope's x, y, z
    axes in world coordinates) and ``size`` (sx, sy, sz in metres, along those axes).

    A scope holds its numbers either as Python floats (``o``, ``r``, ``d``: what the operations
    that only touch the scope work on, t, s, r, center, split and repeat layouts, comp's box
    faces) or as numpy arrays (``origin``, ``rotation``, ``size``: for meshes, leaves, batches),
    and makes the other form when first asked: a derivation of a building's few shapes a rule
    pays numpy's cost per call (about a microsecond) only where it works on meshes.

    - ``o``: the origin ``(x, y, z)`` (m, world);
    - ``r``: the rotation's 9 entries row by row (``rotation.ravel()``), so scope axis ``k`` is
      ``(r[k], r[3 + k], r[6 + k])``;
    - ``d``: the size ``(sx, sy, sz)`` (m).
    """

    __slots__ = ("_o", "_r", "_d", "_origin", "_rotation", "_size")

    def __init__(self, origin, rotation, size):
        self._origin = np.asarray(origin, dtype=float).reshape(3)
        self._rotation = np.asarray(rotation, dtype=float).reshape(3, 3)
        self._size = np.asarray(size, dtype=float).reshape(3)
        self._o = self._r = self._d = None

    @classmethod
    def axis_aligned(cls, origin=(0.0, 0.0, 0.0), size=(1.0, 1.0, 1.0)) -> Scope:
        return cls(np.asarray(origin, float), np.eye(3), np.asarray(size, float))

    @classmethod
    def of_arrays(cls, origin: np.ndarray, rotation: np.ndarray, size: np.ndarray) -> Scope:
        """A scope of float arrays already of shapes (3,), (3, 3) and (3,), taken as they are
        (rows of a batch's stacked arrays): no conversion, for operations that make many."""
        scope = object.__new__(cls)
        scope._origin = origin
        scope._rotation = rotation
        scope._size = size
        scope._o = scope._r = scope._d = None
        return scope

    @classmethod
    def of_floats(cls, o: tuple, r: tuple, d: tuple) -> Scope:
        """A scope of Python floats: origin ``o`` (3), rotation ``r`` (9, row by row), size
        ``d`` (3), taken as they are (tuples of floats)."""
        scope = object.__new__(cls)
        scope._o = o
        scope._r = r
        scope._d = d
        scope._origin = scope._rotation = scope._size = None
        return scope

    def __reduce__(self):
        return (Scope.of_floats, (self.o, self.r, self.d))

    def __repr__(self) -> str:
        return f"Scope(origin={list(self.o)}, rotation={list(self.r)}, size={list(self.d)})"

    # the float form ----------------------------------------------------------------------
    @property
    def o(self) -> tuple:
        o = self._o
        if o is None:
            o = self._o = tuple(self._origin.tolist())
        return o

    @property
    def r(self) -> tuple:
        r = self._r
        if r is None:
            r = self._r = tuple(self._rotation.ravel().tolist())
        return r

    @property
    def d(self) -> tuple:
        d = self._d
        if d is None:
            d = self._d = tuple(self._size.tolist())
        return d

    # the array form ----------------------------------------------------------------------
    @property
    def origin(self) -> np.ndarray:
        origin = self._origin
        if origin is None:
            origin = self._origin = _frozen(self._o, 3)
        return origin

    @property
    def rotation(self) -> np.ndarray:
        rotation = self._rotation
        if rotation is None:
            rotation = self._rotation = _frozen(self._r, (3, 3))
        return rotation

    @property
    def size(self) -> np.ndarray:
        size = self._size
        if size is None:
            size = self._size = _frozen(self._d, 3)
        return size

    @property
    def sx(self) -> float:
        return self.d[0]

    @property
    def sy(self) -> float:
        return self.d[1]

    @property
    def sz(self) -> float:
        return self.d[2]

    @property
    def size_text(self) -> str:
        """The sides for a message, ``"2 x 0 x 1 m"`` (cheap: no numpy array printing)."""
        return f"{self.sx:g} x {self.sy:g} x {self.sz:g} m"

    def axis(self, k: int) -> tuple:
        """Scope axis ``k`` (0, 1, 2: x, y, z) in world coordinates, floats."""
        r = self.r
        return (r[k], r[3 + k], r[6 + k])

    def point(self, x: float, y: float, z: float) -> tuple:
        """The world point (floats, m) at scope coordinates ``(x, y, z)`` (m)."""
        ox, oy, oz = self.o
        r = self.r
        return (
            ox + r[0] * x + r[1] * y + r[2] * z,
            oy + r[3] * x + r[4] * y + r[5] * z,
            oz + r[6] * x + r[7] * y + r[8] * z,
        )

    def to_world(self, local: np.ndarray) -> np.ndarray:
        """Scope coordinates (m, origin at the scope's corner) to world coordinates."""
        return self.origin + np.asarray(local, float) @ self.rotation.T

    def to_local(self, world: np.ndarray) -> np.ndarray:
        """World points to scope coordinates (m)."""
        return (np.asarray(world, float) - self.origin) @ self.rotation
