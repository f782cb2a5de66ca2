"""Readers: every input file format shapegen takes is read here, each in one place.

==========================  ==========================================================
what                        reader
==========================  ==========================================================
bytes and JSON of a file    :mod:`~shapegen.readers.files` (size limits, gzip inflated in
                            a bounded stream, JSON depth bound, one-line errors)
7z archives (``.rpk``)      :func:`~shapegen.readers.archives.unpack_7z`: members, depth,
                            size bounded; damaged streams one line
a lot (``--lot``)           :func:`~shapegen.readers.lot_sources.read_lot`: ``W,D``, corners,
                            a GeoJSON feature, an OBJ face
GeoJSON features            :mod:`~shapegen.readers.geojson` (lots and cities)
OpenStreetMap XML           :mod:`~shapegen.readers.osm`: one way, or every building
coordinate systems          :mod:`~shapegen.readers.crs`: a ``crs`` member, a ``.prj``,
                            ``--crs``; any pyproj system to WGS84 longitude/latitude
WGS84 to local metres       :func:`~shapegen.readers.projection.east_north`
block models                :func:`~shapegen.readers.models.read_model` by extension:
                            shapegen-blocks JSON (:mod:`~shapegen.readers.blocks_json`,
                            its blocks and surfaces in :mod:`~shapegen.readers.block_entries`
                            and :mod:`~shapegen.readers.surface_entries`), OBJ, glTF, PLY
                            and STL (:mod:`~shapegen.readers.meshes`)
==========================  ==========================================================

Rule files are read by :func:`shapegen.grammar.source_files.read_rule_file`, where the grammar
is. :mod:`shapegen.export` writes. Every mistake in an input is one
:class:`~shapegen.errors.InputFormatError` line naming the file.
"""
