"""Ceres' and Vesta's obliquity histories against the published ones (data/long_term_references.toml, with the
citations and what is known of their authors' inputs): Ermakov et al. (2017, GRL 44, 2652), as quoted by NASA's
release of 2017-03-22, and Vaillant, Laskar, Rambaux & Gastineau (2019, A&A 622, A95, abstract).

The published numbers are printed to whole degrees and to the hundred or thousand years, so the budgets are their
printed digits plus our own estimate where it matters (the answer's ``obliquity_error_deg``). Our inputs differ:
the catalogue's Ceres polar moment is 0.3877 (Park et al. 2016's 0.37 mean moment plus 2/3 J2) and Vesta's 0.4208
(Park et al. 2025), where the authors used earlier Dawn values; docs/long_term.md shows how the answer moves with
them (±2 % in Ceres' precession constant moves its range by ~0.1° and its period by 0.25 %)."""
import tomllib

import numpy as np
import pytest

from ephem import api
from ephem.base.paths import data_dir
from ephem.batch.population import crossing_period


def published(key: str) -> dict:
    with open(data_dir() / "long_term_references.toml", "rb") as fh:
        return next(r for r in tomllib.load(fh)["reference"] if r["key"] == key)["values"]


@pytest.fixture(scope="module")
def ceres():
    return api.history("ceres", -3.0e6, 0.0, 500.0)


def test_ceres_range_over_three_million_years(ceres):
    """"From about 2° to about 20°" over the last 3 Myr (Ermakov et al.; Vaillant et al. give 2-20° over 20 Myr):
    the printed whole degrees, ±0.5°, plus our obliquity estimate (0.75° at most over the span). Measured:
    2.12-19.56°."""
    ref = published("ermakov2017")["obliquity_range_last_3Myr_deg"]
    eps = np.asarray(ceres["obliquity_deg"])
    slack = 0.5 + float(np.max(ceres["obliquity_error_deg"]))
    assert eps.min() == pytest.approx(ref["min"], abs=slack)
    assert eps.max() == pytest.approx(ref["max"], abs=slack)


def test_ceres_period_present_value_and_last_maximum(ceres):
    """The period "about 24,500 years" (to the hundred: ±1 %; measured 24 450 yr from the mean crossings), the
    present "4 degrees" (±0.5°; 4.003°) and the last maximum, "about 19 degrees ... 14,000 years ago" (±0.5° on
    the printed degree plus our estimate there, ±1000 yr on the printed thousands; measured 18.5° at −13 830 yr)."""
    ref = published("ermakov2017")
    years, eps = np.asarray(ceres["year"]), np.asarray(ceres["obliquity_deg"])
    assert crossing_period(years, eps) == pytest.approx(ref["obliquity_period_yr"]["value"], rel=0.01)
    assert eps[-1] == pytest.approx(ref["present_obliquity_deg"]["value"], abs=0.5)
    recent = years >= -3.0e4
    i = int(np.argmax(np.where(recent, eps, -np.inf)))
    slack = 0.5 + float(ceres["obliquity_error_deg"][i])
    assert eps[i] == pytest.approx(ref["last_maximum_obliquity_deg"]["value"], abs=slack)
    assert -years[i] == pytest.approx(ref["last_maximum_epoch_yr_before_present"]["value"], abs=1000.0)


def test_vesta_stays_inside_vaillant_et_al_s_range():
    """21-45° over −20..0 Myr (Vaillant et al.; 17-48° had Vesta been in the 2s6 − sV resonance, which their
    polar-moment uncertainty allowed): ours over −3..0 Myr lies inside the printed whole degrees (±0.5°) and
    reaches near both ends (measured 21.5-44.1°), so it is the same non-resonant regime."""
    ref = published("vaillant2019")["vesta_obliquity_range_minus20_0Myr_deg"]
    eps = np.asarray(api.history("vesta", -3.0e6, 0.0, 1000.0)["obliquity_deg"])
    assert ref["min"] - 0.5 <= eps.min() and eps.max() <= ref["max"] + 0.5
    assert eps.min() < ref["min"] + 1.5 and eps.max() > ref["max"] - 1.5
