"""Free rotation: the torque-free rigid body, and the free wobble added to a forced pole.

The torque-free body in Andoyer variables, by Euler-Poinsot, Deprit's normalisation and the Lie series.

- :mod:`ephem.rotation.andoyer`: Andoyer variables of a free rigid body: the conventions, rotations, Hamiltonians, attitude <-> Andoyer.
- :mod:`ephem.rotation.deprit`: Deprit's triangle: the Lie transform that normalises a Hamiltonian and carries functions through it.
- :mod:`ephem.rotation.euler_poinsot`: The exact torque-free motion of a rigid body (the Euler-Poinsot problem) in Jacobi elliptic functions.
- :mod:`ephem.rotation.elliptic_solution`: The elliptic-function solution of the Euler-Poinsot problem in its core frame: the Jacobi functions, the integrals, the constants, the separatrix.
- :mod:`ephem.rotation.free_periods`: The free rigid body's periods and Sadov's action-angle variables, from the exact solution.
- :mod:`ephem.rotation.free_motion`: The free wobble of a catalogue body: its figure axis about the angular momentum, three ways.
- :mod:`ephem.rotation.lie_series`: Lara's perturbation series for short-axis-mode (SAM) free rotation, by a Lie-transform engine in exact arithmetic.
- :mod:`ephem.rotation.sam_series`: Lara's short-axis-mode series evaluated for a body: the torque-free motion from the generated series.
- :mod:`ephem.rotation.poincare`: The non-singular (Poincaré-type and complex) variables that replace Andoyer's near J = 0, and the main problem's action-angle variables.
- :mod:`ephem.rotation.polynomials`: The exact polynomial ring Q(i)[u, U, β] of the Lie-transform engine, with its Poisson bracket.

The package imports none of its modules: importing one loads only what it needs.
"""
