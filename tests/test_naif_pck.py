"""Text PCK kernels: SPICE itself (spiceypy) reads our kernel and its pole follows our track within the
fitting error the kernel states."""
import math
import re

import numpy as np
import pytest

spice = pytest.importorskip("spiceypy")

from ephem import api  # noqa: E402
from ephem.errors import InvalidInputError, NotApplicableError, UnknownBodyError  # noqa: E402
from ephem.naif_pck import write_pck, write_pck_file  # noqa: E402


@pytest.fixture
def kernel(tmp_path):
    loaded = []

    def load(bodies, start, stop, **kwargs):
        path = tmp_path / "ephem.tpc"
        fits = write_pck_file(path, bodies, start, stop, **kwargs)
        spice.furnsh(str(path))
        loaded.append(path)
        return path, fits
    yield load
    spice.kclear()


def spice_pole(naif_id, jd_tdb):
    return np.array([spice.tipbod("J2000", naif_id, (t - 2451545.0) * 86400.0)[2] for t in jd_tdb])


def unit(ra, dec):
    ra, dec = np.radians(ra), np.radians(dec)
    return np.stack([np.cos(dec) * np.cos(ra), np.cos(dec) * np.sin(ra), np.sin(dec)], axis=-1)


def angle_mas(a, b):
    return np.degrees(np.arctan2(np.linalg.norm(np.cross(a, b), axis=1), np.einsum("ij,ij->i", a, b))) * 3.6e6


def test_spice_reads_the_kernel_and_follows_the_track(kernel):
    path, fits = kernel(["vesta", "ceres", "mars"], "2000-01-01", "2020-01-01")
    for fit in fits:
        # epochs off the fitting grid: an odd step
        track = api.track_arrays(fit.body, "2000-01-01", "2020-01-01", 7.123)
        got = spice_pole(fit.naif_id, track["jd_tdb"])
        err = angle_mas(got, unit(track["pole_ra_deg"], track["pole_dec_deg"]))
        # the frame: SPICE's J2000 and our ICRF are taken as one (the kernel says so), so no bias here
        assert err.max() <= fit.fit_error_mas * 1.05 + 1e-3, fit.body
        assert fit.fit_error_mas < 1.0, fit.body              # measured 0.08-0.9 mas over 20 years
        assert fit.fit_error_mas < fit.model["estimated_error_mas"]
    # without the nutation terms SPICE would be far off: the terms matter
    vesta = fits[0]
    assert np.max(np.abs(vesta.nut_prec_ra)) * 3.6e6 > 100 * vesta.fit_error_mas


def test_the_comment_block_states_model_dataset_span_and_errors(kernel):
    path, fits = kernel("itokawa", "2020-01-01", "2030-01-01", dataset="petit2014")
    text = path.read_text()
    assert text.startswith("KPL/PCK\n") and text.count(r"\begindata") == 1
    head = text.split(r"\begindata")[0]
    for needed in ("Itokawa (NAIF ID 2025143), dataset petit2014", "model        hansen",
                   "estimated error of the model", "fitting error (kernel vs track, max)", "valid from   2020-01-01",
                   "J2000", "W0 = 0"):
        assert needed in head, needed
    assert re.search(r"BODY2025143_NUT_PREC_ANGLES = \(", text)


def test_a_planet_puts_its_angles_under_its_barycentre(kernel):
    path, fits = kernel("mars", "2000-01-01", "2010-01-01")
    assert fits[0].angles_id == 4 and "BODY4_NUT_PREC_ANGLES" in path.read_text()
    track = api.track_arrays("mars", "2000-01-01", "2010-01-01", 11.0)
    err = angle_mas(spice_pole(499, track["jd_tdb"]), unit(track["pole_ra_deg"], track["pole_dec_deg"]))
    assert err.max() <= fits[0].fit_error_mas * 1.05 + 1e-3


def test_the_tolerance_picks_the_model_the_kernel_fits():
    text, fits = write_pck("vesta", "2000-01-01", "2010-01-01", tolerance_mas=500)
    m = fits[0].model
    assert m["tolerance_mas"] == 500 and m["estimated_error_mas"] + fits[0].fit_error_mas <= 500
    # the real orbit is not periodic in M: its fit is coarser (measured 14.9 mas) but inside the tolerance
    assert m["name"] == "real_orbit" and 1.0 < fits[0].fit_error_mas < 100.0
    with pytest.raises(NotApplicableError, match="beyond the tolerance of 5 mas"):
        write_pck("vesta", "2000-01-01", "2010-01-01", tolerance_mas=5)
    assert f"model        {fits[0].model['name']}" in text


@pytest.mark.parametrize("args,error,field", [
    (("pluto", "2000-01-01", "2010-01-01"), UnknownBodyError, "pluto"),
    (("vesta", "2010-01-01", "2000-01-01"), InvalidInputError, "stop"),
    (("moon", "2000-01-01", "2010-01-01"), NotApplicableError, "synchronous"),
    (([], "2000-01-01", "2010-01-01"), InvalidInputError, "bodies"),
])
def test_bad_requests_are_clear(args, error, field):
    with pytest.raises(error, match=field):
        write_pck(*args)


def test_a_pole_near_the_icrf_pole_is_refused_not_written_badly():
    # the Earth's pole is 8" from the ICRF pole: RA swings, and the RA/Dec polynomial cannot follow it
    with pytest.raises(NotApplicableError, match="near the ICRF pole"):
        write_pck("earth", "2000-01-01", "2010-01-01")


def test_cli_writes_a_kernel(tmp_path):
    from typer.testing import CliRunner

    from ephem.cli import app

    out = tmp_path / "k.tpc"
    res = CliRunner().invoke(app, ["pck", "vesta", "ceres", "--start", "2000-01-01", "--stop", "2010-01-01",
                                   "--out", str(out)])
    assert res.exit_code == 0, res.output
    assert out.read_text().startswith("KPL/PCK") and "fitting error" in res.stdout
    assert math.isfinite(float(re.search(r"Vesta: fitting error ([0-9.e+-]+) mas", res.stdout).group(1)))
