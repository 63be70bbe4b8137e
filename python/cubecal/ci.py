"""Confidence intervals, equivalent degrees of freedom and noise
identification in AllanTools' shape (``allantools.ci``).

    import cubecal as allantools
    edf = allantools.edf_greenhall(alpha=0, d=2, m=4, N=len(x), overlapping=True)
    lo, hi = allantools.confidence_interval(dev, edf)
    alpha_int, alpha, d, rho = allantools.autocorr_noise_id(x, af=4)

The same names, arguments, defaults and return values as AllanTools'
``allantools/ci.py``; the numbers come from cubecal's C++ library
(``cubecal/stats/edf.hpp``, ``noise_id.hpp``, ``confidence.hpp``). Where
AllanTools returns NaN, fails an assertion or divides by zero, cubecal raises a
:class:`cubecal.UsageError` naming the argument; where AllanTools raises
NotImplementedError, :class:`NoEstimateError` is also a NotImplementedError.
``cubecal.dev`` gives Stable32's noise identification and intervals instead;
docs/allantools-differences/ci.md lists where the two differ and why.

Units: ``dev`` in the deviation's unit (the intervals come back in it),
``x`` phase in seconds or fractional frequency (any unit: the ratios do not
depend on it), ``m``/``af`` averaging factors (tau = m / rate), ``N`` numbers
of points; EDFs and ratios are dimensionless.
"""
import math
import numbers

import numpy as np

from . import _args, _cubecal
from ._args import count, public, usage

__all__ = [
    "ONE_SIGMA_CI", "NoEstimateError", "confidence_interval", "confidence_interval_noiseID", "rn", "rn_theory",
    "rn_boundary", "b1", "b1_theory", "b1_boundary", "b_to_mu", "lag1_acf", "autocorr_noise_id", "detrend",
    "edf_greenhall_simple", "edf_greenhall", "greenhall_BasicSum", "greenhall_sz", "greenhall_sx", "greenhall_sw",
    "greenhall_table1", "greenhall_table2", "greenhall_table3", "edf_totdev", "edf_mtotdev", "edf_simple",
]

#: The confidence of a one-sigma interval, erf(1/sqrt(2)) = 0.6826894921370859.
ONE_SIGMA_CI = math.erf(1.0 / math.sqrt(2.0))

# The smallest number of points AllanTools' lag-1 noise identification takes.
_MIN_LAG1_POINTS = 30


class NoEstimateError(_cubecal.UsageError, NotImplementedError):
    """The method has no estimate for these arguments (fewer than 30 points
    for the lag-1 noise identification, a deviation type without an EDF).
    A cubecal.UsageError and a NotImplementedError, which AllanTools raises
    in these cases."""


def _no_estimate(option, message):
    e = NoEstimateError(" ".join(message.split()))
    e.option = option
    return e


def _whole(value, option, minimum, maximum=_args.INT_MAX):
    """A whole number (AllanTools takes Stable32's 1.0 as well as 1)."""
    return count(value, option, minimum=minimum, maximum=maximum)


# What each exponent argument is, for the messages.
_EXPONENTS = {"alpha": "the frequency-noise exponent (2 white PM, 0 white FM, -2 random-walk FM)",
              "b": "the phase-noise exponent b = alpha - 2 (0 white PM, -2 white FM)",
              "b_hi": "the upper phase-noise exponent b = alpha - 2 (0 white PM, -2 white FM)",
              "mu": "the exponent of B1's bias, tau^mu"}


def _alpha(value, option="alpha", lowest=-4, highest=2):
    """A noise exponent: a whole number (2 or 2.0) from lowest to highest."""
    if isinstance(value, numbers.Real) and not isinstance(value, (bool, np.bool_)):
        if math.isfinite(float(value)) and float(value).is_integer() and lowest <= int(value) <= highest:
            return int(value)
    raise usage(option, f"{option}: {_EXPONENTS[option]}, a whole number from {highest} to {lowest}, "
                        f"is expected, not {_args._shown(value)}")


def _d(value):
    return _whole(value, "d", 1, 3)


