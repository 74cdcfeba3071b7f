"""The single-perturber family: the fidelity ladder of Kinoshita's theory under the orbit's centre.

- :mod:`ephem.sun.bounds`: the span-aware error bounds of the analytic rungs over given epochs, and the per-body
  tables over one orbit they read (with the truncation bound of an e-order).
- :mod:`ephem.sun.rungs`: the rungs, one record each (text, assumptions, price, track, error terms), cheapest first;
  the numerical rungs' error and reach, and the real orbit's (rung 6).
- :mod:`ephem.sun.ladder`: the ladder of one body: estimates, choice by tolerance, price and tracks.
- :mod:`ephem.sun.family`: the ladder behind the common interface of the theories (:class:`SunLadder`).
- :mod:`ephem.sun.geodesic`: What the analytic rungs leave of the geodesic (de Sitter) precession: the ladder's
  ``geodesic`` error term.
- :mod:`ephem.sun.spectrum`: the track's frequencies for the SPICE kernel writer.

The package imports none of its modules: importing one loads only what it needs.
"""
