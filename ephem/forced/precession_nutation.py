"""Precession-nutation model of one body: geometry + Kinoshita's theory, evaluated over time.

The catalogue pole is the *instantaneous* spin axis at its epoch t0; the
theory's mean pole differs from it by the nutation (Δψ(t0), Δε(t0)), which is
removed here (:func:`ephem.forced.kinoshita.mean_pole`: three fixed-point passes; the correction is
second order).

The track follows the issue's definition, in the frame of the orbit and the
mean equinox at t0:

    ψ(t) = (ψ̇ − Ω_gp) (t - t0) + Δψ(t),    ε(t) = ε̄0 + Δε(t)

and the spin axis s(t) = (sin ε sin ψ, sin ε cos ψ, cos ε): s turns about
the orbit normal by -ψ (ψ̇ > 0 is retrograde, as the Earth's precession). ψ̇ is the torque's rate
(Kinoshita); Ω_gp the geodesic (de Sitter) precession, a rotation about the orbit normal in the orbital
sense (:mod:`ephem.orbit.relativity`), which every track carries as what the stars see (``track_rate``). It
is applied as that rotation of the torque's solution: what it leaves (the equinox's extra drift re-phasing
the nutation, and the periodic part of the instantaneous geodesic rate) is an error term of the ladder
(:func:`ephem.sun.bounds.geodesic_bounds`).
"""
from __future__ import annotations

import bisect
import math
from dataclasses import dataclass

import numpy as np

from ..bodies.catalogue import DEFAULT_DATASET, Body, resolve_body
from ..base.errors import InvalidInputError, NotApplicableError
from ..orbit.geometry import icrf_to_ecliptic_matrix, spin_geometry, unit_vector
from ..orbit.hansen import LAPLACE_LIMIT, exact_unavailable
from ..base.budget import checkpoint
from ..orbit.harmonic_grid import GridHarmonics, angle_sum_into
from ..orbit.harmonics import MAX_SHIFT, HarmonicSums, cos_sin_into, shift_factors
from ..orbit.kepler import mean_motion_rad_per_day
from ..orbit.relativity import geodesic_precession_rate
from ..base.memo import bytes_bounded
from .kinoshita import NutationSeries, mean_pole, nutation_series, precession_rate, scaling_factor

#: Rotation-averaging needs the spin much faster than the orbital motion. Against the full rigid
#: body (ephem.forced.rigid_body, docs/rigid_body_study.md) the averaged theory's figure axis is off by 10% of
#: the pole's motion over an orbit at ω/n = 25 for the catalogue Eros ((B-A)/C = 0.73, the worst
#: shape), 5-11 for near-axisymmetric bodies, and by order 1 below ω/n = 3: refuse below 30.
MIN_SPIN_ORBIT_RATIO = 30.0
#: highest e-order of the truncated Hansen coefficients a model accepts (omit the order for exact ones)
MAX_ORDER = 30


@dataclass(frozen=True)
class Track:
    """Spin-axis track over epochs (radians; times JD TDB)."""

    jd_tdb: np.ndarray
    psi: np.ndarray
    delta_psi: np.ndarray
    delta_epsilon: np.ndarray
    obliquity: np.ndarray
    pole_ra: np.ndarray
    pole_dec: np.ndarray


