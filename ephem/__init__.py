"""The ephem package: forced precession and nutation of the spin axes of asteroids, planets and moons.

Kinoshita's theory with exact Hansen coefficients (Petit, Souchay & Lhotka 2014, A&A 565, A79),
checked against a numerical integration of the torque. Start with :mod:`ephem.answers.requests` (answers with
units in the key names) or :func:`ephem.forced.precession_nutation.model_for` (the numeric model: radians, days).

Importing the package is cheap; astropy loads on the first catalogue read.
"""

__version__ = "0.1.0"
