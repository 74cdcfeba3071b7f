"""The constants of JPL's DE421 header: the astronomical unit, the speed of light and the GMs.

Folkner, Williams & Boggs 2009, IPN Progress Report 42-178: its
astronomical unit, the speed of light and the GMs of the Sun, the planetary systems, the Earth and the Moon, in
IAU au^3/day^2. Apart from :mod:`ephem.orbit.de421` (the ephemeris itself) so that the analytic Moon and Sun
(:mod:`ephem.orbit.lunar`) and the orbit histories take the numbers without the kernel's machinery."""
from __future__ import annotations

from ..base.constants import AU_M, DAY_S

#: DE421 astronomical unit, km (DE421 header), and the ratio to the IAU 2012 au.
AU_DE421_KM = 149_597_870.699_626_2
DE_AU = AU_DE421_KM * 1e3 / AU_M
#: Speed of light, au/day.
C_AU_PER_DAY = 299_792_458.0 * DAY_S / AU_M
#: DE421 Earth/Moon mass ratio (header constant EMRAT).
EMRAT = 81.300_569_069_915_3

#: GM of the Sun and of the perturbers (NAIF id: GM), DE421 header constants
#: GM1..GM9, GMB and EMRAT in au_DE421^3/day^2 (Folkner et al. 2009), converted to
#: IAU au^3/day^2. Pluto's is DE405's (its pull on an asteroid is ~1e-13 of the
#: Sun's). The Sun's is k^2 (Gaussian constant): DE421's GMS, and the value MPC
#: and JPL elements are computed with (the IAU 2015 nominal GM_SUN differs by
#: 3e-11). Barycentres 1, 2, 4-9 carry the planet plus its satellites. Nothing
#: here resolves these values from DE405's: the Mars check gives 6.2e-7 au with
#: either set after a century.
GM_SUN_DE421 = 0.01720209895**2 / DE_AU**3
GMB = 0.899_701_152_970_881_167e-9
GM_DE421 = {k: v / DE_AU**3 for k, v in {
    1: 0.491_254_745_145_081_187e-10,    # Mercury
    2: 0.724_345_233_302_178_764e-9,     # Venus
    399: GMB * EMRAT / (1.0 + EMRAT),  # Earth
    301: GMB / (1.0 + EMRAT),          # Moon
    4: 0.954_954_891_857_520_080e-10,    # Mars system
    5: 0.282_534_585_557_186_464e-6,     # Jupiter system
    6: 0.845_972_727_826_697_794e-7,     # Saturn system
    7: 0.129_202_491_678_196_939e-7,     # Uranus system
    8: 0.152_435_890_078_427_628e-7,     # Neptune system
    9: 0.218_869_976_542_596_968e-11,    # Pluto system (DE405 value; negligible here)
}.items()}
PERTURBERS = tuple(GM_DE421)
