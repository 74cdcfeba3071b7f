"""Lara (2014) Table 1: the free-wobble data shipped in data/free_motion.toml, checked against the catalogue."""
import tomllib

import pytest

from ephem.catalogue import data_dir, get_body


def table():
    with open(data_dir() / "free_motion.toml", "rb") as fh:
        return tomllib.load(fh)["body"]


def andoyer_beta(a_over_c: float, b_over_c: float) -> float:
    """β from α(1 + β) = C/A - 1, α(1 - β) = C/B - 1 (Lara 2014 eq. 2)."""
    p, q = 1.0 / a_over_c - 1.0, 1.0 / b_over_c - 1.0
    return (p - q) / (p + q)


def printed(text: str) -> tuple[float, float]:
    """A value printed as ``text`` and half a unit in its last digit."""
    decimals = len(text.split(".")[1]) if "." in text else 0
    return float(text), 0.5 * 10.0 ** -decimals


@pytest.mark.parametrize("row", table(), ids=lambda r: r["name"])
def test_printed_beta_follows_from_the_printed_moments(row):
    # β over every corner of the printed moments' rounding intervals must bracket the printed β
    (a, da), (b, db) = printed(row["A_over_C_printed"]), printed(row["B_over_C_printed"])
    corners = [andoyer_beta(a + sa * da, b + sb * db) for sa in (-1, 1) for sb in (-1, 1)]
    beta, slack = printed(row["beta_printed"])
    assert min(corners) - slack <= beta <= max(corners) + slack
    assert max(corners) - min(corners) < 0.1 * beta  # the check is not vacuous: rounding leaves β to 10%


@pytest.mark.parametrize("row", table(), ids=lambda r: r["name"])
def test_catalogue_moments_are_lara_table_1(row):
    a, b, c = get_body(row["name"]).moments
    assert a / c == pytest.approx(float(row["A_over_C_printed"]), abs=1e-12)
    assert b / c == pytest.approx(float(row["B_over_C_printed"]), abs=1e-12)
    assert 0 < row["J0_arcsec"] < 3600
