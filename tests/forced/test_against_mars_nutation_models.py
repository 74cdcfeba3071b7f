"""Mars' rigid nutation and its liquid core against the outside Mars models (the numbers and their provenance:
data/interiors.toml and docs/interiors.md).

- Konopliv et al. 2006, Icarus 182, 23, Table 5: the rigid Mars nutation (Sun only), as printed in NASA JEOD
  (data_rnp_mars.cc) and TU Delft Tudat (defaultBodies.cpp), two codes that agree. Their ψ_K is minus ours
  (their ψ̇ = −7608 mas/yr, ours +), their I our ε; terms ψ_m sin α, I_m cos α with α = kM or kM + q,
  q = 142.00° at J2000 (ours: 2θ, twice the equinox-to-pericentre angle).
- IAU WGCCRE 2015 (Archinal et al. 2018, CMDA 130:22) Mars pole as printed in NAIF pck00011.tpc: the periodic
  RA/Dec terms of annual to quater-annual period.
- Le Maistre et al. 2023 (Nature 619, 733): F = 0.0615 ± 0.007, P_FCN = −243 ± 3.3 d, as quoted by a secondary
  source (data/interiors.toml), applied with ephem.bodies.interior.

Findings (docs/interiors.md): Konopliv's table is ours scaled by 1/1.0034 (it was built on an older precession rate,
ours is Baland 2020's H_D that reproduces Konopliv 2016's rate) save its pure annual longitude term, 1.8 mas
(0.28%) below ours after that scale, unexplained; WGCCRE's periodic terms are our rigid nutation *with* a liquid core:
without it they miss by up to 19 mas, with Le Maistre's F and P they agree within the printed digits' budget.
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from ephem.base.constants import JULIAN_YEAR_DAYS, MAS
from ephem.bodies.catalogue import get_body
from ephem.bodies.interior import apply_fluid_core, fluid_core_transfer, interior_of, transfer_sigma
from ephem.forced.catalogue_sigmas import input_sigmas
from ephem.forced.precession_nutation import model_for
from ephem.orbit.hansen import hansen_exact

# Konopliv et al. 2006 Table 5 (mas): k -> (ψ_m of kM, I_m of kM, ψ_m of kM+q, I_m of kM+q)
KONOPLIV_2006 = {1: (-632.6, -0.4, -104.5, -49.1), 2: (-44.2, 0.0, 1097.0, 515.7), 3: (-4.0, 0.0, 240.1, 112.8),
                 4: (0.0, 0.0, 40.9, 19.2)}
Q_DEG = 142.00
KONOPLIV_OBLIQUITY_DEG = 25.1893823     # I0 (Konopliv 2016 via Tudat)
KONOPLIV_N_DEG_PER_DAY = 0.52403958828
PRINTED = 0.05          # half a unit of Table 5's last digit, mas
CUTOFF = 0.5            # Table 5 omits arguments whose ψ is below ~0.5 mas (our 4M pure term, 0.41 mas, is absent;
                        # its I_m = −0.4 of M is a term our Sun-only first-order series has not): mas, per amplitude
#: the annual longitude's excess over Table 5 after the scale (test_the_annual_longitude_disagrees_in_its_pure_m_part_only)
ANNUAL_EXCESS = 1.8
FOLKNER_1997 = (7576.0, 35.0)   # Pathfinder + Viking precession rate, mas/yr (research notes 5a)
NAMES = {1: "annual", 2: "semi-annual", 3: "ter-annual", 4: "quater-annual"}

# WGCCRE 2015 Mars (pck00011.tpc): periodic terms (deg) and their angles (deg, deg/century), k = 1..4
WGCCRE_RA = [(0.000068, 198.991226, 19139.4819985), (0.000238, 226.292679, 38280.8511281),
             (0.000052, 249.663391, 57420.7251593), (0.000009, 266.183510, 76560.6367950)]
WGCCRE_DEC = [(0.000051, 122.433576, 19139.9407476), (0.000141, 43.058401, 38280.8753272),
              (0.000031, 57.663379, 57420.7517205), (0.000005, 79.476401, 76560.6495004)]
WGCCRE_SLOW = {"ra": (0.419057, 79.398797, 0.5042615), "dec": (1.591274, 166.325722, 0.5042615)}
WGCCRE_DIGIT_MAS = 0.5e-6 * 3.6e6     # half a unit of the printed 1e-6 deg: 1.8 mas


def konopliv_amplitudes(k: int, q_deg: float = Q_DEG) -> tuple[float, float]:
    """(|Δψ|, |Δε|) of the harmonic kM in Konopliv's table: the kM and kM + q terms summed as phasors."""
    a, b, c, d = KONOPLIV_2006[k]
    q = math.radians(q_deg)
    return abs(a + c * complex(math.cos(q), math.sin(q))), abs(b + d * complex(math.cos(q), math.sin(q)))


