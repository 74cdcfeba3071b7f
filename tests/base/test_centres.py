"""The centres and the perturbers as data (ephem.base.centres, data/centres.toml): the values the constants had, each
with a unit and a source that resolves, found where the other data are, and a malformed file refused naming its field.

The shipped values are nominal constants (IAU 2015 Resolution B3, IERS Conventions 2010): they are compared with the
numbers those documents print, to 1e-15 relative (one rounding of the km -> AU division; the shipped doubles are the
very ones the constants module held, 695 700 km / 149 597 870.7 km per AU).
"""
from __future__ import annotations

import math

import pytest

from ephem.base import centres
from ephem.base.constants import AU_M, GM_EARTH, GM_SUN
from ephem.base.paths import data_dir
from ephem.bodies.catalogue import load_references

#: one rounding of a double
ROUNDING = 1e-15


def test_the_centres_hold_the_published_values():
    assert centres.GM_CENTER["Sun"] == pytest.approx(1.3271244e20, rel=ROUNDING)       # IAU 2015 B3, m^3 s^-2
    assert centres.GM_CENTER["Earth"] == pytest.approx(3.986004e14, rel=ROUNDING)
    assert centres.CENTER_RADIUS_AU["Sun"] == pytest.approx(695_700.0 / 149_597_870.7, rel=ROUNDING)
    assert centres.CENTER_RADIUS_AU["Earth"] == pytest.approx(6378.1366 / 149_597_870.7, rel=ROUNDING)
    assert centres.CENTER_HILL_AU["Sun"] == pytest.approx(2.3e5, rel=ROUNDING)
    assert centres.CENTER_HILL_AU["Earth"] == pytest.approx(0.0100, rel=ROUNDING)
    assert list(centres.GM_CENTER) == ["Sun", "Earth"] and tuple(centres.KNOWN_PERTURBERS) == ("Sun", "Earth", "Moon")


def test_the_data_agree_with_the_constants_and_the_stated_derivation():
    # the GMs the constants module keeps for the Moon's and the Earth's own models are the same nominal values
    assert centres.GM_CENTER["Sun"] == pytest.approx(GM_SUN, rel=ROUNDING)
    assert centres.GM_CENTER["Earth"] == pytest.approx(GM_EARTH, rel=ROUNDING)
    assert centres.AU_KM == pytest.approx(AU_M / 1000.0, rel=ROUNDING)
    # the Earth's Hill radius as data/references.toml's centres_hill derives it: a (m/3M)^(1/3), a = 1 AU, to the
    # three digits the file gives (0.0100)
    assert centres.CENTER_HILL_AU["Earth"] == pytest.approx((GM_EARTH / GM_SUN / 3.0) ** (1.0 / 3.0), abs=5e-5)


def test_every_value_has_a_unit_and_a_source_that_resolves():
    refs = load_references()
    for name, c in centres.centres().items():
        assert set(c.values) == {"gm", "radius", "hill"}, name
        for key, v in c.values.items():
            assert v["unit"] and v["source"] in refs, (name, key, v)
            assert "uncertainty" in v or v.get("no_uncertainty"), (name, key, "a sigma or the reason it has none")


def test_the_file_is_found_where_the_other_data_are(monkeypatch, tmp_path):
    assert centres.data_file().parent == data_dir()
    monkeypatch.setenv("EPHEM_DATA_DIR", str(tmp_path))
    assert centres.data_file().parent == data_dir() == tmp_path


def test_the_moon_torques_the_earth_alone():
    (moon,) = [a for a in centres.admissions() if a.perturber == "Moon"]
    assert moon.admits("Earth", None, "Sun") and moon.admits("my earth", 399, "Sun") and moon.admits(" EARTH ", None, "Sun")
    assert not moon.admits("Mars", 499, "Sun") and not moon.admits("Earth", 399, "Earth")


GOOD = """
[[centre]]
name = "Toyunit"
gm = { value = 35.0, unit = "km3 / s2", source = "toy" }
radius = { value = 400.0, unit = "m", source = "toy" }
hill = { value = 100.0, unit = "km", source = "toy" }
"""


def test_a_file_of_the_same_form_converts_its_units():
    (c,), admissions = centres.parse_centres(GOOD, "toy.toml")
    assert admissions == []
    assert c.gm_m3_s2 == pytest.approx(35.0e9, rel=ROUNDING)
    assert c.radius_au * AU_M == pytest.approx(400.0, rel=1e-14)
    assert c.hill_au * AU_M == pytest.approx(100e3, rel=1e-14)


