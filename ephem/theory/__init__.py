"""The interface every family implements (SpinAxisTheory, Estimate), the cost predictors, the shared track helpers.

- :mod:`ephem.theory.choice`: Every decision a tolerance makes (the model, the e-order, the terms kept, a history's
  orbit model): the cheapest priced candidate that meets it, one rule for every family.
- :mod:`ephem.theory.cost`: What a request will cost, known before it runs: CPU seconds of one core and peak memory.
- :mod:`ephem.theory.interface`: One interface for every theory of a body's spin axis.
- :mod:`ephem.theory.requests`: What a track request asks a family for: the model chosen, the epochs and the request as
  one object each.
- :mod:`ephem.theory.results`: What a family computes for an answer: typed results in the library's own units.
- :mod:`ephem.theory.tracks`: What every family's track shares: the poles it may follow, the rounding of its numbers, its pole vectors and

The package imports none of its modules: importing one loads only what it needs.
"""