def _record(x, option="x", minimum=2):
    a = _args.samples(x, option, dimensions=(1, 2))
    if a.ndim == 2:
        if a.shape[1] != 1:
            raise usage(option, f"{option}: a 1-D array (or an (N, 1) column) is expected, got shape {a.shape}")
        a = a[:, 0]
    if not np.all(np.isfinite(a)):
        raise usage(option, f"{option}: NaN or infinite values; remove them first")
    if a.size < minimum:
        raise usage(option, f"{option}: at least {minimum} points are expected, got {a.size}")
    return np.ascontiguousarray(a)


def _data_type(value):
    if value not in ("phase", "freq"):
        raise usage("data_type", f"data_type must be \"phase\" or \"freq\", not {value!r}")
    return value


def _finite(value, option, what):
    v = float(value)
    if not math.isfinite(v):
        raise usage(option, f"{option}: the arguments give no finite {what} ({v}); N is too short for m")
    return v


########################################################################
# Confidence intervals

@public
def confidence_interval(dev, edf, ci=ONE_SIGMA_CI):
    """Chi-squared confidence interval of a deviation (NIST SP 1065 eq. 45).

    Parameters
    ----------
    dev : float or array_like
        The deviation (e.g. an ADEV), in its own unit; not negative.
    edf : float or array_like
        Equivalent degrees of freedom (positive), one per dev or one for all.
    ci : float, optional
        Confidence of the two-sided interval, 0 < ci < 1; default
        ONE_SIGMA_CI = erf(1/sqrt(2)) = 0.683. As in AllanTools, ci and 1 - ci
        give the same interval (the larger of the two is the confidence).

    Returns
    -------
    (dev_min, dev_max) : (float, float) or (ndarray, ndarray)
        The interval's bounds, in dev's unit: numbers for numbers, arrays of
        the broadcast shape for arrays.
    """
    c = _args.number(ci, "ci")
    if not 0.0 < c < 1.0:
        raise usage("ci", f"ci: a confidence between 0 and 1 (exclusive) is expected, not {ci!r}")
    c = max(c, 1.0 - c)
    try:
        d, e = np.broadcast_arrays(np.asarray(dev, dtype=np.float64), np.asarray(edf, dtype=np.float64))
    except (TypeError, ValueError):
        raise usage("edf", "edf: one number, or an array the shape of dev's, is expected") from None
    if not np.all(np.isfinite(d)) or np.any(d < 0.0):
        raise usage("dev", f"dev: a finite deviation, not negative, is expected, not {_args._shown(dev)}")
    if not np.all(np.isfinite(e)) or np.any(e <= 0.0):
        raise usage("edf", f"edf: positive equivalent degrees of freedom are expected, not {_args._shown(edf)} "
                           "(an EDF of 0 means the estimator has no interval)")
    lo, hi = _cubecal._ci_intervals(np.ascontiguousarray(d.ravel()), np.ascontiguousarray(e.ravel()), c)
    if d.ndim == 0:
        return (np.float64(lo[0]), np.float64(hi[0]))
    return (lo.reshape(d.shape), hi.reshape(d.shape))


# Greenhall's (d, overlapping, modified) for the deviation types AllanTools'
# confidence_interval_noiseID knows.
_DEV_TYPES = {
    "adev": (2, False, False),
    "oadev": (2, True, False),
    "mdev": (2, True, True),
    "tdev": (2, True, True),
    "hdev": (3, False, False),
    "ohdev": (3, True, False),
}


