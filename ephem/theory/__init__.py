"""The interface every family implements (SpinAxisTheory, Estimate), the cost predictors, the shared track helpers.

- :mod:`ephem.theory.cost`: What a request will cost, known before it runs: CPU seconds of one core and peak memory.
- :mod:`ephem.theory.interface`: One interface for every theory of a body's spin axis.
- :mod:`ephem.theory.tracks`: What every family's track shares: the poles it may follow, the rounding of its numbers, its pole vectors and

The package imports none of its modules: importing one loads only what it needs.
"""
