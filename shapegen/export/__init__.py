"""Readers and writers: shapegen-blocks JSON, meshes (glTF, OBJ, PLY, STL), pictures."""