@public
def confidence_interval_noiseID(x, dev, af, dev_type="adev", data_type="phase", ci=ONE_SIGMA_CI):
    """Confidence interval of a deviation at averaging factor af, with the
    noise type identified from the data: autocorr_noise_id, then
    edf_greenhall, then confidence_interval.

    Parameters
    ----------
    x : array_like
        The time series: phase (s) or fractional frequency, as data_type says.
    dev : float
        The deviation at tau = af / rate, in its own unit.
    af : int
        Averaging factor (tau = af * tau0).
    dev_type : str, optional
        "adev", "oadev", "mdev", "tdev", "hdev" or "ohdev" (default "adev").
    data_type : str, optional
        "phase" (default) or "freq".
    ci : float, optional
        Confidence, default ONE_SIGMA_CI (0.683).

    Returns
    -------
    (dev_min, dev_max) : (float, float)
        The interval's bounds, in dev's unit.

    Raises
    ------
    NoEstimateError
        (a NotImplementedError) for fewer than 30 points at af, or another
        dev_type.

    Notes
    -----
    As AllanTools, the EDF is taken on N = len(x) points whatever data_type,
    and the noise identification differences up to d = 3 for the Hadamard
    types, 2 otherwise.
    """
    if dev_type not in _DEV_TYPES:
        raise _no_estimate("dev_type", f"dev_type: {dev_type!r} has no EDF here; one of "
                                       f"{', '.join(_DEV_TYPES)} is expected")
    d, overlapping, modified = _DEV_TYPES[dev_type]
    data = _record(x)
    m = _whole(af, "af", 1)
    alpha_int = autocorr_noise_id(data, m, data_type=data_type, dmin=0, dmax=3 if d == 3 else 2)[0]
    edf = edf_greenhall(alpha=alpha_int, d=d, m=m, N=len(data), overlapping=overlapping, modified=modified)
    return confidence_interval(dev, edf, ci)


########################################################################
# Noise identification by R(n)

@public
def rn(x, af, rate):
    """R(n) = MVAR / AVAR of a phase record at averaging factor af.

    Parameters
    ----------
    x : array_like
        Phase (s; any unit: the ratio does not depend on it).
    af : int
        Averaging factor.
    rate : float
        Sampling rate (Hz); the ratio does not depend on it (AllanTools asks
        the deviations at tau = af * rate, which is af / rate at rate 1 only:
        cubecal takes the averaging factor af at every rate).

    Returns
    -------
    float
        MVAR over the non-overlapping AVAR at af (dimensionless).
    """
    _args.rate(rate)
    data = _record(x)
    m = _whole(af, "af", 1)
    if 3 * m >= len(data):
        raise usage("af", f"af: {m} needs more than {3 * m} phase points for MVAR; x has {len(data)}")
    v = _cubecal._ci_rn_ratio(data, m)
    if not v > 0.0:
        raise usage("x", f"x: the Allan variance at af = {m} is 0 (constant frequency); R(n) is undefined")
    return v


@public
def rn_theory(af, b):
    """R(n) expected for a noise type (IEEE 1139-2008).

    Parameters
    ----------
    af : float
        Averaging factor (positive).
    b : int
        Exponent of the phase PSD, b = alpha - 2: 0 white PM, -1 flicker PM,
        -2 white FM, ... (-6 random-run FM).

    Returns
    -------
    float
        1/af for white PM; for flicker PM, with the phase bandwidth
        f_h = 1/(2 tau0), (3 ln(256/27)/2) / (1.038 + 3 ln(pi af)); 1
        otherwise (dimensionless).
    """
    m = _args.number(af, "af", positive=True)
    alpha = _alpha(b, "b", lowest=-6, highest=0) + 2
    return _cubecal._ci_rn_expected(m, alpha)


@public
def rn_boundary(af, b_hi):
    """R(n) boundary between noise types b_hi - 1 and b_hi: the geometric
    mean of their expected R(n).

    Parameters
    ----------
    af : float
        Averaging factor (positive).
    b_hi : int
        The upper phase-PSD exponent (b = alpha - 2), -5 to 0.

    Returns
    -------
    float
        sqrt(rn_theory(af, b_hi) * rn_theory(af, b_hi - 1)) (dimensionless).
    """
    b = _alpha(b_hi, "b_hi", lowest=-5, highest=0)
    return np.sqrt(rn_theory(af, b) * rn_theory(af, b - 1))


########################################################################
# Noise identification by B1

