"""The long term: orbit histories over millions of years, and the spin integrated along them.

The secular and N-body orbit histories, the averaged spin integrated along them, a body's history, and the long-term
model added to every family.

- :mod:`ephem.longterm.averaged_spin`: The spin axis over millennia and millions of years: the averaged spin equation along a moving orbit.
- :mod:`ephem.longterm.cubic_spline`: Not-a-knot cubic splines on numpy alone: the orbit histories' interpolant, as scipy's ``CubicSpline`` builds it.
- :mod:`ephem.longterm.history`: The spin axis over millennia and millions of years: a body's history, through its own theory.
- :mod:`ephem.longterm.nbody_orbit`: Long-term orbit-plane histories (millions of years) from an N-body integration with REBOUND (WHFast).
- :mod:`ephem.longterm.orbit_selection`: How a history's orbit model was chosen (issue 39): every model as the choice saw it, the rule and the reason.
- :mod:`ephem.longterm.secular_orbit`: The orbits over long spans by Laplace–Lagrange secular theory: the planets' orbit planes and eccentricities,
- :mod:`ephem.longterm.with_long_term`: The ladder across spans: every family's models, and the long-term model beyond them.

The package imports none of its modules: importing one loads only what it needs.
"""
