"""Physical and astronomical constants (SI unless the name says otherwise)."""
import math

#: Julian year in days (IAU).
JULIAN_YEAR_DAYS = 365.25
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
#: Radians per arcsecond.
ARCSEC = math.pi / 648_000.0
#: Radians per milliarcsecond.
MAS = ARCSEC / 1000.0

#: Gravitational parameter of each orbit centre the catalogue may name.
GM_CENTER = {"Sun": GM_SUN, "Earth": GM_EARTH}
