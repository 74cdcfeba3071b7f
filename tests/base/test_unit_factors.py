"""ephem.base.units.unit_factor: the exact factors that let the catalogue load without astropy.units agree with
astropy's own conversions, and a pair outside them goes through astropy (with its refusal for a unit that does not
convert)."""
import pytest

from ephem.base.units import _EXACT_FACTORS, unit_factor


@pytest.mark.parametrize("pair", sorted(_EXACT_FACTORS))
def test_each_exact_factor_is_astropys(pair):
    import astropy.units as u

    unit, target = pair
    # astropy's scale is a ratio of SI scales: equal to the factor to a couple of roundings
    assert unit_factor(unit, target) == pytest.approx((1.0 * u.Unit(unit)).to_value(u.Unit(target)), rel=4e-16)


def test_the_same_unit_is_one_and_other_pairs_go_through_astropy():
    assert unit_factor("km2", "km2") == 1.0
    assert unit_factor("arcsec", "deg") == pytest.approx(1.0 / 3600.0, rel=1e-15)
    with pytest.raises(ValueError):
        unit_factor("km", "deg")


def test_every_unit_the_catalogue_writes_converts_to_what_it_is_read_as():
    """The shipped catalogues load (every value converted) and their bodies' derived quantities match astropy's route:
    Ceres' semi-major axis in AU as written, its rotation period in hours."""
    from ephem.bodies.catalogue import get_body

    b = get_body("ceres")
    assert b.orbit.a_au == pytest.approx(b.values["orbit.a"].value * unit_factor(b.values["orbit.a"].unit, "AU"),
                                         rel=1e-15)
