"""Physical and astronomical constants (SI unless the name says otherwise)."""
import math

#: Julian year in days (IAU).
JULIAN_YEAR_DAYS = 365.25
#: Julian century in days (T in the IAU and IERS polynomials).
JULIAN_CENTURY_DAYS = 36525.0
#: Seconds per day.
DAY_S = 86400.0
#: J2000.0 as a TDB Julian date.
J2000_JD = 2451545.0
#: Astronomical unit, m (IAU 2012 Resolution B2).
AU_M = 149_597_870_700.0
#: Heliocentric gravitational constant, m^3 s^-2 (IAU 2015 Resolution B3, nominal TDB-compatible).
GM_SUN = 1.3271244e20
#: Geocentric gravitational constant, m^3 s^-2 (IAU 2015 Resolution B3, nominal).
GM_EARTH = 3.986004e14
#: IAU 2006 general precession in longitude p_A, its linear term, arcsec per Julian century (Capitaine et al.
#: 2003, P03; IERS Conventions 2010 eq. 5.39): the rate at which the mean equinox of date regresses.
GENERAL_PRECESSION_ARCSEC_PER_CENTURY = 5028.796195
#: Speed of light in vacuum, m/s (exact, SI).
SPEED_OF_LIGHT_M_S = 299_792_458.0
#: Radians per arcsecond.
ARCSEC = math.pi / 648_000.0
#: Radians per milliarcsecond.
MAS = ARCSEC / 1000.0

# The orbit centres' GM, radius and Hill radius are data (data/centres.toml), read by ephem.base.centres.

#: Julian dates accepted anywhere (times and epochs alike), open interval: 4713 BC to AD 22666.
JD_RANGE = (0.0, 1e7)
#: The poles a spin-axis track can follow: the figure axis (the body's axis of largest inertia, which circles the
#: angular momentum by the free wobble), the angular momentum, the figure axis's forced motion
#: (``forced_figure``: the figure axis without its free wobble, which is then not an error: the analogue of the IERS's
#: celestial intermediate pole, whose free wobble is polar motion), or a synchronous body's mean rotation axis
#: (``mean_rotation``: the pole of its mean-Earth/rotation frame, the IAU's lunar pole; its figure axis is turned from
#: it by the degree-3 field, 78.56″ for the Moon). Each family says which it follows (``SpinAxisTheory.axes``).
AXES = ("figure", "angular_momentum", "forced_figure", "mean_rotation")
#: The pole whose free wobble is left to polar motion (:data:`AXES`)
FORCED_FIGURE = "forced_figure"


def followed_axis(axis: str) -> str:
    """The axis a theory computes for a requested one: the forced figure axis is the figure axis's track (its free
    wobble is neither added nor counted as an error)."""
    return "figure" if axis == FORCED_FIGURE else axis
#: Rounding floor of any pole computed in double precision through a few rotations (radians, 0.2 µas): the
#: ``rounding`` term of every track's error estimate.
ROUNDING = 1e-12
