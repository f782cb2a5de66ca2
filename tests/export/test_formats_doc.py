"""The examples in docs/formats.md are valid and mean what the text says."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from shapegen.readers.blocks_json import model_from_dict
from shapegen.readers.models import read_model

DOCS = Path(__file__).resolve().parents[2] / "docs"


def test_json_example_reads_as_documented():
    text = (DOCS / "formats.md").read_text()
    example = re.search(r"```json\n(.*?)```", text, re.DOTALL).group(1)
    model = model_from_dict(json.loads(example))
    pier, cap = model.blocks
    assert (pier.id, cap.id) == ("pier", "cap")
    assert pier.volume == pytest.approx(1 * 2 * 1)
    assert cap.volume == pytest.approx(1.5 * 0.4 * 1)  # from the hull of its vertices
    assert cap.tags == ("capital",) and cap.density == 2400 and not cap.fixed
    assert model.loads[0].block == "cap"


def test_bundled_arch_example():
    model = read_model(DOCS / "examples" / "arch.json")
    assert len(model.blocks) == 24
    assert min(b.vertices[:, 1].min() for b in model.blocks) == 0.0  # springings on the ground
