"""Catalogue loading and validation: every value sourced, every bad record named.

Values against their sources: the WGCCRE poles (tests/bodies/test_against_wgccre.py), the Earth's pole as ERFA's CIP
(tests/earth/test_against_erfa.py) and its spin rate as the IERS's (tests/earth/test_against_iau2006.py), Lara (2014)'s
moments (tests/rotation/test_against_lara2014.py).
"""
import math
import re

import numpy as np
import pytest

from ephem.bodies.catalogue import get_body, load_catalogue, load_references, parse_catalogue
from ephem.bodies.datasets import available_datasets
from ephem.base.errors import InvalidInputError, UnknownBodyError

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


DERIVED = GOOD.replace('''[body.inertia]
A = { value = 0.3433, unit = "", source = "x" }
B = { value = 0.3546, unit = "", source = "x" }
C = { value = 0.42, unit = "", source = "x" }''', '''[body.inertia.derived_from]
method = "gravity_and_polar_moment"
polar_moment = { value = 0.42, unit = "", uncertainty = 0.003, source = "x" }
J2 = { value = 0.0711, unit = "", uncertainty = 1.4e-8, source = "x" }
C22 = { value = 0.0027, unit = "", uncertainty = 7e-8, source = "x" }
S22 = { value = 0.0008, unit = "", uncertainty = 1.8e-8, source = "x" }''')


@pytest.mark.parametrize("old, new, field", [
    ('J2 = { value = 0.0711', 'J3 = { value = 0.0711', "inertia.derived_from"),
    ('method = "gravity_and_polar_moment"', 'method = "guess"', "inertia.derived_from.method"),
    ('polar_moment = { value = 0.42', 'polar_moment = { value = 0.05', "inertia.derived_from"),
    ('uncertainty = 0.003, source', 'uncertainty = 0.003, no_uncertainty = "", source',
     "inertia.derived_from.polar_moment.no_uncertainty"),
    ('uncertainty = 0.003, source', 'uncertainty = 0.003, no_uncertainty = "twice", source',
     "inertia.derived_from.polar_moment.no_uncertainty"),
    ('period = { value = 5.342, unit = "h", source = "x" }',
     'period = { value = 5.342, unit = "h", source = "x" }\nrate = { value = 1617.0, unit = "deg/d", source = "x" }',
     "rotation"),
    ('[body.inertia.derived_from]', '[body.inertia]\nA = { value = 0.3, unit = "", source = "x" }\n'
     '[body.inertia.derived_from]', "inertia"),
    ('S22 = { value = 0.0008, unit = "", uncertainty = 1.8e-8, source = "x" }',
     'S22 = { value = 0.0008, unit = "", uncertainty = 1.8e-8, source = "x" }\n'
     '[[body.correlation]]\ninputs = ["pole.ra", "pole.dec"]\nvalue = 0.5\nsource = "x"', "correlation[0].inputs"),
])
def test_bad_derivations_and_reasons_name_the_field(old, new, field):
    text = DERIVED.replace(old, new, 1)
    assert text != DERIVED
    with pytest.raises(InvalidInputError) as info:
        parse_catalogue(text, "t")
    assert info.value.field == field and info.value.body == "Testa"


def test_derived_moments_carry_their_covariance_and_stated_correlations_load():
    """The moments from one polar moment with a σ: each σ and their correlations (near 1: C-bar dominates), a
    stated RA-Dec correlation, a rotation rate for a period, and a section's reason for its values without a
    σ."""
    text = (DERIVED
            .replace('ra = { value = 309.03, unit = "deg", source = "x" }',
                     'ra = { value = 309.03, unit = "deg", uncertainty = 0.01, source = "x" }')
            .replace('dec = { value = 42.23, unit = "deg", source = "x" }',
                     'dec = { value = 42.23, unit = "deg", uncertainty = 0.02, source = "x" }')
            .replace('period = { value = 5.342, unit = "h", source = "x" }',
                     'rate = { value = 1617.0, unit = "deg/d", uncertainty = 1e-6, source = "x" }')
            .replace('[body.orbit]', '[body.orbit]\nno_uncertainty = "a test orbit"')
            + '[[body.correlation]]\ninputs = ["pole.ra", "pole.dec"]\nvalue = -0.3\nsource = "x"\n')
    b = parse_catalogue(text, "t").get("Testa")
    assert b.values["inertia.C"].uncertainty == pytest.approx(0.003, rel=1e-9)
    assert b.correlations[("inertia.A", "inertia.C")] > 0.99
    assert b.correlations[("pole.ra", "pole.dec")] == pytest.approx(-0.3, abs=1e-15)
    assert b.values["orbit.a"].no_uncertainty == "a test orbit" and b.values["pole.ra"].no_uncertainty is None
    assert b.hd == pytest.approx(0.0711 / 0.42, rel=1e-12)
    assert b.rotation_period_hours == pytest.approx(8640.0 / 1617.0, rel=1e-14)


def test_petit_pole_uncertainties_are_carried():
    v = get_body("vesta", "petit2014").values
    assert v["pole.ra"].uncertainty == 0.003 and v["pole.ra"].unit == "deg"


