"""The bodies: the catalogue (orbit, pole, rotation, moments, each value with unit, uncertainty and source), the moments of inertia, and catalogue import.

- :mod:`ephem.bodies.catalogue`: The body catalogue: orbits, spin poles, rotation periods and moments of inertia.
- :mod:`ephem.bodies.importer`: Bring your own data: a dataset built from a user's orbit file and pole/period table (docs/catalogue_import.md).
- :mod:`ephem.bodies.inertia`: Principal moments of inertia from what is measured, with their covariance.

The package imports none of its modules: importing one loads only what it needs.
"""
