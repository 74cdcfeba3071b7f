"""The Earth's lunisolar model from the catalogue: the series on its pole and orbit, rigid and non-rigid.

:func:`ephem.earth.lunisolar.earth_lunisolar`'s series wired to
the catalogue's pole and orbit (:class:`LunisolarEarth`, :func:`lunisolar_earth`); and the non-rigid rung's model on
IAU 2006's precession (:class:`NonRigidEarth`).

The track follows :mod:`ephem.forced.precession_nutation`'s definition in the frame of the catalogue's orbit and
the mean equinox at the pole epoch t0:

    ψ(t) = ψ̇ (t − t0) + Δψ(t),    ε(t) = ε̄ + Δε(t),

with the catalogue pole the instantaneous axis at t0: ε̄ and the mean equinox are the catalogue's obliquity and
equinox with the series' own Δε(t0), Δψ(t0) removed (exactly, not by iteration: the lunisolar series depend on
time only). ``axis="figure"`` serves the figure-axis series (the Oppolzer terms included: the analogue of the
IAU's CIP), ``axis="angular_momentum"`` the angular-momentum one. Radians and days unless a name says otherwise.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import lru_cache
import numpy as np
from ..bodies.catalogue import Body, is_earth
from ..base.constants import ARCSEC, J2000_JD, JULIAN_YEAR_DAYS
from ..base.constants import JULIAN_CENTURY_DAYS as DAYS_PER_CENTURY
from ..base.errors import NotApplicableError
from ..orbit.geometry import icrf_to_ecliptic_matrix, spin_geometry, unit_vector
from ..forced.kinoshita import mean_pole
from ..orbit.lunar import lunisolar_data, obliquity_arcsec
from .lunisolar import earth_lunisolar
from ..forced.precession_nutation import Track
from ..orbit.relativity import geodesic_precession_rate


#: Sidebands ±j ψ̇ a track carries about each lunisolar term (the Earth's precession is slow, its terms many)
TRACK_SIDEBANDS = 1
#: Amplitude cut of the served track's series (mas): the cut the residual envelope was measured with.
TRACK_CUT_MAS = 0.1
#: The series are built at IAU 2006's ε_A; a pole whose mean obliquity departs by more is refused.
MAX_OBLIQUITY_MISMATCH = 60.0 * ARCSEC
#: The tides' secular change of the precession constant, which the averaged spin equation leaves out (relative per
#: year; the long-term estimate's α neighbour drifts at it). The Moon's share of α goes as a⁻³ with the Moon receding
#: at 3.82 ± 0.07 cm/yr (lunar laser ranging: Dickey et al. 1994, Science 265, 482) from 3.844e8 m; the whole of α
#: as H_d/ω with H_d ∝ ω² (the figure follows the spin over such spans), i.e. as ω, which tidal braking slows at
#: 6.39 ± 0.03e-22 rad/s² (the predicted tidal deceleration of Morrison, Stephenson, Hohenkerk & Zawilski 2021,
#: "Addendum 2020 to 'Measurement of the Earth's rotation: 720 BC to AD 2015'", Proc. R. Soc. A 477) from
#: 7.292115e-5 rad/s: 2.77e-10 per year. Both lower α towards the future; the magnitudes add (about 4.8e-10 per
#: year with the Moon's 69 % share), a sign-blind bound, as La2004's own tidal parameters are not ours.
MOON_RECESSION_PER_YEAR = 0.0382 / 3.844e8
SPIN_BRAKING_PER_YEAR = 6.39e-22 / 7.292115e-5 * 86400.0 * JULIAN_YEAR_DAYS


def tidal_constant_drift(moon_share: float) -> float:
    """The relative change of the precession constant per year that tides cause (:data:`MOON_RECESSION_PER_YEAR`,
    :data:`SPIN_BRAKING_PER_YEAR`), for the Moon's share ``moon_share`` of it."""
    return 3.0 * MOON_RECESSION_PER_YEAR * moon_share + SPIN_BRAKING_PER_YEAR


