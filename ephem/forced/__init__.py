"""The forced theory of one perturber: Kinoshita's equations and what is built on them.

The precession-nutation model of a body, second order, the numerical reference, the rigid body, the rotation scale,
error bounds and uncertainty; and a synchronous rotator's Cassini state, which any family of synchronous bodies
borrows (the Moon's).

- :mod:`ephem.forced.cassini`: The Cassini state of a synchronous rotator: the mean pole of the Moon (Cassini's laws).
- :mod:`ephem.forced.catalogue_sigmas`: A body's catalogue inputs with their 1-σ: what the forced model reads, in which units, how correlated.
- :mod:`ephem.forced.describe`: The forced model of one perturber in words: the theory, what it assumes, and the warnings a body earns.
- :mod:`ephem.forced.integration`: Numerical reference: the rotation-averaged solar torque integrated along the Keplerian orbit.
- :mod:`ephem.forced.interior_response`: A body's interior applied to its forced nutation: the non-rigid series, and
  what it changes and leaves.
- :mod:`ephem.forced.kinoshita`: Kinoshita's theory of the forced precession and nutation, one perturber on a fixed Keplerian orbit.
- :mod:`ephem.forced.physics_errors`: Error terms from physics the fixed-orbit, rotation-averaged theories leave out.
- :mod:`ephem.forced.pole_uncertainty`: The pole's 1-σ along a track, propagated from the catalogue's 1-σ uncertainties.
- :mod:`ephem.forced.precession_nutation`: Precession-nutation model of one body: geometry + Kinoshita's theory, evaluated over time.
- :mod:`ephem.forced.rigid_body`: Rung 7: the full rigid body, spinning and torqued by the Sun, without rotation averaging.
- :mod:`ephem.forced.rigid_numerics`: Generic numerics of a rigid body's integration: normalised moments, attitude quaternions, ODE helpers.
- :mod:`ephem.forced.rotation_scale`: The rotation-scale terms: what averaging the solar torque over the rotation leaves out, in closed form.
- :mod:`ephem.forced.second_order`: Second order in the torque: the equinox drifts under the precession, and the nutation feeds back.
- :mod:`ephem.forced.uncertainty`: Propagation of the catalogue's 1-sigma uncertainties to the precession and nutation.

The package imports none of its modules: importing one loads only what it needs.
"""
