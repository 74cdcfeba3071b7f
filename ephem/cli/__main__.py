"""``python -m ephem.cli``: what the ``ephem`` script runs."""
from . import main

main()
