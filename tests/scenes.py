"""Synthetic bodies for the tests: a pole at a chosen obliquity on a chosen orbit."""
import math

from ephem.catalogue import Body, Orbit, Pole
from ephem.geometry import ecliptic_to_icrf


def synthetic_body(e=0.1, obliquity_deg=30.0, hd=0.1, period_hours=5.0, a_au=2.0, node_of_equator_deg=40.0,
                   peri_deg=70.0, mean_anomaly_deg=0.0, name="synthetic", moments=None) -> Body:
    """A body on an orbit in the ecliptic whose pole stands at a chosen obliquity."""
    lon = math.radians(node_of_equator_deg - 90.0)
    pole = ecliptic_to_icrf(lon, math.radians(90.0 - obliquity_deg))
    ra = math.degrees(math.atan2(pole[1], pole[0])) % 360.0
    dec = math.degrees(math.atan2(pole[2], math.hypot(pole[0], pole[1])))  # exact near the poles, unlike asin
    return Body(name, Orbit(a_au, e, 0.0, 0.0, peri_deg, mean_anomaly_deg, 2451545.0), Pole(ra, dec),
                period_hours, dynamical_ellipticity=None if moments else hd, moments=moments)
