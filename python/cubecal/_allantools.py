"""The statistics in AllanTools' shape: replacing `import allantools` by
`import cubecal` keeps a script working.

    taus, devs, errs, ns = cubecal.oadev(data, rate=1.0, data_type="phase", taus=None)

Same arguments, defaults (data_type "phase", taus "octave") and return value as
AllanTools: the averaging factors are chosen as AllanTools chooses them
(m = round(tau * rate), 0 < m < the number of phase points, "all", "octave",
"decade", "log10" spaced on the phase record's length), points with fewer than
two terms are dropped, errs = dev / sqrt(n), and ns is a float array. The
deviations are cubecal's (docs/formulas/stability.md), equal to AllanTools' to
rounding; `cubecal.dev` gives Stable32's grids and limits with noise
identification, EDF and confidence intervals instead.
"""
import numbers

import numpy as np

from . import _args, _cubecal
from ._args import public, usage


def _phase_points(data, data_type):
    n = np.shape(data)[0]
    if data_type == "freq":
        return n + 1
    if data_type == "phase":
        return n
    raise usage("data_type", f"data_type must be \"phase\" or \"freq\", not {data_type!r}")


def _tau_list(taus, n, rate):
    """AllanTools' tau_generator on a phase record of n points."""
    if taus is None or (isinstance(taus, (list, tuple)) and len(taus) == 0):
        taus = "octave"
    if isinstance(taus, str):
        if taus == "all":
            return (1.0 / rate) * np.linspace(1.0, n, n)
        if taus == "octave":
            maxn = np.floor(np.log2(n))
            return (1.0 / rate) * np.logspace(0, int(maxn), int(maxn + 1), base=2.0)
        if taus == "log10":
            maxn = np.log10(n)
            return (1.0 / rate) * np.logspace(0, maxn, int(10 * maxn), base=10.0)
        if taus == "decade":
            maxn = int(np.floor(np.log10(n)))
            return np.array([f * (1.0 / rate) * 10.0 ** k for k in range(maxn + 1) for f in (1.0, 2.0, 4.0)])
        if taus.startswith("log:"):
            try:
                k = int(taus[4:])
            except ValueError:
                k = 0
            if not 1 <= k <= 1000:
                raise usage("taus", f"taus: '{taus}': log:K takes a whole number of taus per decade, 1 to 1000")
            j = np.arange(0, int(np.ceil(k * np.log10(max(n, 1)))) + 1)
            return (1.0 / rate) * np.round(10.0 ** (j / k))
        raise usage("taus", f"taus must be \"all\", \"octave\", \"decade\", \"log10\", \"log:K\" or an array of taus, "
                            f"not {taus!r}")
    t = _args.samples([taus] if isinstance(taus, numbers.Real) else taus, "taus")
    if not np.all(np.isfinite(t)) or np.any(t <= 0.0):
        raise usage("taus", "taus: every tau must be a positive number of seconds")
    return t


def _factors(taus, n, rate, maximum_m=None):
    with np.errstate(over="ignore"):
        m = np.round(_tau_list(taus, n, rate) * rate)
    keep = (m < n) & (m > 0)
    if maximum_m is not None:
        keep &= m <= maximum_m
    m = m[keep]
    return np.unique(m).astype(np.int64)


def _statistic(stat, data, rate, data_type, taus, total=False):
    """total: the total statistics' limit, as AllanTools sets it: m up to a
    third of the record (of the frequency points for HTOT, whose grid
    AllanTools also spaces on them)."""
    rate = _args.rate(rate)
    data = _args.samples(data)
    n = _phase_points(data, data_type)
    if not total:
        m = _factors(taus, n, rate)
    elif stat == "htotdev":
        m = _factors(taus, n - 1, rate, (n - 1) / 3.0)
    else:
        m = _factors(taus, n, rate, n / 3.0)
    devs, ns = _cubecal._deviation(stat, data, rate, data_type, m)
    keep = ns > 1
    m, devs, ns = m[keep], devs[keep], ns[keep].astype(np.float64)
    return m / rate, devs, devs / np.sqrt(ns), ns


@public
def adev(data, rate=1.0, data_type="phase", taus=None):
    """Allan deviation (non-overlapping): (taus, devs, errs, ns)."""
    return _statistic("adev", data, rate, data_type, taus)


@public
def oadev(data, rate=1.0, data_type="phase", taus=None):
    """Overlapping Allan deviation: (taus, devs, errs, ns)."""
    return _statistic("oadev", data, rate, data_type, taus)


