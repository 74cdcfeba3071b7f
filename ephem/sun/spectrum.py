"""The single-perturber track's frequencies for the SPICE kernel writer.

The harmonics of the mean anomaly with the
precession's sidebands (:func:`mean_anomaly_spectrum`), and the half peak-to-peak nutation of a body's series."""
from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

from ..base.constants import J2000_JD, JULIAN_CENTURY_DAYS, MAS
from ..bodies.catalogue import Body
from ..forced.kinoshita import pole_displacements
from ..forced.precession_nutation import PrecessionNutation, cached_model
from ..theory.interface import Spectrum

#: Sidebands ±j ψ̇ a track carries about each harmonic of the mean anomaly (the second-order theory's mixing
#: of the precession into the nutation phases, and the kernel's linear-in-T phases).
TRACK_SIDEBANDS = 3
#: Highest multiple of the mean anomaly in a track's spectrum: beyond the last harmonic of the nutation
#: series that moves the pole by a hundredth of the aim, by HARMONIC_MARGIN (its products with others),
#: at most twice the series' own and MAX_MULTIPLE.
MAX_MULTIPLE = 64
HARMONIC_MARGIN = 4


def mean_anomaly_spectrum(m: PrecessionNutation, aim_mas: float, psi_dot: float) -> Spectrum:
    """Harmonics k = 0..kmax of the mean anomaly (k = 0: the precession alone), with ψ̇ (rad/day)."""
    series = m.nutation
    kmax_series = int(series.multiple.max()) if series.multiple.size else 1
    amp = pole_displacements(series, m.obliquity)
    big = series.multiple[amp > 0.01 * aim_mas * MAS]
    kmax = int(min(MAX_MULTIPLE, 2 * kmax_series, (int(big.max()) if big.size else 1) + HARMONIC_MARGIN))
    ks = np.arange(0, kmax + 1)
    amplitude = np.zeros(ks.size)
    for k, a in zip(series.multiple, amp):
        if k <= kmax:
            amplitude[int(k)] = a
    m_j2000 = float(m.mean_anomaly(J2000_JD))
    return Spectrum(tuple(int(k) for k in ks), np.degrees(ks * m_j2000) % 360.0,
                    np.degrees(ks * m.mean_motion) * JULIAN_CENTURY_DAYS, amplitude,
                    math.degrees(psi_dot * (J2000_JD - m.pole_epoch)) % 360.0,
                    math.degrees(psi_dot) * JULIAN_CENTURY_DAYS, TRACK_SIDEBANDS, "k: multiple of the mean anomaly")


@lru_cache(maxsize=512)
def semi_amplitudes(body: Body, order: int | None) -> tuple[float, float]:
    """Half the peak-to-peak Δψ, Δε (radians) of the body's nutation series (Petit et al. Table 4)."""
    return cached_model(body, order).nutation.semi_peak_to_peak()
