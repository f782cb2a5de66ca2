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

from shapegen.lazy_names import lazy_names

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

# Each name loads its module on first use: a worker process (python -m shapegen.city.worker)
# imports this package before its own module, and needs neither the lots' readers nor the
# parent's scheduling and tables.
_HOMES = {
    "CRS_CHOICES": "city_lots",
    "City": "city_lots",
    "CityLot": "city_lots",
    "city_from_polygons": "city_lots",
    "read_lots": "city_lots",
    "CityProgress": "run",
    "CityRun": "run",
    "run_city": "run",
    "lot_seed": "work",
}

__getattr__, __dir__ = lazy_names(__name__, _HOMES, __all__)
