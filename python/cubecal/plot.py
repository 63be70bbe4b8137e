"""AllanTools' ``Plot``: a log-log figure of Datasets' results, on matplotlib.

    ds = cubecal.Dataset(data=x, rate=1.0); ds.compute("adev")
    p = cubecal.Plot(no_display=True)   # Agg: no window, for files and tests
    p.plot(ds, errorbars=True, grid=True)
    p.save("adev.png")

Same arguments and attributes (``fig``, ``ax``, ``plt``) as AllanTools'
``allantools.plot.Plot``. Headless-safe: with ``no_display=True``, or on a
machine with no display (Linux without DISPLAY or WAYLAND_DISPLAY) and no
backend chosen (MPLBACKEND), matplotlib's non-interactive Agg backend is
used.
"""
import os
import sys

from . import _args
from ._cubecal import Error

__all__ = ["Plot", "PlotError"]


class PlotError(Error, RuntimeError):
    """Plot cannot work here: matplotlib is missing (a cubecal.Error and, as
    AllanTools raises, a RuntimeError)."""


def _headless():
    if os.environ.get("MPLBACKEND"):
        return False
    if not sys.platform.startswith("linux"):
        return False
    return not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"))


class Plot:
    """A log-log figure (tau on x, the statistic on y) of Dataset results.

    Parameters
    ----------
    no_display : bool, default False
        True: use the Agg backend (no window; ``save`` only), as for tests.

    Attributes
    ----------
    fig : matplotlib.figure.Figure
        The figure (``matplotlib.pyplot.subplots()``).
    ax : matplotlib.axes.Axes
        Its axes, log-scaled on both.
    plt : module
        ``matplotlib.pyplot``.

    Raises
    ------
    PlotError
        matplotlib is not installed (Debian: python3-matplotlib).
    """

    def __init__(self, no_display=False):
        no_display = _args.flag(no_display, "no_display")
        try:
            import matplotlib
            if no_display or ("matplotlib.pyplot" not in sys.modules and _headless()):
                matplotlib.use("Agg")
            import matplotlib.pyplot as plt
        except ImportError:
            raise PlotError("Plot: matplotlib is required for plotting; install it "
                            "(Debian: apt-get install python3-matplotlib)") from None
        self.plt = plt
        self.fig, self.ax = plt.subplots()
        self.ax.set_xscale("log")
        self.ax.set_yscale("log")

    def plot(self, atDataset, errorbars=False, grid=False, **kwargs):
        """Draw a Dataset's result: stat against tau (s), labelled with the
        statistic's name.

        Parameters
        ----------
        atDataset : cubecal.Dataset
            A Dataset after compute().
        errorbars : bool, default False
            Draw ``stat_err`` as error bars.
        grid : bool, default False
            Draw the major and minor grid.
        **kwargs
            Passed to ``matplotlib.axes.Axes.plot`` (or ``errorbar``).
        """
        errorbars = _args.flag(errorbars, "errorbars")
        grid = _args.flag(grid, "grid")
        out = getattr(atDataset, "out", None)
        if not isinstance(out, dict) or out.get("taus") is None or out.get("stat") is None:
            raise _args.usage("atDataset", "atDataset: a Dataset after compute() is expected")
        if errorbars:
            self.ax.errorbar(out["taus"], out["stat"], yerr=out["stat_err"], **kwargs)
        else:
            self.ax.plot(out["taus"], out["stat"], **kwargs)
        self.ax.set_xlabel("Tau")
        self.ax.set_ylabel(out["stat_id"])
        if grid:
            self.ax.grid(True, which="minor", ls="-", color="0.65")
            self.ax.grid(True, which="major", ls="-", color="0.25")
        else:
            self.ax.grid(False)

    def show(self):
        """Show the figure (``matplotlib.pyplot.show()``; nothing with Agg)."""
        self.plt.show()

    def save(self, f):
        """Save the figure.

        Parameters
        ----------
        f : str, os.PathLike or file object
            Where to write; the format follows the name's extension (".png",
            ".pdf", ".svg", ...), as ``matplotlib.figure.Figure.savefig``.
        """
        self.fig.savefig(f)
