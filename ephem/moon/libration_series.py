"""The Moon's physical librations as a series: its terms, their evaluation, and the shipped series on disk.

:class:`PhysicalLibrations` holds what :func:`ephem.moon.physical_librations.moon_physical_librations` solves (ρ,
σ, τ and the small rotation θ as series in the Delaunay arguments; the frames and angles of that module's
docstring) and evaluates it: angles, rates, Euler angles, attitude, angular velocity, the pole. The shipped
series (``data/moon_librations``, written by tools/derive_moon_librations.py) are read here, so a request needs
no build. Radians and days; JD TDB.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np

from ..base.constants import JULIAN_CENTURY_DAYS
from ..base.paths import data_dir
from ..orbit.lunar import delaunay_arguments, delaunay_rates
from .libration_frames import GENERAL_PRECESSION_RATE, rodrigues


def canonical_sign(k: np.ndarray) -> np.ndarray:
    """+1 or −1 per row of multipliers (n, 5): the sign that makes the first non-zero of (Ω, D, F, l, l') positive
    (the convention of :mod:`ephem.earth.lunisolar`); +1 for the zero row."""
    sign = np.zeros(k.shape[0], dtype=int)
    for i in (4, 3, 2, 0, 1):
        undecided = sign == 0
        sign[undecided] = np.sign(k[undecided, i])
    sign[sign == 0] = 1
    return sign


def pole_amplitude(rho: np.ndarray, sigma: np.ndarray) -> np.ndarray:
    """The largest displacement of the pole over a term's phase: the spectral norm of [[ρc, ρs], [σc, σs]]."""
    a, b, c, d = rho[:, 0], rho[:, 1], sigma[:, 0], sigma[:, 1]
    s = a * a + b * b + c * c + d * d
    det = a * d - b * c
    return np.sqrt(0.5 * (s + np.sqrt(np.maximum(s * s - 4.0 * det * det, 0.0))))


@dataclass(frozen=True, eq=False)
class LibrationTerm:
    """One term of the forced physical librations: ρ, σ, τ = Σ c cos φ + s sin φ, φ = k · (l, l', F, D, Ω).

    Angles in radians; ``rho``, ``sigma``, ``tau`` are (cos, sin) pairs. ``pole_amplitude`` is the largest
    displacement of the pole over the term's phase (rad), ``tau_amplitude`` that of τ."""

    multipliers: tuple
    frequency: float          # rad/day, k · (dl/dt, dl'/dt, dF/dt, dD/dt, dΩ/dt) at J2000
    period_days: float        # 2π / |frequency|
    rho: tuple
    sigma: tuple
    tau: tuple
    pole_amplitude: float
    tau_amplitude: float

    @property
    def argument(self) -> str:
        """The argument as text, e.g. "l - 2F"."""
        parts = []
        for m, name in zip(self.multipliers, ("l", "l'", "F", "D", "Ω")):
            if m:
                coef = "" if abs(m) == 1 else str(abs(m))
                parts.append(("-" if m < 0 else "+") + " " + coef + name)
        text = " ".join(parts)
        return text[2:] if text.startswith("+ ") else "-" + text[2:]


@dataclass(frozen=True, eq=False)
class PhysicalLibrations:
    """The Moon's forced physical librations about its Cassini state (module docstring): a series in the Delaunay
    arguments, radians and days.

    ρ: the lunar equator's inclination to the ecliptic minus I; σ: sin I times its node's longitude minus Ω (the
    pole's displacement across the meridian, toward increasing longitude); τ: the libration in longitude (the
    prime meridian ahead of its mean). The pole is at colatitude I + ρ, ecliptic longitude Ω + 90° + σ / sin I
    (Meeus 1998 ch. 53). ``multipliers`` (n, 5) of (l, l', F, D, Ω); ``rho``, ``sigma``, ``tau`` (n, 2) cos and
    sin coefficients; ``constant`` the constant (ρ, σ, τ) (ρ's is zero by construction: I is its mean)."""

    multipliers: np.ndarray
    rho: np.ndarray
    sigma: np.ndarray
    tau: np.ndarray
    constant: np.ndarray
    equator_inclination: float            # I (rad): the mean pole's colatitude, solved with the series
    moments: tuple
    sun: bool
    grid: tuple
    model: str                            # "constant", "linear" or "full" (module docstring, "Solution")
    steps: int                            # fixed-point steps taken
    rotation: tuple = field(default=None, repr=False)   # θ's series: (multipliers, cos (n, 3), sin (n, 3), constant)
    offset: tuple | None = None           # the constant θ imposed (rad), or None

    @property
    def frequencies(self) -> np.ndarray:
        """rad/day at J2000."""
        return self.multipliers @ delaunay_rates(0.0)

    @property
    def pole_amplitudes(self) -> np.ndarray:
        return pole_amplitude(self.rho, self.sigma)

    @property
    def tau_amplitudes(self) -> np.ndarray:
        return np.hypot(self.tau[:, 0], self.tau[:, 1])

    def __len__(self) -> int:
        return self.multipliers.shape[0]

    def term(self, multipliers) -> LibrationTerm:
        """The term of these multipliers (either sign), or a zero term."""
        k = np.asarray(multipliers, dtype=int).reshape(1, 5)
        sign = int(canonical_sign(k)[0])
        k = k * sign
        hit = np.nonzero(np.all(self.multipliers == k, axis=1))[0]
        freq = float(k[0] @ delaunay_rates(0.0))
        if hit.size == 0:
            zero = (0.0, 0.0)
            return LibrationTerm(tuple(int(x) for x in k[0]), freq, 2 * math.pi / abs(freq) if freq else math.inf,
                                 zero, zero, zero, 0.0, 0.0)
        i = int(hit[0])
        # a caller's multipliers of the other sign: sin(−φ) = −sin φ
        pair = lambda a: (float(a[i, 0]), float(a[i, 1]) * sign)  # noqa: E731
        return LibrationTerm(tuple(int(x) for x in k[0] * sign), freq * sign,
                             2 * math.pi / abs(freq) if freq else math.inf, pair(self.rho), pair(self.sigma),
                             pair(self.tau), float(self.pole_amplitudes[i]), float(self.tau_amplitudes[i]))

    def table(self, cut: float = 0.0) -> list[LibrationTerm]:
        """The terms whose pole or τ amplitude exceeds ``cut`` (rad), largest first."""
        amp = np.maximum(self.pole_amplitudes, self.tau_amplitudes)
        order = np.argsort(-amp, kind="stable")
        return [self.term(self.multipliers[i]) for i in order if amp[i] > cut]

    def truncated(self, cut: float) -> "PhysicalLibrations":
        """The series without the terms whose pole and τ amplitudes are both at most ``cut`` (rad)."""
        keep = np.maximum(self.pole_amplitudes, self.tau_amplitudes) > cut
        return PhysicalLibrations(self.multipliers[keep], self.rho[keep], self.sigma[keep], self.tau[keep],
                                  self.constant, self.equator_inclination, self.moments, self.sun, self.grid,
                                  self.model, self.steps, self.rotation, self.offset)

    def omitted_bound(self, cut: float) -> tuple[float, float]:
        """(pole, τ), rad: the most the terms at or below ``cut`` can move the pole and τ (the sums of their
        amplitudes: the triangle inequality). Only the series' own truncation: the theory's error is apart."""
        pole, tau = self.pole_amplitudes, self.tau_amplitudes
        small = np.maximum(pole, tau) <= cut
        return float(pole[small].sum()), float(tau[small].sum())

    def _phases(self, jd_tdb) -> tuple[np.ndarray, np.ndarray, tuple]:
        jd = np.asarray(jd_tdb, dtype=float)
        args = delaunay_arguments(jd).reshape(-1, 5)
        phase = args @ self.multipliers.T.astype(float)
        return np.cos(phase), np.sin(phase), jd.shape

    def angles(self, jd_tdb) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """ρ, σ, τ (rad) at JD TDB (any shape)."""
        c, s, shape = self._phases(jd_tdb)
        out = [(c @ a[:, 0] + s @ a[:, 1] + k0).reshape(shape)
               for a, k0 in zip((self.rho, self.sigma, self.tau), self.constant)]
        return out[0], out[1], out[2]

    def rates(self, jd_tdb) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """dρ/dt, dσ/dt, dτ/dt (rad/day) at JD TDB: the series differentiated term by term."""
        c, s, shape = self._phases(jd_tdb)
        nu = self.frequencies
        out = [((s @ (-nu * a[:, 0]) + c @ (nu * a[:, 1]))).reshape(shape) for a in (self.rho, self.sigma, self.tau)]
        return out[0], out[1], out[2]

    def rotation_vector(self, jd_tdb) -> tuple[np.ndarray, np.ndarray]:
        """θ and dθ/dt (..., 3): the small rotation (rad, rad/day, in the reference frame's axes) taking the frame
        R of :func:`reference_frame` to the principal axes, B = R exp([θ×]): the variable the equations solve
        for (the Euler angles are exact functions of it)."""
        k, c, s, const = self.rotation
        jd = np.asarray(jd_tdb, dtype=float)
        phase = delaunay_arguments(jd).reshape(-1, 5) @ k.T.astype(float)
        cp, sp = np.cos(phase), np.sin(phase)
        nu = k @ delaunay_rates(0.0)
        theta = cp @ c + sp @ s + const
        dtheta = sp @ (-nu[:, None] * c) + cp @ (nu[:, None] * s)
        return theta.reshape(jd.shape + (3,)), dtheta.reshape(jd.shape + (3,))

    def euler_angles(self, jd_tdb, node=None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The principal axes' 3-1-3 Euler angles (φ, θ, ψ) from the mean ecliptic and equinox of date (rad), B =
        Rz(φ) Rx(θ) Rz(ψ): φ = Ω + π + σ / sin I (the equator's ascending node), θ = I + ρ, ψ = F + τ − σ / sin I
        (the long axis from that node along the equator). Ω, F: IERS Conventions (2010) eq. 5.43; ``node``
        replaces Ω."""
        jd = np.asarray(jd_tdb, dtype=float)
        rho, sigma, tau = self.angles(jd)
        args = delaunay_arguments(jd)
        om = args[..., 4] if node is None else np.asarray(node, dtype=float)
        dphi = sigma / math.sin(self.equator_inclination)
        return om + math.pi + dphi, self.equator_inclination + rho, args[..., 2] + tau - dphi

    def attitude(self, jd_tdb, node=None, mean_frame: bool = False) -> np.ndarray:
        """The principal axes (columns a, b, c: a toward the mean Earth, c the pole) in the mean ecliptic and
        equinox of date, (..., 3, 3): Rz(φ) Rx(θ) Rz(ψ) of :meth:`euler_angles`. ``mean_frame``: the axes of the
        mean-Earth/rotation frame instead, the principal axes turned back by the ``offset`` (B exp(−[θ_off×]));
        the same without an offset."""
        phi, theta, psi = self.euler_angles(jd_tdb, node)
        cp, sp, ct, st, cs, ss = np.cos(phi), np.sin(phi), np.cos(theta), np.sin(theta), np.cos(psi), np.sin(psi)
        axes = np.stack([
            np.stack([cp * cs - sp * ct * ss, -cp * ss - sp * ct * cs, sp * st], axis=-1),
            np.stack([sp * cs + cp * ct * ss, -sp * ss + cp * ct * cs, -cp * st], axis=-1),
            np.stack([st * ss, st * cs, ct], axis=-1)], axis=-2)
        if mean_frame and self.offset is not None:
            q, _ = rodrigues(np.asarray(self.offset, dtype=float))
            axes = axes @ q.T
        return axes

    def angular_velocity(self, jd_tdb, inertial: bool = True) -> np.ndarray:
        """The Moon's angular velocity in its principal axes (..., 3), rad/day, from the Euler angles' rates:
        (φ̇ sin θ sin ψ + θ̇ cos ψ, φ̇ sin θ cos ψ − θ̇ sin ψ, φ̇ cos θ + ψ̇). ``inertial``: relative to space (the
        frame of date turns at −p_A about the ecliptic pole: φ̇ − p_A); else relative to the frame of date."""
        jd = np.asarray(jd_tdb, dtype=float)
        phi, theta, psi = self.euler_angles(jd)
        drho, dsigma, dtau = self.rates(jd)
        t = (jd - 2451545.0) / JULIAN_CENTURY_DAYS
        rates = np.moveaxis(np.array([delaunay_rates(float(x)) for x in np.ravel(t)]).reshape(np.shape(t) + (5,)),
                            -1, 0)
        dd = dsigma / math.sin(self.equator_inclination)
        dphi = rates[4] + dd - (GENERAL_PRECESSION_RATE if inertial else 0.0)
        dpsi = rates[2] + dtau - dd
        st = np.sin(theta)
        return np.stack([dphi * st * np.sin(psi) + drho * np.cos(psi), dphi * st * np.cos(psi) - drho * np.sin(psi),
                         dphi * np.cos(theta) + dpsi], axis=-1)

    def pole(self, jd_tdb, node=None, mean_frame: bool = False) -> np.ndarray:
        """The lunar pole (the principal axis of largest moment), unit vectors (..., 3) in the mean ecliptic and
        equinox of date: colatitude I + ρ, longitude Ω + 90° + σ / sin I (exactly: Eckhardt's and Meeus's
        definitions). ``node``: Ω (rad) at the epochs; by default the Delaunay Ω of IERS Conventions (2010) eq.
        5.43. ``mean_frame``: the mean-Earth/rotation frame's pole (:meth:`attitude`)."""
        if mean_frame and self.offset is not None:
            return self.attitude(jd_tdb, node, mean_frame=True)[..., :, 2]
        phi, theta, _ = self.euler_angles(jd_tdb, node)
        lon = phi - 0.5 * math.pi
        return np.stack([np.sin(theta) * np.cos(lon), np.sin(theta) * np.sin(lon), np.cos(theta)], axis=-1)

    def pole_offset(self, jd_tdb, node=None, mean_frame: bool = False) -> np.ndarray:
        """The pole minus the Cassini pole (colatitude I, longitude Ω + 90°), (..., 3): small angles (rad) in the
        mean ecliptic and equinox of date, to first order ρ along the meridian away from the ecliptic pole plus σ
        across it toward increasing longitude. ``mean_frame``: of the mean-Earth/rotation frame's pole."""
        if node is None:
            node = delaunay_arguments(np.asarray(jd_tdb, dtype=float))[..., 4]
        I = self.equator_inclination
        lon = np.asarray(node, dtype=float) + 0.5 * math.pi
        mean = np.stack([math.sin(I) * np.cos(lon), math.sin(I) * np.sin(lon), np.full(np.shape(lon), math.cos(I))],
                        axis=-1)
        return self.pole(jd_tdb, node, mean_frame) - mean


# ----------------------------------------------------------------------------- the shipped series (data)

#: the shipped series (tools/derive_moon_librations.py writes them): one CSV per moment set, so a request needs no
#: 2-second build
SHIPPED_DIR = "moon_librations"
_COLUMNS = ("l", "lp", "F", "D", "Omega", "rho_cos", "rho_sin", "sigma_cos", "sigma_sin", "tau_cos", "tau_sin")


def write_series_csv(series: PhysicalLibrations, path) -> None:
    """Write ``series`` (its ρ, σ, τ terms, constants, I and the build's settings; radians, exact reprs) to a CSV
    that :func:`read_series_csv` reads back (θ's own series, :meth:`PhysicalLibrations.rotation_vector`'s, is not
    written)."""
    lines = [f"# the Moon's forced physical librations (ephem.moon.physical_librations, model {series.model}): ρ, σ, τ "
             "in radians, cos and sin of the multipliers · (l, l', F, D, Ω); tools/derive_moon_librations.py",
             "# moments = " + ", ".join(repr(float(x)) for x in series.moments),
             f"# equator_inclination_rad = {float(series.equator_inclination)!r}",
             "# constant = " + ", ".join(repr(float(x)) for x in series.constant),
             f"# sun = {series.sun}; grid = {', '.join(str(g) for g in series.grid)}; steps = {series.steps}",
             ",".join(_COLUMNS)]
    for k, r, s, t in zip(series.multipliers, series.rho, series.sigma, series.tau):
        lines.append(",".join([str(int(x)) for x in k] + [repr(float(x)) for x in (*r, *s, *t)]))
    with open(path, "w", encoding="utf-8") as fh:
        fh.write("\n".join(lines) + "\n")


def read_series_csv(path) -> PhysicalLibrations:
    """A series written by :func:`write_series_csv`."""
    header = {}
    with open(path, encoding="utf-8") as fh:
        text = fh.read().splitlines()
    for line in text:
        if line.startswith("# ") and " = " in line:
            for part in line[2:].split("; "):
                key, value = part.split(" = ", 1)
                header[key.strip()] = value
    rows = np.array([[float(x) for x in line.split(",")] for line in text if line and line[0] in "-0123456789"])
    k = rows[:, :5].astype(int)
    return PhysicalLibrations(k, rows[:, 5:7], rows[:, 7:9], rows[:, 9:11],
                              np.array([float(x) for x in header["constant"].split(",")]),
                              float(header["equator_inclination_rad"]),
                              tuple(float(x) for x in header["moments"].split(",")), header["sun"] == "True",
                              tuple(int(x) for x in header["grid"].split(",")), "full", int(header["steps"]))


@lru_cache(maxsize=1)
def _shipped() -> dict:
    out = {}
    for path in sorted((data_dir() / SHIPPED_DIR).glob("*.csv")):
        series = read_series_csv(path)
        out[series.moments] = series
    return out


def shipped_series(moments) -> PhysicalLibrations | None:
    """The shipped series (the default model, grid and Sun) of these moments (A, B, C), or None."""
    return _shipped().get(tuple(float(x) for x in moments))
