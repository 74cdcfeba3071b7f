"""Exports: what the answers computed, written out as nutation tables, figures and SPICE text kernels.

The package renders what it is given (a nutation answer, a track's arrays, the track function the kernel fit
samples) and asks the answers nothing itself; the requests that feed it are :mod:`ephem.answers.figures` and
:mod:`ephem.answers.kernels`.

- :mod:`ephem.exports.pck_fit`: Fitting a NAIF text PCK to the spin-axis track: the IAU orientation tables, the kernel's evaluation, the greedy choice of angles.
- :mod:`ephem.exports.pck_kernel`: A NAIF text PCK as SPICE reads it: the records of a kernel (BodyFit, PckResult), its frames, its pole evaluated as SPICE does.
- :mod:`ephem.exports.pck_text`: The text of a NAIF text PCK (``KPL/PCK``): the comment block that says what was fitted and how well, and each body's data block.
- :mod:`ephem.exports.plot_drawing`: How each kind of plot is drawn on a matplotlib figure: axes' units and scales, panels, titles.
- :mod:`ephem.exports.qtable`: Answers as astropy tables: the one builder of the ``QTable`` a notebook gets and of the ECSV the service and the CLI write.
- :mod:`ephem.exports.tables`: Nutation tables in the layouts of Petit, Souchay & Lhotka (2014), as CSV, Markdown, LaTeX or JSON.
- :mod:`ephem.exports.work_precision`: The work-precision chart of a request: every model's estimated error against its predicted cost, with hover titles in SVG.

The package imports none of its modules: importing one loads only what it needs.
"""