@pytest.fixture(scope="module")
def mars():
    return model_for("mars")


def ours(m, k: int) -> tuple[float, float]:
    s = m.nutation
    i = int(np.flatnonzero(s.multiple == k)[0])
    return math.hypot(s.lon_sin[i], s.lon_cos[i]) / MAS, math.hypot(s.obl_sin[i], s.obl_cos[i]) / MAS


def scale(m) -> float:
    """Our semi-annual amplitudes over Konopliv's (mean of longitude and obliquity): the ratio of the two series'
    K, i.e. of the precession rates they were built on."""
    (lo, ob), (kl, ko) = ours(m, 2), konopliv_amplitudes(2)
    return 0.5 * (lo / kl + ob / ko)


def test_konoplivs_phase_q_is_our_twice_equinox_to_pericentre(mars):
    """q = 142.00° (printed to 0.005°) against our 2θ from the catalogue's pole and orbit: the same geometry."""
    assert math.degrees(2 * mars.equinox_to_pericentre) == pytest.approx(Q_DEG, abs=0.01)


def test_konoplivs_scale_is_an_older_precession_rate(mars):
    """The semi-annual ratio is 1.0034: Konopliv's table is built on a torque rate 0.34% below ours (7589 against
    7613.9 mas/yr), far beyond our H_D's σ (0.03%, Baland 2020), within 1σ of the rate measured before it (Folkner
    et al. 1997, 7576 ± 35 mas/yr observable + 6.75 geodesic). The budget of the check: Folkner's 2σ."""
    s = scale(mars)
    ours_rate = mars.precession_rate * JULIAN_YEAR_DAYS / MAS
    hd_rel = input_sigmas(get_body("mars"))["inertia.dynamical_ellipticity"] / get_body("mars").hd
    assert abs(s - 1.0) > 5 * hd_rel
    implied_observable = ours_rate / s - mars.geodesic_rate * JULIAN_YEAR_DAYS / MAS
    assert abs(implied_observable - FOLKNER_1997[0]) <= 2 * FOLKNER_1997[1]


@pytest.mark.parametrize("k", [2, 3, 4, 1])
def test_term_by_term_against_konopliv_2006(mars, k):
    """Each harmonic's amplitudes (longitude, obliquity), ours divided by the common scale, against Table 5's.
    Budget per amplitude: the printed digits (2 entries, 2 × 0.05 mas), Table 5's cutoff (0.5 mas: terms it omits
    or we lack), the scale's own rounding (0.05/515.7 relative × the amplitude). The annual longitude is the one
    term outside it (test below): here only its obliquity is checked."""
    s = scale(mars)
    for what, mine, theirs in zip(("longitude", "obliquity"), ours(mars, k), konopliv_amplitudes(k)):
        if k == 1 and what == "longitude":
            continue
        budget = 2 * PRINTED + CUTOFF + PRINTED / 515.7 * theirs
        assert abs(mine / s - theirs) <= budget, (NAMES[k], what, mine / s, theirs, budget)


