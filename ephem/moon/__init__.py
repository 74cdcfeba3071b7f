"""The Moon's family (and synchronous rotators): the Cassini state, the physical librations and the rigid integration.

- :mod:`ephem.moon.costs`: What the Moon's family (a synchronous rotator) will cost before it runs: its predictors, with its own unit costs.
- :mod:`ephem.moon.family`: The Moon's family behind the common interface: its models' estimates, results, history and spectrum.
- :mod:`ephem.moon.kernel_rung`: The ``de421`` model of the Moon's family: JPL's DE421 lunar orientation itself, inside
  its span.
- :mod:`ephem.moon.libration_frames`: The Moon's frames in small rotations: the general precession that turns the frame of date, [v×] and exp([θ×]).
- :mod:`ephem.moon.libration_forcing`: The torque on the Moon's turning reference frame, over the torus of the Delaunay arguments.
- :mod:`ephem.moon.libration_angles`: The Moon's libration angles: the Cassini state's turning frame R, and Eckhardt's ρ, σ, τ from the rotation θ.
- :mod:`ephem.moon.libration_chains`: The Moon's physical librations solved linearly, chain by chain: the harmonic balance on the torus of the arguments.
- :mod:`ephem.moon.libration_modes`: The Moon's free librations about its Cassini state: the periods of the linearised system's free modes.
- :mod:`ephem.moon.libration_series`: The Moon's physical librations as a series: its terms, their evaluation, and the shipped series on disk.
- :mod:`ephem.moon.lunar_kernel`: JPL's DE421 lunar orientation, read where the install put it: its Euler angles and
  frame kernel.
- :mod:`ephem.moon.model`: A synchronous rotator's pole from its Cassini state: the model the family serves, and its integrated track.
- :mod:`ephem.moon.orientation`: The Moon's orientation beyond the rigid libration theory: what lunar laser ranging
  observes.
- :mod:`ephem.moon.physical_librations`: The Moon's forced physical librations about its Cassini state: the pole and the prime meridian.
- :mod:`ephem.moon.results`: The Moon family's own result: the Cassini state its theory derives, beside the precession answer's values.
- :mod:`ephem.moon.rigid_integration`: The full rigid synchronous satellite, integrated: the independent check of the Cassini-state theory.

The Cassini state itself is :mod:`ephem.forced.cassini` (issue 43): the physics of any synchronous rotator, below the
families, so that another family (a binary asteroid's secondary) borrows it without importing the Moon's.

The package imports none of its modules: importing one loads only what it needs.
"""
