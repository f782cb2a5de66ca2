"""The CityEngine annotations the Inspector honours (cga_annotations): what the state says of
each attr, the sections and their order, and the values the API takes or refuses for them."""

import json

import pytest
from editor_http import request, serving
from editor_stack import annotated_project

from shapegen import pipeline
from shapegen.editor.annotations import asset_choices, inspector_sections
from shapegen.editor.attrs import RequestError, checked_values, range_warnings


@pytest.fixture
def annotated(tmp_path):
    return annotated_project(tmp_path)


def rows(state) -> dict:
    return {a["name"]: a for a in state["attrs"]}


def test_the_state_says_how_each_attr_is_shown(annotated):
    with serving(annotated) as server:
        state = json.loads(request(server, "GET", "/api/state")[2])
    attrs = rows(state)
    offset = attrs["offset"]
    assert (offset["kind"], offset["minimum"], offset["maximum"]) == ("number", 0, 0.9)
    assert offset["free"] and offset["restricted"]
    assert offset["description"] == "Shift of the upper block along x (m)"
    assert (attrs["angle"]["step"], attrs["angle"]["restricted"]) == (15, True)
    assert (attrs["loose"]["step"], attrs["loose"]["restricted"]) == (15, False)
    assert attrs["angle"]["grid"] == 15 and attrs["loose"]["grid"] is None  # only restricted
    assert attrs["stone"]["choices"] == ["limestone", "granite", "marble"]
    assert attrs["stone"]["kind"] == "string" and attrs["stone"]["restricted"]
    assert attrs["detail"]["choices"] == ["low", "high"]  # CityEngine's older string @Range
    assert attrs["lanes"]["choices"] == [1, 2, 4] and not attrs["lanes"]["restricted"]
    assert attrs["size"]["choices"] == [1, 2, 3]  # read from the hidden array attr
    assert attrs["sizes"]["hidden"] and attrs["sizes"]["kind"] == "array"
    assert attrs["tint"]["kind"] == "color" and attrs["tint"]["group"] == ["Look"]
    assert attrs["tint"]["description"] == "Colour of the upper block"
    assert attrs["asset"]["kind"] == "file"
    assert attrs["asset"]["choices"] == ["doors/door.obj", "near.obj", "plate.obj"]
    assert attrs["textures"]["kind"] == "directory" and attrs["textures"]["choices"] == ["doors"]
    assert attrs["mortar"]["kind"] == "bool" and attrs["mortar"]["order"] == 2
    # a @Group holds for the attrs after it, until the next one; a bare @Group leaves it
    assert attrs["asset"]["group"] == ["Look"] and attrs["courses"]["group"] == ["Structure"]
    assert attrs["depth"]["group"] == ["Structure", "Deep"]
    assert attrs["loose_end"]["group"] == []
    assert attrs["offset"]["group"] == [] and attrs["offset"]["order"] is None


def test_sections_follow_group_and_order_and_leave_hidden_attrs_out(annotated):
    sections = inspector_sections(pipeline.load(str(annotated)).catalogue)
    assert sections == [
        {
            "group": [],
            "attrs": ["offset", "angle", "loose", "stone", "detail", "lanes", "size", "loose_end"],
        },
        {"group": ["Structure"], "attrs": ["courses", "mortar"]},  # @Order(1), @Order(2)
        {"group": ["Structure", "Deep"], "attrs": ["depth"]},
        {"group": ["Look"], "attrs": ["tint", "asset", "textures"]},  # group order 2 after 1
    ]


def test_asset_choices_list_files_next_to_the_rule_and_in_the_projects_assets(annotated):
    assert asset_choices(annotated, ["OBJ"]) == ["doors/door.obj", "near.obj", "plate.obj"]
    assert asset_choices(annotated) == ["doors/door.obj", "doors/door.png", "near.obj",
                                        "plate.obj"]  # fmt: skip
    assert asset_choices(annotated, directories=True) == ["doors"]
    assert asset_choices(None) == []


@pytest.mark.parametrize(
    ("payload", "status", "message"),
    [
        ({"stone": "slate"}, 400, "attr 'stone' takes one of 'limestone', 'granite', 'marble'"),
        ({"detail": "mid"}, 400, "attr 'detail' takes one of 'low', 'high'; got 'mid'"),
        ({"size": 5}, 400, "attr 'size' takes one of 1, 2, 3; got 5"),
        ({"tint": "red"}, 400, "attr 'tint' is a @Color: it takes \"#rrggbb\"; got 'red'"),
        ({"tint": "#12345"}, 400, "is a @Color"),
        ({"sizes": [1, 2]}, 400, "attr 'sizes' is an array: the editor shows it but cannot set"),
        ({"mortar": "yes"}, 400, "attr 'mortar' takes true or false"),
    ],
)
def test_values_the_annotations_refuse(annotated, payload, status, message):
    grammar = pipeline.load(str(annotated))
    with pytest.raises(RequestError) as caught:
        checked_values(grammar, {}, payload)
    assert caught.value.status == status
    assert message in str(caught.value)


def test_values_the_annotations_take(annotated):
    grammar = pipeline.load(str(annotated))
    taken = {
        "angle": 45,  # on the stepsize's grid
        "loose": 52.5,  # restricted=false: outside the range and off the grid
        "lanes": 3,  # an unrestricted @Enum takes other values
        "stone": "marble",
        "tint": "#FFEE00",
        "asset": "elsewhere/other.obj",  # a path not listed may still be found by the rules
        "mortar": True,
    }
    assert checked_values(grammar, {}, taken) == {**taken, "angle": 45.0, "lanes": 3.0}