@public
def b1(x, af, rate):
    """Barnes' B1 ratio of a phase record at averaging factor af: the sample
    variance of the non-overlapping frequency averages over their Allan
    variance.

    Parameters
    ----------
    x : array_like
        Phase (s; any unit: the ratio does not depend on it).
    af : int
        Averaging factor; at least 3 averages are needed.
    rate : float
        Sampling rate (Hz); the ratio does not depend on it (see rn).

    Returns
    -------
    float
        The B1 ratio (dimensionless).
    """
    _args.rate(rate)
    data = _record(x)
    m = _whole(af, "af", 1)
    if (len(data) - 1) // m < 3:
        raise usage("af", f"af: {m} leaves fewer than 3 frequency averages of the {len(data)} phase points")
    v = _cubecal._ci_b1_ratio(data, m)
    if not v > 0.0:
        raise usage("x", f"x: the averages at af = {m} do not vary; B1 is undefined")
    return v


@public
def b1_theory(N, mu):
    """Expected B1 ratio for N averages and bias exponent mu (Howe, Beard,
    Greenhall & Riley, PTTI 2000, Table 3).

    Parameters
    ----------
    N : int
        Number of frequency averages (at least 2).
    mu : int
        Exponent of the bias, tau^mu: 2 .. -2 (see b_to_mu).

    Returns
    -------
    float
        The expected B1 (dimensionless).
    """
    n = _args.number(N, "N", minimum=2.0)
    mu = _alpha(mu, "mu", lowest=-2, highest=3)
    return _cubecal._ci_b1_expected(n, mu)


@public
def b1_boundary(b_hi, N):
    """B1 boundary between the noise types b_hi - 1 and b_hi: the geometric
    mean of their expected B1 ratios (as AllanTools; its arithmetic-mean
    branch is never taken).

    Parameters
    ----------
    b_hi : int
        The upper phase-PSD exponent (b = alpha - 2), -5 to 0.
    N : int
        Number of frequency averages.

    Returns
    -------
    float
        The boundary (dimensionless).
    """
    b = _alpha(b_hi, "b_hi", lowest=-5, highest=0)
    lo = b1_theory(N, b_to_mu(b - 1))
    hi = b1_theory(N, b_to_mu(b))
    return np.sqrt(lo * hi)


@public
def b_to_mu(b):
    """The bias exponent mu of B1 for phase-PSD exponent b (alpha = b + 2).

    Parameters
    ----------
    b : int
        0 (white PM) to -6 (random-run FM).

    Returns
    -------
    int
        -2 for white and flicker PM (b = 0, -1), -alpha - 1 = -b - 3 below.
    """
    alpha = _alpha(b, "b", lowest=-6, highest=0) + 2
    return -2 if alpha >= 1 else -alpha - 1


########################################################################
# Noise identification by the lag-1 autocorrelation

@public
def lag1_acf(x, detrend_deg=1):
    """Lag-1 autocorrelation of x about its mean (Riley & Greenhall 2004, eq. 2).

    Parameters
    ----------
    x : array_like
        The series (any unit), at least 2 points, not constant.
    detrend_deg : int, optional
        Accepted and not used, as in AllanTools (detrend first with detrend()).

    Returns
    -------
    float
        sum (x[n]-mean)(x[n+1]-mean) / sum (x[n]-mean)^2 (dimensionless).
    """
    _whole(detrend_deg, "detrend_deg", 0)
    data = _record(x)
    if np.all(data == data[0]):
        raise usage("x", "x: a constant series has no autocorrelation")
    return _cubecal._ci_lag1_acf(data)