def test_the_annual_longitude_disagrees_in_its_pure_m_part_only(mars):
    """Investigated disagreement: our annual Δψ is 1.8 mas (0.3%) above Konopliv's after the common scale. Split
    into Table 5's arguments (M and M + q: ours are f C0_1 and f X_1 with the Hansen coefficients of (a/r)³), the
    M + q part agrees within its printed digit and the whole excess is in the pure-M term (ψ = −632.6 against our
    −634.4 after the scale). Not explained by: truncation in e (ours at e¹..e⁵ moves it the other way or not at all),
    the obliquity (ψ ∝ cos ε: 4e-5 for 0.0024°), the geodesic annual nutation (0.565 mas, Baland et al. 2023), the
    mean motion (3e-5). Konopliv's table has a term our model lacks (I = −0.4 mas cos M), a sign that its series
    holds more than the Sun's torque on a fixed ellipse. This test fails if the disagreement goes away or moves."""
    s = scale(mars)
    h = hansen_exact(mars.eccentricity)
    i = int(np.flatnonzero(h.k == 1)[0])
    f = 0.5 * mars.scaling_factor * math.cos(mars.obliquity) / mars.mean_motion / MAS
    pure, plus_q = f * h.c0[i] / s, f * 0.5 * (h.c2[i] + h.s2[i]) / s
    assert abs(abs(plus_q) - abs(KONOPLIV_2006[1][2])) <= 2 * PRINTED
    excess = abs(pure) - abs(KONOPLIV_2006[1][0])
    assert 2 * PRINTED + CUTOFF < excess < 2.5, excess


def _hand_core_change(k: int, F: float, P: float) -> tuple[float, float, float, float]:
    """Konopliv's real-valued core formula (Tudat's updateCorrections; research notes 1b) on Table 5's kM and
    kM + q terms, summed at the harmonic kM: the change of (ψ_K sin, ψ_K cos, I sin, I cos) coefficients, mas.
    Independent of ephem.bodies.interior."""
    sin_i = math.sin(math.radians(KONOPLIV_OBLIQUITY_DEG))
    a = k * math.radians(KONOPLIV_N_DEG_PER_DAY)
    s0 = 2 * math.pi / P
    g = F * a / (a * a - s0 * s0)
    q = math.radians(Q_DEG)
    out = np.zeros(4)
    for (psi, inc), phase in (((KONOPLIV_2006[k][0], KONOPLIV_2006[k][1]), 0.0),
                              ((KONOPLIV_2006[k][2], KONOPLIV_2006[k][3]), q)):
        d_inc = g * (a * inc + s0 * psi * sin_i)
        d_psi = g * (a * psi + s0 * inc / sin_i)
        # d_psi sin(kM + phase), d_inc cos(kM + phase)
        out += (d_psi * math.cos(phase), d_psi * math.sin(phase), -d_inc * math.sin(phase), d_inc * math.cos(phase))
    return tuple(out)


def test_the_hand_computation_of_the_research_notes():
    """The reference the next test holds the library to: Konopliv's real-valued core formula (as Tudat implements
    it) on Table 5's 2M + q term reproduces the research notes' ΔI = +8.89, Δψ = +37.94 mas (printed to 0.01:
    budget 0.005); and the library's T(σ) at the semi-annual prograde frequency, with the catalogue's Mars
    parameters, is the notes' 1.0255 (+2.6%, printed to 1e-4: budget 5e-5)."""
    sin_i = math.sin(math.radians(KONOPLIV_OBLIQUITY_DEG))
    a = 2 * math.radians(KONOPLIV_N_DEG_PER_DAY)
    s0 = 2 * math.pi / -243.0
    g = 0.0615 * a / (a * a - s0 * s0)
    d_inc = g * (a * 515.7 + s0 * 1097.0 * sin_i)
    d_psi = g * (a * 1097.0 + s0 * 515.7 / sin_i)
    assert d_inc == pytest.approx(8.89, abs=0.005)
    assert d_psi == pytest.approx(37.94, abs=0.005)
    mi = interior_of("Mars")
    F, P = (mi.parameters[n].value for n in ("fcn_amplitude_factor", "fcn_period_days"))
    assert float(fluid_core_transfer(a, F, P)) == pytest.approx(1.0255, abs=5e-5)


