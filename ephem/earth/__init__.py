"""The Earth's family: the lunisolar theory under the Moon and the Sun, and the non-rigid Earth.

- :mod:`ephem.earth.costs`: What the Earth's lunisolar theory will cost before it runs: its predictors, with its own unit costs.
- :mod:`ephem.earth.de421_integration`: The Earth's pole integrated under DE421's Moon and Sun: the numerical reference of the lunisolar series.
- :mod:`ephem.earth.estimates`: The error estimate of the Earth's lunisolar track, and the amplitude cut a tolerance asks of its series.
- :mod:`ephem.earth.family`: The Earth's family behind the common interface: its texts, costs, precession and nutation results, spectrum.
- :mod:`ephem.earth.model`: The Earth's lunisolar model from the catalogue: the series wired to the catalogue's pole and orbit.
- :mod:`ephem.earth.lunisolar`: The Earth's forced precession and nutation under the Moon and the Sun (rigid Earth, first order).
- :mod:`ephem.earth.nonrigid`: The non-rigid Earth's correction to each nutation term: the IERS 1996 transfer function.

The package imports none of its modules: importing one loads only what it needs.
"""