@public
def autocorr_noise_id(x, af, data_type="phase", dmin=0, dmax=2):
    """Noise identification by the lag-1 autocorrelation (Riley & Greenhall 2004).

    Phase data are decimated by af (every af-th point) and their quadratic
    removed; frequency data are averaged over af and their line removed.
    The series is then differenced until d >= dmin and (rho < 0.25 or
    d >= dmax), rho = r1 / (1 + r1).

    Parameters
    ----------
    x : array_like
        Phase (s) or fractional frequency, as data_type says; at least 30
        points after the decimation or averaging.
    af : int
        Averaging factor.
    data_type : str, optional
        "phase" (default) or "freq".
    dmin : int, optional
        Fewest differences taken (default 0).
    dmax : int, optional
        Most differences taken (default 2; 3 for the Hadamard deviations).

    Returns
    -------
    alpha_int : int
        The noise exponent of the frequency PSD, rounded: +2 white PM ...
        -2 random-walk FM (-4 with dmax = 3).
    alpha : float
        The unrounded estimate.
    d : int
        Differences taken.
    rho : float
        r1 / (1 + r1) of the last series.

    Raises
    ------
    NoEstimateError
        (a NotImplementedError, as AllanTools raises) for fewer than 30 points.
    """
    data = _record(x)
    m = _whole(af, "af", 1)
    phase = _data_type(data_type) == "phase"
    lo = _whole(dmin, "dmin", 0, 16)
    hi = _whole(dmax, "dmax", 0, 16)
    r = _cubecal._ci_lag1_noise_id(data, m, phase, lo, hi)
    if r is None:
        left = -(-len(data) // m) if phase else len(data) // m
        what = "phase points taken every af-th" if phase else "averages of af frequency points"
        raise _no_estimate("af", f"af: {m} leaves {left} {what}; the lag-1 noise identification needs "
                                 f"{_MIN_LAG1_POINTS}: use a smaller af")
    alpha_int, alpha, d, rho = r
    return alpha_int, np.float64(alpha), d, np.float64(rho)


@public
def detrend(x, deg=1):
    """x minus its least-squares polynomial of degree deg in the index.

    Parameters
    ----------
    x : array_like
        The series (any unit), at least deg + 1 points.
    deg : int, optional
        Degree of the polynomial, 0 to 8 (default 1: a line).

    Returns
    -------
    ndarray
        The residual, in x's unit.
    """
    k = _whole(deg, "deg", 0, 8)
    data = _record(x, minimum=k + 1)
    return _cubecal._ci_detrend(data, k)


########################################################################
# Equivalent degrees of freedom

def _greenhall_pieces(alpha, d):
    return _alpha(alpha), _d(d)


def _filter_factor(F, option="F"):
    """A positive filter factor; float('inf') (a point sample) as well."""
    if isinstance(F, numbers.Real) and not isinstance(F, (bool, np.bool_)) and float(F) == math.inf:
        return math.inf
    return _args.number(F, option, positive=True)


def _point_sample(F, alpha):
    """F and alpha, refusing a point sample (F infinite, Greenhall's kernel
    at alpha + 2) of a noise steeper than white FM, which has no kernel."""
    f = _filter_factor(F)
    if f == math.inf and alpha > 0:
        raise usage("F", f"F: a point sample (F = inf) is defined for alpha <= 0 only, not alpha = {alpha}")
    return f


@public
def edf_greenhall_simple(alpha, d, m, S, F, N):
    """Greenhall's eq. (13) summed directly, at every size (no tables).

    Parameters
    ----------
    alpha : int
        Noise exponent, 2 .. -4.
    d : int
        Order of the phase difference: 1, 2 (Allan) or 3 (Hadamard).
    m : float
        Averaging factor.
    S : float
        Stride factor: 1 non-overlapping, m fully overlapping.
    F : float
        Filter factor: 1 modified, m unmodified (inf: a point sample).
    N : int
        Number of phase points.

    Returns
    -------
    float
        The EDF (dimensionless).
    """
    a, dd = _greenhall_pieces(alpha, d)
    mm = _args.number(m, "m", positive=True)
    s = _args.number(S, "S", positive=True)
    f = _point_sample(F, a)
    n = _args.number(N, "N", positive=True)
    if n < mm / f + mm * dd:
        raise usage("N", f"N: {N!r} phase points are fewer than the filter's span m/F + m d = {mm / f + mm * dd:g}")
    return _finite(_cubecal._ci_greenhall_eq13(a, dd, mm, s, f, n), "N", "EDF")


@public
def edf_greenhall(alpha, d, m, N, overlapping=False, modified=False, verbose=False):
    """Equivalent degrees of freedom of a variance on d-th phase differences
    (Greenhall & Riley, PTTI 2003; Greenhall 2004).

    Parameters
    ----------
    alpha : int
        Noise exponent of the frequency PSD, +2 (white PM) to -4 (random-run
        FM); alpha + 2 d > 1.
    d : int
        1 (first difference), 2 (Allan variances) or 3 (Hadamard variances).
    m : int
        Averaging factor, tau = m / rate.
    N : int
        Number of phase points.
    overlapping : bool, optional
        True for oadev, ohdev, mdev, tdev (default False).
    modified : bool, optional
        True for mdev, tdev (default False).
    verbose : bool, optional
        Print the case of the algorithm that answered, as AllanTools does.

    Returns
    -------
    float
        The EDF (dimensionless).

    Notes
    -----
    Unmodified white PM with ceil(r) <= d, where AllanTools raises
    NotImplementedError, is answered by the direct sum (case "4.1").
    """
    a, dd = _greenhall_pieces(alpha, d)
    if a + 2 * dd <= 1:
        raise _no_estimate("alpha", f"alpha: {a} with d = {dd} has no EDF (alpha + 2 d > 1 is needed)")
    mm = _whole(m, "m", 1, _args.SIZE_MAX)
    n = _whole(N, "N", 1, _args.SIZE_MAX)
    over = _args.flag(overlapping, "overlapping")
    mod = _args.flag(modified, "modified")
    span = mm * (dd + 1) if mod else 1 + mm * dd
    if n < span:
        raise usage("N", f"N: {n} phase points are fewer than the {span} that one term at m = {mm} spans")
    edf, case = _cubecal._ci_edf_greenhall(a, dd, mm, n, over, mod)
    if _args.flag(verbose, "verbose"):
        print("case %s edf= %3f" % (case, edf))
    return _finite(edf, "N", "EDF")


@public
def greenhall_BasicSum(J, M, S, F, alpha, d):
    """Greenhall's eq. (10), the basic sum over J lags of M terms.

    Parameters
    ----------
    J, M : int
        Lags summed and number of terms.
    S : float
        Stride factor.
    F : float
        Filter factor (inf: a point sample).
    alpha : int
        Noise exponent, 2 .. -4.
    d : int
        Difference order, 1 .. 3.

    Returns
    -------
    float
        The sum (dimensionless).
    """
    a, dd = _greenhall_pieces(alpha, d)
    return _cubecal._ci_greenhall_basic_sum(_args.number(J, "J", minimum=0.0), _args.number(M, "M", positive=True),
                                            _args.number(S, "S", positive=True), _point_sample(F, a), a, dd)


@public
def greenhall_sz(t, F, alpha, d):
    """Greenhall's eq. (9): sx under the d-th difference, at lag t (units of tau).

    Parameters
    ----------
    t : float
        Lag, in units of tau.
    F : float
        Filter factor (inf: a point sample).
    alpha : int
        Noise exponent, 2 .. -4.
    d : int
        Difference order, 1 .. 3.

    Returns
    -------
    float
        sz(t) (dimensionless).
    """
    a, dd = _greenhall_pieces(alpha, d)
    return _cubecal._ci_greenhall_sz(_args.number(t, "t"), _point_sample(F, a), a, dd)


@public
def greenhall_sx(t, F, alpha):
    """Greenhall's eq. (8): sw under the averaging filter of length 1/F.

    Parameters
    ----------
    t : float
        Lag, in units of tau.
    F : float
        Filter factor (inf: a point sample).
    alpha : int
        Noise exponent, 2 .. -4.

    Returns
    -------
    float
        sx(t) (dimensionless).
    """
    a = _alpha(alpha)
    return _cubecal._ci_greenhall_sx(_args.number(t, "t"), _point_sample(F, a), a)


@public
def greenhall_sw(t, alpha):
    """Greenhall's eq. (7): the generalized autocovariance kernel at lag t.

    Parameters
    ----------
    t : float
        Lag, in units of tau.
    alpha : int
        Noise exponent, 2 .. -4.

    Returns
    -------
    float
        sw(t) (dimensionless).
    """
    return _cubecal._ci_greenhall_sw(_args.number(t, "t"), _alpha(alpha))


def _coefficients(pair):
    a0, a1 = pair
    return (-1, -1) if a0 == 0.0 and a1 == 0.0 else (a0, a1)


@public
def greenhall_table1(alpha, d):
    """Greenhall's Table 1 (modified variances, large r).

    Parameters
    ----------
    alpha : int
        Noise exponent, 2 .. -4.
    d : int
        Difference order, 1 .. 3.

    Returns
    -------
    (a0, a1) : (float, float)
        The coefficients of 1/EDF = (a0 - a1/r)/r; (-1, -1) where the
        variance does not converge, as AllanTools.
    """
    a, dd = _greenhall_pieces(alpha, d)
    return _coefficients(_cubecal._ci_greenhall_table1(a, dd))


@public
def greenhall_table2(alpha, d):
    """Greenhall's Table 2 (unmodified variances, large r).

    Parameters
    ----------
    alpha : int
        Noise exponent, 2 .. -4.
    d : int
        Difference order, 1 .. 3.

    Returns
    -------
    (a0, a1) : (float, float)
        The coefficients; (-1, -1) where the variance does not converge.
    """
    a, dd = _greenhall_pieces(alpha, d)
    return _coefficients(_cubecal._ci_greenhall_table2(a, dd))


@public
def greenhall_table3(alpha, d):
    """Greenhall's Table 3 (unmodified flicker PM): the log factor b0 + b1 ln m.

    Parameters
    ----------
    alpha : int
        Noise exponent; only 1 (flicker PM) has a row.
    d : int
        Difference order, 1 .. 3.

    Returns
    -------
    (b0, b1) : (float, float)
        The coefficients (dimensionless).
    """
    a, dd = _greenhall_pieces(alpha, d)
    if a != 1:
        raise usage("alpha", f"alpha: Table 3 is for flicker PM (alpha = 1) only, not {a}")
    return _cubecal._ci_greenhall_table3(dd)


@public
def edf_totdev(N, m, alpha):
    """Equivalent degrees of freedom of TOTDEV (NIST SP 1065, Table 11:
    b N/m - c for white, flicker and random-walk FM; edf_simple otherwise).

    Parameters
    ----------
    N : int
        Number of phase points.
    m : int
        Averaging factor.
    alpha : int
        Noise exponent, 2 .. -2 (other values: N - 1, as edf_simple).

    Returns
    -------
    float
        The EDF (dimensionless).
    """
    a = _alpha(alpha, lowest=-8, highest=8)
    if a in (0, -1, -2):
        n = _whole(N, "N", 1, _args.SIZE_MAX)
        mm = _whole(m, "m", 1, _args.SIZE_MAX)
        return _cubecal._ci_edf_totvar(a, mm, n)
    return edf_simple(N, m, a)


@public
def edf_mtotdev(N, m, alpha):
    """Equivalent degrees of freedom of MTOTDEV by NIST SP 1065 Table 8,
    b N/m - c, at every m (cubecal.dev takes MDEV's EDF below m = 10, as
    Stable32).

    Parameters
    ----------
    N : int
        Number of phase points.
    m : float
        Averaging factor.
    alpha : int
        Noise exponent, 2 .. -2.

    Returns
    -------
    float
        The EDF (dimensionless; the table's line, negative where N/m is small).
    """
    a = _alpha(alpha, lowest=-2, highest=2)
    n = _args.number(N, "N", positive=True)
    mm = _args.number(m, "m", positive=True)
    return _cubecal._ci_edf_mtotvar_table(a, mm, n)


@public
def edf_simple(N, m, alpha):
    """Equivalent degrees of freedom of the overlapping ADEV by the simple
    approximations of NIST SP 1065, Table 5 (Stein 1985).

    Parameters
    ----------
    N : int
        Number of phase points.
    m : int
        Averaging factor, tau = m * tau0.
    alpha : int
        Noise exponent: 2 white PM, 1 flicker PM, 0 white FM, -1 flicker FM,
        -2 random-walk FM; any other whole number gives N - 1 (uncorrelated).

    Returns
    -------
    float
        The EDF (dimensionless).
    """
    a = _alpha(alpha, lowest=-8, highest=8)
    n = _whole(N, "N", 2, _args.SIZE_MAX)
    mm = _whole(m, "m", 1, _args.SIZE_MAX)
    if a in (2, 1) and n <= 2 * mm:
        raise usage("N", f"N: {n} phase points are too few for m = {mm} (more than 2 m are needed)")
    return _finite(_cubecal._ci_edf_simple(a, mm, n), "N", "EDF")
