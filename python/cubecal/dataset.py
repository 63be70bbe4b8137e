"""AllanTools' ``Dataset``: a record, its sampling and tau grid, and the
result of one of cubecal's deviation calls on it.

    ds = cubecal.Dataset(data=x, rate=1.0, data_type="phase", taus="octave")
    out = ds.compute("oadev")         # {"taus", "stat", "stat_err", "stat_n"}
    ds.write_results("oadev.txt")     # AllanTools' text table
    cubecal.Plot(no_display=True).plot(ds)

Same arguments, attributes (``inp``, ``out``) and file format as AllanTools'
``allantools.dataset.Dataset``; ``compute`` calls cubecal's AllanTools-shaped
functions (``cubecal.oadev``, ``cubecal.mdev``, ...), so the numbers are
cubecal's, equal to AllanTools' to rounding.
"""
import importlib

import numpy as np

from . import _args
from ._cubecal import UsageError

__all__ = ["Dataset", "UnknownFunctionError", "NotADeviationError"]

# Functions Dataset computes besides the *dev ones, as AllanTools.
_WHITELISTED = ("theo1", "mtie", "tierms")
# cubecal's own calls whose name ends in "dev" but which are not
# AllanTools-shaped (they do not return taus, devs, errs, ns).
_NOT_ALLANTOOLS = ("dev",)
# AllanTools' functions that are not deviations: Dataset refuses them with
# the RuntimeError AllanTools raises, whether cubecal has them or not.
_ALLANTOOLS_OTHERS = frozenset((
    "calc_adev_phase", "calc_pdev_phase", "calc_gcodev_phase", "calc_hdev_phase", "calc_mtotdev_phase",
    "calc_htotdev_freq", "calc_gradev_phase", "mtie_rolling_window", "mtie_phase_fast", "psd2allan",
    "adev2psd_piecewise_approx", "psd_piecewise_to_adev", "input_to_phase", "tau_generator", "tau_reduction",
    "remove_small_ns", "trim_data", "three_cornered_hat_phase", "frequency2phase", "phase2radians",
    "phase2frequency", "frequency2fractional"))


class UnknownFunctionError(UsageError, AttributeError):
    """Dataset.compute: no such function in cubecal (a cubecal.UsageError and,
    as AllanTools raises, an AttributeError)."""


class NotADeviationError(UsageError, RuntimeError):
    """Dataset.compute: the function is not a deviation Dataset can compute (a
    cubecal.UsageError and, as AllanTools raises, a RuntimeError)."""


def _error(kind, message):
    e = kind(message)
    e.option = "function"
    return e


