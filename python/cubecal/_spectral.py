"""cubecal.psd and cubecal.davar: `cubecal psd` and `cubecal davar` on a
file or on arrays; each result's to_dict() is the command's JSON."""
import os

from . import _args, _cubecal
from ._data import channels_of, string_list
from ._read import read_args
from ._result import Quantity, Result, _fmt


class Welch(Result):
    """The plan of a Welch power spectral density."""

    __slots__ = ()
    _spec = """
    window: str -- the window (hann, hamming, blackman, rectangular)
    segment_length: int -- samples per segment
    overlap: float -- the fraction of a segment shared with the next (0 to 1)
    overlap_samples: int -- the samples shared
    detrend: str -- none, constant or linear
    segments: int -- segments averaged
    samples_used: int -- samples the segments cover
    resolution_hz: float -- the bin width, Hz
    enbw_hz: float -- the window's equivalent noise bandwidth, Hz
    bins_per_decade?: int -- log bands per decade the density is averaged over (0: every bin)
    pieces?: int -- contiguous pieces of the record (split at gaps)
    pieces_used?: int -- the pieces long enough for a segment
    """

    def _summary(self):
        return f"{self.window}, {self.segments} segments of {self.segment_length} samples, " \
               f"{_fmt(self.resolution_hz)} Hz bins"


class PowerLawTerm(Result):
    """A term h_alpha f^alpha of a power-law fit to a spectrum."""

    __slots__ = ()
    _spec = """
    alpha: int -- the exponent of f
    h: float -- the coefficient, in `unit`
    sigma: float -- its 1-sigma uncertainty, in `unit`
    valid: bool -- whether the fit determines it
    unit: str -- the unit of h (the density unit times Hz^-alpha)
    f_lo_hz: float -- lower end of the band the term dominates, Hz
    f_hi_hz: float -- upper end, Hz
    """


class PowerLawFit(Result):
    """The power-law fit S(f) = sum h_alpha f^alpha of a spectrum."""

    __slots__ = ()
    _spec = """
    f_lo_hz: float -- lower end of the fitted band, Hz
    f_hi_hz: float -- upper end, Hz
    bands: int -- the log bands fitted
    chi2: float -- the fit's chi-squared
    dof: int -- its degrees of freedom
    scale: float -- the fit's scale factor
    terms: list[PowerLawTerm] -- the terms
    covariance: matrix -- the covariance of the terms' h (one row and column per term)
    """

    def _summary(self):
        return f"{len(self.terms)} terms over {_fmt(self.f_lo_hz)} .. {_fmt(self.f_hi_hz)} Hz"


class AllanTermDisplay(Result):
    """An IEEE 952 term in its display unit."""

    __slots__ = ()
    _spec = """
    value: float -- the value, in `unit`
    sigma: float -- its 1-sigma uncertainty, in `unit`
    unit: str -- the display unit (e.g. "deg/sqrt(h)")
    """


class AllanTerm(Result):
    """An IEEE 952 term (N, B, K, Q, R) a power-law coefficient stands for."""

    __slots__ = ()
    _spec = """
    term: str -- N, B, K, Q or R
    alpha: int -- the power-law exponent it comes from
    valid: bool -- whether the fit determines it
    value: float -- the term, in `unit`
    sigma: float -- its 1-sigma uncertainty, in `unit`
    unit: str -- the unit in the data unit and seconds (e.g. "deg/s*sqrt(s)")
    display: AllanTermDisplay -- the same in the display unit
    """


class DensityRate(Result):
    """A rate sensor's density in the unit rate sensors are quoted in."""

    __slots__ = ()
    _spec = """
    unit: str -- the unit, e.g. "(deg/h)^2/Hz"
    values: array -- the density at each frequency, in `unit`
    """


class SpectrumChannel(Result):
    """A channel's one-sided power spectral density and its fit."""

    __slots__ = ()
    _spec = """
    name: str -- the channel
    unit: str | None -- its unit (None: none given)
    density_unit: str -- the unit of density (unit^2/Hz)
    frequency_hz: array -- the frequency of each bin or band, Hz
    density: array -- the one-sided power spectral density, in density_unit
    edf: array -- equivalent degrees of freedom of each bin or band
    bins: int_array -- the bins averaged into each band
    density_rate?: DensityRate -- rate sensors: the density in (deg/h)^2/Hz
    fit?: PowerLawFit | None -- the power-law fit (None when it failed)
    fit_error?: str -- why the fit failed
    allan_terms?: list[AllanTerm] -- the IEEE 952 terms of the fit
    """

    def _summary(self):
        return f"{self.name!r}, {len(self.frequency_hz)} frequencies, {self.density_unit}"


