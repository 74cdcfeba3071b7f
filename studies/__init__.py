"""Studies of the library: the scripts behind the committed charts and the tables of docs/*.md.

They are not the library. ``ephem`` and ``service`` never import this package (tests/house/test_studies_outside_library.py
checks it), and the wheel does not ship it (pyproject.toml packages only ``ephem`` and ``service``): the studies
run from a checkout, from the project root, each as a module:

* ``python -m studies.accuracy [--out DIR] [--quick]``: the fidelity ladder's speed-against-accuracy charts
  (docs/accuracy.md);
* ``python -m studies.free_motion [--out DIR] [--quick]``: the torque-free solutions' charts (docs/free_motion.md);
* ``python -m studies.rigid_body``: rung 5 against the full rigid body as ω/n falls, and rung 7's cost
  (the tables of docs/rigid_body_study.md);
* ``python -m studies.rotation_scale [--out DIR] [--quick]``: the rotation-scale terms' error estimate against
  the full rigid body over a generated population (docs/accuracy.md);
* ``python -m studies.estimate_ratios [--out DIR] [--quick]``: estimate over true error per rung and term
  (docs/accuracy.md);
* ``python -m studies.rung_choice [--out DIR] [--label NAME]``: which model each tolerance picks and what it
  costs, for a before/after comparison (docs/accuracy.md);
* ``python -m studies.moon``: the Moon's pole per model against the IAU WGCCRE model (docs/moon.md);
* ``python -m studies.earth_nutation_residual [PREFIX]``: the Earth's nutation minus IAU 2000A, rigid and
  times the IERS 1996 transfer function (the chart of docs/earth.md);
* ``python -m studies.mars_core_chart [--prefix P]``: Mars' non-rigid rung against the rigid one and the IAU
  WGCCRE 2015 pole, and its cost (the chart of docs/interiors.md).
"""
