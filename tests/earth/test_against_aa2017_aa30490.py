"""A&A (2017) article aa30490-17, Table A.4, "Main orbital coefficients for Moon and Sun" (data/lunisolar.toml):
the forcing spectrum of ephem.earth.lunisolar (the Moon's and the Sun's B0, B1, B2 functions) against it."""
import pytest

from ephem.earth import lunisolar as L


# Table A.4 of A&A 2017 (aa30490-17), "main orbital coefficients" (data/lunisolar.toml): the
# zonal B0 = (a/r)^3 (1 - 3 sin^2 beta)/2, the B1 = (a/r)^3 y z and the B2 = (a/r)^3 (x^2 - y^2)
# functions of each perturber (x, y, z its unit vector, ecliptic and equinox of date). Ratios to
# the constant B0 remove the normalising distance.
TABLE_A4 = {body: {tuple(int(v) for v in row[:5]): (row[5], row[6])
                   for row in L.lunisolar_data()["orbital_coefficients_reference"][body]}
            for body in ("moon", "sun")}


@pytest.mark.parametrize("body", ["moon", "sun"])
def test_forcing_spectrum_matches_published_orbital_coefficients(body):
    # G1 = B0 - B2/2 and G2 = B1 in that normalisation; agreement to 2e-6 of the constant B0,
    # i.e. < 0.04 mas on the 18.6-yr nutation (our Moon is Meeus's truncation of ELP-2000/82).
    spec = L.orbital_spectrum((body,), 0.0)
    g0 = spec.const[0]
    table = TABLE_A4[body]
    ref0 = table[(0, 0, 0, 0, 0)][1]
    for k, (kind, value) in table.items():
        if not any(k):
            continue
        row = [i for i, m in enumerate(spec.multipliers) if tuple(m) == k or tuple(-m) == k]
        assert row, k
        c = spec.cos_[row[0]]
        ours = {"B0": c[0], "B1": c[1], "B2": -2.0 * c[0]}[kind]
        assert ours / g0 == pytest.approx(value / ref0, abs=2e-6), (body, k)
        assert abs(spec.sin_[row[0], 0]) < 1e-9 * abs(g0)        # symmetric forcing: no sin part in G1
