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

The data are taken as AllanTools takes them: a list, a 1-D array or a column
of shape (N, 1), converted to one float64 array once per call; NaN at the
ends of frequency data are trimmed (AllanTools' frequency2phase does so
before integrating); a rate of zero raises cubecal.RateError, which is also
the RuntimeError AllanTools raises; no tau left raises cubecal.TauError, also
the UserWarning AllanTools raises.
"""
import numbers

import numpy as np

from . import _args, _cubecal
from ._args import TauError, public, usage
from ._conversions import frequency2phase, phase2frequency, trim_nan_ends


def _data_type(data_type):
    if data_type not in ("phase", "freq"):
        raise usage("data_type", f"data_type must be \"phase\" or \"freq\", not {data_type!r}")
    return data_type


def _record(data, data_type, option="data"):
    """The samples as one 1-D float64 array (converted once), frequency data
    with the NaN at their ends trimmed as AllanTools trims them."""
    _data_type(data_type)
    a = _args.series(data, option)
    if data_type == "freq":
        a = trim_nan_ends(a)
        if a.size == 0:
            raise usage(option, f"{option}: every sample is NaN")
    return a


def _phase_points(a, data_type):
    return a.shape[0] + 1 if data_type == "freq" else a.shape[0]


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


def _kept(m, rate, devs, errs, ns):
    """AllanTools' remove_small_ns: the points of at least two terms, taus
    in seconds and ns as floats; TauError when none is left."""
    keep = ns > 1
    if not np.any(keep):
        raise usage("taus", "taus: no tau leaves a deviation of two terms or more on this record "
                            "(a shorter tau or a longer record)", TauError)
    ns = ns[keep].astype(np.float64)
    errs = [e[keep] for e in errs] if isinstance(errs, list) else errs[keep]
    return m[keep] / rate, devs[keep], errs, ns


def _statistic(stat, data, rate, data_type, taus, total=False, offset_free=False):
    """total: the total statistics' limit, as AllanTools sets it: m up to a
    third of the record (of the frequency points for HTOT, whose grid
    AllanTools also spaces on them). offset_free: frequency data with their
    mean taken out (AllanTools integrates them so; the time errors depend
    on it)."""
    rate = _args.rate(rate)
    data = _record(data, data_type)
    n = _phase_points(data, data_type)
    if not total:
        m = _factors(taus, n, rate)
    elif stat == "htotdev":
        m = _factors(taus, n - 1, rate, (n - 1) / 3.0)
    else:
        m = _factors(taus, n, rate, n / 3.0)
    if offset_free and data_type == "freq":
        data = data - np.mean(data)
    devs, ns = _cubecal._deviation(stat, data, rate, data_type, m)
    return _kept(m, rate, devs, devs / np.sqrt(ns.clip(1)), ns)


_PARAMETERS = """
    Parameters
    ----------
    data : array_like
        Phase (s) or fractional frequency (dimensionless): a list, a 1-D
        array or a column of shape (N, 1). NaN at the ends of frequency data
        are trimmed.
    rate : float
        Sampling rate, Hz (default 1.0).
    data_type : {"phase", "freq"}
        What `data` holds (default "phase").
    taus : None, str or array_like
        Averaging times, s, or "all", "octave" (default), "decade", "log10",
        "log:K" (K per decade).