@pytest.mark.parametrize("text, field", [
    (GOOD.replace('unit = "km3 / s2"', 'unit = "kg"'), "centre 'Toyunit'.gm: unit 'kg'"),
    (GOOD.replace(', source = "toy" }\nradius', ' }\nradius'), "centre 'Toyunit'.gm: expected a table"),
    (GOOD.replace("value = 35.0", "value = -35.0"), "centre 'Toyunit'.gm: the value must be a positive"),
    (GOOD.replace("value = 100.0", "value = 0.1"), "Hill radius"),
    (GOOD + '[[perturber]]\nname = "Toymoon"\ntheory = "t"\ntorques = [{ body = "X" }]\n', "perturber 'Toymoon'.torques"),
    (GOOD + '[[perturber]]\nname = "Toymoon"\ntorques = [{ center = "Sun" }]\n', "perturber 'Toymoon': say which"),
    ("[[planet]]\n", "unknown tables"),
])
def test_a_malformed_file_is_refused_naming_its_field(text, field):
    with pytest.raises(ValueError) as err:
        centres.parse_centres(text, "toy.toml")
    assert field in str(err.value) and str(err.value).startswith("toy.toml"), str(err.value)


def test_a_refused_registration_adds_nothing(tmp_path):
    before = (dict(centres.GM_CENTER), tuple(centres.KNOWN_PERTURBERS))
    clash = tmp_path / "clash.toml"
    clash.write_text(GOOD + GOOD.replace("Toyunit", "Sun"), encoding="utf-8")
    with pytest.raises(ValueError, match="'Sun' is known already"):
        centres.register_centres(clash)
    nowhere = tmp_path / "nowhere.toml"
    nowhere.write_text(GOOD + '[[perturber]]\nname = "Toymoon"\ntheory = "t"\ntorques = [{ center = "Nowhere" }]\n',
                       encoding="utf-8")
    with pytest.raises(ValueError, match="'Nowhere', which is no known centre"):
        centres.register_centres(nowhere)
    assert (dict(centres.GM_CENTER), tuple(centres.KNOWN_PERTURBERS)) == before
    with pytest.raises(ValueError, match="shipped centres"):
        centres.unregister_centres(centres.data_file())
    assert math.isfinite(centres.GM_CENTER["Sun"])


def test_a_name_in_another_case_is_the_known_one(tmp_path):
    path = tmp_path / "cased.toml"
    path.write_text(GOOD + '[[perturber]]\nname = "sun"\ntheory = "t"\ntorques = [{ center = "toyunit" }]\n'
                    '[[perturber]]\nname = "MOON"\ntheory = "t"\ntorques = [{ center = "toyunit" }]\n',
                    encoding="utf-8")
    assert centres.register_centres(path) == ("Toyunit", "Sun", "Moon")
    try:
        assert tuple(centres.KNOWN_PERTURBERS) == ("Sun", "Earth", "Toyunit", "Moon")
        assert {(a.perturber, a.center) for a in centres.admissions() if a.origin == str(path)} == {
            ("Sun", "Toyunit"), ("Moon", "Toyunit")}
    finally:
        centres.unregister_centres(path)
    assert tuple(centres.KNOWN_PERTURBERS) == ("Sun", "Earth", "Moon")


def test_a_centre_taken_out_comes_back_only_with_its_values(tmp_path):
    """The per-body caches are keyed by the body, not by its centre's GM: a centre re-registered with other values
    would be answered from what its first values computed, so it is refused, naming the centre."""
    first, same, other = (tmp_path / f"{n}.toml" for n in ("first", "same", "other"))
    first.write_text(GOOD.replace("Toyunit", "Toyreturning"), encoding="utf-8")
    same.write_text(GOOD.replace("Toyunit", "Toyreturning"), encoding="utf-8")
    other.write_text(GOOD.replace("Toyunit", "Toyreturning").replace("value = 35.0", "value = 36.0"),
                     encoding="utf-8")
    centres.register_centres(first)
    centres.unregister_centres(first)
    with pytest.raises(ValueError, match="'Toyreturning' was known to this process with other values"):
        centres.register_centres(other)
    assert "Toyreturning" not in centres.GM_CENTER
    assert centres.register_centres(same) == ("Toyreturning",)
    centres.unregister_centres(same)
