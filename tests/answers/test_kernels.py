"""Text PCK kernels (ephem.answers.kernels): the owner of the nutation-precession angles, and what the writer refuses
(bad requests, bodies it cannot write, a fit it cannot reach) before writing anything.

The kernels it writes, read back by SPICE itself against our track: tests/exports/test_against_spice.py.
"""
import pytest

from ephem.answers import kernels as pck
from ephem.exports import pck_kernel
from ephem.base.errors import InvalidInputError, NotApplicableError, UnknownBodyError


def test_angles_owner_is_zzbodbry():
    assert pck_kernel.angles_owner(2000004) == 2000004       # asteroid: its own ID
    assert pck_kernel.angles_owner(399) == 3 and pck_kernel.angles_owner(499) == 4 and pck_kernel.angles_owner(301) == 3
    assert pck_kernel.angles_owner(65001) == 6               # extended satellite code
    assert pck_kernel.angles_owner(10) == 10 and pck_kernel.angles_owner(1000093) == 1000093


@pytest.mark.parametrize("kwargs, error, field", [
    ({"bodies": ["Vesta"], "start": "2040-01-01", "stop": "2020-01-01"}, InvalidInputError, "stop"),
    ({"bodies": ["Vesta"], "start": "2020-01-01", "stop": "2020-01-01"}, InvalidInputError, "stop"),
    ({"bodies": [], "start": "2020-01-01", "stop": "2021-01-01"}, InvalidInputError, "bodies"),
    ({"bodies": ["Vesta", "vesta"], "start": "2020-01-01", "stop": "2021-01-01"}, InvalidInputError, "bodies"),
    ({"bodies": ["Vesta"], "start": "2020-01-01", "stop": "2021-01-01", "max_angles": 201},
     InvalidInputError, "max_angles"),
    ({"bodies": ["Vesta"], "start": "2020-01-01", "stop": "2021-01-01", "fit_tolerance_mas": float("nan")},
     InvalidInputError, "fit_tolerance_mas"),
    ({"bodies": ["Vesta"], "start": "2020-01-01", "stop": "2021-01-01", "fit_tolerance_mas": -1.0},
     InvalidInputError, "fit_tolerance_mas"),
    ({"bodies": ["Vesta"], "start": "not a date", "stop": "2021-01-01"}, InvalidInputError, "start"),
])
def test_bad_inputs_name_the_field(kwargs, error, field):
    with pytest.raises(error) as exc:
        pck.write_pck(**kwargs)
    assert exc.value.field == field


def test_unknown_body_and_moon():
    with pytest.raises(UnknownBodyError):
        pck.write_pck(["Vulcan"], "2020-01-01", "2021-01-01")
    text = pck.write_pck(["Vesta", "Moon"], "2020-01-01", "2021-01-01").text
    assert "BODY301_POLE_RA" in text and "BODY2000004_POLE_RA" in text


def test_body_without_naif_id(vesta_like):
    with pytest.raises(InvalidInputError) as exc:
        pck.write_pck([vesta_like], "2020-01-01", "2021-01-01")
    assert exc.value.field == "naif_id"


def test_unreachable_fit_is_refused_not_written():
    """Four angles cannot follow Vesta's nutation to 1 µas over 20 years: refused, naming the span's end
    and the best error reached (a number, never NaN)."""
    with pytest.raises(InvalidInputError) as exc:
        pck.write_pck("Vesta", "2020-01-01", "2040-01-01", fit_tolerance_mas=0.001, max_angles=4)
    assert exc.value.field == "stop" and "best " in str(exc.value) and "nan" not in str(exc.value).lower()