@public
def mdev(data, rate=1.0, data_type="phase", taus=None):
    """Modified Allan deviation: (taus, devs, errs, ns)."""
    return _statistic("mdev", data, rate, data_type, taus)


@public
def tdev(data, rate=1.0, data_type="phase", taus=None):
    """Time deviation, tau * MDEV / sqrt(3): (taus, devs, errs, ns)."""
    return _statistic("tdev", data, rate, data_type, taus)


@public
def hdev(data, rate=1.0, data_type="phase", taus=None):
    """Hadamard deviation (non-overlapping): (taus, devs, errs, ns)."""
    return _statistic("hdev", data, rate, data_type, taus)


@public
def ohdev(data, rate=1.0, data_type="phase", taus=None):
    """Overlapping Hadamard deviation: (taus, devs, errs, ns)."""
    return _statistic("ohdev", data, rate, data_type, taus)


@public
def totdev(data, rate=1.0, data_type="phase", taus=None):
    """Total deviation: (taus, devs, errs, ns)."""
    return _statistic("totdev", data, rate, data_type, taus)


@public
def mtotdev(data, rate=1.0, data_type="phase", taus=None):
    """Modified total deviation: (taus, devs, errs, ns), m up to a third of the record."""
    return _statistic("mtotdev", data, rate, data_type, taus, total=True)


@public
def ttotdev(data, rate=1.0, data_type="phase", taus=None):
    """Time total deviation, tau * MTOT / sqrt(3): (taus, devs, errs, ns)."""
    return _statistic("ttotdev", data, rate, data_type, taus, total=True)


@public
def htotdev(data, rate=1.0, data_type="phase", taus=None):
    """Hadamard total deviation (OHDEV at m = 1): (taus, devs, errs, ns)."""
    return _statistic("htotdev", data, rate, data_type, taus, total=True)


def _offset_free(data, data_type):
    """AllanTools integrates frequency data to phase with the mean frequency
    taken out; the time errors depend on it (cubecal.dev keeps the offset)."""
    if data_type != "freq":
        return data
    y = _args.samples(data)
    with np.errstate(invalid="ignore", over="ignore"):
        return y - np.nanmean(y)


@public
def tierms(data, rate=1.0, data_type="phase", taus=None):
    """Time interval error, rms: (taus, devs, errs, ns); errs are dev / sqrt(n)
    (AllanTools returns zeros there). Frequency data: the mean frequency
    taken out first, as AllanTools does."""
    return _statistic("tierms", _offset_free(data, data_type), rate, data_type, taus)


@public
def mtie(data, rate=1.0, data_type="phase", taus=None):
    """Maximum time interval error: (taus, devs, errs, ns). Frequency data:
    the mean frequency taken out first, as AllanTools does."""
    return _statistic("mtie", _offset_free(data, data_type), rate, data_type, taus)


_NOISE_TYPES = {"wp": 2, "fp": 1, "wf": 0, "ff": -1, "rf": -2}


@public
def gradev(data, rate=1.0, data_type="phase", taus=None, ci=0.9, noisetype="wp"):
    """Gap-resistant overlapping Allan deviation, as AllanTools' gradev:
    (taus, devs, [err_lo, err_hi], ns), NaN marking missing samples.

    The deviations and ns equal AllanTools' for phase data (every term whose
    three points are there). Frequency data are not turned into phase
    through the gaps (AllanTools' cumsum carries a NaN to the record's end):
    a term counts when none of the samples its two averages span is missing.
    The errors are the distances to cubecal's chi-squared interval at `ci`
    for the noise type `noisetype` ("wp", "fp", "wf", "ff", "rf"; None: the
    type identified on the longest stretch without a gap), with the EDF of a
    record without gaps giving as many terms (docs/formulas/stability.md §7a).
    """
    rate = _args.rate(rate)
    if noisetype is not None and (not isinstance(noisetype, str) or noisetype not in _NOISE_TYPES):
        raise usage("noisetype", f"noisetype must be one of {', '.join(_NOISE_TYPES)} or None, not {noisetype!r}")
    ci = _args.number(ci, "ci")
    data = _args.samples(data)
    n = _phase_points(data, data_type)
    m = _factors(taus, n, rate)
    alpha = None if noisetype is None else _NOISE_TYPES[noisetype]
    devs, ns, lo, hi = _cubecal._deviation_missing(data, rate, data_type, m, ci, alpha)
    keep = ns > 1
    m, devs, ns, lo, hi = m[keep], devs[keep], ns[keep].astype(np.float64), lo[keep], hi[keep]
    return m / rate, devs, [devs - lo, hi - devs], ns