@dataclass(frozen=True, eq=False)
class LunisolarEarth:
    """The Earth's lunisolar precession-nutation from the catalogue's pole and orbit (radians, days)."""

    body: Body
    series: object                       # ephem.earth.lunisolar.LunisolarSeries
    axis: str
    perturbers: tuple[str, ...]          # canonical names ("Moon", "Sun")
    obliquity: float                     # ε̄: mean obliquity on the catalogue orbit at t0
    pole_epoch: float                    # t0
    nutation_at_pole_epoch: tuple[float, float]
    icrf_from_orbit: np.ndarray = field(repr=False)   # columns: mean equinox at t0, W × it, W (ICRF)
    orbit_tilt: float = 0.0              # the catalogue orbit normal from the J2000 ecliptic pole
    geodesic_rate: float = 0.0           # Ω_gp (rad/day): the geodesic precession the track adds (ephem.orbit.relativity)

    @property
    def precession_rate(self) -> float:
        """ψ̇ of the torque (rad/day): the first-order lunisolar rate (the precession answer's)."""
        return float(self.series.precession_rate)

    @property
    def track_rate(self) -> float:
        """The track's ψ̇ (rad/day): the torque's less the geodesic precession, which turns the axis about the
        orbit normal in the orbital (prograde) sense."""
        return self.precession_rate - self.geodesic_rate

    @property
    def hd(self) -> float:
        return self.series.hd

    @property
    def spin_rate(self) -> float:
        return self.series.spin_rate

    @property
    def scaling_factor(self) -> float:
        """2 ψ̇ / cos ε̄: the K of one perturber on a circular orbit in the ecliptic giving the same rate."""
        return 2.0 * self.precession_rate / math.cos(self.obliquity)

    def angles(self, jd_tdb):
        """ψ, Δψ, Δε, ε (radians) at JD TDB."""
        t = np.asarray(jd_tdb, dtype=float)
        dpsi, deps = self.series.nutation_at(t)
        return self.track_rate * (t - self.pole_epoch) + dpsi, dpsi, deps, self.obliquity + deps

    def track(self, jd_tdb) -> Track:
        t = np.asarray(jd_tdb, dtype=float)
        psi, dpsi, deps, eps = self.angles(t)
        se = np.sin(eps)
        v = np.stack([se * np.sin(psi), se * np.cos(psi), np.cos(eps)], axis=-1) @ self.icrf_from_orbit.T
        ra = np.remainder(np.arctan2(v[..., 1], v[..., 0]), 2.0 * math.pi)
        dec = np.arctan2(v[..., 2], np.hypot(v[..., 0], v[..., 1]))
        return Track(t, psi, dpsi, deps, eps, ra, dec)


def check_earth(body: Body) -> None:
    if not is_earth(body) or body.orbit.center != "Sun":
        raise NotApplicableError(body.name, "the lunisolar theory (the Moon as a perturber) is modelled for the "
                                 "Earth only")


@lru_cache(maxsize=64)
def lunisolar_earth(body: Body, axis: str = "figure", cut_mas: float = TRACK_CUT_MAS,
                    perturbers: tuple[str, ...] = ("Moon", "Sun")) -> LunisolarEarth:
    """The lunisolar model of the Earth ``body`` (its H_d, spin rate, pole and orbit)."""
    check_earth(body)
    series = earth_lunisolar(cut_mas=cut_mas, perturbers=tuple(p.lower() for p in perturbers), hd=float(body.hd),
                             axis=axis, spin_rate=body.spin_rate_rad_per_day)
    ecl_from_icrf = icrf_to_ecliptic_matrix()
    s_ecl = ecl_from_icrf @ unit_vector(math.radians(body.pole.ra_deg), math.radians(body.pole.dec_deg))
    o = body.orbit
    geo = spin_geometry(s_ecl, *(math.radians(x) for x in (o.i_deg, o.node_deg, o.peri_deg)), body.name)
    t0 = body.pole.epoch_jd_tdb
    # the lunisolar series does not depend on the mean pole: one pass of the fixed point is exact
    eps_mean, _, dpsi0, deps0 = mean_pole(geo.obliquity, geo.equinox_to_pericentre,
                                          lambda *_: series.nutation_at(np.array(t0)), passes=1)
    eps_a = obliquity_arcsec((t0 - J2000_JD) / DAYS_PER_CENTURY) * ARCSEC
    if abs(eps_mean - eps_a) > MAX_OBLIQUITY_MISMATCH:
        raise NotApplicableError(body.name, (
            f"the pole gives a mean obliquity of {math.degrees(eps_mean):.6f} deg on the orbit, "
            f"{abs(eps_mean - eps_a) / ARCSEC:.1f} arcsec from IAU 2006's {math.degrees(eps_a):.6f} deg at its "
            f"epoch; the lunisolar series are built at the latter (accepted within "
            f"{MAX_OBLIQUITY_MISMATCH / ARCSEC:g} arcsec)"))
    gamma, y_true, w = geo.orbit_frame
    x_mean = math.cos(dpsi0) * gamma + math.sin(dpsi0) * y_true
    icrf_from_orbit = ecl_from_icrf.T @ np.vstack([x_mean, np.cross(w, x_mean), w]).T
    tilt = math.atan2(float(np.linalg.norm(w[:2])), float(w[2]))
    return LunisolarEarth(body, series, axis, tuple(perturbers), eps_mean, t0, (dpsi0, deps0), icrf_from_orbit, tilt,
                          geodesic_precession_rate(o.a_au, o.e, o.center))


