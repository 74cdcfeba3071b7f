"""The foundation: constants, errors, units, time parsing, the work budget, bounded caches and where the data live.

- :mod:`ephem.base.budget`: A request's budget: predicted costs charged before the work, and a deadline while it runs.
- :mod:`ephem.base.centres`: The centres an orbit may name and the perturbers a body may name, read from data/centres.toml on first use.
- :mod:`ephem.base.constants`: Physical and astronomical constants (SI unless the name says otherwise).
- :mod:`ephem.base.disk_cache`: Arrays built from shipped data, kept on disk between processes.
- :mod:`ephem.base.errors`: Exceptions raised by the science core.
- :mod:`ephem.base.extras`: The optional extras of the distribution: which one a feature needs, checked before the feature runs.
- :mod:`ephem.base.grids`: Even grids of epochs that float64 can hold: the one rule every track, figure, kernel and history grid obeys.
- :mod:`ephem.base.lazy`: The faces' lazy names: each public name loads its own module on first use (PEP 562).
- :mod:`ephem.base.memo`: Caches of per-body work bounded in bytes, not in entries.
- :mod:`ephem.base.paths`: Where the shipped data live (the catalogue, the references, the reference tables, the lunar series).
- :mod:`ephem.base.times`: Times at the boundary: ISO 8601 (UTC unless a scale is named) or Julian dates (TDB).
- :mod:`ephem.base.units`: astropy at the boundary: ``Time`` and ``Quantity`` in, and out on request (and the
  catalogue's unit factors, which need no astropy).

The package imports none of its modules: importing one loads only what it needs.
"""
