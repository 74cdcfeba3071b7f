"""astropy Time and Quantity at the api boundary: in, and out on request."""
import numpy as np
import pytest
from astropy import units as u
from astropy.time import Time

from ephem import api
from ephem.base.errors import InvalidInputError
from ephem.base.times import to_jd_tdb
from ephem.base.units import unit_of, with_units

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


#: numbers whose keys name no unit because they have none (ratios, counts, identifiers)
DIMENSIONLESS = {"dynamical_ellipticity", "dynamical_ellipticity_uncertainty", "e", "multiple", "naif_id", "spin_orbit_ratio", "min_spin_orbit_ratio",
                 "moments_over_C", "delaunay_multipliers"}


def _numeric_keys(answer, path="", found=None):
    """(key, path) of every number or number array in an answer, outside dicts whose own key names the
    unit of all their entries (error_terms_mas)."""
    found = {} if found is None else found
    if isinstance(answer, list):
        for v in answer:
            _numeric_keys(v, path + "[]", found)
    elif isinstance(answer, dict):
        for k, v in answer.items():
            numbers = isinstance(v, (int, float)) and not isinstance(v, bool)
            array = isinstance(v, list) and v and isinstance(v[0], (int, float)) and not isinstance(v[0], bool)
            if numbers or array:
                found.setdefault(k, path)
            elif isinstance(v, (dict, list)) and not (isinstance(v, dict) and unit_of(k) is not None):
                _numeric_keys(v, f"{path}.{k}", found)
    return found


def test_every_number_of_every_answer_names_its_unit_or_has_none():
    answers = {"precession": api.precession("vesta"), "nutation": api.nutation("vesta"),
               "track": api.track("mars", "2000-01-01", "2002-01-01", 100.0, free_wobble_phase_deg=30),
               "free motion": api.free_motion_answer("eros", 2451545, 2451645, 10.0),
               "Earth precession": api.precession("earth"), "Earth nutation": api.nutation("earth"),
               "Earth track": api.track("earth", "2020-01-01", "2021-01-01", 30.0), "bodies": api.list_bodies()}
    unnamed = {k: f"{name}{path}" for name, a in answers.items() for k, path in _numeric_keys(a).items()
               if unit_of(k) is None and k not in DIMENSIONLESS and not (k == "jd_tdb" or k.endswith("_jd_tdb"))}
    assert not unnamed, f"numbers with no unit in their name: {unnamed}"


def test_rates_per_century_come_back_as_quantities_per_century():
    plain = api.nutation("earth")["terms"][0]
    q = api.nutation("earth", quantities=True)["terms"][0]
    rate_keys = [k for k in plain if k.endswith("_per_century")]
    assert rate_keys, "the Earth's nutation terms carry rates per century"
    for k in rate_keys:
        per_year = u.arcsec / u.yr if k.endswith("_arcsec_per_century") else u.mas / u.yr
        # a century is 100 Julian years: per year the number is a hundredth; astropy's hyr -> yr factor is
        # 0.010000000000000002 (1 ulp) and each division rounds once: within 4 ulp (1e-15 relative)
        assert q[k].to_value(per_year) == pytest.approx(plain[k] / 100.0, rel=1e-15, abs=0.0)
    assert unit_of("geodesic_arcsec_per_century") == "arcsec / hyr"
