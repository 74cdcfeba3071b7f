"""The answers: one request each (checks, charges, computes through the family) rendered with units in the keys.

- :mod:`ephem.answers.requests`: The library's public answers: plain dicts with the contract's keys and units.

The package imports none of its modules: importing one loads only what it needs.
"""
