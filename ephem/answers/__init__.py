"""The answers: one request each (checks, charges, computes through the family), rendered with units in the keys.

- :mod:`ephem.answers.requests`: The library's public answers: precession, nutation, tracks, histories, the free motion, the catalogue.
- :mod:`ephem.answers.render`: The one place answers are rendered: the families' typed results in, the contract's dicts out.
- :mod:`ephem.answers.results`: The answers as objects a notebook holds: the contract's dicts, with their table, a plain copy and a short repr.
- :mod:`ephem.answers.batches`: The batch answer: a table of bodies through the vectorised theory, bounded like the rest.
- :mod:`ephem.answers.figures`: Publication-quality plots of spin-axis tracks, the free wobble and histories (matplotlib, PNG and SVG).
- :mod:`ephem.answers.kernels`: NAIF SPICE text PCK kernels (``KPL/PCK``) fitted to the spin-axis track.
- :mod:`ephem.answers.parameters`: The answers' shared parameter descriptions: each numpydoc entry written once, filled into each docstring.

The package imports none of its modules: importing one loads only what it needs.
"""
