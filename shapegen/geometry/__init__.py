"""Polygon-mesh geometry for the shapes of a derivation: meshes, cuts, extrusion, face frames,
offsets, setbacks and roofs. Pure functions on plain data; it imports only :mod:`shapegen.model`
and the layers below it."""
