"""Measure how CityEngine's runtime offsets an attr's random stream by the attr's name.

A development tool, run with the python of an environment with PyPRT (never a dependency)::

    /tmp/prt/bin/python tools/measure_attr_offsets.py [PACKAGES_FOLDER]

Building_From_FootprintSMALL's compiled rule (``bin/*.cgb``, a Java class file) names its attr
``Eave_Ht`` by the constant ``Default$Eave_Ht``; its default is ``96 / rand(5, 10)`` on a 96 m2
lot. The tool renames that constant (the class file's constant pool, lengths rewritten), packs
the package again (7z, LZMA, as PyPRT reads it) and reads the attr back from PyPRT for seed 0:
the draw gives the stream's start, and so the offset ``k`` the name gives. It adds the numbers to
``tests/data/cityengine_random.json`` under ``attr_offsets``.
"""

import json
import shutil
import struct
import subprocess
import sys
import tempfile
from pathlib import Path

import pyprt

MODULUS, MULTIPLIER, INCREMENT = 714025, 4096, 150889
LOT = [0.0, 0.0, 8.0, 12.0, 0.0, 8.0, 12.0, 0.0, 0.0, 0.0, 0.0, 0.0]  # 12 x 8 m, 96 m2
NAMES = ["Default$Eave_Ht", "Default$Eave_Hu", "Default$Eave_Hs", "Default$Eave_Iu",
         "Default$E", "Default$F", "Default$EE", "Default$Eave_Htt", "Default$OBJECTID",
         "Default$minBuildingHeight"]  # fmt: skip
# every one-character name, and a few of two: how one character moves the offset
NAMES += [f"Default${c}" for c in "0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZ_abcdefghijklmnopqrstuvwxyz"
          if f"Default${c}" not in NAMES]  # fmt: skip
NAMES += [f"Default${a}{b}" for a in "AB" for b in "ABCD"]
SIZES = {3: 4, 4: 4, 5: 8, 6: 8, 7: 2, 8: 2, 9: 4, 10: 4, 11: 4, 12: 4, 15: 3, 16: 2, 18: 4}


def renamed_class(data: bytes, old: bytes, new: bytes) -> bytes:
    """The class file with its Utf8 constant ``old`` replaced by ``new``."""
    count = struct.unpack(">H", data[8:10])[0]
    out, at, index, hits = bytearray(data[:10]), 10, 1, 0
    while index < count:
        tag = data[at]
        if tag == 1:
            length = struct.unpack(">H", data[at + 1 : at + 3])[0]
            text = data[at + 3 : at + 3 + length]
            if text == old:
                text, hits = new, hits + 1
            out += bytes([1]) + struct.pack(">H", len(text)) + text
            at, index = at + 3 + length, index + 1
            continue
        out += data[at : at + 1 + SIZES[tag]]
        at, index = at + 1 + SIZES[tag], index + (2 if tag in (5, 6) else 1)
    if hits != 1:
        raise SystemExit(f"{old!r} found {hits} times in the constant pool")
    return bytes(out + data[at:])


def offset_of(package: Path, name: str, work: Path) -> tuple[int, float]:
    folder = Path(tempfile.mkdtemp(dir=work))
    subprocess.run(["7z", "x", f"-o{folder}", str(package)], check=True, capture_output=True)
    (compiled,) = (folder / "bin").glob("*.cgb")
    compiled.write_bytes(renamed_class(compiled.read_bytes(), b"Default$Eave_Ht", name.encode()))
    repacked = work / f"{folder.name}.rpk"
    packing = ["-t7z", "-m0=LZMA", "-ms=off", "-mhc=off", "-mtm=off", "-mta=off", "-mtc=off"]
    subprocess.run(["7z", "a", *packing, str(repacked), "."], cwd=folder, check=True,
                   capture_output=True)  # fmt: skip
    generator = pyprt.ModelGenerator([pyprt.InitialShape(LOT)])
    (model,) = generator.generate_model([{"seed": 0}], str(repacked), "com.esri.pyprt.PyEncoder",
                                        {"emitReport": False, "emitGeometry": False})  # fmt: skip
    value = model.get_attributes()[name.split("$", 1)[1]]
    state = round((96.0 / value - 5.0) / 5.0 * (MODULUS - 1))
    start = (state - INCREMENT) * pow(MULTIPLIER, -1, MODULUS) % MODULUS
    return start, value  # seed 0: the stream's start is k itself


# the corpus's packages: ../shared/cga-corpus/packages of the checkout, or the folder named
default = Path(__file__).resolve().parents[2] / "shared" / "cga-corpus" / "packages"
packages = Path(sys.argv[1]) if len(sys.argv) > 1 else default
package = packages / "Esri+pyprt__data_Building_From_FootprintSMALL__fc6ce924.rpk"
fixture = Path(__file__).resolve().parents[1] / "tests" / "data" / "cityengine_random.json"
work = Path(tempfile.mkdtemp())
values = {}
for name in NAMES:
    k, value = offset_of(package, name, work)
    values[name] = {"k": k, "Eave_Ht_value": value}
    print(name, k, value)
shutil.rmtree(work)
measured = json.loads(fixture.read_text())
measured["attr_offsets"] = {
    "package": "data_Building_From_FootprintSMALL__fc6ce924",
    "lot": "12x8 (area 96 m2)",
    "seed": 0,
    "what": "the compiled rule's constant Default$Eave_Ht renamed (tools/measure_attr_offsets.py): "
    "the attr's value 96 / rand(5, 10) for seed 0 under each name, and the offset k it gives; "
    "OBJECTID and minBuildingHeight give the offsets measured in the extrusion package, so k "
    "follows from the name, not the file",
    "values": values,
}
fixture.write_text(json.dumps(measured, indent=1) + "\n")
