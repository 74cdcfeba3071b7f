"""Catalogue loading and validation: every value sourced, every bad record named."""
import math
import re

import pytest

from ephem.catalogue import available_datasets, get_body, load_catalogue, load_references, parse_catalogue
from ephem.errors import InvalidInputError, UnknownBodyError

BODIES = ["Ceres", "Vesta", "Eros", "Steins", "Itokawa", "Earth", "Moon", "Mars"]

GOOD = """
[[body]]
name = "Testa"
naif_id = 2999999
[body.orbit]
epoch = { value = 2460200.5, unit = "d", source = "x" }
a = { value = 2.36, unit = "AU", source = "x" }
e = { value = 0.09, unit = "", source = "x" }
i = { value = 7.1, unit = "deg", source = "x" }
node = { value = 103.7, unit = "deg", source = "x" }
peri = { value = 151.7, unit = "deg", source = "x" }
mean_anomaly = { value = 169.2, unit = "deg", source = "x" }
[body.pole]
ra = { value = 309.03, unit = "deg", source = "x" }
dec = { value = 42.23, unit = "deg", source = "x" }
[body.rotation]
period = { value = 5.342, unit = "h", source = "x" }
[body.inertia]
A = { value = 0.3433, unit = "", source = "x" }
B = { value = 0.3546, unit = "", source = "x" }
C = { value = 0.42, unit = "", source = "x" }
"""


def test_both_datasets_hold_all_eight_bodies():
    assert set(available_datasets()) >= {"current", "petit2014"}
    for ds in ("current", "petit2014"):
        assert sorted(load_catalogue(ds).names) == sorted(BODIES)


@pytest.mark.parametrize("ds", ["current", "petit2014"])
def test_every_source_resolves_in_the_references(ds):
    refs = load_references()
    for b in load_catalogue(ds).bodies:
        for where, m in b.values.items():
            assert m.source in refs, f"{b.name} {where}: {m.source}"
            assert {"authors", "year", "journal", "where"} <= set(refs[m.source]), m.source


def test_lookup_by_name_any_case_and_naif_id():
    assert get_body("VESTA").name == "Vesta"
    assert get_body(2000004).name == "Vesta"
    assert get_body("2000433").name == "Eros"


def test_unknown_body_lists_the_known_ones():
    with pytest.raises(UnknownBodyError) as info:
        get_body("Pallas")
    for name in BODIES:
        assert name in str(info.value)


def test_unknown_dataset():
    with pytest.raises(InvalidInputError, match="dataset"):
        load_catalogue("nope")


def test_ecliptic_pole_is_converted_to_icrf():
    text = GOOD.replace('ra = { value = 309.03, unit = "deg", source = "x" }\ndec = { value = 42.23, unit = "deg", source = "x" }',
                        'frame = "ecliptic_j2000"\nlon = { value = 0.0, unit = "deg", source = "x" }\n'
                        'lat = { value = 90.0, unit = "deg", source = "x" }')
    b = parse_catalogue(text, "t").get("Testa")
    assert b.pole.ra_deg == pytest.approx(270.0, abs=1e-4)           # ecliptic pole in the ICRF:
    assert b.pole.dec_deg == pytest.approx(90 - 23.4392911, abs=1e-4)  # RA 270°, Dec 90° − ε0


def test_units_are_converted():
    text = GOOD.replace('period = { value = 5.342, unit = "h"', 'period = { value = 0.22258333333, unit = "d"')
    assert parse_catalogue(text, "t").get("Testa").rotation_period_hours == pytest.approx(5.342)


@pytest.mark.parametrize("old, new, field", [
    ('e = { value = 0.09', 'e = { value = 1.2', "orbit.e"),
    ('e = { value = 0.09', 'e = { value = nan', "orbit.e"),
    ('a = { value = 2.36', 'a = { value = -1.0', "orbit.a_au"),
    ('period = { value = 5.342', 'period = { value = -3', "rotation_period_hours"),
    ('dec = { value = 42.23', 'dec = { value = 95', "pole.dec_deg"),
    ('A = { value = 0.3433', 'A = { value = 0.5', "inertia"),
    ('unit = "AU", source = "x" }', 'unit = "kg", source = "x" }', "orbit.a"),
    ('i = { value = 7.1, unit = "deg", source = "x" }', 'i = { value = 7.1, unit = "deg" }', "orbit.i"),
])
def test_bad_records_name_the_body_and_the_field(old, new, field):
    text = GOOD.replace(old, new, 1)
    assert text != GOOD
    with pytest.raises(InvalidInputError) as info:
        parse_catalogue(text, "t")
    assert info.value.field == field
    assert info.value.body == "Testa"
    assert re.match(r"Testa: ", str(info.value))


def test_petit_pole_uncertainties_are_carried():
    v = get_body("vesta", "petit2014").values
    assert v["pole.ra"].uncertainty == 0.003 and v["pole.ra"].unit == "deg"


def test_current_poles_are_the_wgccre_values():
    # Archinal et al. (2018) Table 4: Vesta α0 = 309.031, δ0 = 42.235; Ceres 291.418, 66.764
    assert (get_body("vesta").pole.ra_deg, get_body("vesta").pole.dec_deg) == (309.031, 42.235)
    assert (get_body("ceres").pole.ra_deg, get_body("ceres").pole.dec_deg) == (291.418, 66.764)
    # Lara (2014) Table 1 (C = 1): H_d = (C − (A+B)/2)/C by another order of 3 operations, a few ε; 1e-12
    assert math.isclose(get_body("eros").hd, 1 - (0.229427 + 0.963754) / 2, rel_tol=1e-12)


def test_earth_pole_is_the_cip_at_j2000():
    # the catalogue holds the instantaneous axis: for the Earth, ERFA's IAU 2006/2000A CIP at J2000.0
    import erfa
    x, y = erfa.xy06(2451545.0, 0.0)
    b = get_body("earth")
    ra, dec = math.radians(b.pole.ra_deg), math.radians(b.pole.dec_deg)
    assert math.cos(dec) * math.cos(ra) == pytest.approx(x, abs=1e-9)  # 0.2 mas
    assert math.cos(dec) * math.sin(ra) == pytest.approx(y, abs=1e-9)


def test_spin_rate_of_the_earth_is_the_iers_nominal_one():
    # IERS Conventions (2010), Table 1.1: the Earth's nominal mean angular velocity ω = 7.292115e-5 rad/s,
    # from the catalogue's sidereal period 23.9344719 h through Body.spin_rate_rad_per_day (rad/day);
    # the IERS value has 7 digits: agreement to half its last one
    assert get_body("earth").spin_rate_rad_per_day / 86400.0 == pytest.approx(7.292115e-5, abs=0.5e-11)
