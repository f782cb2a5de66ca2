"""The file encoders of the PyPRT API: the generated models written to a folder.

``com.esri.prt.codecs.OBJEncoder`` writes ``<baseName>_0.obj`` (every initial shape's leaves,
one group per leaf), ``com.esri.prt.codecs.GLTFEncoder`` ``<baseName>_0.glb`` (shapegen's glTF
writer); both write beside it ``CGAReport.txt`` (a line per report: the initial shape's index,
the key, the value), ``CGAPrint.txt`` (what ``print`` wrote) and ``CGAError.txt`` (the CGA
errors and warnings). ``com.esri.prt.codecs.I3SEncoder`` writes ``<baseName>.slpk`` (a Scene
Layer Package, :mod:`shapegen.prt.i3s_encoder`) and ``com.esri.prt.codecs.FBXEncoder``
``<baseName>_0.fbx`` (binary FBX, :mod:`shapegen.prt.fbx_encoder`), each with the same three
files. The OBJ and FBX encoders write the texture coordinates and materials an initial shape
read from an OBJ file carries (:mod:`shapegen.prt.initial_textures`); the glTF and I3S encoders
do not, and say so in ``CGAError.txt`` and on standard error. Every file is written
atomically. Other encoders are refused with one line.

``outputPath`` is treated as PyPRT treats it (``src/cpp/client/ModelGenerator.cpp`` of
Esri/pyprt): without it the files go to the folder ``pyprt_fallback_output`` in the system's
temporary folder, made if missing, with a warning; a folder that does not exist is refused
(PyPRT logs that it "is not valid or does not exist" and writes nothing), so a script that runs
here runs on PyPRT too. PyPRT's own examples make the folder first
(``os.makedirs(path, exist_ok=True)``), and the refusal says so.
"""

from __future__ import annotations

__all__ = ["file_encoder", "ENCODERS"]

import sys
import tempfile
import warnings
from collections.abc import Callable, Mapping
from pathlib import Path

import numpy as np

from shapegen.errors import OptionError
from shapegen.export.atomic import atomic_write
from shapegen.prt.fbx_encoder import fbx_writer
from shapegen.prt.generated_models import GeneratedModel
from shapegen.prt.i3s_encoder import i3s_writer

OBJ_ENCODER = "com.esri.prt.codecs.OBJEncoder"
GLTF_ENCODER = "com.esri.prt.codecs.GLTFEncoder"
I3S_ENCODER = "com.esri.prt.codecs.I3SEncoder"
FBX_ENCODER = "com.esri.prt.codecs.FBXEncoder"
FILE_OPTIONS = ("outputPath", "baseName")
TEXTURING = (OBJ_ENCODER, FBX_ENCODER)
"""The encoders that write an initial shape's texture coordinates and textures."""


def file_encoder(name: str, options: Mapping[str, object]) -> Callable[[list], None]:
    """The writer of encoder ``name`` with ``options``, checked before anything is generated."""
    if name not in ENCODERS:
        raise OptionError(
            f"encoder {name!r} is not supported by shapegen; it has com.esri.pyprt.PyEncoder,"
            f" {', '.join(ENCODERS)}"
        )
    # each encoder checks its own options (beyond the folder and name) before anything is made
    write_geometry = ENCODERS[name]({k: v for k, v in options.items() if k not in FILE_OPTIONS})
    folder = _output_folder(name, options)
    base = str(options.get("baseName", "base_name"))
    if not base or "/" in base or "\\" in base:
        raise OptionError(f"{name}: baseName {base!r} is not a file name")

    def write(models: list[GeneratedModel]) -> None:
        write_geometry(models, folder, base)
        errors = [e for m in models for e in m.get_cga_errors()]
        if name not in TEXTURING and any(m.initial_texture is not None for m in models):
            # said, not silently dropped: the initial shapes carry textures this writer leaves
            left_out = (
                f"{name}: shapegen's encoder writes no texture coordinates or textures; those"
                " of the initial shapes are left out (the OBJ and FBX encoders write them)"
            )
            print(f"shapegen.prt: {left_out}", file=sys.stderr)
            errors.append(left_out)
        _write_text(folder / "CGAReport.txt", _report_lines(models))
        _write_text(folder / "CGAPrint.txt", "".join(m.get_cga_prints() for m in models))
        _write_text(folder / "CGAError.txt", "".join(f"{e}\n" for e in errors))

    return write


#: Where PyPRT writes a file encoder's output when no ``outputPath`` is given (in the system's
#: temporary folder).
FALLBACK_FOLDER = "pyprt_fallback_output"


def _output_folder(name: str, options: Mapping[str, object]) -> Path:
    """The folder ``outputPath`` names, or PyPRT's fallback folder (made) when it is absent."""
    if "outputPath" not in options:
        folder = Path(tempfile.gettempdir()) / FALLBACK_FOLDER
        try:
            folder.mkdir(exist_ok=True)
        except OSError as exc:
            raise OptionError(
                f"{name}: cannot make {str(folder)!r}: {exc.strerror or exc}"
            ) from None
        warnings.warn(
            f"{name}: encoder option 'outputPath' was not given; writing to {folder}, as PyPRT"
            " does",
            stacklevel=3,
        )
        return folder
    folder = Path(str(options["outputPath"]))
    if not str(options["outputPath"]) or not folder.is_dir():
        what = "is not a folder" if folder.exists() else "does not exist"
        raise OptionError(
            f"{name}: outputPath {str(folder)!r} {what}; make the folder first"
            " (os.makedirs(path, exist_ok=True)), as PyPRT needs too"
        )
    return folder


