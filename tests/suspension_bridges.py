"""The five suspension bridges of Patow 2012's Table 1, the truth data of the cable model
(tests/statics/test_cables.py) and of the search on it (tests/search/test_cable_search.py)."""

from typing import NamedTuple


class Bridge(NamedTuple):
    name: str
    main_span: float  # m (Table 1)
    sag: float  # the main cable's sag: Table 1's height above the road, m
    length: float  # between the anchorages: main span and both side spans, m
    lanes: int  # Table 1
    tracks: int  # Table 1
    cables: int  # Table 1
    table_2_diameter: float  # the D_direct column of Table 2, m, published to two decimals
    built_diameter: float  # the main-cable diameter published for the bridge as built, m


BRIDGES = [
    Bridge("Golden Gate", 1280.0, 152.0, 1966.0, 6, 0, 2, 0.92, 0.924),
    Bridge("Akashi Kaikyo", 1991.0, 217.08, 3911.0, 6, 0, 2, 1.19, 1.122),
    Bridge("Humber", 1410.0, 125.5, 2220.0, 4, 0, 2, 0.89, 0.70),
    Bridge("Manhattan", 448.0, 61.3, 890.0, 7, 4, 4, 0.49, 0.53),
    Bridge("Brooklyn", 487.0, 43.12, 1053.0, 6, 0, 4, 0.45, 0.40),
]