@pytest.mark.parametrize("k", [1, 2, 3, 4])
def test_our_core_change_is_the_hand_one(mars, k):
    """apply_fluid_core on our rigid harmonic kM against the hand formula on Konopliv's terms, coefficient by
    coefficient (ours in Konopliv's signs: ψ_K = −ψ). Budget: the two rigid series' scale (|1 − s| × the change),
    Table 5's digits and cutoff times the larger |T − 1| of the two components (0.15 at the semi-annual, 1.07 at the
    ter-annual's resonant retrograde part), for the annual the unexplained 1.8 mas of its pure-M longitude times the
    same factor, the obliquities' difference (0.0024°, 4e-5 relative), plus 0.01 mas."""
    mi = interior_of("Mars")
    F, P = (mi.parameters[n].value for n in ("fcn_amplitude_factor", "fcn_period_days"))
    s = mars.nutation
    i = int(np.flatnonzero(s.multiple == k)[0])
    rigid = (s.lon_sin[i] / MAS, s.lon_cos[i] / MAS, s.obl_sin[i] / MAS, s.obl_cos[i] / MAS)
    new = apply_fluid_core(*rigid, k * mars.mean_motion, mars.obliquity, F, P)
    change = np.array([float(n) - r for n, r in zip(new, rigid)]) * np.array([-1, -1, 1, 1])
    hand = np.array(_hand_core_change(k, F, P))
    nu, s0 = k * mars.mean_motion, 2 * math.pi / P
    t_max = max(abs(F * nu / (nu - s0)), abs(F * nu / (nu + s0)))     # |T(±kn) − 1|
    unexplained = ANNUAL_EXCESS if k == 1 else 0.0
    budget = abs(scale(mars) - 1) * np.abs(hand) + (2 * PRINTED + CUTOFF + unexplained) * t_max \
        + 1e-4 * np.abs(hand) + 0.01
    assert np.all(np.abs(change - hand) <= budget), (k, change, hand, budget)


# --- WGCCRE 2015 -------------------------------------------------------------------------------------------------

JD = np.arange(2451545.0, 2451545.0 + 40 * JULIAN_YEAR_DAYS, 1.0)      # 2000-2040, daily


def _design(m):
    t = JD - 2451545.0
    cols = [np.ones_like(t), t, t * t]
    for k in range(1, 7):
        cols += [np.sin(k * m.mean_motion * t), np.cos(k * m.mean_motion * t)]
    return np.stack(cols, axis=1)


def periodic_amplitudes(m, ra, dec) -> np.ndarray:
    """(2, 4): the RA and Dec amplitudes (mas, in the angle itself) of the harmonics kM, k = 1..4, fitted over
    2000-2040 with a quadratic trend and k up to 6 (the leakage from WGCCRE's slow term, 0.5°/century, into a
    quadratic over 40 years is below 0.01 mas)."""
    a = _design(m)
    out = np.empty((2, 4))
    for row, y in enumerate((np.unwrap(ra) / MAS, dec / MAS)):
        c, *_ = np.linalg.lstsq(a, y - y.mean(), rcond=None)
        out[row] = [math.hypot(c[3 + 2 * j], c[4 + 2 * j]) for j in range(4)]
    return out


def wgccre_pole(jd) -> tuple[np.ndarray, np.ndarray]:
    """α0, δ0 (radians) of the WGCCRE 2015 Mars model (pck00011.tpc)."""
    T = (np.asarray(jd) - 2451545.0) / 36525.0
    ra = 317.269202 - 0.10927547 * T
    dec = 54.432516 - 0.05827105 * T
    for amp, a0, rate in WGCCRE_RA + [WGCCRE_SLOW["ra"]]:
        ra = ra + amp * np.sin(np.radians(a0 + rate * T))
    for amp, a0, rate in WGCCRE_DEC + [WGCCRE_SLOW["dec"]]:
        dec = dec + amp * np.cos(np.radians(a0 + rate * T))
    return np.radians(ra), np.radians(dec)


def with_core(m, F, P):
    s = m.nutation
    new = apply_fluid_core(s.lon_sin, s.lon_cos, s.obl_sin, s.obl_cos, s.multiple * m.mean_motion, m.obliquity, F, P)
    return dataclasses.replace(m, nutation=dataclasses.replace(s, **dict(zip(("lon_sin", "lon_cos", "obl_sin",
                                                                                  "obl_cos"), new))))


def _track_amplitudes(m):
    tr = m.track(JD)
    return periodic_amplitudes(m, tr.pole_ra, tr.pole_dec)