@dataclass(frozen=True, eq=False)
class NonRigidEarth:
    """The non-rigid Earth rung (``nonrigid``): our lunisolar nutation times the IERS 1996 transfer function on the IAU 2006
    precession, the Earth's model for tolerances the rigid theory cannot meet.
    
    The rigid rung (``lunisolar``, :mod:`ephem.earth.model`) is Kinoshita's first-order theory for a rigid Earth: 63 mas
    rms from IAU 2000A in Δψ over 1900–2100, and its linear precession misses IAU 2006's quadratic ψ_A by 39 mas in 30
    years. This rung serves, at each epoch,
    
    * the precession of IAU 2006 (P03, Capitaine et al. 2003, A&A 412, 567), the observed one, through ERFA's
      Fukushima–Williams angles (``erfa.pfw06``, frame bias included): a first-order theory has neither P03's
      second-order and planetary contributions nor the ecliptic's motion;
    * our nutation (:func:`ephem.earth.lunisolar.earth_lunisolar`, amplitude cut 0.1 mas, the request's axis) with
      the precession–nutation coupling added and every circular component times the IERS 1996 transfer function
      T(σ) of the elastic mantle, the fluid core and the oceans (:func:`ephem.earth.nonrigid.non_rigid_series`),
      applied on the ecliptic and equinox of date as IAU 2000A's is (``erfa.fw2m``).
    
    What it leaves out, against ERFA's IAU 2006/2000A, is measured (``data/lunisolar.toml [nonrigid_track]``) and is
    the ``nutation_residual`` term: MHB2000's anelastic and ocean corrections beyond the 1996 transfer function, the
    planetary nutation (IAU 2000A's 687 planetary terms; ``erfa.nut00b`` replaces them by a constant), the terms under
    the cut and second-order terms. The free core nutation's free mode, which IAU 2000A leaves out too, and IAU 2006's
    own error are ``iau_reference``. The pole is the CIP's analogue (the figure axis), or the angular momentum with
    ``axis_relation`` as the rigid rung's.
    
    TT and TDB differ by under 2 ms, 1e-10 of a precession day: ERFA's TT argument takes the TDB Julian date. The
    track's ψ and ε are read off the pole in the rigid model's frame (the catalogue orbit, the mean equinox at its pole
    epoch), as every Earth track's; Δψ and Δε are the non-rigid series' nutation. Radians and days.

    ``rigid``: the lunisolar model of the same body, axis and cut (its frame, obliquity and pole epoch); ``series``
    its non-rigid series (:func:`ephem.earth.estimates.nonrigid_earth` builds both).
    """

    rigid: LunisolarEarth
    series: object = field(repr=False)       # ephem.earth.lunisolar.LunisolarSeries, every term times T(σ)

    # the attributes the wobble, the estimates and the answers read, as the rigid model's
    @property
    def body(self) -> Body:
        return self.rigid.body

    @property
    def axis(self) -> str:
        return self.rigid.axis

    @property
    def perturbers(self) -> tuple[str, ...]:
        return self.rigid.perturbers

    @property
    def obliquity(self) -> float:
        return self.rigid.obliquity

    @property
    def pole_epoch(self) -> float:
        return self.rigid.pole_epoch

    @property
    def icrf_from_orbit(self) -> np.ndarray:
        return self.rigid.icrf_from_orbit

    @property
    def hd(self) -> float:
        return self.rigid.hd

    def pole(self, jd_tdb) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The pole's unit vectors (..., 3) in the GCRS (the ICRF's axes) and the nutation Δψ, Δε (radians)."""
        import erfa    # astropy's ERFA: imported on first use, as the estimates' comparison does

        t = np.asarray(jd_tdb, dtype=float)
        gamb, phib, psib, epsa = erfa.pfw06(t, 0.0)
        dpsi, deps = self.series.nutation_at(t)
        matrix = erfa.fw2m(gamb, phib, psib + dpsi, epsa + deps)       # GCRS -> true equator and equinox of date
        return matrix[..., 2, :], dpsi, deps

    def track(self, jd_tdb) -> Track:
        t = np.asarray(jd_tdb, dtype=float)
        v, dpsi, deps = self.pole(t)
        s = v @ self.icrf_from_orbit
        mean_psi = self.rigid.track_rate * (t - self.pole_epoch)
        raw = np.arctan2(s[..., 0], s[..., 1])
        psi = mean_psi + np.remainder(raw - mean_psi + math.pi, 2.0 * math.pi) - math.pi
        eps = np.arctan2(np.hypot(s[..., 0], s[..., 1]), s[..., 2])
        ra = np.remainder(np.arctan2(v[..., 1], v[..., 0]), 2.0 * math.pi)
        dec = np.arctan2(v[..., 2], np.hypot(v[..., 0], v[..., 1]))
        return Track(t, psi, dpsi, deps, eps, ra, dec)


def residual_envelope() -> float:
    """The measured envelope (mas) of sin ε|Δψ| + |Δε| of the non-rigid series against ``erfa.nut00a`` over
    1900–2100 (``data/lunisolar.toml [nonrigid_track]``)."""
    return float(lunisolar_data()["nonrigid_track"]["residual_envelope_mas"])
