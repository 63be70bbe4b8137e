"""AllanTools' conversions and tau bookkeeping (allantools/allantools.py),
with its signatures, defaults and return values: frequency2phase,
phase2frequency, phase2radians, frequency2fractional, trim_data,
tau_generator, tau_reduction, remove_small_ns, input_to_phase and
mtie_rolling_window. Plain array bookkeeping on NumPy; the statistics are
in cubecal/_allantools.py."""
import numbers

import numpy as np

from . import _args
from ._args import RateError, TauError, public, usage


def trim_nan_ends(a):
    """The 1-D array `a` without the NaN before its first and after its last
    number (a view; NaN inside are kept)."""
    if a.size == 0 or not (np.isnan(a[0]) or np.isnan(a[-1])):
        return a
    good = np.flatnonzero(~np.isnan(a))
    return a[:0] if good.size == 0 else a[good[0]:good[-1] + 1]


@public
def trim_data(x):
    """Leading and trailing NaN removed; NaN inside are kept.

    Parameters
    ----------
    x : array_like
        The samples (a list, a 1-D array, or rows of a 2-D array: a row is
        NaN when all its values are).

    Returns
    -------
    array_like
        The slice of `x` from its first to its last sample that is not NaN,
        of x's own type (a view of an array); empty when every sample is NaN.
    """
    try:
        a = np.asarray(x, dtype=np.float64)
    except (TypeError, ValueError):
        raise usage("x", "x: an array of numbers is expected") from None
    if a.ndim == 0:
        raise usage("x", "x: an array of numbers is expected, not a single number")
    nan = np.isnan(a) if a.ndim == 1 else np.isnan(a.reshape(a.shape[0], -1)).all(axis=1)
    good = np.flatnonzero(~nan)
    if good.size == 0:
        return x[:0]
    return x[good[0]:good[-1] + 1]


@public
def frequency2phase(freqdata, rate):
    """Fractional frequency integrated to phase, as AllanTools integrates it.

    NaN at the ends are trimmed, the mean frequency is taken out, and the
    cumulative sum times 1 / rate follows a first phase point of 0.

    Parameters
    ----------
    freqdata : array_like
        Fractional frequency (dimensionless), N samples (1-D or (N, 1)).
    rate : float
        Sampling rate, Hz.

    Returns
    -------
    ndarray
        Phase, s: N + 1 points (of the trimmed record), the first 0.
    """
    rate = _args.rate(rate)
    y = trim_nan_ends(_args.series(freqdata, "freqdata"))
    with np.errstate(invalid="ignore"):
        y = y - (np.nanmean(y) if y.size else 0.0)
    x = np.empty(y.size + 1)
    x[0] = 0.0
    np.cumsum(y, out=x[1:])
    x[1:] *= 1.0 / rate
    return x


@public
def phase2frequency(phase, rate):
    """Phase differenced to fractional frequency: rate * diff(phase).

    Parameters
    ----------
    phase : array_like
        Phase, s, N points.
    rate : float
        Sampling rate, Hz.

    Returns
    -------
    ndarray
        Fractional frequency (dimensionless), N - 1 samples.
    """
    rate = _args.rate(rate)
    return rate * np.diff(_args.series(phase, "phase"))


@public
def phase2radians(phasedata, v0):
    """Phase in seconds to phase in radians: 2 pi v0 x.

    Parameters
    ----------
    phasedata : array_like
        Phase, s.
    v0 : float
        Nominal frequency of the oscillator, Hz.

    Returns
    -------
    ndarray
        Phase, rad.
    """
    v0 = _args.number(v0, "v0")
    return 2.0 * np.pi * v0 * _args.series(phasedata, "phasedata")


@public
def frequency2fractional(frequency, mean_frequency=-1):
    """Frequency in Hz to fractional frequency: (f - mu) / mu.

    Parameters
    ----------
    frequency : array_like
        Frequency, Hz.
    mean_frequency : float
        The nominal frequency mu, Hz; -1 (default): the mean of `frequency`.

    Returns
    -------
    list of float
        Fractional frequency (dimensionless), a list as AllanTools returns it.
    """
    f = _args.series(frequency, "frequency")
    mu = float(np.mean(f)) if mean_frequency == -1 else _args.number(mean_frequency, "mean_frequency")
    if mu == 0.0:
        raise usage("mean_frequency", "mean_frequency: the nominal frequency must not be zero")
    return ((f - mu) / mu).tolist()


@public
def input_to_phase(data, rate, data_type):
    """Phase data as they are; frequency data integrated by frequency2phase.

    Parameters
    ----------
    data : array_like
        Phase (s) or fractional frequency.
    rate : float
        Sampling rate, Hz.
    data_type : {"phase", "freq"}
        What `data` holds.

    Returns
    -------
    array_like
        Phase, s (`data` itself for phase data).
    """
    if data_type == "phase":
        return data
    if data_type == "freq":
        return frequency2phase(data, rate)
    raise usage("data_type", f"data_type must be \"phase\" or \"freq\", not {data_type!r}")