"""


def _documented(summary, unit="dimensionless", notes=""):
    """The numpydoc docstring of an AllanTools-shaped deviation."""

    def attach(function):
        function.__doc__ = f"""{summary}
{_PARAMETERS}
    Returns
    -------
    taus : ndarray
        Averaging times used, s (m / rate).
    devs : ndarray
        Deviations ({unit}).
    errs : ndarray
        devs / sqrt(ns).
    ns : ndarray
        Number of terms of each deviation (floats).

    Raises
    ------
    cubecal.RateError
        A rate that cannot be taken (zero: also AllanTools' RuntimeError).
    cubecal.TauError
        No tau leaves two terms (also AllanTools' UserWarning).
    {notes}"""
        return function

    return attach


@public
@_documented("Allan deviation (non-overlapping).")
def adev(data, rate=1.0, data_type="phase", taus=None):
    return _statistic("adev", data, rate, data_type, taus)


@public
@_documented("Overlapping Allan deviation.")
def oadev(data, rate=1.0, data_type="phase", taus=None):
    return _statistic("oadev", data, rate, data_type, taus)


@public
@_documented("Modified Allan deviation.")
def mdev(data, rate=1.0, data_type="phase", taus=None):
    return _statistic("mdev", data, rate, data_type, taus)


@public
@_documented("Time deviation, tau MDEV / sqrt(3).", "s")
def tdev(data, rate=1.0, data_type="phase", taus=None):
    return _statistic("tdev", data, rate, data_type, taus)


@public
@_documented("Hadamard deviation (non-overlapping).")
def hdev(data, rate=1.0, data_type="phase", taus=None):
    return _statistic("hdev", data, rate, data_type, taus)


@public
@_documented("Overlapping Hadamard deviation.")
def ohdev(data, rate=1.0, data_type="phase", taus=None):
    return _statistic("ohdev", data, rate, data_type, taus)


@public
@_documented("Total deviation.")
def totdev(data, rate=1.0, data_type="phase", taus=None):
    return _statistic("totdev", data, rate, data_type, taus)


@public
@_documented("Modified total deviation, m up to a third of the phase points.")
def mtotdev(data, rate=1.0, data_type="phase", taus=None):
    return _statistic("mtotdev", data, rate, data_type, taus, total=True)


@public
@_documented("Time total deviation, tau MTOT / sqrt(3), m up to a third of the phase points.", "s")
def ttotdev(data, rate=1.0, data_type="phase", taus=None):
    return _statistic("ttotdev", data, rate, data_type, taus, total=True)


@public
@_documented("Hadamard total deviation (OHDEV at m = 1), m up to a third of the frequency points.")
def htotdev(data, rate=1.0, data_type="phase", taus=None):
    return _statistic("htotdev", data, rate, data_type, taus, total=True)


@public
@_documented("Time interval error, rms. Frequency data: the mean frequency taken out first, as AllanTools does; "
             "errs are devs / sqrt(ns) (AllanTools returns zeros there).", "s")
def tierms(data, rate=1.0, data_type="phase", taus=None):
    return _statistic("tierms", data, rate, data_type, taus, offset_free=True)


@public
@_documented("Maximum time interval error. Frequency data: the mean frequency taken out first, as AllanTools does.",
             "s")
def mtie(data, rate=1.0, data_type="phase", taus=None):
    return _statistic("mtie", data, rate, data_type, taus, offset_free=True)


def _phase_of(data, rate, data_type, option="data"):
    """Phase (s) of the data, as one float64 array: frequency integrated as
    AllanTools' frequency2phase integrates it (ends trimmed, mean removed)."""
    a = _record(data, data_type, option)
    return frequency2phase(a, rate) if data_type == "freq" else a


@public
@_documented("Parabolic deviation (Vernotte et al. 2016), OADEV at m = 1; ns = N - 2m terms of N phase points.")
def pdev(data, rate=1.0, data_type="phase", taus=None):
    rate = _args.rate(rate)
    phase = _phase_of(data, rate, data_type)
    m = _factors(taus, phase.shape[0], rate)
    var, ns = _cubecal._pvar(phase, rate, m)
    devs = np.sqrt(var)
    return _kept(m, rate, devs, devs / np.sqrt(ns.clip(1)), ns)


@public
def gcodev(data_1, data_2, rate=1.0, data_type="phase", taus=None):
    """Groslambert codeviation (Allan covariance) of two records of one length.

    With three clocks A, B, C and the measurements AB and BC, the
    codeviation of AB and BC estimates clock B's ADEV free of the
    (uncorrelated) noise of the instruments.

    Parameters
    ----------
    data_1, data_2 : array_like
        Phase (s) or fractional frequency of the two measurements, of one length.
    rate, data_type, taus
        As `adev`.

    Returns
    -------
    (taus, devs, errs, ns)
        As `adev`; devs is sqrt(|covariance|) (dimensionless), whatever the
        covariance's sign, as AllanTools returns it.
    """
    rate = _args.rate(rate)
    phase_1 = _phase_of(data_1, rate, data_type, "data_1")
    phase_2 = _phase_of(data_2, rate, data_type, "data_2")
    m = _factors(taus, phase_1.shape[0], rate)
    cov, ns = _cubecal._allan_covariance(phase_1, phase_2, rate, m)
    devs = np.sqrt(np.abs(cov))
    return _kept(m, rate, devs, devs / np.sqrt(ns.clip(1)), ns)


@public
def theo1(data, rate=1.0, data_type="phase", taus=None):
    """Theo1 deviation (NIST SP 1065 eq. 30) at even averaging factors m.

    Odd factors of the grid are left out.

    Parameters
    ----------
    data : array_like
        Phase (s) or fractional frequency, as `adev`.
    rate : float
        Sampling rate, Hz.
    data_type : {"phase", "freq"}
        What `data` holds.
    taus : None, str or array_like
        As `adev`.

    Returns
    -------
    taus : ndarray
        m / rate, s (Theo1 at m averages over 0.75 m / rate).
    devs : ndarray
        Theo1 deviations, without bias correction.
    errs : ndarray
        devs / sqrt(N - m), N phase points (as AllanTools).
    ns : ndarray
        (N - m) m / 2, the number of squared terms.
    """
    rate = _args.rate(rate)
    phase = _phase_of(data, rate, data_type)
    n = phase.shape[0]
    m = _factors(taus, n, rate)
    m = m[m % 2 == 0]
    devs, ns = _cubecal._deviation("theo1", phase, rate, "phase", m)
    return _kept(m, rate, devs, devs / np.sqrt(np.maximum(n - m, 1)), ns)


_NOISE_TYPES = {"wp": 2, "fp": 1, "wf": 0, "ff": -1, "rf": -2}


@public
def gradev(data, rate=1.0, data_type="phase", taus=None, ci=0.9, noisetype="wp"):
    """Gap-resistant overlapping Allan deviation, as AllanTools' gradev:
    (taus, devs, [err_lo, err_hi], ns), NaN marking missing samples.

    The deviations and ns equal AllanTools' for phase data (every term whose
    three points are there). Frequency data are not turned into phase
    through the gaps (AllanTools' cumsum carries a NaN to the record's end):
    a term counts when none of the samples its two averages span is missing;
    NaN at their ends are trimmed first, as AllanTools trims them.
    The errors are the distances to cubecal's chi-squared interval at `ci`
    for the noise type `noisetype` ("wp", "fp", "wf", "ff", "rf"; None: the
    type identified on the longest stretch without a gap), with the EDF of a
    record without gaps giving as many terms (docs/formulas/stability.md §7a).

    Parameters
    ----------
    data : array_like
        Phase (s) or fractional frequency, NaN where a sample is missing.
    rate : float
        Sampling rate, Hz.
    data_type : {"phase", "freq"}
        What `data` holds.
    taus : None, str or array_like
        As `adev`.
    ci : float
        Confidence of the interval, 0 to 1 (default 0.9).
    noisetype : {"wp", "fp", "wf", "ff", "rf"} or None
        The noise type of the interval; None: identified.

    Returns
    -------
    taus : ndarray
        Averaging times, s.
    devs : ndarray
        Deviations (dimensionless).
    [err_lo, err_hi] : list of two ndarrays
        Distances from devs down and up to the interval's ends.
    ns : ndarray
        Number of terms (floats).
    """
    rate = _args.rate(rate)
    if noisetype is not None and (not isinstance(noisetype, str) or noisetype not in _NOISE_TYPES):
        raise usage("noisetype", f"noisetype must be one of {', '.join(_NOISE_TYPES)} or None, not {noisetype!r}")
    ci = _args.number(ci, "ci")
    data = _record(data, data_type)
    n = _phase_points(data, data_type)
    m = _factors(taus, n, rate)
    alpha = None if noisetype is None else _NOISE_TYPES[noisetype]
    devs, ns, lo, hi = _cubecal._deviation_missing(data, rate, data_type, m, ci, alpha)
    return _kept(m, rate, devs, [devs - lo, hi - devs], ns)


# AllanTools' per-factor kernels: (dev, err, n) at one averaging factor.

def _factor(mj, option="mj"):
    return _args.count(mj, option, minimum=1, maximum=2 ** 62)


def _one(stat, phase, rate, mj):
    m = np.array([mj], dtype=np.int64)
    devs, ns = _cubecal._deviation(stat, phase, rate, "phase", m)
    return float(devs[0]), int(ns[0])


def _stride(stride, mj, allowed):
    s = _factor(stride, "stride")
    if s not in allowed:
        raise usage("stride", f"stride: {' or '.join(map(str, sorted(set(allowed))))} (overlapping"
                              f"{'' if len(set(allowed)) == 1 else ' or not'}) is what cubecal computes at "
                              f"mj = {mj}, not {s}")
    return s


@public
def calc_adev_phase(phase, rate, mj, stride):
    """ADEV (stride = mj) or OADEV (stride = 1) of phase data at one factor.

    Parameters
    ----------
    phase : array_like
        Phase, s (1-D or a column).
    rate : float
        Sampling rate, Hz.
    mj : int
        Averaging factor, tau = mj / rate.
    stride : int
        1 (overlapping) or mj (non-overlapping).

    Returns
    -------
    (dev, deverr, n) : (float, float, int)
        The deviation, dev / sqrt(n) and the number of terms; (0.0, 0.0, 1)
        when the record is too short for mj, as AllanTools.
    """
    rate = _args.rate(rate)
    mj = _factor(mj)
    stat = "oadev" if _stride(stride, mj, (1, mj)) == 1 else "adev"
    dev, n = _one(stat, _args.series(phase, "phase"), rate, mj)
    if n == 0:
        return 0.0, 0.0, 1
    return dev, dev / np.sqrt(n), n


@public
def calc_hdev_phase(phase, rate, mj, stride):
    """HDEV (stride = mj) or OHDEV (stride = 1) of phase data at one factor.

    Parameters
    ----------
    phase : array_like
        Phase, s (1-D or a column).
    rate : float
        Sampling rate, Hz.
    mj : int
        Averaging factor, tau = mj / rate.
    stride : int
        1 (overlapping) or mj (non-overlapping).

    Returns
    -------
    (dev, deverr, n) : (float, float, int)
        As `calc_adev_phase`; (0.0, 0.0, 1) when the record is too short.
    """
    rate = _args.rate(rate)
    mj = _factor(mj)
    stat = "ohdev" if _stride(stride, mj, (1, mj)) == 1 else "hdev"
    dev, n = _one(stat, _args.series(phase, "phase"), rate, mj)
    if n == 0:
        return 0.0, 0.0, 1
    return dev, dev / np.sqrt(n), n


@public
def calc_pdev_phase(phase, rate, mj):
    """PDEV of phase data at one factor.

    Parameters
    ----------
    phase : array_like
        Phase, s (1-D or a column).
    rate : float
        Sampling rate, Hz.
    mj : int
        Averaging factor, tau = mj / rate.

    Returns
    -------
    (dev, deverr, n) : (float, float, int)
        The deviation (dimensionless), dev / sqrt(n), n = N - 2 mj; (0, 0, 0)
        when the record has fewer than 2 mj + 1 points, as AllanTools.
    """
    rate = _args.rate(rate)
    mj = _factor(mj)
    var, ns = _cubecal._pvar(_args.series(phase, "phase"), rate, np.array([mj], dtype=np.int64))
    if ns[0] == 0:
        return 0, 0, 0
    dev = float(np.sqrt(var[0]))
    return dev, dev / np.sqrt(ns[0]), int(ns[0])


@public
def calc_gcodev_phase(phase_1, phase_2, rate, mj, stride):
    """Groslambert codeviation of two phase records at one factor, stride 1 (overlapping).

    Parameters
    ----------
    phase_1, phase_2 : array_like
        Phase, s, of one length.
    rate : float
        Sampling rate, Hz.
    mj : int
        Averaging factor.
    stride : int
        1 (the only stride cubecal computes).

    Returns
    -------
    (dev, deverr, n) : (float, float, int)
        sqrt(|covariance|) (dimensionless), dev / sqrt(n), n = N - 2 mj.
    """
    rate = _args.rate(rate)
    mj = _factor(mj)
    _stride(stride, mj, (1,))
    cov, ns = _cubecal._allan_covariance(_args.series(phase_1, "phase_1"), _args.series(phase_2, "phase_2"), rate,
                                         np.array([mj], dtype=np.int64))
    if ns[0] == 0:
        return 0.0, 0.0, 1
    dev = float(np.sqrt(abs(cov[0])))
    return dev, dev / np.sqrt(ns[0]), int(ns[0])


@public
def calc_mtotdev_phase(phase, rate, m):
    """MTOT deviation of phase data at one factor m.

    Parameters
    ----------
    phase : array_like
        Phase, s, N points.
    rate : float
        Sampling rate, Hz.
    m : int
        Averaging factor.

    Returns
    -------
    (dev, error, n) : (float, float, int)
        The deviation (dimensionless), dev / sqrt(n), n = N - 3m + 1.

    Raises
    ------
    cubecal.UsageError
        When the record has fewer than 3m points (AllanTools fails an assertion).
    """
    rate = _args.rate(rate)
    m = _factor(m, "m")
    dev, n = _one("mtotdev", _args.series(phase, "phase"), rate, m)
    if n == 0:
        raise usage("m", f"m: {m} needs a record of at least {3 * m} phase points")
    return dev, dev / np.sqrt(n), n


@public
def calc_htotdev_freq(freq, m):
    """HTOT deviation of fractional frequency at one factor m, the total
    kernel at every m (m = 1 included; htotdev takes OHDEV there).

    Parameters
    ----------
    freq : array_like
        Fractional frequency (dimensionless), L points.
    m : int
        Averaging factor.

    Returns
    -------
    (dev, error, n) : (float, float, int)
        The deviation (dimensionless), dev / sqrt(n), n = L - 3m + 1.
    """
    m = _factor(m, "m")
    var, ns = _cubecal._htotvar_frequency(_args.series(freq, "freq"), np.array([m], dtype=np.int64))
    if ns[0] == 0:
        raise usage("m", f"m: {m} needs a record of at least {3 * m} frequency points")
    dev = float(np.sqrt(var[0]))
    return dev, dev / np.sqrt(ns[0]), int(ns[0])


@public
def mtie_phase_fast(phase, rate=1.0, data_type="phase", taus=None):
    """MTIE by binary decomposition (Bregni 2001) on the first 2^K points.

    The windows of 2, 4, 8 ... 2^K points (K = floor(log2 N)) of the record
    truncated to 2^K points; `taus` is not used (as AllanTools).

    Returns
    -------
    taus : ndarray
        (2^k - 1) / rate, s: the span of each window (AllanTools returns 2^(k-1) unscaled).
    devs : ndarray
        MTIE of each window length, s.
    errs : ndarray
        devs / sqrt(ns).
    ns : ndarray
        Number of windows, 2^K - 2^k + 1.
    """
    rate = _args.rate(rate)
    x = _phase_of(phase, rate, data_type, "phase")
    k_max = int(np.floor(np.log2(x.shape[0])))
    x = x[: 2 ** k_max]
    m = np.array([2 ** k - 1 for k in range(1, k_max + 1)], dtype=np.int64)
    devs, ns = _cubecal._deviation("mtie", x, rate, "phase", m) if m.size else (np.zeros(0), np.zeros(0, np.int64))
    return _kept(m, rate, devs, devs / np.sqrt(ns.clip(1)), ns)


@public
def three_cornered_hat_phase(phasedata_ab, phasedata_bc, phasedata_ca, rate, taus, function):
    """Three-cornered hat: clock A's deviation from the three pairs' phase.

    var_A = (var_AB + var_CA - var_BC) / 2, negative values set to zero.

    Parameters
    ----------
    phasedata_ab, phasedata_bc, phasedata_ca : array_like
        Phase differences A-B, B-C, C-A, s.
    rate : float
        Sampling rate, Hz.
    taus : None, str or array_like
        As `adev`.
    function : callable
        The deviation, e.g. cubecal.oadev.

    Returns
    -------
    tau_ab : ndarray
        Averaging times, s.
    dev_a : ndarray
        Clock A's deviation.
    err_a : list of float
        dev_a / sqrt(ns).
    ns_ab : ndarray
        The AB deviation's number of terms.
    """
    if not callable(function):
        raise usage("function", f"function: a deviation such as cubecal.oadev is expected, not {function!r}")
    tau_ab, dev_ab, _, ns_ab = function(phasedata_ab, data_type="phase", rate=rate, taus=taus)
    tau_bc, dev_bc, _, _ = function(phasedata_bc, data_type="phase", rate=rate, taus=taus)
    tau_ca, dev_ca, _, _ = function(phasedata_ca, data_type="phase", rate=rate, taus=taus)
    if not (len(dev_ab) == len(dev_bc) == len(dev_ca)):
        raise usage("phasedata_bc", "phasedata_ab, phasedata_bc and phasedata_ca must give the same taus "
                                    "(records of one length)")
    var_a = 0.5 * (dev_ab * dev_ab + dev_ca * dev_ca - dev_bc * dev_bc)
    var_a[var_a < 0] = 0.0
    dev_a = np.sqrt(var_a)
    err_a = [d / np.sqrt(n) for d, n in zip(dev_a, ns_ab)]
    return tau_ab, dev_a, err_a, ns_ab
