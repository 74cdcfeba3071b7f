"""The bodies: the catalogue, the moments of inertia, and catalogue import.

The catalogue holds each body's orbit, pole, rotation and moments, each value with its unit, uncertainty and source.

- :mod:`ephem.bodies.catalogue`: The body catalogue: orbits, spin poles, rotation periods and moments of inertia (the records, a dataset's TOML read into them, the lookups).
- :mod:`ephem.bodies.measured`: A catalogue value as published (value, unit, uncertainty, source), and the values a body record's tables give.
- :mod:`ephem.bodies.datasets`: Where the datasets of bodies live, and which there are: the shipped ones and a user's own.
- :mod:`ephem.bodies.inertia`: Principal moments of inertia from what is measured, with their covariance.
- :mod:`ephem.bodies.interior`: The interior model of a body for its forced nutation: rigid, or a transfer function of
  the circular components (data/interiors.toml).
- :mod:`ephem.bodies.importer`: Bring your own data: a dataset built from a user's orbit file and pole/period table (docs/catalogue_import.md).
- :mod:`ephem.bodies.orbit_files`: The orbit files an import reads: MPCORB, SBDB JSON, SBDB CSV.
- :mod:`ephem.bodies.pole_table`: The pole/period table an import reads.
- :mod:`ephem.bodies.import_records`: What an import reads (orbit and pole records, each value), its error naming file, line and field, and the readers both files share.

The package imports none of its modules: importing one loads only what it needs.
"""