@pytest.fixture(scope="module")
def amplitudes(mars):
    mi = interior_of("Mars")
    F, P = (mi.parameters[n] for n in ("fcn_amplitude_factor", "fcn_period_days"))
    core = _track_amplitudes(with_core(mars, F.value, P.value))
    # the core's σ on each fitted amplitude: central differences in F and P (linear, independent)
    dF = (_track_amplitudes(with_core(mars, F.value + F.sigma, P.value))
          - _track_amplitudes(with_core(mars, F.value - F.sigma, P.value))) / 2
    dP = (_track_amplitudes(with_core(mars, F.value, P.value + P.sigma))
          - _track_amplitudes(with_core(mars, F.value, P.value - P.sigma))) / 2
    wg = np.array([[a * 3.6e6 for a, _, _ in WGCCRE_RA], [a * 3.6e6 for a, _, _ in WGCCRE_DEC]])
    return {"rigid": _track_amplitudes(mars), "core": core, "core_sigma": np.hypot(dF, dP), "wgccre": wg,
            "scale": scale(mars)}


def _budget(amplitudes, k_index):
    """Per amplitude: WGCCRE's printed digit (1.8 mas), the rigid series' scale spread (|1 − s| × A: the JPL series
    are tied to Konopliv's), and for the annual harmonic the unexplained 1.8 mas of Konopliv's pure-M longitude
    (× sin ε on the sky = 0.8 mas) and his 0.4 mas obliquity term."""
    wg = amplitudes["wgccre"][:, k_index]
    extra = (ANNUAL_EXCESS * math.sin(math.radians(25.19)) + 0.4) / np.array([math.cos(math.radians(52.886)), 1.0]) \
        if k_index == 0 else 0.0
    return WGCCRE_DIGIT_MAS + abs(amplitudes["scale"] - 1) * wg + extra


@pytest.mark.parametrize("k", [1, 2, 3, 4])
def test_wgccre_periodic_terms_are_the_rigid_nutation_with_the_core(amplitudes, k):
    """Our pole with Le Maistre's core meets WGCCRE's RA and Dec amplitudes of each harmonic within the budget
    (plus 2σ of the core's parameters)."""
    j = k - 1
    budget = _budget(amplitudes, j) + 2 * amplitudes["core_sigma"][:, j]
    diff = amplitudes["core"][:, j] - amplitudes["wgccre"][:, j]
    assert np.all(np.abs(diff) <= budget), (NAMES[k], amplitudes["core"][:, j], amplitudes["wgccre"][:, j], budget)


def test_the_rigid_nutation_misses_wgccre_at_the_semi_and_ter_annual(amplitudes):
    """Without the core the semi-annual misses by 19 mas in RA and 12 in Dec and the ter-annual by 7 and 3: beyond
    the same budget (the comparison above can fail)."""
    for j in (1, 2):
        miss = np.abs(amplitudes["rigid"][:, j] - amplitudes["wgccre"][:, j])
        assert np.any(miss > _budget(amplitudes, j)), (j, miss)