@dataclass(frozen=True)
class PrecessionNutation:
    """The forced precession and nutation of one body, first order in the torque.

    Rates in rad/day, angles in radians, times JD TDB.
    """

    body: str
    dataset: str
    hd: float
    mean_motion: float           # n, rad/day
    spin_rate: float             # ω, rad/day
    eccentricity: float
    scaling_factor: float        # K = 3 n² H_d / ω, rad/day
    obliquity: float             # mean obliquity ε̄0 at the pole epoch
    equinox_to_pericentre: float  # θ̄ from the mean equinox at t0
    precession_rate: float       # ψ̇, rad/day
    nutation: NutationSeries
    pole_epoch: float            # t0
    orbit_epoch: float
    mean_anomaly_at_epoch: float  # M at orbit_epoch
    nutation_at_pole_epoch: tuple[float, float]  # (Δψ(t0), Δε(t0))
    icrf_from_orbit: np.ndarray  # columns: mean equinox, W × equinox, W in ICRF
    order: int | None
    #: Ω_gp (rad/day), the geodesic precession about the orbit normal (:mod:`ephem.orbit.relativity`); 0 for a
    #: model of the torque alone (the full rigid body's reference, which measures rotation averaging)
    geodesic_rate: float = 0.0

    @property
    def track_rate(self) -> float:
        """The track's mean ψ̇ (rad/day): the torque's rate less the geodesic precession (module docstring)."""
        return self.precession_rate - self.geodesic_rate

    @property
    def spin_orbit_ratio(self) -> float:
        return self.spin_rate / self.mean_motion

    def mean_anomaly(self, jd_tdb) -> np.ndarray:
        return self.mean_anomaly_at_epoch + self.mean_motion * (np.asarray(jd_tdb, dtype=float) - self.orbit_epoch)

    def nutation_at(self, jd_tdb) -> tuple[np.ndarray, np.ndarray]:
        """Δψ, Δε (radians) at epochs (JD TDB)."""
        return self.nutation.evaluate(self.mean_anomaly(jd_tdb))

    def angles(self, jd_tdb) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """ψ, Δψ, Δε and ε (radians) at epochs: the cheap part of a track."""
        t = np.asarray(jd_tdb, dtype=float)
        dpsi, deps = self.nutation_at(t)
        psi = self.track_rate * (t - self.pole_epoch) + dpsi
        return psi, dpsi, deps, self.obliquity + deps

    def angles_grid(self, jd_start: float, step_days: float, count: int):
        """As :meth:`angles` on the grid t_j = jd_start + j step_days: (t, ψ, Δψ, Δε, ε), no trigonometric call
        per epoch (:meth:`_kernel`)."""
        return self._kernel(_Epochs(None, jd_start, step_days, count), pole=False)[:5]

    @property
    def catalogue_pole_orbit(self) -> np.ndarray:
        """The catalogue pole (the spin axis at the pole epoch, mean pole plus nutation there), a unit vector (3,)
        in the orbit frame: where every integration and offset starts."""
        dpsi0, deps0 = self.nutation_at_pole_epoch
        return self.pole_orbit_frame(dpsi0, self.obliquity + deps0)

    def pole_orbit_frame(self, psi, eps) -> np.ndarray:
        """Spin-axis unit vectors (..., 3) in the frame of the orbit and mean equinox at t0."""
        se = np.sin(eps)
        return np.stack([se * np.sin(psi), se * np.cos(psi), np.cos(eps)], axis=-1)

    def track(self, jd_tdb) -> Track:
        """Track at any epochs (JD TDB, any shape and order): the numbers of the plain path
        ``track_from_angles(t, *angles(t))`` (numpy's sin, cos, arctan2 at every epoch; the reference the tests
        hold this to) to ~1e-15 rad, by :meth:`_kernel` (no sin or cos per epoch)."""
        t = np.asarray(jd_tdb, dtype=float)
        flat = t.reshape(-1)
        _, psi, dpsi, deps, eps, ra, dec = self._kernel(_Epochs(flat, 0.0, 0.0, flat.size), pole=True)
        return Track(t, *(a.reshape(t.shape) for a in (psi, dpsi, deps, eps, ra, dec)))

    def track_grid(self, jd_start: float, step_days: float, count: int) -> Track:
        """Track on the evenly spaced grid t_j = jd_start + j step_days: the numbers of :meth:`track` at those
        epochs, faster (the nutation by one matrix product per block with a table all blocks share, no cos M at
        all: :meth:`_kernel`)."""
        return Track(*self._kernel(_Epochs(None, jd_start, step_days, count), pole=True))

    def _kernel(self, epochs: _Epochs, pole: bool):
        """(t, ψ, Δψ, Δε, ε, RA, Dec) at the epochs (RA, Dec None without ``pole``), by blocks that stay in cache,
        written in place into one array (its rows), with no sin or cos per epoch:

        * Δψ, Δε: on a grid, one matrix product per block of the harmonics' coefficients rotated to each
          sub-block's start with a table shared by all (:class:`ephem.orbit.harmonic_grid.GridHarmonics`); at any
          epochs from cos M and sin M (a table of 4096 angles and a short Taylor series,
          :func:`ephem.orbit.harmonics.cos_sin_into`) by a power table and one matrix product
          (:class:`ephem.orbit.harmonics.HarmonicSums`);
        * ψ = ψ̇ (t - t0) + Δψ and ε = ε̄0 + Δε, the same operations as :meth:`angles`;
        * the pole: cos and sin of ε, and the rotation by ψ folded into the orbit-to-ICRF matrix, by a Taylor
          series about the block's middle ψ and ε with the terms the block's spread needs
          (:func:`ephem.orbit.harmonics.shift_factors`; the 4096-angle table where a block spreads beyond
          0.01 rad: a fast precession, unsorted epochs, large steps, a large nutation);
        * RA: the block's middle RA_r plus atan u, u = tan(RA - RA_r) from cross and dot products of v's
          equatorial part with v_r's, by its odd Taylor series (:func:`_ra_into`; numpy's arctan2 where the block
          strays too far in RA: near the celestial poles, fast tracks); Dec = arcsin v_z (atan2(v_z, hypot(v_x,
          v_y)) where a block may reach |v_z| > 0.9: near the poles arcsin would amplify v's rounding). With
          numpy's AVX-512 kernels arctan2 and arcsin cost a quarter and a sixth of a numpy.sin, the RA series as
          much as arctan2; on CPUs (or numpy builds) without them arctan2 costs a whole sin, the series a third.
        """
        count = epochs.count
        grid = epochs.given is None
        rows = (5 if grid else 4) + (2 if pole else 0)
        out = np.empty((rows, count))          # one allocation: fresh pages cost more than the arithmetic here
        if grid:
            t, psi, nut, eps = out[0], out[1], out[2:4], out[4]
        else:
            t, psi, nut, eps = epochs.given, out[0], out[1:3], out[3]
        ra, dec = (out[-2], out[-1]) if pole else (None, None)
        series = self.nutation
        sin_coef, cos_coef = series._sin_coef, series._cos_coef
        if grid:
            harmonics = GridHarmonics(float(self.mean_anomaly(epochs.start)), self.mean_motion * epochs.step, count,
                                      series.multiple, sin_coef, cos_coef, cap=_KERNEL_BLOCK)
            block = harmonics.block
            index = np.arange(block, dtype=float)
        else:
            sums = HarmonicSums(series.multiple, sin_coef, cos_coef, count, cap=_KERNEL_BLOCK)
            block = sums.block
        work = np.empty((_KERNEL_ROWS, block))
        rate, t0, eps0 = self.track_rate, self.pole_epoch, self.obliquity
        for start in range(0, count, block):
            checkpoint()
            m = min(block, count - start)
            sl = slice(start, start + m)
            tb, pb, eb = t[sl], psi[sl], eps[sl]
            if grid:
                np.add(index[:m], float(start), out=tb)      # t = jd_start + step j, as np.arange makes it
                tb *= epochs.step
                tb += epochs.start
            if grid:
                harmonics.into(start, m, nut[:, sl])
            else:
                c, s, mb = work[0, :m], work[1, :m], work[2, :m]
                np.subtract(tb, self.orbit_epoch, out=mb)   # M = M0 + n (t - t_orb), as mean_anomaly
                mb *= self.mean_motion
                mb += self.mean_anomaly_at_epoch
                cos_sin_into(mb, c, s, work[3:7, :m])
                sums.into(c, s, nut[:, sl])
            np.subtract(tb, t0, out=pb)                      # ψ = ψ̇ (t - t0) + Δψ, as angles
            pb *= rate
            pb += nut[0, sl]
            np.add(nut[1, sl], eps0, out=eb)                 # ε = ε̄0 + Δε
            if pole:
                self._pole_block(pb, eb, ra[sl], dec[sl], work[:, :m])
        return t, psi, nut[0], nut[1], eps, ra, dec

    def _pole_block(self, psi, eps, ra, dec, work) -> None:
        """RA in [0, 2π) and Dec of the pole at one block's ψ, ε (see :meth:`_kernel`), into ra, dec."""
        ce, se, vx, vy, vz, cd, sd, tmp = work[:8]
        eps_ref, eps_spread = _spread(eps)
        if eps_spread <= MAX_SHIFT:                 # cos ε, sin ε about the middle ε_r
            np.subtract(eps, eps_ref, out=work[8])
            sd = shift_factors(work[8], eps_spread, cd, sd, work[9])
            angle_sum_into(cd, sd, math.cos(eps_ref), math.sin(eps_ref), ce, se, tmp)
        else:
            cos_sin_into(eps, ce, se, work[7:11])
        r = self.icrf_from_orbit
        signs = (-1.0, -1.0, 1.0)                   # v_x, v_y negated: RA = atan2(-v_y, -v_x) + π
        psi_ref, psi_spread = _spread(psi)
        cd, sd = work[5], work[6]
        if psi_spread <= MAX_SHIFT:
            # v = sin ε (sin ψ a + cos ψ b) + cos ε w (a, b, w: the matrix's columns) with ψ = ψ_r + δ:
            # sin ψ a + cos ψ b = cos δ p + sin δ q, p = sin ψ_r a + cos ψ_r b, q = cos ψ_r a - sin ψ_r b
            np.subtract(psi, psi_ref, out=work[8])
            sd = shift_factors(work[8], psi_spread, cd, sd, work[9])
            cr, sr = math.cos(psi_ref), math.sin(psi_ref)
            for v, row, sign in zip((vx, vy, vz), r, signs):
                np.multiply(cd, sign * (sr * row[0] + cr * row[1]), out=v)
                np.multiply(sd, sign * (cr * row[0] - sr * row[1]), out=tmp)
                v += tmp
                v *= se
                np.multiply(ce, sign * row[2], out=tmp)
                v += tmp
        else:
            cos_sin_into(psi, cd, sd, work[7:11])          # cos ψ, sin ψ
            sd *= se                                        # the orbit-frame pole (sin ε sin ψ, sin ε cos ψ, cos ε)
            cd *= se
            for v, row, sign in zip((vx, vy, vz), r, signs):
                np.multiply(sd, sign * row[0], out=v)
                np.multiply(cd, sign * row[1], out=tmp)
                v += tmp
                np.multiply(ce, sign * row[2], out=tmp)
                v += tmp
        # how far v strays from its value v_r at the block's middle epoch: at most the spreads of ψ and ε there
        # (|∂v/∂ψ| = sin ε <= 1, |∂v/∂ε| = 1), plus v's rounding; None where a spread was not measured
        mid = psi.size // 2
        stray = psi_spread + eps_spread + 1e-15 if psi_spread <= MAX_SHIFT and eps_spread <= MAX_SHIFT else None
        _ra_into(vx, vy, mid, stray, ra, cd, work[6], tmp)
        if stray is not None:
            z_bound = abs(float(vz[mid])) + stray
        else:
            z_bound = max(-float(vz.min()), float(vz.max()))
        if z_bound <= _ARCSIN_DEC_LIMIT:
            np.arcsin(vz, out=dec)
        else:
            np.multiply(vx, vx, out=tmp)
            np.multiply(vy, vy, out=cd)
            tmp += cd
            np.sqrt(tmp, out=tmp)
            np.arctan2(vz, tmp, out=dec)

    def track_from_angles(self, t, psi, dpsi, deps, eps) -> Track:
        """The track whose angles (radians) at the epochs ``t`` are given (any theory's ψ, Δψ, Δε, ε in this
        model's orbit frame), with the pole's RA and Dec."""
        ra = np.empty(t.shape)
        dec = np.empty(t.shape)
        se = np.sin(eps)
        self._pole_into(se * np.sin(psi), se * np.cos(psi), np.cos(eps), ra, dec)
        return Track(t, psi, dpsi, deps, eps, ra, dec)

    def _pole_into(self, x, y, z, ra, dec) -> None:
        """RA in [0, 2π) and Dec of the orbit-frame unit vectors (x, y, z), written into ra, dec (the plain path:
        numpy's arctan2 at every epoch)."""
        r = self.icrf_from_orbit
        xi = r[0, 0] * x + r[0, 1] * y + r[0, 2] * z
        yi = r[1, 0] * x + r[1, 1] * y + r[1, 2] * z
        zi = r[2, 0] * x + r[2, 1] * y + r[2, 2] * z
        np.arctan2(yi, xi, out=ra)
        ra += (ra < 0.0) * _TWO_PI
        ra[ra >= _TWO_PI] = 0.0   # -1e-17 + 2π rounds to 2π: RA = 0
        np.arctan2(zi, np.sqrt(xi * xi + yi * yi), out=dec)  # unit vectors: no overflow to guard


