"""Free rotation: the torque-free rigid body (Andoyer variables, Euler-Poinsot, Deprit's normalisation, the Lie series) and the free wobble added to a forced pole.

- :mod:`ephem.rotation.andoyer`: Andoyer variables of a free rigid body, and the non-singular variables that replace them near J = 0.
- :mod:`ephem.rotation.deprit`: Deprit's triangle: the Lie transform that normalises a Hamiltonian and carries functions through it.
- :mod:`ephem.rotation.euler_poinsot`: The exact torque-free motion of a rigid body (the Euler-Poinsot problem) in Jacobi elliptic functions.
- :mod:`ephem.rotation.free_motion`: The free wobble of a catalogue body: its figure axis about the angular momentum, three ways.
- :mod:`ephem.rotation.lie_series`: Lara's perturbation series for short-axis-mode (SAM) free rotation, by a Lie-transform engine in exact arithmetic.
- :mod:`ephem.rotation.polynomials`: The exact polynomial ring Q(i)[u, U, β] of the Lie-transform engine, with its Poisson bracket.

The package imports none of its modules: importing one loads only what it needs.
"""
