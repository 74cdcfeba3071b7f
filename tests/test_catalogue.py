"""Catalogue loading and validation: every value sourced, every bad record named.

Values against their sources: the WGCCRE poles (tests/test_against_wgccre.py), the Earth's pole as ERFA's CIP
(tests/test_against_erfa.py) and its spin rate as the IERS's (tests/test_against_iau2006.py), Lara (2014)'s
moments (tests/test_against_lara2014.py).
"""
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


def test_a_pole_given_in_ecliptic_coordinates_comes_back_through_the_inverse_rotation():
    # Pole.from_ecliptic (the catalogue's ecliptic_j2000 records, the tests' and studies' synthetic bodies) against
    # the ICRF -> ecliptic rotation applied to its result: the same lon/lat to a few ulp of a degree (1e-10 deg)
    import math

    import numpy as np

    from ephem.catalogue import Pole
    from ephem.geometry import icrf_to_ecliptic_matrix

    for lon, lat in ((0.0, 90.0), (17.0, 66.0), (200.5, -30.25), (359.0, 0.5), (123.0, -89.9)):
        p = Pole.from_ecliptic(lon, lat, body="x")
        ra, dec = math.radians(p.ra_deg), math.radians(p.dec_deg)
        v = icrf_to_ecliptic_matrix() @ np.array([math.cos(dec) * math.cos(ra), math.cos(dec) * math.sin(ra),
                                                  math.sin(dec)])
        assert math.degrees(math.atan2(v[2], math.hypot(v[0], v[1]))) == pytest.approx(lat, abs=1e-10)
        if abs(lat) < 90.0:     # the longitude of the ecliptic pole is undefined
            back = math.degrees(math.atan2(v[1], v[0])) % 360.0
            assert min(abs(back - lon), 360.0 - abs(back - lon)) < 1e-10
        assert 0.0 <= p.ra_deg < 360.0 and p.body == "x"


def test_the_catalogue_page_is_generated_from_the_data():
    """docs/catalogue.md is what tools/generate_catalogue_doc.py makes of data/ now: every value, unit, 1-sigma
    (or "none given") and source, so the page cannot drift from the data."""
    import importlib.util
    from pathlib import Path

    root = Path(__file__).resolve().parent.parent
    spec = importlib.util.spec_from_file_location("generate_catalogue_doc", root / "tools" / "generate_catalogue_doc.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    page = (root / "docs" / "catalogue.md").read_text(encoding="utf-8")
    assert page == mod.render(), "docs/catalogue.md is stale: run python tools/generate_catalogue_doc.py"
    assert "| pole.ra | 309.031 | deg | none given |" in page          # Vesta's, as the data give it
    assert "| rotation.period | 9.07417 | h | 1.9e-08 |" in page         # Ceres', with its published 1-sigma