def _spread(x: np.ndarray) -> tuple[float, float]:
    """(x_r, the largest |x - x_r|) for a block of angles, x_r its middle element (a track's ψ or ε over consecutive
    epochs stays close to it); the spread is rounded up by 2^-20 of itself (NaN in a block: NaN)."""
    ref = float(x[x.size // 2])
    return ref, max(ref - float(x.min()), float(x.max()) - ref) * (1.0 + 2.0**-20)


def _ra_into(vx, vy, mid: int, stray: float | None, ra, u, u2, tmp) -> None:
    """RA = atan2(-v_y, -v_x) + π in [0, 2π) of a block of pole vectors whose x and y come negated (vx, vy), into
    ``ra``: RA_r at the block's middle vector plus atan u, u = (x_r y - y_r x)/(x_r x + y_r y) = tan(RA - RA_r), by
    the odd series of atan with the terms |u|'s bound needs (an alternating series: what it leaves out is below its
    first omitted term, kept under 2^-57 rad), while |u| <= :data:`_RA_SERIES_LIMIT`; else numpy's arctan2.
    |u| is bounded from ``stray`` (how far the vectors are from the middle one: their equatorial parts then are
    within asin(stray/ρ_r) of its direction, ρ_r its length), or measured when ``stray`` is None. u, u2, tmp: work
    arrays the size of the block."""
    xr, yr = float(vx[mid]), float(vy[mid])
    rho = math.hypot(xr, yr)
    bound = math.inf
    if stray is not None and stray < 0.5 * rho:
        q = stray / rho
        bound = q / math.sqrt(1.0 - q * q)
    if bound <= _RA_SERIES_LIMIT or (stray is None and rho > 0.0):
        np.multiply(vy, xr, out=u)                 # x_r y - y_r x (in the negated coordinates: the same)
        np.multiply(vx, yr, out=tmp)
        u -= tmp
        np.multiply(vx, xr, out=u2)                # x_r x + y_r y
        np.multiply(vy, yr, out=tmp)
        u2 += tmp
        if stray is None:   # measured: every vector on the reference's side (a positive dot product), |u| small
            bound = max(-float(u.min()), float(u.max())) / float(u2.min()) if float(u2.min()) > 0.0 else math.inf
        u /= u2             # (NaN in a block, a non-finite v: the bound is NaN, not <=, and arctan2 takes it)
    if not bound <= _RA_SERIES_LIMIT:
        np.arctan2(vy, vx, out=ra)                 # atan2(-y, -x) in [-π, π]: RA - π
        ra += math.pi
        if float(ra.max()) >= _TWO_PI:             # RA a hair below 2π rounds up to it: that is RA = 0
            ra[ra >= _TWO_PI] = 0.0
        return
    ra_r = math.atan2(yr, xr) + math.pi
    n = bisect.bisect_left(_ATAN_LIMITS, bound) + 1  # atan u = u Σ_{i<n} (-u²)^i/(2i+1)
    np.multiply(u, u, out=u2)
    if n > 1:
        np.multiply(u2, _ATAN_COEF[n - 1], out=ra)
        for i in range(n - 2, 0, -1):
            ra += _ATAN_COEF[i]
            ra *= u2
        ra += 1.0
        ra *= u
    else:
        np.copyto(ra, u)
    ra += ra_r
    reach = math.atan(bound)
    if ra_r - reach < 0.0:                         # the block may cross RA = 0 from above
        ra[ra < 0.0] += _TWO_PI
    if ra_r + reach >= _TWO_PI - 1e-15:           # ... or reach 2π (rounded up from a hair below: RA = 0)
        ra[ra >= _TWO_PI] -= _TWO_PI
    if ra_r - reach < 0.0 and float(ra.max()) >= _TWO_PI:
        ra[ra >= _TWO_PI] = 0.0


@dataclass(frozen=True)
class _Epochs:
    """The epochs of a kernel call: ``given`` (a flat float array), or the grid start + step j, j < count."""

    given: np.ndarray | None
    start: float
    step: float
    count: int


_TWO_PI = 2.0 * math.pi
#: the kernel's RA takes atan's series while a block's |tan(RA - RA_r)| stays below this (4 terms at most)
_RA_SERIES_LIMIT = 0.01
#: for n = 1, 2, …: the largest |u| at which n terms of atan's series leave out less than 2^-57 rad
_ATAN_LIMITS = tuple((2.0**-57 * (2 * n + 1)) ** (1.0 / (2 * n + 1)) for n in range(1, 12))
_ATAN_COEF = tuple((-1.0) ** i / (2 * i + 1) for i in range(12))
#: the kernel's Dec is arcsin v_z while a block's |v_z| stays below this (Dec within ±64°: arcsin's slope
#: 1/sqrt(1 - z²) <= 2.3 turns v's rounding into <= 1e-15 rad); beyond, atan2(v_z, hypot(v_x, v_y))
_ARCSIN_DEC_LIMIT = 0.9
#: rows of the kernel's work table: cos M, sin M, M (or the grid's temporary), cos_sin_into's 4; the pole's 8
#: (cos ε, sin ε, v, cos δψ, sin δψ, a temporary) and the series' 3-4 reuse them after the sums
_KERNEL_ROWS = 11
#: epochs per block of the kernel (on a grid a multiple of the harmonics' sub-block; fewer where the harmonic sums'
#: table would pass BLOCK_BYTES): measured faster than 8192 or 32768 here (numpy's ~1 µs a call against L2)
_KERNEL_BLOCK = 16384


def check_applicable(body: Body, spin_rate: float, mean_motion: float) -> None:
    """Refuse bodies whose rotation is too slow to average the torque over (a synchronous one, as the Moon, is
    served by :mod:`ephem.moon.family` instead)."""
    ratio = spin_rate / mean_motion
    if ratio < MIN_SPIN_ORBIT_RATIO:
        synchronous = abs(ratio - 1.0) < 0.01
        what = "synchronous with its orbit" if synchronous else "slow compared with its orbital motion"
        raise NotApplicableError(
            body.name,
            f"the rotation is {what} (spin rate / orbital mean motion ω/n = {ratio:.4g}); Kinoshita's theory "
            f"averages the torque over the rotation and needs ω/n >= {MIN_SPIN_ORBIT_RATIO:g} (below, its pole "
            f"departs from the full rigid body's by more than 10% of the forced motion)"
            + ("; a synchronous rotator's pole is served by the Cassini-state theory (ephem.moon.family) when its "
               "orbit's centre torques it (the catalogue's perturbers)" if synchronous else ""),
            ratio=ratio, threshold=MIN_SPIN_ORBIT_RATIO)


def check_domain(body: Body, order: int | None = None) -> None:
    """The theory's domain, checked before any work: a fast enough rotation (:func:`check_applicable`)
    and, for exact coefficients, an eccentricity whose Fourier series can be summed."""
    orb = body.orbit
    check_applicable(body, body.spin_rate_rad_per_day, mean_motion_rad_per_day(orb.a_au, orb.center))
    why = exact_unavailable(orb.e) if order is None else None
    if why is not None:
        raise NotApplicableError(body.name, why)


def build_model(body: Body, order: int | None = None) -> PrecessionNutation:
    """Precession-nutation model of ``body``.

    ``order`` None uses exact Hansen coefficients; an integer truncates them
    at that power of e (the paper: 4).
    """
    orb = body.orbit
    n = mean_motion_rad_per_day(orb.a_au, orb.center)
    omega = body.spin_rate_rad_per_day
    check_domain(body, order)
    K = scaling_factor(n, omega, body.hd)

    ecl_from_icrf = icrf_to_ecliptic_matrix()
    s_ecl = ecl_from_icrf @ unit_vector(math.radians(body.pole.ra_deg), math.radians(body.pole.dec_deg))
    i, node, peri = (math.radians(x) for x in (orb.i_deg, orb.node_deg, orb.peri_deg))
    geo = spin_geometry(s_ecl, i, node, peri, body.name)

    t0 = body.pole.epoch_jd_tdb
    m0 = math.radians(orb.mean_anomaly_deg)
    m_t0 = m0 + n * (t0 - orb.epoch_jd_tdb)
    last = {}

    def nutation_at_pole_epoch(eps_trial: float, theta_trial: float) -> tuple[float, float]:
        last["series"] = nutation_series(K, n, eps_trial, orb.e, theta_trial, order)
        dpsi_a, deps_a = last["series"].evaluate(np.array([m_t0]))
        return float(dpsi_a[0]), float(deps_a[0])

    # the series of the last pass reproduces the catalogue pole at t0 exactly (see mean_pole)
    eps_mean, theta_mean, dpsi0, deps0 = mean_pole(geo.obliquity, geo.equinox_to_pericentre, nutation_at_pole_epoch)
    series = last["series"]

    gamma, y_true, w = geo.orbit_frame
    x_mean = math.cos(dpsi0) * gamma + math.sin(dpsi0) * y_true
    frame_ecl = np.vstack([x_mean, np.cross(w, x_mean), w])  # rows in ecliptic
    icrf_from_orbit = ecl_from_icrf.T @ frame_ecl.T

    return PrecessionNutation(
        body=body.name, dataset=body.dataset, hd=body.hd, mean_motion=n, spin_rate=omega,
        eccentricity=orb.e, scaling_factor=K, obliquity=eps_mean, equinox_to_pericentre=theta_mean,
        precession_rate=precession_rate(K, eps_mean, orb.e, order), nutation=series,
        pole_epoch=t0, orbit_epoch=orb.epoch_jd_tdb, mean_anomaly_at_epoch=m0,
        nutation_at_pole_epoch=(dpsi0, deps0), icrf_from_orbit=icrf_from_orbit, order=order,
        geodesic_rate=geodesic_precession_rate(orb.a_au, orb.e, orb.center))


def check_order(order: int | None) -> int | None:
    """``order`` if it is None (exact Hansen coefficients) or an integer in [0, MAX_ORDER]; else
    :class:`InvalidInputError` naming ``order``."""
    if order is None:
        return None
    if isinstance(order, bool) or not isinstance(order, int) or order < 0 or order > MAX_ORDER:
        raise InvalidInputError("order", f"eccentricity order must be an integer in [0, {MAX_ORDER}] or omitted "
                                f"for exact Hansen coefficients, got {order!r}")
    return order


@bytes_bounded
def cached_model(body: Body, order: int | None = None) -> PrecessionNutation:
    """:func:`build_model`, memoised (a pure function of immutable inputs). The bodies are the callers' (a
    service's clients'), and a model's size grows with the eccentricity: the cache is bounded in bytes, shared
    with the other per-body caches (:mod:`ephem.base.memo`), not in entries."""
    return build_model(body, order)


def model_for(body: str | int | Body, dataset: str = DEFAULT_DATASET, order: int | None = None) -> PrecessionNutation:
    """Validated model of a catalogue body (by name or NAIF id) or of a :class:`Body`.

    Parameters
    ----------
    body : str, int or Body
        A catalogue body's name (any case) or NAIF id, or a :class:`~ephem.bodies.catalogue.Body` of the user's own.
    dataset : str
        The catalogue dataset a name or id is looked up in ("current", "petit2014" or one the user imported).
    order : int or None
        The e-power to which the Hansen coefficients are expanded (0 to :data:`MAX_ORDER`); None: the exact
        coefficients. Refused past the Laplace limit (e > 0.6627), where the series diverge.

    Returns
    -------
    PrecessionNutation
        The body's first-order forced precession and nutation: angles in radians, rates in rad/day, times JD TDB
        (kept per body and order: the same object for the same question).
    """
    b = resolve_body(body, dataset)
    order = check_order(order)
    if order is not None and b.orbit.e > LAPLACE_LIMIT:
        raise InvalidInputError(
            "order", f"e = {b.orbit.e} exceeds the Laplace limit {LAPLACE_LIMIT:.4f}: the e-power series "
            "diverge; omit the order to use exact Hansen coefficients", b.name)
    return cached_model(b, order)
