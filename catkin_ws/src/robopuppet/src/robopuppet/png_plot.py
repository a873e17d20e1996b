"""Figures written as PNG files with matplotlib's Agg backend (no display needed).

matplotlib is imported when the first figure is made (pyplot()), so that a command that plots
nothing starts sooner.
"""
DPI = 80


def pyplot():
    """Return matplotlib.pyplot on the Agg backend."""
    import matplotlib  # pylint: disable=import-outside-toplevel  (see the module docstring)
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt  # pylint: disable=import-outside-toplevel
    return plt


def write_png(path, figure):
    """Write a figure to path as a PNG at DPI and close it, also when writing fails."""
    try:
        figure.savefig(path, format='png', dpi=DPI)
    finally:
        pyplot().close(figure)