class Dataset:
    """A record and the result of one statistic on it (AllanTools' Dataset).

    Parameters
    ----------
    data : array_like, optional
        Phase (s) or fractional frequency (dimensionless) samples.
    rate : float, default 1.0
        Sampling rate (Hz).
    data_type : {"phase", "freq"}, default "phase"
        What ``data`` holds.
    taus : array_like or str, optional
        Taus (s) to compute at, or "all", "octave", "decade" (None:
        "octave", as the deviation functions).

    Attributes
    ----------
    inp : dict
        The input: "data", "rate" (Hz), "data_type", "taus".
    out : dict
        The last result: "taus" (s), "stat", "stat_err", "stat_n" (numpy
        arrays, as the function returns them) and "stat_id" (the
        function's name); before compute(), the same keys and "stat_unc",
        all None.
    """

    def __init__(self, data=None, rate=1.0, data_type="phase", taus=None):
        self.inp = {"data": None, "rate": None, "data_type": None, "taus": None}
        self.out = {"taus": None, "stat": None, "stat_err": None, "stat_n": None, "stat_unc": None,
                    "stat_id": None}
        self.set_input(data, rate=rate, data_type=data_type, taus=taus)

    def set_input(self, data, rate=1.0, data_type="phase", taus=None):
        """Set the input (when not given to the constructor); checked when
        compute() runs.

        Parameters
        ----------
        data : array_like
            Phase (s) or fractional frequency (dimensionless) samples.
        rate : float, default 1.0
            Sampling rate (Hz).
        data_type : {"phase", "freq"}, default "phase"
            What ``data`` holds.
        taus : array_like or str, optional
            Taus (s), or "all", "octave", "decade".
        """
        self.inp["data"] = data
        self.inp["rate"] = rate
        self.inp["data_type"] = data_type
        self.inp["taus"] = taus

    def compute(self, function):
        """Compute a statistic of the input with cubecal's function of that
        name, and keep it in ``out``.

        Parameters
        ----------
        function : str
            The name of a cubecal deviation in AllanTools' shape: one ending
            in "dev" ("adev", "oadev", "mdev", "tdev", "hdev", "ohdev",
            "totdev", "mtotdev", "ttotdev", "htotdev", ...) or "theo1",
            "mtie", "tierms".

        Returns
        -------
        dict
            "taus" (s), "stat" (the deviation: fractional frequency, or s for
            tdev, ttotdev, mtie, tierms), "stat_err" (its error, same unit)
            and "stat_n" (terms averaged). ``out`` holds a copy with
            "stat_id" = function.

        Raises
        ------
        UnknownFunctionError
            No such function (an AttributeError too).
        NotADeviationError
            Not one of the functions above (a RuntimeError too).
        cubecal.UsageError
            The input (data, rate, data_type, taus) cannot be computed.
        """
        name = _args.text(function, "function")
        package = importlib.import_module(__package__)
        func = getattr(package, name, None) if not name.startswith("_") else None
        if name in _ALLANTOOLS_OTHERS:
            func = None
        elif func is None or name in _NOT_ALLANTOOLS or not callable(func):
            raise _error(UnknownFunctionError, f"function: cubecal has no AllanTools deviation {name!r}; use one of "
                                               f"adev, oadev, mdev, tdev, hdev, ohdev, totdev, mtotdev, ttotdev, "
                                               f"htotdev, theo1, mtie, tierms")
        if func is None or (not name.endswith("dev") and name not in _WHITELISTED):
            raise _error(NotADeviationError, f"function: {name!r} is not a deviation; use a name ending in 'dev' "
                                             f"or one of {', '.join(_WHITELISTED)}")
        result = func(self.inp["data"], rate=self.inp["rate"], data_type=self.inp["data_type"],
                      taus=self.inp["taus"])
        result = {key: result[i] for i, key in enumerate(("taus", "stat", "stat_err", "stat_n"))}
        self.out = result.copy()
        self.out["stat_id"] = name
        return result

    def write_results(self, filename, digits=5, header_params={}):  # noqa: B006 (AllanTools' default)
        """Write the last result as AllanTools' text table (overwrites).

        Lines: "# Generated by cubecal VERSION", the input's data type and
        rate, one "# key: value" per ``header_params`` item, a header row,
        then per tau: AF, tau (s), N, alpha ("NaN": not identified here),
        stat - err/2, stat, stat + err/2 (gradev: its lower and upper
        distances), in ``digits`` significant digits.

        Parameters
        ----------
        filename : str or os.PathLike
            Path of the file to write.
        digits : int, default 5
            Significant digits of the numbers (1 to 17).
        header_params : dict, default {}
            More header lines, "# key: value".
        """
        path = _args.path(filename, "filename")
        digits = _args.count(digits, "digits", minimum=1, maximum=17)
        if not isinstance(header_params, dict):
            raise _args.usage("header_params", "header_params: a dict is expected")
        if self.out.get("taus") is None or self.out.get("stat_id") is None:
            raise _args.usage("", "write_results: nothing computed yet; call compute() first")
        from . import __version__
        taus = np.asarray(self.out["taus"], dtype=np.float64)
        stat = np.asarray(self.out["stat"], dtype=np.float64)
        err = np.asarray(self.out["stat_err"], dtype=np.float64)
        ns = np.asarray(self.out["stat_n"])
        rate = float(self.inp["rate"])
        sid = self.out["stat_id"]
        w = digits + 5
        lines = [f"# Generated by cubecal {__version__}\n",
                 f"# Input data type: {self.inp['data_type']}\n",
                 f"# Input data rate: {self.inp['rate']}\n"]
        lines += [f"# {key}: {val}\n" for key, val in header_params.items()]
        lines.append(f"{'AF':>5s} {'Tau':>{w}s} {'N':>10s} {'alpha':>5s} {'min_' + sid:>{w}} {sid:>{w}} "
                     f"{'max_' + sid:>{w}} \n")
        p = digits - 1
        for i in range(len(taus)):
            af = int(round(taus[i] * rate))
            if err.ndim == 2:  # gradev's [lower, upper] distances
                lo, hi = stat[i] - err[0, i], stat[i] + err[1, i]
            else:
                lo, hi = stat[i] - err[i] / 2, stat[i] + err[i] / 2
            lines.append(f"{af:5d} {taus[i]:.{p}e} {int(ns[i]):10d} {'NaN':5s} {lo:.{p}e} {stat[i]:.{p}e} "
                         f"{hi:.{p}e} \n")
        with open(path, "w") as fp:
            fp.writelines(lines)
