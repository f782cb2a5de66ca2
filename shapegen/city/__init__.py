"""One rule over the lots of a city, on this machine's cores or on a Dask cluster.

>>> import shapegen
>>> from shapegen.city import city_from_polygons, run_city
>>> city = city_from_polygons([[(0, 0), (12, 0), (12, 8), (0, 8)],
...                            [(20, 0), (30, 2), (28, 12), (19, 9)]])
>>> run = run_city(city, shapegen.load_grammar("wall_windows"), "out/city")   # doctest: +SKIP
>>> [(r["id"], r["status"], r["stands"]) for r in run.records]              # doctest: +SKIP
[('#1', 'ok', True), ('#2', 'ok', True)]

See docs/city.md: the command ``shapegen city``, the output folder and resuming a run.
"""

from shapegen.city.city_lots import CRS_CHOICES, City, CityLot, city_from_polygons, read_lots
from shapegen.city.run import CityProgress, CityRun, run_city
from shapegen.city.work import lot_seed

__all__ = [
    "CRS_CHOICES",
    "City",
    "CityProgress",
    "CityRun",
    "CityLot",
    "city_from_polygons",
    "lot_seed",
    "read_lots",
    "run_city",
]
