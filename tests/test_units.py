"""astropy Time and Quantity at the api boundary: in, and out on request."""
import numpy as np
import pytest
from astropy import units as u
from astropy.time import Time

from ephem import api
from ephem.errors import InvalidInputError
from ephem.timeparse import to_jd_tdb
from ephem.units import unit_of, with_units

# building a UTC Time after the leap-second table ends warns "dubious year": the test's inputs, not ours
pytestmark = pytest.mark.filterwarnings("ignore::erfa.ErfaWarning")


def test_a_time_in_any_scale_gives_its_tdb_julian_date():
    t = Time("2030-06-01T12:00:00", scale="utc")
    assert to_jd_tdb(t) == pytest.approx(t.tdb.jd, abs=1e-9)   # 2 ulp of a JD near 2.46e6 (ulp 4.7e-10 d)
    assert abs(to_jd_tdb(Time(2451545.0, format="jd", scale="tt")) - 2451545.0) < 2e-3 / 86400  # |TDB-TT| < 2 ms
    with pytest.raises(InvalidInputError, match="start"):
        to_jd_tdb(Time(["2030-01-01", "2031-01-01"]), "start")


def test_quantities_in_give_the_same_track_as_plain_numbers():
    plain = api.track("vesta", "2030-01-01", "2031-01-01", 30.0, tolerance_mas=1000.0)
    units = api.track("vesta", Time("2030-01-01"), Time("2031-01-01"), 720 * u.hour, tolerance_mas=1 * u.arcsec)
    assert units["pole_ra_deg"] == plain["pole_ra_deg"] and units["model"]["name"] == plain["model"]["name"]
    wobble = api.track("mars", "2030-01-01", "2030-01-02", 1.0, model="hansen",
                       free_wobble_phase_deg=np.pi / 2 * u.rad, free_wobble_J_arcsec=100 * u.mas)
    assert wobble["model"]["free_wobble"]["phase_deg"] == pytest.approx(90.0)
    assert wobble["model"]["free_wobble"]["J_arcsec"] == pytest.approx(0.1)


@pytest.mark.parametrize("kwargs,field", [({"step_days": 3 * u.m}, "step_days"),
                                          ({"tolerance_mas": 1 * u.s}, "tolerance_mas")])
def test_a_quantity_in_the_wrong_unit_names_the_field(kwargs, field):
    args = {"step_days": 10.0, **kwargs}
    with pytest.raises(InvalidInputError, match=field):
        api.track("vesta", "2030-01-01", "2031-01-01", **args)


def test_quantities_out_carry_the_units_their_names_state():
    tr = api.track("vesta", "2030-01-01", "2030-03-01", 30.0, quantities=True)
    assert isinstance(tr["jd_tdb"], Time) and tr["jd_tdb"].scale == "tdb"
    assert tr["pole_dec_deg"].unit == u.deg and tr["psi_arcsec"].unit == u.arcsec
    assert tr["model"]["cost_ms"].unit == u.ms
    plain = api.track("vesta", "2030-01-01", "2030-03-01", 30.0)
    # the same degrees through astropy's and numpy's deg -> rad: an ulp or two of |dec| <= π/2 (ulp 2.2e-16)
    assert np.allclose(tr["pole_dec_deg"].to_value(u.rad), np.radians(plain["pole_dec_deg"]), rtol=0, atol=1e-15)
    p = api.precession("itokawa", quantities=True)
    assert p["precession_rate_arcsec_per_year"].to(u.deg / u.yr).value == pytest.approx(
        api.precession("itokawa")["precession_rate_arcsec_per_year"] / 3600.0)
    n = api.nutation("vesta", quantities=True)
    assert n["terms"][0]["period_days"].unit == u.day and n["mean_motion_deg_per_day"].unit == u.deg / u.day
    f = api.free_motion_answer("earth", "2030-01-01", "2030-02-01", 10 * u.day, J_arcsec=0.5 * u.arcsec,
                               quantities=True)
    assert f["wobble_period_days"].unit == u.day and f["figure_axis_offset_x_arcsec"].unit == u.arcsec


def test_unit_names():
    assert unit_of("precession_rate_arcsec_per_year") == "arcsec / yr"
    assert unit_of("amp_mas_uncertainty") == "mas" and unit_of("dynamical_ellipticity") is None
    assert with_units({"e": 0.1, "name": "x", "a_au": 2.0})["a_au"] == 2.0 * u.AU


def test_a_track_reports_the_obliquity_uncertainty():
    eros = api.track("eros", "2030-01-01", "2030-03-01", 30.0)
    assert eros["obliquity_deg_uncertainty"] == api.precession("eros")["obliquity_deg_uncertainty"] > 0.0
    assert api.track("vesta", "2030-01-01", "2030-03-01", 30.0)["obliquity_deg_uncertainty"] is None  # unknown
