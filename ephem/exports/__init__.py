"""Exports: nutation tables, plots and SPICE text kernels.

- :mod:`ephem.exports.pck`: NAIF SPICE text PCK kernels (``KPL/PCK``) fitted to the spin-axis track.
- :mod:`ephem.exports.pck_fit`: Fitting a NAIF text PCK to the spin-axis track (:mod:`ephem.exports.pck` describes the kernel and the fit):
- :mod:`ephem.exports.pck_kernel`: A NAIF text PCK as SPICE reads it: the records of a kernel (BodyFit, PckResult), its frames, its pole evaluated as SPICE does.
- :mod:`ephem.exports.pck_text`: The text of a NAIF text PCK (``KPL/PCK``): the comment block that says what was fitted and how well,
- :mod:`ephem.exports.plot_drawing`: How each kind of plot is drawn on a matplotlib figure: axes' units and scales, panels, titles.
- :mod:`ephem.exports.plots`: Publication-quality plots of spin-axis tracks and of the free wobble (matplotlib, PNG and SVG).
- :mod:`ephem.exports.tables`: Nutation tables in the layouts of Petit, Souchay & Lhotka (2014), as CSV, Markdown, LaTeX or JSON.

The package imports none of its modules: importing one loads only what it needs.
"""
