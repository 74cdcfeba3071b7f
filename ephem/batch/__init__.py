"""Batches: the theory vectorised over a table of bodies, and catalogues on Dask.

- :mod:`ephem.batch.cluster`: The Dask cluster of a batch: an existing one at a scheduler's address, or a local one, and its dashboard.
- :mod:`ephem.batch.distributed`: Catalogues of bodies on a distributed engine (issue 19): ``ephem batch INPUT --out OUT``.
- :mod:`ephem.batch.manifest`: A batch's manifest: resume the work in OUT, or refuse it when the input or the settings changed.
- :mod:`ephem.batch.partitions`: A batch's input: its format and columns checked, then split *streaming* into partitions under ``OUT/_input/``.
- :mod:`ephem.batch.population`: Precession and nutation of a population of bodies at once: the single-perturber theory vectorised over bodies.
- :mod:`ephem.batch.rows`: A bad row marked in a batch core's output columns: its reason in ``error``, NaN or "" in the rest.
- :mod:`ephem.batch.tangents`: Forward-mode derivatives of the population core's values for its σ columns.
- :mod:`ephem.batch.task`: One task of a batch: an input partition through the core (``ephem.batch.population``), its answer written atomically.

The package imports none of its modules: importing one loads only what it needs.
"""