def _write_obj(models: list[GeneratedModel], folder: Path, base: str) -> None:
    """Every model's leaves, one group per initial shape. Faces lying on an initial shape read
    from an OBJ file (:mod:`shapegen.prt.initial_textures`) carry its texture coordinates
    (``f v/vt``) and its material (``usemtl``, in ``<baseName>.mtl`` with its ``Kd`` and
    ``map_Kd``, the texture copied beside), as PyPRT 1.12's OBJ encoder writes them."""
    from shapegen.prt.initial_textures import face_textures, placed_textures

    textured = any(m.initial_texture is not None for m in models)
    lines = [f"# {len(models)} initial shapes"]
    if textured:
        lines.append(f"mtllib {base}.mtl")
    offset, uv_offset, current = 1, 1, None
    library: dict = {}  # (name, rgb, texture) -> the material's name in the library
    for k, model in enumerate(models):
        vertices = model.get_vertices()
        lines.append(f"g shape_{k}")
        lines.extend(
            f"v {vertices[i]:.6f} {vertices[i + 1]:.6f} {vertices[i + 2]:.6f}"
            for i in range(0, len(vertices), 3)
        )
        texture = model.initial_texture
        corner = offset
        for leaf in [*model.model.blocks, *model.model.surfaces] if vertices else []:
            polygons = list(getattr(leaf, "polygons", None) or leaf.faces)
            for polygon, (uv, source, _) in zip(
                polygons, face_textures(leaf, polygons, texture), strict=True
            ):
                ring = [str(corner + int(i)) for i in polygon]
                if textured:
                    look = _obj_material(leaf, texture, source, uv, library)
                    if look != current:
                        lines.append(f"usemtl {look}")
                        current = look
                if uv is not None:
                    lines.extend(f"vt {u:.6f} {v:.6f}" for u, v in np.asarray(uv))
                    ring = [f"{c}/{uv_offset + n}" for n, c in enumerate(ring)]
                    uv_offset += len(ring)
                lines.append("f " + " ".join(ring))
            corner += len(leaf.vertices)
        offset += len(vertices) // 3
    if textured:
        images = placed_textures([key[2] for key in library if key[2]], folder)
        entries = []
        for (_, rgb, image), name in library.items():
            entries += [f"newmtl {name}", "Kd " + " ".join(f"{c:.6f}" for c in rgb)]
            if image:
                entries.append(f"map_Kd {images[image][1]}")
            entries.append("")
        _write_text(folder / f"{base}.mtl", "\n".join(entries))
    _write_text(folder / f"{base}_0.obj", "\n".join(lines) + "\n")


def _obj_material(leaf, texture, source, uv, library: dict) -> str:
    """The library name of a face's material: its OBJ material (the rule's colour over
    ``Kd``; the texture where the face has coordinates), else the leaf's colour or white."""
    from shapegen.prt.initial_textures import face_look

    look = leaf.appearance
    own = look.color if look is not None and look.color is not None else None
    name, rgb, image = face_look(own, texture, source, uv)
    name = name or "default"
    key = (name, tuple(round(float(c), 6) for c in rgb), image)
    if key not in library:
        taken = set(library.values())
        unique, n = name, 0
        while unique in taken:
            n += 1
            unique = f"{name}_{n}"
        library[key] = unique
    return library[key]


def _write_gltf(models: list[GeneratedModel], folder: Path, base: str) -> None:
    """One glTF of every model: each block renamed after its shape (``s0_b3``) so that ids
    stay unique."""
    from dataclasses import replace

    from shapegen.export.gltf import encode_glb
    from shapegen.model.model import Model

    blocks, surfaces = [], []
    for k, model in enumerate(models):
        blocks += [replace(b, id=f"s{k}_{b.id}") for b in model.model.blocks]
        surfaces += model.model.surfaces
    with atomic_write(folder / f"{base}_0.glb", "wb") as handle:
        handle.write(encode_glb(Model(blocks, ground=None, surfaces=surfaces)))


def _report_lines(models: list[GeneratedModel]) -> str:
    lines = []
    for k, model in enumerate(models):
        for key, value in model.model.metadata.get("reports", {}).items():
            for item in value if isinstance(value, list) else [value]:
                lines.append(f"{k}\t{key!r}\t{item!r}\n")
    return "".join(lines)


def _write_text(path: Path, text: str) -> None:
    with atomic_write(path, "w") as handle:
        handle.write(text)


def _plain_writer(name: str, writer: Callable) -> Callable[[Mapping[str, object]], Callable]:
    """An encoder that takes no option but ``outputPath`` and ``baseName``."""

    def prepare(options: Mapping[str, object]) -> Callable:
        if options:
            raise OptionError(
                f"{name} takes {', '.join(FILE_OPTIONS)}; not {', '.join(sorted(options))}"
            )
        return writer

    return prepare


ENCODERS = {
    OBJ_ENCODER: _plain_writer(OBJ_ENCODER, _write_obj),
    GLTF_ENCODER: _plain_writer(GLTF_ENCODER, _write_gltf),
    I3S_ENCODER: i3s_writer,
    FBX_ENCODER: fbx_writer,
}
"""Each encoder's name and what checks its options (all but ``outputPath`` and ``baseName``)
and returns its writer ``(models, folder, base_name)``."""
