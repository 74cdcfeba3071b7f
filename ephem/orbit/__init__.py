"""The orbit and its geometry, shared by every family.

Kepler's equation, frames, Hansen coefficients, harmonic sums, relativity, the DE421 ephemeris and the analytic Moon
and Sun (the Delaunay arguments).

- :mod:`ephem.orbit.de421`: The Sun's position seen from a body, from the JPL ephemeris DE421 (offline).
- :mod:`ephem.orbit.de421_header`: The constants of DE421's header: its au, the speed of light, the GMs of the Sun, the planets and the Moon.
- :mod:`ephem.orbit.geometry`: Spin-pole and orbit geometry: obliquity, the body's equinox, the angle to pericentre.
- :mod:`ephem.orbit.hansen`: Hansen (Cayley) coefficients of the three functions that drive the nutation.
- :mod:`ephem.orbit.harmonic_grid`: Harmonic sums on an even grid with no sin or cos per point: the tracks' and the
  grids' engine.
- :mod:`ephem.orbit.harmonics`: Harmonic sums Σ_k S_k sin kx + C_k cos kx, k = 1..K, at many angles x: the engine the theories' series run on.
- :mod:`ephem.orbit.kepler`: Two-body orbit: Kepler's equation, anomalies and the orbit's orientation.
- :mod:`ephem.orbit.lunar`: The analytic Moon and Sun seen from the Earth, in the Delaunay arguments: shared by the Earth and the Moon.
- :mod:`ephem.orbit.relativity`: The geodesic (de Sitter) precession: the relativistic turning of a spinning body's axis as it orbits a mass.

The package imports none of its modules: importing one loads only what it needs.
"""