HINT = "built as given (a range is a hint, as in CityEngine)"


def test_a_range_is_a_hint_a_value_outside_is_taken_with_one_warning(annotated):
    grammar = pipeline.load(str(annotated))
    taken = {"angle": 60, "offset": 1.5, "loose": 52.5, "courses": 3}
    assert checked_values(grammar, {}, taken) == {k: float(v) for k, v in taken.items()}
    assert range_warnings(grammar, taken, grammar.attrs) == [
        f"attr angle=60 is outside its @Range [0, 45]: {HINT}",
        f"attr offset=1.5 is outside its @Range [0, 0.9]: {HINT}",  # @Free: its range holds
    ]  # loose is restricted=false, courses has no @Range: no warning
    assert range_warnings(grammar, {"angle": 15, "offset": 0.9}, grammar.attrs) == []
    # the stepsize is the slider's: a value between its steps is a hint's matter too
    assert range_warnings(grammar, {"angle": 20, "loose": 20}, grammar.attrs) == [
        "attr angle=20 is off its @Range stepsize 15 from 0 (the values nearest are 15 and 30):"
        f" {HINT}"
    ]


def test_the_command_line_and_the_page_say_the_same_of_a_value_outside_its_range(annotated, capsys):
    from shapegen.cli import main

    assert main(["build", str(annotated), "--set", "angle=60", "--set", "offset=0.95", "-q"]) == 0
    said = [line for line in capsys.readouterr().err.splitlines() if "@Range" in line]
    with serving(annotated) as server:
        status, _, content = request(server, "POST", "/api/attrs", {"angle": 60, "offset": 0.95})
    assert status == 200, content
    page = [w for w in json.loads(content)["warnings"] if "@Range" in w]
    assert said == [w.replace("attr ", "shapegen: warning: --set ", 1) for w in page]
    assert len(page) == 2


def test_the_page_sets_annotated_attrs_through_the_api(annotated):
    with serving(annotated) as server:
        status, _, content = request(server, "POST", "/api/attrs", {"tint": "#336699"})
        assert status == 200
        assert rows(json.loads(content))["tint"]["value"] == "#336699"
        status, _, content = request(server, "POST", "/api/attrs", {"loose": 60})
        assert status == 200 and rows(json.loads(content))["loose"]["value"] == 60
        status, _, content = request(server, "POST", "/api/attrs", {"angle": 10})
        assert status == 200 and "steps by 15" not in content.decode()
        state = json.loads(content)
        assert rows(state)["angle"]["value"] == 10
        assert state["warnings"][0] == (
            "attr angle=10 is off its @Range stepsize 15 from 0 (the values nearest are 0 and"
            " 15): built as given (a range is a hint, as in CityEngine)"
        )


# CityEngine's unit annotations, in a .cga file as CityEngine writes them
UNITS_CGA = """\
version "2023.0"

@Angle
attr pitch = 30

@Angle @Range(min=0, max=60)
attr tilt = 10

@Percent
attr share = 0.25

@Distance
attr setback = 1.5

@Percent @Enum(0.1, 0.2)
attr step = 0.1

@StartRule
Lot --> extrude(1 + setback) s(1, '1, 1) Box
Box --> label("box") i("builtin:cube")
"""


def test_unit_annotations_give_the_unit_and_cityengines_default_slider(tmp_path):
    rule = tmp_path / "units.cga"
    rule.write_text(UNITS_CGA, encoding="utf-8")
    with serving(rule) as server:
        state = json.loads(request(server, "GET", "/api/state")[2])
        attrs = rows(state)
        assert {n: a["unit"] for n, a in attrs.items()} == {
            "pitch": "angle", "tilt": "angle", "share": "percent", "setback": "distance",
            "step": "percent",
        }  # fmt: skip
        # without a @Range: CityEngine's slider, [0, 360] degrees or [0, 1] (0 to 100 %),
        # no bound on a value, and no range for the search
        pitch, share = attrs["pitch"], attrs["share"]
        assert (pitch["minimum"], pitch["maximum"], pitch["restricted"]) == (0, 360, False)
        assert (share["minimum"], share["maximum"], share["restricted"]) == (0, 1, False)
        assert not pitch["ranged"] and not share["ranged"]
        assert (attrs["setback"]["minimum"], attrs["setback"]["ranged"]) == (None, False)
        # a @Range is the slider's, restricted, and the search's
        tilt = attrs["tilt"]
        assert (tilt["minimum"], tilt["maximum"], tilt["restricted"], tilt["ranged"]) == (
            0, 60, True, True
        )  # fmt: skip
        assert attrs["step"]["choices"] == [0.1, 0.2] and attrs["step"]["minimum"] is None
        status, _, content = request(server, "POST", "/api/attrs", {"pitch": 400, "share": 1.5})
        assert status == 200, content
        assert {a["name"]: a["value"] for a in json.loads(content)["attrs"]}["pitch"] == 400
        status, _, content = request(server, "POST", "/api/attrs", {"tilt": 61})
        assert status == 200 and rows(json.loads(content))["tilt"]["value"] == 61
        assert "attr tilt=61 is outside its @Range [0, 60]" in json.loads(content)["warnings"][0]
        status, _, content = request(server, "POST", "/api/settings", {"free": ["pitch"]})
        assert status == 400 and b"cannot be free" in content
        assert request(server, "POST", "/api/settings", {"free": ["tilt"]})[0] == 200