@public
def tau_generator(data, rate, taus=None, v=False, even=False, maximum_m=-1):
    """AllanTools' tau list: averaging factors from taus in seconds or a keyword.

    Parameters
    ----------
    data : array_like
        The record the factors are for (its length N).
    rate : float
        Sampling rate, Hz; zero raises cubecal.RateError (a RuntimeError).
    taus : None, str or array_like
        Taus, s, or "all" (m = 1 .. N), "octave" (default; 1, 2, 4 ...),
        "decade" (1, 2, 4, 10, 20, 40 ...), "log10" (about 10 per decade),
        "log:K" (K per decade).
    v : bool
        Print the factors.
    even : bool
        Keep even factors only (Theo1).
    maximum_m : float
        The largest factor kept; -1 (default): N.

    Returns
    -------
    data : ndarray
        `data` as an array.
    m : ndarray
        The averaging factors (floats, sorted, unique, 0 < m < N, m <= maximum_m).
    taus : ndarray
        m / rate, s.
    """
    from ._allantools import _tau_list

    if isinstance(rate, numbers.Real) and not isinstance(rate, bool) and rate == 0:
        raise usage("rate", "rate: the sampling rate must not be zero", RateError)
    rate = _args.rate(rate)
    data = np.array(data)
    n = len(data)
    t = _tau_list(taus, n, rate)
    limit = n if maximum_m == -1 else _args.number(maximum_m, "maximum_m")
    with np.errstate(over="ignore", invalid="ignore"):
        m = np.round(t * rate)
    m = np.unique(m[(m < n) & (m > 0) & (m <= limit)])
    if v:
        print("tau_generator: ", m)
    taus_used = m / rate
    if even:
        keep = m % 2 == 0
        m, taus_used = m[keep], taus_used[keep]
    return data, m, taus_used


@public
def tau_reduction(ms, rate, n_per_decade):
    """At most about `n_per_decade` factors per decade of a dense ("all") list.

    A factor is kept where round(n_per_decade * log10(m)) changes at the next
    factor, as AllanTools keeps it (the last factor is dropped).

    Parameters
    ----------
    ms : array_like of int
        Averaging factors, increasing.
    rate : float
        Sampling rate, Hz.
    n_per_decade : int
        Factors to keep per decade.

    Returns
    -------
    ms : ndarray of int64
        The factors kept.
    taus : ndarray
        ms / rate, s.
    """
    rate = _args.rate(rate)
    ms = np.asarray(ms).astype(np.int64)
    if ms.ndim != 1 or np.any(ms < 1):
        raise usage("ms", "ms: a 1-D list of averaging factors of 1 or more is expected")
    k = _args.number(n_per_decade, "n_per_decade", positive=True)
    step = np.rint(k * np.log10(ms))
    keep = step[1:] != step[:-1]
    ms = ms[:-1][keep]
    return ms, ms / rate


@public
def remove_small_ns(taus, devs, deverrs, ns):
    """The points of a deviation with more than one term.

    Parameters
    ----------
    taus, devs : ndarray
        Taus (s) and deviations.
    deverrs : ndarray or list of two ndarrays
        The errors, or [lower, upper] errors.
    ns : ndarray
        Number of terms of each point.

    Returns
    -------
    (taus, devs, deverrs, ns)
        Those where ns > 1, deverrs as given (an array or a list of two).

    Raises
    ------
    cubecal.TauError
        When no point is left (also the UserWarning AllanTools raises).
    """
    taus, devs, ns = np.asarray(taus), np.asarray(devs), np.asarray(ns)
    keep = ns > 1
    if isinstance(deverrs, list):
        if len(deverrs) != 2:
            raise usage("deverrs", "deverrs: an array or a list of two arrays (lower, upper) is expected")
        errs = [np.asarray(deverrs[0])[keep], np.asarray(deverrs[1])[keep]]
    else:
        errs = np.asarray(deverrs)[keep]
    if not np.any(keep):
        raise usage("ns", "ns: no point has more than one term", TauError)
    return taus[keep], devs[keep], errs, ns[keep]


@public
def mtie_rolling_window(a, window):
    """A read-only view of `a` with a last axis of `window` consecutive samples.

    Parameters
    ----------
    a : ndarray
        The samples (windows along the last axis).
    window : int
        Window length, 1 to a.shape[-1].

    Returns
    -------
    ndarray
        Shape a.shape[:-1] + (a.shape[-1] - window + 1, window), a view.
    """
    a = np.asarray(a)
    window = _args.count(window, "window", minimum=1, maximum=max(a.shape[-1], 1) if a.ndim else 1)
    return np.lib.stride_tricks.sliding_window_view(a, window, axis=-1)
