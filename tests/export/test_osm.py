"""OpenStreetMap ways: reading, projection to local metres, placing a bridge, the CLI.

Expected values come from closed forms on the WGS84 ellipsoid (meridian radius of curvature M and
prime-vertical radius N at a latitude) and from the published lengths of a degree of latitude and
longitude, never from the module under test.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from shapegen import Block, Model
from shapegen.cli import main
from shapegen.errors import InputFormatError
from shapegen.export.osm import place_on_way
from shapegen.readers.models import read_model
from shapegen.readers.osm import OsmNode, OsmWay, read_way
from shapegen.readers.projection import east_north

REPO = Path(__file__).resolve().parents[2]
STRAIT = REPO / "docs" / "examples" / "strait.osm"
CROSSING = 1001  # the way across the strait in the sample

A = 6_378_137.0  # WGS84 semi-major axis, m
F = 1 / 298.257223563
E2 = F * (2 - F)


def radii(lat_degrees: float) -> tuple[float, float]:
    """Meridian (M) and prime-vertical (N) radii of curvature of WGS84 at a latitude, m."""
    s2 = math.sin(math.radians(lat_degrees)) ** 2
    return A * (1 - E2) / (1 - E2 * s2) ** 1.5, A / math.sqrt(1 - E2 * s2)


def small_offset(lat0, lon0, lat1, lon1) -> tuple[float, float]:
    """East and north from (lat0, lon0) to (lat1, lon1) with the radii at the mid-latitude, m.

    Accurate to about 1e-5 relative over a few kilometres, independent of the module's
    earth-centred construction.
    """
    middle = 0.5 * (lat0 + lat1)
    m, n = radii(middle)
    return (
        n * math.cos(math.radians(middle)) * math.radians(lon1 - lon0),
        m * math.radians(lat1 - lat0),
    )


def initial_heading(lat0, lon0, lat1, lon1) -> float:
    """Direction at (lat0, lon0) towards (lat1, lon1), degrees clockwise from north.

    The mid-latitude azimuth less half the convergence of the meridians over the step,
    dlon sin(lat): the direction turns by that much between the two ends.
    """
    east, north = small_offset(lat0, lon0, lat1, lon1)
    convergence = (lon1 - lon0) * math.sin(math.radians(0.5 * (lat0 + lat1))) / 2
    return (math.degrees(math.atan2(east, north)) - convergence) % 360


def osm_document(nodes, ways) -> str:
    """An OSM XML text: nodes as (id, lat, lon), ways as (id, [refs])."""
    lines = ['<?xml version="1.0" encoding="UTF-8"?>', '<osm version="0.6">']
    lines += [f'  <node id="{i}" lat="{lat}" lon="{lon}"/>' for i, lat, lon in nodes]
    for way_id, refs in ways:
        lines.append(f'  <way id="{way_id}">')
        lines += [f'    <nd ref="{ref}"/>' for ref in refs]
        lines.append('    <tag k="highway" v="primary"/>')
        lines.append("  </way>")
    lines.append("</osm>")
    return "\n".join(lines) + "\n"


# ------------------------------------------------------------------------------ projection
# Length of one degree of latitude and of longitude on WGS84, m (published tables).
DEGREE_LENGTHS = [
    (0.0, 110_574.0, 111_320.0),
    (45.0, 111_132.0, 78_847.0),
    (60.0, 111_412.0, 55_800.0),
]


@pytest.mark.parametrize(("lat", "per_degree_lat", "per_degree_lon"), DEGREE_LENGTHS)
def test_a_hundredth_of_a_degree_matches_the_published_degree_lengths(
    lat, per_degree_lat, per_degree_lon
):
    north_step = east_north(lat + 0.01, 10.0, lat, 10.0)
    east_step = east_north(lat, 10.01, lat, 10.0)
    assert north_step[1] == pytest.approx(per_degree_lat / 100, abs=0.02)
    assert abs(north_step[0]) < 1e-6
    assert east_step[0] == pytest.approx(per_degree_lon / 100, abs=0.02)


@pytest.mark.parametrize("lat", [-60.0, -12.5, 0.0, 37.8, 51.5, 70.0])
def test_north_and_east_steps_follow_the_radii_of_curvature(lat):
    m, n = radii(lat + 0.005)
    north = east_north(lat + 0.01, -3.0, lat, -3.0)[1]
    assert north == pytest.approx(m * math.radians(0.01), abs=1e-3)
    # About 1112 m with the mean earth radius; the ellipsoid puts it within 0.6 %.
    assert north == pytest.approx(6_371_008.8 * math.radians(0.01), rel=6e-3)
    m, n = radii(lat)
    east = east_north(lat, -2.99, lat, -3.0)[0]
    # A point on the parallel (a circle of radius N cos(lat)) dlon away: east = r sin(dlon).
    radius = n * math.cos(math.radians(lat))
    assert east == pytest.approx(radius * math.sin(math.radians(0.01)), abs=1e-6)
    equator = east_north(0.0, -2.99, 0.0, -3.0)[0]
    assert east / equator == pytest.approx(math.cos(math.radians(lat)), rel=5e-3)


def test_projection_is_vectorized_and_origin_is_zero():
    lat = np.array([37.0, 37.001, 36.999])
    lon = np.array([-122.0, -122.0, -121.999])
    points = east_north(lat, lon, 37.0, -122.0)
    assert points.shape == (3, 2)
    assert np.allclose(points[0], 0.0, atol=1e-9)
    assert points[1][1] > 0 > points[2][1] and points[2][0] > 0


# ------------------------------------------------------------------------------ the way
def way_of(*coordinates) -> OsmWay:
    return OsmWay(1, tuple(OsmNode(k, lat, lon) for k, (lat, lon) in enumerate(coordinates)))


@pytest.mark.parametrize(
    ("step", "heading"),
    [((0.001, 0.0), 0.0), ((0.0, 0.001), 90.0), ((-0.001, 0.0), 180.0), ((0.0, -0.001), 270.0)],
)
def test_cardinal_headings(step, heading):
    way = way_of((48.0, 2.0), (48.0 + step[0], 2.0 + step[1]))
    # Due east or west the direction is north of the parallel by dlon sin(lat) / 2 (0.0004 deg).
    assert (way.heading - heading + 180) % 360 - 180 == pytest.approx(0.0, abs=1e-3)
    expected = initial_heading(48.0, 2.0, 48.0 + step[0], 2.0 + step[1])
    assert way.heading == pytest.approx(expected, abs=1e-5)


@pytest.mark.parametrize("lat", [0.0, 37.8, -45.0])
def test_diagonal_heading_follows_the_radii(lat):
    way = way_of((lat, 5.0), (lat + 0.002, 5.003))
    assert way.heading == pytest.approx(initial_heading(lat, 5.0, lat + 0.002, 5.003), abs=1e-5)


def test_l_shaped_way_lengths():
    # North 0.01 degree along a meridian on the equator, then east 0.01 degree.
    way = way_of((0.0, 0.0), (0.01, 0.0), (0.01, 0.01))
    m, _ = radii(0.005)
    _, n = radii(0.01)
    leg_north = m * math.radians(0.01)
    leg_east = n * math.cos(math.radians(0.01)) * math.radians(0.01)
    assert way.polyline_length == pytest.approx(leg_north + leg_east, abs=0.01)
    assert way.straight_length == pytest.approx(math.hypot(leg_north, leg_east), abs=0.01)
    assert way.heading == pytest.approx(initial_heading(0.0, 0.0, 0.01, 0.01), abs=1e-4)


def test_sample_way_is_read_in_order_with_its_tags():
    way = read_way(STRAIT, CROSSING)
    assert [node.id for node in way.nodes] == [1, 2, 3, 4]
    assert way.tags["highway"] == "primary" and way.tags["name"]
    first, last = way.nodes[0], way.nodes[-1]
    east, north = small_offset(first.lat, first.lon, last.lat, last.lon)
    assert way.straight_length == pytest.approx(math.hypot(east, north), abs=0.01)
    assert 2500 < way.straight_length < 3000  # a strait about 2.7 km wide
    segments = sum(
        math.hypot(*small_offset(p.lat, p.lon, q.lat, q.lon))
        for p, q in zip(way.nodes[:-1], way.nodes[1:], strict=True)
    )
    assert way.polyline_length == pytest.approx(segments, abs=0.02)
    assert way.polyline_length > way.straight_length
    expected = initial_heading(first.lat, first.lon, last.lat, last.lon)
    assert way.heading == pytest.approx(expected, abs=1e-4)


def test_negative_ids_of_unsaved_edits(tmp_path):
    path = tmp_path / "new.osm"
    path.write_text(osm_document([(-1, 10.0, 20.0), (-2, 10.01, 20.0)], [(-5, [-1, -2])]))
    way = read_way(path, -5)
    assert [node.id for node in way.nodes] == [-1, -2]


# ------------------------------------------------------------------------------ placement
@pytest.mark.parametrize(
    ("end", "x_axis"),
    [((0.0, 0.001), (1.0, 0.0, 0.0)), ((0.001, 0.0), (0.0, 0.0, -1.0)),
     ((0.0, -0.001), (-1.0, 0.0, 0.0)), ((-0.001, 0.0), (0.0, 0.0, 1.0))],
)  # fmt: skip
def test_placement_turns_x_along_the_way_and_centres_the_width(end, x_axis):
    box = Block.box([0.0, 0.0, -1.0], [10.0, 2.0, 3.0], id="deck")  # z middle at 1
    model = Model([box], metadata={"attrs": {"length": 10.0}})
    way = way_of((0.0, 0.0), end)
    placed = place_on_way(model, way)
    block = placed.blocks[0]
    x_axis = np.array(x_axis)
    z_axis = np.cross(x_axis, [0.0, 1.0, 0.0])  # right-handed, y up: z = x cross y
    expected = np.array(
        [x * x_axis + [0.0, y, 0.0] + (z - 1.0) * z_axis for x, y, z in box.vertices]
    )
    assert np.allclose(block.vertices, expected, atol=1e-9)
    assert block.volume == pytest.approx(box.volume)  # faces still outward
    assert np.allclose(block.centroid, expected.mean(axis=0), atol=1e-9)
    assert placed.metadata["attrs"] == {"length": 10.0}
    assert placed.metadata["osm"]["way"] == 1


def test_placement_of_a_closed_way_is_an_error():
    way = way_of((0.0, 0.0), (0.001, 0.0), (0.0, 0.0))
    with pytest.raises(InputFormatError, match="coincide"):
        place_on_way(Model([Block.box([0, 0, 0], [1, 1, 1])]), way)


# ------------------------------------------------------------------------------ the command
def run(argv, capsys) -> tuple[int, str]:
    status = main([str(a) for a in argv])
    return status, capsys.readouterr().err


def test_build_a_bridge_on_the_sample_way(tmp_path, capsys):
    out, report_path = tmp_path / "out.json", tmp_path / "r.json"
    argv = ["build", "suspension_bridge.grammar", "--osm", STRAIT, "--way", CROSSING]
    status, err = run([*argv, "-o", out, "--report", report_path, "-q"], capsys)
    assert status == 0, err
    report = json.loads(report_path.read_text())
    way = report["osm"]
    first, last = way["first_node"], way["last_node"]
    east, north = small_offset(first["lat"], first["lon"], last["lat"], last["lon"])
    straight = math.hypot(east, north)
    assert report["attrs"]["length"] == pytest.approx(straight, abs=0.01)
    assert way["straight_length"] == pytest.approx(straight, abs=0.01)
    assert way["polyline_length"] > way["straight_length"]
    assert way["way"] == CROSSING and way["nodes"] == 4
    expected = initial_heading(first["lat"], first["lon"], last["lat"], last["lon"])
    assert way["heading"] == pytest.approx(expected, abs=1e-4)

    model = read_model(out)
    along_axis = np.array([east, -north]) / straight  # the way's direction in (x, z)
    across_axis = np.array([-along_axis[1], along_axis[0]])

    def along_across(tag):
        points = np.vstack([b.vertices for b in model.blocks if tag in b.tags])
        plan = points[:, [0, 2]]
        return plan @ along_axis, plan @ across_axis, points

    along, across, deck = along_across("deck panel")
    assert along.min() == pytest.approx(0.0, abs=0.05)
    assert along.max() == pytest.approx(straight, abs=0.05)
    assert across.min() == pytest.approx(-across.max(), abs=0.1)  # centred on the way
    # The deck's ends, projected back to latitude and longitude (mid-latitude radii), are the
    # way's end nodes: within 3e-6 degree, 0.3 m (the tangent plane and the mid-latitude
    # formula differ by some 0.1 m over 2.7 km; a wrong turn or sign is off by hundreds).
    for end_along, node in ((0.0, first), (straight, last)):
        ends = deck[np.abs(along - end_along) < 0.05]
        x, z = ends[:, 0].mean(), ends[:, 2].mean()
        m, n = radii(0.5 * (first["lat"] + node["lat"]))
        lat = first["lat"] + math.degrees(-z / m)
        middle = math.radians(0.5 * (first["lat"] + lat))
        lon = first["lon"] + math.degrees(x / (n * math.cos(middle)))
        assert lat == pytest.approx(node["lat"], abs=3e-6)
        assert lon == pytest.approx(node["lon"], abs=3e-6)

    along, across, _ = along_across("cable")
    assert along.min() == pytest.approx(0.0, abs=0.05)
    assert along.max() == pytest.approx(straight, abs=0.05)
    assert across.min() == pytest.approx(-across.max(), abs=0.1)  # the two cables either side
    assert min(b.vertices[:, 1].min() for b in model.blocks) == pytest.approx(0.0, abs=1e-9)


def test_optimize_on_a_way_keeps_its_length(tmp_path, capsys):
    report_path = tmp_path / "r.json"
    status, err = run(
        ["build", "suspension_bridge.grammar", "--osm", STRAIT, "--way", CROSSING, "--optimize",
         "--report", report_path, "-q"],
        capsys,
    )  # fmt: skip
    assert status == 0, err
    report = json.loads(report_path.read_text())
    assert report["attrs"]["length"] == pytest.approx(report["osm"]["straight_length"])
    # the cable figures are in the cable structure's assessment
    assert report["analysis"]["structure"] == "cable"
    assert report["analysis"]["main_span"] <= report["osm"]["straight_length"]
    assert "optimization" in report and "analysis" in report


NODES = [(1, 37.80, -122.47), (2, 37.81, -122.47), (3, 37.82, -122.48)]
BAD_FILES = [
    ("no way with id 9 (ways: 5, 6)", osm_document(NODES, [(5, [1, 2]), (6, [2, 3])])),
    ("way 9 has 1 node; a bridge needs at least two", osm_document(NODES, [(9, [1])])),
    ("way 9 has 0 nodes", osm_document(NODES, [(9, [])])),
    ("way 9 refers to node 4, which is not in the file", osm_document(NODES, [(9, [1, 4])])),
    ("node 2 has lat='95'", osm_document([(1, 0, 0), (2, 95, 0)], [(9, [1, 2])])),
    ("node 2 has lon='east'", osm_document([(1, 0, 0), (2, 0, "east")], [(9, [1, 2])])),
    ("node 2 has lat='nan'", osm_document([(1, 0, 0), (2, "nan", 0)], [(9, [1, 2])])),
    ("the first and last nodes of way 9 coincide", osm_document(NODES, [(9, [1, 2, 1])])),
    ("invalid XML", '<osm version="0.6"><node id="1" lat="0" lon="0"></osm>'),
    ("invalid XML", ""),
    ("not an OSM XML file (root element <gpx>", "<gpx><way id='9'/></gpx>"),
    ("has id 'x'; OSM ids are integers", "<osm><way id='x'/></osm>"),
]


@pytest.mark.parametrize(("message", "text"), BAD_FILES)
def test_bad_osm_files_fail_with_one_line(tmp_path, capsys, message, text):
    path = tmp_path / "bad.osm"
    path.write_text(text)
    out, report_path = tmp_path / "out.json", tmp_path / "r.json"
    status, err = run(
        ["build", "suspension_bridge.grammar", "--osm", path, "--way", 9, "-o", out,
         "--report", report_path, "-q"],
        capsys,
    )  # fmt: skip
    assert status == 2
    assert err.startswith("shapegen: error: ") and err.count("\n") == 1, err
    assert message in err and str(path) in err
    assert "Traceback" not in err
    assert not out.exists() and not report_path.exists()


BAD_COMMANDS = [
    ("--osm and --way go together", ["suspension_bridge.grammar", "--osm", STRAIT]),
    ("--osm and --way go together", ["suspension_bridge.grammar", "--way", "1001"]),
    ("has no attr 'length'", ["wall_windows.grammar", "--osm", STRAIT, "--way", "1001"]),
    ("--set length conflicts with --osm",
     ["suspension_bridge.grammar", "--set", "length=2000", "--osm", STRAIT, "--way", "1001"]),
    ("invalid int value", ["suspension_bridge.grammar", "--osm", STRAIT, "--way", "first"]),
    ("no_such.osm: cannot read",
     ["suspension_bridge.grammar", "--osm", "no_such.osm", "--way", "1"]),
    # Way 1002 (the 460 m south approach) is shorter than the grammar's main span.
    ("the main spans are longer than the bridge",
     ["suspension_bridge.grammar", "--osm", STRAIT, "--way", "1002"]),
]  # fmt: skip


@pytest.mark.parametrize(("message", "arguments"), BAD_COMMANDS)
def test_bad_osm_commands_fail_cleanly(tmp_path, capsys, message, arguments):
    out = tmp_path / "out.json"
    status, err = run(["build", *arguments, "-o", out, "-q"], capsys)
    assert status == 2
    assert err.startswith("shapegen: error: ") and message in err, err
    assert "Traceback" not in err
    assert not out.exists()