class Spectrum(Result):
    """The result of cubecal.psd: `cubecal psd --format json` as a typed
    object (to_dict() is that document)."""

    __slots__ = ()
    _spec = """
    command: str -- "psd"
    file: str -- the record (a path, or "<arrays>")
    rate_hz: float -- its sampling rate, Hz
    samples: int -- its samples per channel
    pieces: int -- its contiguous pieces
    pieces_used: int -- the pieces long enough for a segment
    one_sided: bool -- always True: the densities are one-sided
    welch?: Welch -- the Welch plan (absent without channels)
    channels: list[SpectrumChannel] -- each channel's spectrum
    """

    def _summary(self):
        names = ", ".join(c.name for c in self.channels)
        return f"{names}; {self.samples} samples at {_fmt(self.rate_hz)} Hz"


class BandedSpectrum(Result):
    """A channel's spectrum in log bands (analyze's spectral view)."""

    __slots__ = ()
    _spec = """
    bins_per_decade: int -- log bands per decade (0: every bin)
    density_unit: str -- the unit of density (the channel's unit squared per Hz)
    frequency_hz: array -- the frequency of each band, Hz
    density: array -- the one-sided power spectral density, in density_unit
    edf: array -- equivalent degrees of freedom of each band
    bins: int_array -- the bins averaged into each band
    first_bin: int_array -- the first bin of each band
    """


class TermComparison(Quantity):
    """An IEEE 952 term from the spectrum's fit beside the Allan curve's five-term fit."""

    __slots__ = ()
    _spec = """
    term: str -- N, B, K, Q or R
    alpha: int -- the power-law exponent it comes from
    allan_fit: Quantity -- the same term from the Allan curve's five-term fit
    difference_sigmas: float | None -- (spectrum - allan) / sqrt(sigma_spectrum^2 + sigma_allan^2)
    """


class SpectralView(Result):
    """A channel's spectral view in an analysis (analyze psd=True)."""

    __slots__ = ()
    _spec = """
    method: str -- how it is made
    welch: Welch -- the Welch plan
    spectrum: BandedSpectrum -- the spectrum in log bands
    fit: PowerLawFit | None -- the power-law fit (None when it failed)
    fit_error?: str -- why it failed
    terms: list[TermComparison] -- each term beside the Allan curve's
    """


class DavarWindow(Result):
    """The window or the step of a dynamic Allan deviation."""

    __slots__ = ()
    _spec = """
    samples: int -- its length, samples
    seconds: float -- its length, s
    asked: str -- as it was asked for ("" : the default)
    """


class DavarIntervals(Result):
    """The confidence intervals of a dynamic Allan deviation."""

    __slots__ = ()
    _spec = """
    enabled: bool -- whether the cells have intervals
    ci?: float -- their confidence (0 to 1)
    edf?: str -- the EDF method (greenhall or simple)
    alpha?: int | str -- the fixed noise type, or "identified per cell"
    """


class DavarExcludedTau(Result):
    """A tau left out of a dynamic Allan deviation, and why."""

    __slots__ = ()
    _spec = """
    tau: float -- the tau, s
    reason: str -- why
    """


class DavarChannel(Result):
    """A channel's dynamic Allan deviation: a tau x time matrix."""

    __slots__ = ()
    _spec = """
    name: str -- the channel
    t_start: array -- each window's start, s
    t: array -- each window's centre, s
    m: int_array -- averaging factors
    tau: array -- averaging times, s
    n: int_array -- terms per window at each tau
    missing_samples: ndarray -- missing samples in each window
    dev: matrix -- the deviation, taus x windows, in the channel's unit (NaN: a cell without a term)
    terms?: ndarray -- the terms behind each cell, taus x windows
    lo?: matrix -- lower ends of the intervals, taus x windows, in the channel's unit
    hi?: matrix -- upper ends, taus x windows
    edf?: matrix -- equivalent degrees of freedom, taus x windows
    alpha?: ndarray -- the noise type of each cell, taus x windows (float with NaN where a cell is empty)
    """

    def _summary(self):
        return f"{self.name!r}, {len(self.tau)} taus x {len(self.t)} windows"


