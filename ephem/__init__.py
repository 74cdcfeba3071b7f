"""The ephem package: forced precession and nutation of the spin axes of asteroids, planets and moons.

Kinoshita's theory with exact Hansen coefficients (Petit, Souchay & Lhotka 2014, A&A 565, A79),
checked against a numerical integration of the torque. Start with :mod:`ephem.answers.requests` (answers with
units in the key names) or :func:`ephem.forced.precession_nutation.model_for` (the numeric model: radians, days).

Importing the package is cheap; astropy loads on the first catalogue read.

Its faces, then its packages from the answers down (docs/architecture.md):

- :mod:`ephem.api`: the public face, every name a program, the CLI or the service needs (``__all__``).
- :mod:`ephem.host`: the hosts' interface beside it: a request's budget, the caches, the warm-up (docs/hosts.md).
- :mod:`ephem.cli`: the ``ephem`` command and its subcommands, through :mod:`ephem.api`.
- :mod:`ephem.answers`: one module per kind of request: checks, charges the budget, computes, renders the dicts.
- :mod:`ephem.exports`: nutation tables, plot drawing, the SPICE kernel's fit and text, astropy tables.
- :mod:`ephem.batch`: the theory vectorised over a table of bodies, and catalogues on Dask.
- :mod:`ephem.families`: which family serves a body under its perturbers (the registry of families).
- :mod:`ephem.sun`: the single-perturber fidelity ladder of Kinoshita's theory.
- :mod:`ephem.earth`: the lunisolar theory of the Earth, rigid and non-rigid.
- :mod:`ephem.moon`: the Moon and synchronous rotators: the Cassini state's pole, the physical librations.
- :mod:`ephem.longterm`: the orbit over millennia (secular and N-body) and the spin axis's history along it.
- :mod:`ephem.theory`: the interface every family implements, its typed results, the costs, the choice by tolerance.
- :mod:`ephem.forced`: the forced theory of one perturber: Kinoshita's equations and what is built on them.
- :mod:`ephem.rotation`: free rotation: Andoyer, Euler-Poinsot, Deprit, the Lie series; the free wobble.
- :mod:`ephem.bodies`: the catalogue (each value with unit, uncertainty and source), the moments, catalogue import.
- :mod:`ephem.orbit`: Kepler, frames, Hansen coefficients, harmonic sums, relativity, DE421, the analytic Moon and Sun.
- :mod:`ephem.base`: constants, errors, units, time parsing, the work budget, bounded caches, data paths.
"""

__version__ = "0.1.0"
