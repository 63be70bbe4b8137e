"""cubecal.psd and cubecal.davar: `cubecal psd` and `cubecal davar` on a
file or on arrays; each result's to_dict() is the command's JSON."""
import os

from . import _args, _cubecal
from ._data import channels_of, string_list
from ._read import read_args
from ._result import Result


class Spectrum(Result):
    """The result of cubecal.psd, as `cubecal psd --format json`: welch {window,
    segment_length, overlap, detrend, ...} and channels [{name, unit,
    frequency_hz, density (unit^2/Hz, one-sided), density_rate ((deg/h)^2/Hz for
    rate sensors), edf, fit {terms [{alpha, h, sigma}], f_lo, f_hi, ...},
    allan_terms [{term, value, sigma, display}]}]."""


class DynamicAllan(Result):
    """The result of cubecal.davar, as `cubecal davar --format json`: window,
    step, windows, intervals and channels [{name, t (window centres, s), tau,
    dev (tau x time), n, and with intervals lo, hi, edf, alpha}]."""


def _source(data, rate, names, read_options):
    """(path, read args, arrays, names, rate) of a call's data."""
    if isinstance(data, (str, os.PathLike)):
        if names is not None:
            raise _args.usage("names", "names: give columns= to choose the columns of a file")
        ro = dict(read_options)
        if rate is not None:
            ro["rate"] = rate
        return _args.path(data, "data"), read_args(**ro), [], [], 0.0
    if read_options:
        raise _args.usage(next(iter(read_options)),
                          f"{', '.join(read_options)}: options of a file; data are arrays here")
    names, arrays = channels_of(data, names)
    if rate is None:
        rate = getattr(data, "rate_hz", None)
        if not rate:
            raise _args.usage("rate", "rate: give the sampling rate of the arrays in Hz")
    return None, read_args(), arrays, names, _args.rate(rate)


def _duration_or_samples(value, option):
    """A duration ("1h", "60s") as it is, or a whole number of samples as text."""
    if isinstance(value, str):
        return value
    return str(_args.count(value, option))


@_args.public
def psd(data, rate=None, unit=None, window="hann", segment=0, fmin=0.0, overlap=0.5, detrend="constant",
        bins_per_decade=0, fit=True, fit_min=0.0, fit_max=0.0, names=None, threads=0, **read_options):
    """One-sided power spectral density of each channel by Welch's method
    (equal to scipy.signal.welch), its power-law fit and the IEEE 952 terms
    the fitted coefficients stand for, as `cubecal psd`.

    data: a path (read_options as cubecal.read) or arrays sampled at `rate`
    Hz. unit: one for all channels or one per channel (default: from the
    names, else none). window: hann, hamming, blackman, rectangular;
    segment: samples per segment (0: about n/8, or from fmin); overlap: the
    fraction shared; detrend: none, constant, linear; bins_per_decade: 0 for
    every bin, K to average over K log bands per decade; fit_min/fit_max: the
    fitted band in Hz. Returns a Spectrum.
    """
    a = _cubecal._PsdArgs()
    a.window, a.segment = _args.text(window, "window"), _args.count(segment, "segment")
    a.fmin, a.overlap = _args.number(fmin, "fmin"), _args.number(overlap, "overlap")
    a.detrend, a.bins_per_decade = _args.text(detrend, "detrend"), _args.count(bins_per_decade, "bins_per_decade")
    a.fit, a.fit_min = _args.flag(fit, "fit"), _args.number(fit_min, "fit_min")
    a.fit_max = _args.number(fit_max, "fit_max")
    a.units = string_list(unit, "unit")
    a.threads = _args.threads(threads)
    path, ra, arrays, names, rate = _source(data, rate, names, read_options)
    try:
        d, spectra = _cubecal._psd(path, ra, arrays, names, rate, a)
    except _cubecal.UsageError as e:
        if e.option != "fit_range":
            raise
        # The band is the CLI's --fit-range; here it is fit_min and fit_max.
        keyword = "fit_max" if fit_max and not fit_min else "fit_min"
        raise _args.usage(keyword, "fit_min, fit_max: " + str(e).split(": ", 1)[-1]) from None
    for channel, arrays_of in zip(d["channels"], spectra):
        channel.update(arrays_of)  # the long arrays come as NumPy arrays, not as lists
    return Spectrum(d)


@_args.public
def davar(data, rate=None, window=None, step=None, taus="log:10", data_type="freq", intervals=True, ci=0.683,
          alpha=None, names=None, threads=0, **read_options):
    """Dynamic Allan deviation, as `cubecal davar`: the overlapping Allan
    deviation of a window sliding along the record, a tau x time matrix per
    channel (exact, from block sums).

    window, step: a duration ("1h", "60s") or a number of samples (default: a
    tenth of the record, a tenth of the window); taus: a grid or taus in
    seconds; alpha: a fixed noise type for the intervals, -2 to +2 (default:
    identified in each cell). Returns a DynamicAllan.
    """
    a = _cubecal._DavarArgs()
    a.type = _args.text(data_type, "data_type")
    a.window = "" if window is None else _duration_or_samples(window, "window")
    a.step = "" if step is None else _duration_or_samples(step, "step")
    a.taus = _args.taus(taus)
    a.intervals = _args.flag(intervals, "intervals")
    a.ci = _args.number(ci, "ci")
    a.alpha = _args.optional_count(alpha, "alpha", minimum=-_args.INT_MAX, maximum=_args.INT_MAX)
    a.threads = _args.threads(threads)
    path, ra, arrays, names, rate = _source(data, rate, names, read_options)
    return DynamicAllan(_cubecal._davar(path, ra, arrays, names, rate, a))