def test_a_pole_given_in_ecliptic_coordinates_comes_back_through_the_inverse_rotation():
    # Pole.from_ecliptic (the catalogue's ecliptic_j2000 records, the tests' and studies' synthetic bodies) against
    # the ICRF -> ecliptic rotation applied to its result: the same lon/lat to a few ulp of a degree (1e-10 deg)
    import math

    import numpy as np

    from ephem.bodies.catalogue import Pole
    from ephem.orbit.geometry import icrf_to_ecliptic_matrix

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

    root = Path(__file__).resolve().parents[2]
    spec = importlib.util.spec_from_file_location("generate_catalogue_doc", root / "tools" / "generate_catalogue_doc.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    page = (root / "docs" / "catalogue.md").read_text(encoding="utf-8")
    assert page == mod.render(), "docs/catalogue.md is stale: run python tools/generate_catalogue_doc.py"
    assert "| pole.ra | 309.031 | deg | not published: the WGCCRE 2015 report" in page   # Vesta's, with the reason
    assert "| rotation.period | 9.07416939185 | h | 1.90603e-08 |" in page   # Ceres', derived from Dawn's W' ± σ
    assert "| inertia.A, inertia.B | +0.59" in page                     # the Moon's moments, from one β and γ


# ----------------------------------------------------------------------------- the curated dataset (issue 18)

def test_every_current_value_has_a_sigma_or_the_reason_it_has_none():
    """Every value of `current` has a source that resolves and exactly one of a 1-sigma and a reason why none is
    published (epochs are definitions, not measurements)."""
    refs = load_references()
    for b in load_catalogue("current").bodies:
        for key, m in b.values.items():
            assert m.source in refs, (b.name, key, m.source)
            if key.endswith(".epoch"):
                continue
            assert (m.uncertainty is not None) != bool(m.no_uncertainty), (b.name, key)
            if m.no_uncertainty:
                assert len(m.no_uncertainty) > 20, (b.name, key, m.no_uncertainty)    # a reason, not a shrug


def _inputs(b, *keys):
    return [b.values[f"inertia.derived_from.{k}"].value for k in keys]


@pytest.mark.parametrize("name", ["Ceres", "Vesta"])
def test_dawn_moments_rederive_from_gravity_and_moment(name):
    """Eq. 31's identities, independent of the loader's route: H_d = J2/C-bar, (B - A)/4 = sqrt(C22² + S22²),
    and Ceres' mean moment (A + B + C)/3 = Park et al.'s 0.37; double-precision rounding of a few operations."""
    b = get_body(name)
    A, B, C = b.moments
    J2, C22, S22 = _inputs(b, "J2", "C22", "S22")
    assert b.hd == pytest.approx(J2 / C, rel=1e-12)
    assert (B - A) / 4.0 == pytest.approx(math.hypot(C22, S22), rel=1e-9)
    if name == "Ceres":
        assert (A + B + C) / 3.0 == pytest.approx(0.37, rel=1e-12)
    else:
        assert C == pytest.approx(0.4208, rel=1e-12)
    # the moments' earlier hand-derived values (the catalogue before issue 18), printed to 8 digits
    earlier = {"Ceres": (0.36069012, 0.36164339, 0.38766649), "Vesta": (0.34410219, 0.35537602, 0.4208)}[name]
    assert np.allclose((A, B, C), earlier, rtol=0, atol=0.5e-8)


@pytest.mark.parametrize("name,axes", [("Steins", (3.415, 2.85, 2.21)), ("Itokawa", (0.2675, 0.147, 0.1045))])
def test_ellipsoid_moments_rederive_from_the_axes(name, axes):
    """A uniform ellipsoid's H_d = (a² + b² − 2c²) / (2(a² + b²)) from the semi-axes (km), and the moments per
    unit mass the catalogue carried before (printed to 7 significant digits)."""
    a, b, c = axes
    body = get_body(name)
    assert body.hd == pytest.approx((a * a + b * b - 2 * c * c) / (2 * (a * a + b * b)), rel=1e-12)
    earlier = {"Steins": (2.60132, 3.309265, 3.956945), "Itokawa": (0.00650585, 0.0164953, 0.01863305)}[name]
    assert np.allclose(body.moments, earlier, rtol=1e-6)


def test_the_moons_moments_rederive_beta_and_gamma():
    A, B, C = get_body("moon").moments
    beta, gamma = (get_body("moon").values[f"inertia.derived_from.{k}"].value for k in ("beta", "gamma"))
    assert (C - A) / B == pytest.approx(beta, rel=1e-9) and (B - A) / C == pytest.approx(gamma, rel=1e-9)


def test_a_period_from_a_rate_is_360_over_the_rate():
    ceres = get_body("ceres")
    rate = ceres.values["rotation.rate"]
    assert ceres.rotation_period_hours == pytest.approx(360.0 / rate.value * 24.0, rel=1e-14)
    assert ceres.values["rotation.period"].uncertainty == pytest.approx(
        ceres.rotation_period_hours * rate.uncertainty / rate.value, rel=1e-12)


@pytest.mark.parametrize("name,moments_hd", [("Earth", 0.0032789), ("Mars", 0.0053635)])
def test_an_explicit_hd_refines_the_moments_and_says_why(name, moments_hd):
    """The Earth's (IERS 2010) and Mars' (Baland et al. 2020) H_d override the Lara (2014) moments' (printed
    to 5 digits) by less than a per cent, and the record's note says why."""
    b = get_body(name)
    assert b.hd_from == "dynamical_ellipticity"
    assert b.hd_from_moments == pytest.approx(moments_hd, rel=1e-4)
    assert abs(b.hd / b.hd_from_moments - 1.0) < 0.01
    assert "overrides" in b.values["inertia.dynamical_ellipticity"].note
