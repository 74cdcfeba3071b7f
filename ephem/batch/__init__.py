"""Batches: the theory vectorised over a table of bodies, and catalogues on Dask.

- :mod:`ephem.batch.distributed`: Catalogues of bodies on a distributed engine (issue 19): ``ephem batch INPUT --out OUT``.
- :mod:`ephem.batch.population`: Precession and nutation of a population of bodies at once: the single-perturber theory vectorised over bodies.

The package imports none of its modules: importing one loads only what it needs.
"""
