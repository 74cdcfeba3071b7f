"""The single-perturber family: the fidelity ladder of Kinoshita's theory under the orbit's centre.

- :mod:`ephem.sun.ladder`: The fidelity ladder: models of rising cost and accuracy, each with an error estimate; a tolerance picks one.

The package imports none of its modules: importing one loads only what it needs.
"""