def test_over_four_decades_the_core_moves_our_pole_by_the_expected_semi_annual_amount(mars):
    """Our rigid pole against WGCCRE's over 2000-2040: a few tens of mas (the catalogue pole's rounding, 9 mas at
    J2000, and the rates' difference), and the core's semi-annual change of our pole, fitted on the sky from the two
    tracks, against the hand value from Konopliv's rigid amplitudes: the prograde component gains (T(+2n) − 1)|P|,
    the retrograde loses (1 − T(−2n))|R|, so the displacement's semi-annual ellipse has semi-axes |ΔP| + |ΔR| and
    ||ΔP| − |ΔR||. Budget: the scale (0.34%), Table 5's digits (0.1 mas × |T − 1|), the fit (0.05 mas)."""
    mi = interior_of("Mars")
    F, P = (mi.parameters[n].value for n in ("fcn_amplitude_factor", "fcn_period_days"))
    rigid = mars.track(JD)
    ra_w, dec_w = wgccre_pole(JD)

    def vec(ra, dec):
        return np.stack([np.cos(dec) * np.cos(ra), np.cos(dec) * np.sin(ra), np.sin(dec)], axis=-1)

    def separation_mas(u, v):   # atan2(|u×v|, u·v): an arccos of the dot resolves 9 mas only in 0.5-mas steps
        return np.arctan2(np.linalg.norm(np.cross(u, v), axis=-1), np.sum(u * v, axis=-1)) / MAS

    sep_mas = separation_mas(vec(ra_w, dec_w), vec(rigid.pole_ra, rigid.pole_dec))
    # at J2000 the track is at the catalogue pole, WGCCRE's rounded to 1e-5 deg: the separation is that rounding's
    # (9.9 mas; an earlier arccos read 9.2), within the half-unit's bound hypot(0.5e-5 cos δ, 0.5e-5) deg = 21 mas
    pole = get_body("mars").pole
    rounding = separation_mas(vec(ra_w[0], dec_w[0]), vec(math.radians(pole.ra_deg), math.radians(pole.dec_deg)))
    assert sep_mas[0] == pytest.approx(rounding, abs=0.01)   # the track's start: the catalogue pole to 1e-12 rad
    assert 0.0 < rounding <= math.hypot(0.5e-5 * math.cos(dec_w[0]), 0.5e-5) * 3.6e6
    assert 20.0 < sep_mas.max() < 100.0

    core = with_core(mars, F, P).track(JD)
    d_east = (np.unwrap(core.pole_ra) - np.unwrap(rigid.pole_ra)) * np.cos(rigid.pole_dec) / MAS
    d_north = (core.pole_dec - rigid.pole_dec) / MAS
    a = _design(mars)
    ce, *_ = np.linalg.lstsq(a, d_east, rcond=None)
    cn, *_ = np.linalg.lstsq(a, d_north, rcond=None)
    t = np.linspace(0, 2 * math.pi, 721)
    x = ce[5] * np.sin(t) + ce[6] * np.cos(t)
    y = cn[5] * np.sin(t) + cn[6] * np.cos(t)
    r = np.hypot(x, y)
    # hand: Konopliv's 2M and 2M+q as circular components P = (I + ψ sin I)/2, R = (I − ψ sin I)/2 (phasors)
    sin_i = math.sin(math.radians(KONOPLIV_OBLIQUITY_DEG))
    q = complex(math.cos(math.radians(Q_DEG)), math.sin(math.radians(Q_DEG)))
    psi = KONOPLIV_2006[2][0] + KONOPLIV_2006[2][2] * q
    inc = KONOPLIV_2006[2][1] + KONOPLIV_2006[2][3] * q
    pro, retro = abs(inc + psi * sin_i) / 2, abs(inc - psi * sin_i) / 2
    a2 = 2 * math.radians(KONOPLIV_N_DEG_PER_DAY)
    s0 = 2 * math.pi / P
    d_pro = pro * F * a2 / (a2 - s0)
    d_retro = retro * F * a2 / (a2 + s0)
    s = scale(mars)
    tol = abs(s - 1) * (d_pro + abs(d_retro)) + 0.1 * F + 0.05
    assert r.max() == pytest.approx((d_pro + abs(d_retro)) * s, abs=tol)
    assert r.min() == pytest.approx(abs(d_pro - abs(d_retro)) * s, abs=tol)


# --- the served non-rigid rung against WGCCRE 2015 ------------------------------------------------------------------

@pytest.fixture(scope="module")
def served_amplitudes():
    """The RA and Dec amplitudes of the served tracks ('nonrigid' and the rigid 'second_order' it starts from),
    fitted over 2000-2040 as WGCCRE's."""
    from ephem.sun.ladder import Ladder
    ladder = Ladder(get_body("mars"), axis="angular_momentum")
    out = {}
    for rung in ("nonrigid", "second_order"):
        tr = ladder.track(rung, JD)
        out[rung] = periodic_amplitudes(ladder.model, tr.pole_ra, tr.pole_dec)
    return out


@pytest.mark.parametrize("k", [1, 2, 3, 4])
def test_the_served_nonrigid_track_meets_wgccre(amplitudes, served_amplitudes, k):
    """The track a user gets with model 'nonrigid' (second order in the torque, the geodesic precession, the core)
    meets WGCCRE 2015's amplitude of each harmonic within the same budget as the first-order series with the core
    above, and the rigid 'second_order' track misses the semi-annual one (so the comparison can fail)."""
    j = k - 1
    budget = _budget(amplitudes, j) + 2 * amplitudes["core_sigma"][:, j]
    diff = served_amplitudes["nonrigid"][:, j] - amplitudes["wgccre"][:, j]
    assert np.all(np.abs(diff) <= budget), (NAMES[k], served_amplitudes["nonrigid"][:, j], budget)
    if k == 2:
        miss = np.abs(served_amplitudes["second_order"][:, j] - amplitudes["wgccre"][:, j])
        assert np.any(miss > _budget(amplitudes, j)), miss