class DynamicAllan(Result):
    """The result of cubecal.davar: `cubecal davar --format json` as a typed
    object (to_dict() is that document)."""

    __slots__ = ()
    _spec = """
    command: str -- "davar"
    statistic: str -- "oadev"
    file: str -- the record (a path, or "<arrays>")
    rate_hz: float -- its sampling rate, Hz
    type: str -- the data type (freq or phase)
    samples: int -- its samples per channel
    missing_samples: int -- the missing samples (gaps="skip")
    window: DavarWindow -- the sliding window
    step: DavarWindow -- the step between windows
    windows: int -- the windows
    window_points: int -- the taus of a window
    intervals: DavarIntervals -- how the intervals were made
    excluded_taus: list[DavarExcludedTau] -- taus left out
    channels: list[DavarChannel] -- each channel's matrix
    """

    def _summary(self):
        names = ", ".join(c.name for c in self.channels)
        return f"{names}; {self.windows} windows of {_fmt(self.window.seconds)} s every {_fmt(self.step.seconds)} s"


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
    """One-sided power spectral density by Welch's method, as `cubecal psd`.

    Equal to scipy.signal.welch; with its power-law fit and the IEEE 952
    terms the fitted coefficients stand for.

    Parameters
    ----------
    data : str, os.PathLike, array_like, dict, cubecal.Record or DataFrame
        A path (read_options as cubecal.read) or arrays sampled at `rate`.
    rate : float, optional
        Sampling rate of arrays, Hz.
    unit : str or list of str, optional
        One unit for all channels or one per channel (default: from the
        names, else none: densities in u^2/Hz).
    window : str
        hann, hamming, blackman or rectangular.
    segment : int
        Samples per segment (0: about n/8, or from fmin).
    fmin : float
        Lowest frequency to resolve, Hz (0: from segment).
    overlap : float
        Fraction of a segment shared with the next (0 to 1).
    detrend : str
        none, constant or linear.
    bins_per_decade : int
        0 for every bin, K to average over K log bands per decade.
    fit : bool
        Fit the power law and give the IEEE 952 terms.
    fit_min, fit_max : float
        The fitted band, Hz (0: the whole spectrum).
    names : list of str, optional
        Names of array channels.
    threads : int
        Worker threads (0: every core).
    **read_options
        cubecal.read's options for a path.

    Returns
    -------
    Spectrum
        `cubecal psd --format json` as a typed object: each channel's
        frequency_hz (Hz) and density (unit^2/Hz) as arrays.
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
        d = _cubecal._psd(path, ra, arrays, names, rate, a)
    except _cubecal.UsageError as e:
        if e.option != "fit_range":
            raise
        # The band is the CLI's --fit-range; here it is fit_min and fit_max.
        keyword = "fit_max" if fit_max and not fit_min else "fit_min"
        raise _args.usage(keyword, "fit_min, fit_max: " + str(e).split(": ", 1)[-1]) from None
    return Spectrum(d)


@_args.public
def davar(data, rate=None, window=None, step=None, taus="log:10", data_type="freq", intervals=True, ci=0.683,
          alpha=None, names=None, threads=0, **read_options):
    """Dynamic Allan deviation, as `cubecal davar`.

    The overlapping Allan deviation of a window sliding along the record: a
    tau x time matrix per channel, exact, from block sums.

    Parameters
    ----------
    data : str, os.PathLike, array_like, dict, cubecal.Record or DataFrame
        A path (read_options as cubecal.read; gaps="skip" leaves missing
        samples out) or arrays sampled at `rate`.
    rate : float, optional
        Sampling rate of arrays, Hz.
    window, step : str or int, optional
        A duration ("1h", "60s") or a number of samples (default: a tenth of
        the record, a tenth of the window).
    taus : str or sequence of float
        A grid ("log:10", "octave", ...) or taus in s.
    data_type : str
        freq or phase.
    intervals : bool
        Confidence intervals of every cell.
    ci : float
        Their confidence (0 to 1).
    alpha : int, optional
        A fixed noise type for the intervals, -2 to +2 (default: identified
        in each cell).
    names : list of str, optional
        Names of array channels.
    threads : int
        Worker threads (0: every core).
    **read_options
        cubecal.read's options for a path.

    Returns
    -------
    DynamicAllan
        `cubecal davar --format json` as a typed object: each channel's dev
        a (taus, windows) array in its unit, NaN where a cell has no term.
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
