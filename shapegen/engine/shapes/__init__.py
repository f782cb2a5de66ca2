"""The shape and the geometry kernels of CGA's scope operations: :class:`~.shape.Shape` (a scope
and what fills it), split sizes, trim planes and the coordinate frames of a shape."""
