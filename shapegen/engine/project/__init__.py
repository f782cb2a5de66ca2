"""A rule's project on disk: where the bundled rules live, CityEngine rule packages (``.rpk``),
and the asset search that finds and reads the files a rule names."""
