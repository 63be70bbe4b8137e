"""cubecal.analyze: `cubecal analyze` on a file or on arrays."""
import os

import numpy as np

from . import _args, _cubecal
from ._args import usage
from ._data import channels_of, number_list, string_list
from ._read import read_args
from ._result import AllanCurve, ExcludedTau, MergedTau, ModelChannel, Quantity, Result, _fmt  # noqa: F401
from ._spectral import SpectralView  # noqa: F401  (a channel's spectral view)


class AnalysisInput(Result):
    """The record an analysis was made of."""

    __slots__ = ()
    _spec = """
    file: str -- the record (a path, or "<arrays>")
    samples: int -- samples per channel
    rate_hz: float -- the sampling rate, Hz
    duration_s: float -- the record's length, s
    segments: int -- contiguous pieces (split at gaps)
    gaps: str -- how gaps were read: error, split or skip
    """


class NoiseTerm(Quantity):
    """An IEEE 952 noise term (N, B, K, Q or R) in its display unit."""

    __slots__ = ()
    _spec = """
    tau_range_s?: array -- [lo, hi], the taus it was read over or fitted from, s
    read_at_tau_s?: float -- N: the tau it is read at, s
    white_at_read_tau?: bool -- N: whether the -1/2 region contains that tau
    no_minimum_within_record?: bool -- B: the curve has no minimum inside the record (B is a bound)
    significant?: bool -- K: whether it is significant
    """


class ReportedEstimate(Quantity):
    """The estimate behind a term reported as an upper bound."""

    __slots__ = ()
    _spec = """
    source?: str -- where it comes from (read-off or fit)
    """


class ReportedTerm(NoiseTerm):
    """A term as every output reports it: the estimate or an upper bound."""

    __slots__ = ()
    _spec = """
    source: str -- read-off, fit or UPPER BOUND
    upper_bound: bool -- whether value is an upper bound (then sigma is None)
    significance_sigmas?: float -- K: the sigmas a K must stand clear of zero to be reported
    estimate?: ReportedEstimate | None -- K: the estimate behind a bound (None: none)
    """

    def _summary(self):
        return ("< " if self.upper_bound else "") + super()._summary()


class ReportedTerms(Result):
    """The terms every output reports: one N, K only when significant, B only with a minimum."""

    __slots__ = ()
    _spec = """
    white_noise: ReportedTerm -- N, the angle (velocity) random walk
    rate_random_walk: ReportedTerm -- K
    bias_instability: ReportedTerm -- B
    """

    def _summary(self):
        return "; ".join(f"{k} {t._summary()}" for k, t in (("N", self.white_noise), ("B", self.bias_instability),
                                                             ("K", self.rate_random_walk)))


class CurveMinimum(Result):
    """Where an Allan curve is lowest."""

    __slots__ = ()
    _spec = """
    tau_s: float -- the tau of the minimum, s
    tau_range_s: array -- [lo, hi], the taus around it, s
    """


class ValueWithUnit(Result):
    """A value with its unit."""

    __slots__ = ()
    _spec = """
    value: float | None -- the value, in `unit`
    unit: str -- its unit
    """


class NoiseFit(Result):
    """The weighted fit sigma^2(tau) = sum C_k tau^k, k = -2..2, of an Allan curve."""

    __slots__ = ()
    _spec = """
    method: str -- how it is fitted
    note: str -- what its terms are
    quantization: NoiseTerm -- Q
    arw: NoiseTerm -- N
    bias_instability: NoiseTerm -- B
    rate_random_walk: NoiseTerm -- K
    rate_ramp: NoiseTerm -- R
    coefficients: array -- C_-2 .. C_2, in the unit squared times s^-k
    coefficients_sigma: array -- their 1-sigma uncertainties
    chi2: float -- the fit's chi-squared
    dof: int -- its degrees of freedom
    rms_rel_residual: float -- rms relative residual of the fitted deviation
    """


class Densities(Result):
    """The noise densities of the reported N and K."""

    __slots__ = ()
    _spec = """
    white: Quantity -- the white-noise density, in the channel's unit per sqrt(Hz)
    random_walk: Quantity -- the random-walk density, in the channel's unit per s per sqrt(Hz)
    white_si: Quantity -- the white-noise density in SI units
    random_walk_si: Quantity -- the random-walk density in SI units
    white_source: str -- where N comes from
    random_walk_source: str -- where K comes from
    """


class AccelerometerTerms(Result):
    """An accelerometer's terms in the units inertial navigation quotes."""

    __slots__ = ()
    _spec = """
    velocity_random_walk: list[Quantity] -- N in several units (m/s/sqrt(h), ...)
    bias_instability: list[Quantity] -- B in several units (mg, m/s^2, ...)
    acceleration_random_walk: list[Quantity] -- K in several units
    """


class AccelerometerView(Result):
    """An accelerometer's read-off and fitted terms in navigation units."""

    __slots__ = ()
    _spec = """
    read_off: AccelerometerTerms -- the slope read-offs
    fit: AccelerometerTerms -- the five-term fit's
    """


class BiasChoice(Result):
    """Which bias instability to trust: the read-off's or the fit's."""

    __slots__ = ()
    _spec = """
    trust: str -- the one to trust
    fit_over_read_off: float | None -- the fit's B over the read-off's (None: not compared)
    beyond_combined_sigma: bool -- whether they differ by more than their combined sigma
    other_terms_share_at_minimum: float -- the share of the other terms at the curve's minimum
    reason: str -- why
    """


class NoiseAnalysis(Result):
    """A channel's noise terms: slope read-offs, the five-term fit and the reported terms."""

    __slots__ = ()
    _spec = """
    method: str -- how the terms are read off
    arw: NoiseTerm -- N read off the -1/2 line at tau = 1 s, e.g. deg/sqrt(h)
    bias_instability: NoiseTerm -- B = sigma_min / 0.664, e.g. deg/h
    time_constant_s: float | None -- T, the tau of the minimum inside the record, s (None: none)
    time_constant_range_s: array | None -- [lo, hi] around T, s
    time_constant_rel_sigma: float | None -- T's relative uncertainty: half the central interval of ln T over records at the analysis's confidence
    curve_minimum: CurveMinimum -- where the curve is lowest, inside the record or not
    sigma_min: ValueWithUnit -- the lowest deviation, in the channel's unit
    rate_random_walk: NoiseTerm -- K at tau = 3 s, e.g. deg/h/sqrt(h)
    quantization: NoiseTerm -- Q
    rate_ramp: NoiseTerm -- R
    fit: NoiseFit -- the five-term fit
    reported: ReportedTerms -- the terms every output reports
    densities: Densities -- the densities of the reported N and K
    accelerometer?: AccelerometerView -- accelerometers: the terms in navigation units
    bias_instability_choice: BiasChoice -- which B to trust
    adev?: AllanCurve -- the curve the terms are read from (the compensated series')
    """

    def _summary(self):
        return self.reported._summary()


class GaussMarkovModel(Result):
    """A first-order Gauss-Markov bias model with white noise."""

    __slots__ = ()
    _spec = """
    sigma: float -- the Gauss-Markov process's standard deviation, in the channel's unit
    tau_s: float -- its correlation time, s
    sigma_n: float -- the white noise per sample, in the channel's unit
    residual_rms_log: float -- rms of log(model / measured) over the Allan curve
    residual_chi2: float -- chi-squared of the model over the Allan curve
    """


class SensorModel(Result):
    """A channel's sensor models: the paper's random walk and a Gauss-Markov alternative."""

    __slots__ = ()
    _spec = """
    unit: str -- the channel's unit
    samples: int -- the samples the models are fitted on
    sigma_n: float | None -- white noise per sample, in `unit` (None: no fit)
    sigma_mu: float | None -- the bias random walk's step per sample, in sigma_mu_unit
    sigma_mu_unit?: str -- the unit of sigma_mu (unit/s)
    lsb: float -- the quantization step modelled, in `unit` (0: none)
    residual_rms_log?: float -- rms of log(model / measured) over the Allan curve
    residual_chi2?: float -- chi-squared of the model over the Allan curve
    error?: str -- why the random-walk model could not be fitted
    gauss_markov: GaussMarkovModel | None -- the Gauss-Markov model (None: no fit)
    gauss_markov_error?: str -- why it could not be fitted
    better_fit?: str -- gauss_markov or random_walk
    adev?: AllanCurve -- the curve the models were fitted to, when not the record's
    composite?: ModelChannel -- the composite model (the twin, or analyze's composite=)
    """


class Drift(Result):
    """A channel's bias drift (drift.csv)."""

    __slots__ = ()
    _spec = """
    window_s: float -- the moving-average window, s
    fixed_bias: float -- the fixed bias (the mean), in the channel's unit
    points: int -- the points of drift.csv
    file: str -- "drift.csv"
    """


class TemperatureFit(Result):
    """A polynomial bias(T) = offset + sum_p coeff[p] (T - t_ref)^p."""

    __slots__ = ()
    _spec = """
    t_ref: float -- the reference temperature, degC
    offset: float -- the bias at t_ref, in the channel's unit
    offset_sigma: float -- its 1-sigma uncertainty
    coeff: array -- coeff[0] is p = 1: in the channel's unit per degC^p
    coeff_sigma: array -- their 1-sigma uncertainties
    coeff_cov: matrix -- the covariance of offset and coeff
    r2: float -- the fit's R^2
    residual_rms: float -- rms residual, in the channel's unit
    method_text?: str -- how it is fitted
    """


class TemperatureNoiseModel(Result):
    """The noise model of a joint temperature fit."""

    __slots__ = ()
    _spec = """
    sigma_n: float -- white noise per sample, in the channel's unit
    sigma_mu: float -- the bias random walk's step, in sigma_mu_unit
    sigma_mu_unit: str -- its unit (unit/s)
    lsb: float -- the quantization step modelled
    iterations: int -- iterations of the joint fit
    converged: bool -- whether it converged
    """


class TemperatureAnalysis(TemperatureFit):
    """A channel's temperature coefficients and the compensated analysis."""

    __slots__ = ()
    _spec = """
    sensor: str -- the temperature column
    order: int -- the polynomial's order
    unit: str -- unit of the first coefficient (unit/degC)
    coeff_units: list[str] -- the unit of each coefficient
    method: str -- random_walk_gls (joint with the bias random walk) or ols
    method_text: str -- how it is fitted
    noise_model?: TemperatureNoiseModel -- the joint fit's noise model
    joint_error?: str -- why the joint fit was not made
    ols: TemperatureFit -- the ordinary least-squares fit beside it
    compensated: NoiseAnalysis -- the noise terms of the compensated series (with its adev)
    compensated_model: SensorModel -- the sensor models of the compensated series
    """


class AnalysisChannel(Result):
    """One channel of an analysis."""

    __slots__ = ()
    _spec = """
    name: str -- the channel
    unit: str -- its unit
    kind: str -- the kind of sensor (rate, acceleration, magnetic, ...)
    mean: float -- the fixed bias (the mean), in `unit`
    stddev: float -- the standard deviation, in `unit`
    adev: AllanCurve -- the overlapping Allan deviation with intervals, in `unit`
    adev_stride?: int_array -- a streamed run: the stride of each tau's terms
    noise: NoiseAnalysis -- the noise terms
    model: SensorModel -- the sensor models (and the composite model)
    drift: Drift -- the bias drift
    temperature?: TemperatureAnalysis -- with a temperature: the coefficients and the compensated analysis
    spectral?: SpectralView -- with psd=True: the spectral view
    """

    def _summary(self):
        return f"{self.name!r} ({self.unit}): " + self.noise._summary()


class Covariance(Result):
    """The covariance of the channels."""

    __slots__ = ()
    _spec = """
    channels: list[str] -- the channels, in the matrix's order
    matrix: matrix -- the covariance, in `unit`
    samples: int -- the samples it is computed over
    unit: str -- its unit (the first channel's squared)
    """


class CompositeSettings(Result):
    """How analyze fitted each channel's composite model."""

    __slots__ = ()
    _spec = """
    method: str -- how it is fitted
    model: str -- the model asked for
    selection_replicates: int -- bootstrap replicates of the WIC's optimism (0: asymptotic)
    bootstrap: int -- bootstrap replicates of the uncertainties
    seed: int -- the bootstrap's seed
    robust: bool -- whether the robust wavelet variance was fitted
    robust_efficiency?: float -- its Gaussian efficiency
    """


class TwinCheckChannel(Result):
    """A channel's twin check: its twins' mean Allan curve against the measured one."""

    __slots__ = ()
    _spec = """
    name: str -- the channel
    tau: array -- averaging times, s
    measured: array -- the measured deviation, in the channel's unit
    twins: array -- sqrt of the twins' mean Allan variance
    twins_lo: array -- the smallest twin's deviation
    twins_hi: array -- the largest twin's deviation
    max_error_10s: float | None -- the largest |twins / measured - 1| up to 10 s
    max_error_100s: float | None -- the same up to 100 s
    max_error: float -- the largest over every tau
    max_error_tau_s: float -- its tau, s
    """


class TwinCheck(Result):
    """Twins simulated at the record's length and set against it (analyze --twin-check)."""

    __slots__ = ()
    _spec = """
    twins: int -- the twins simulated per channel
    seed: int -- the first seed
    samples: int -- samples per twin
    note: str -- what the numbers are
    channels: list[TwinCheckChannel] -- each channel's check
    """


class Analysis(Result):
    """The result of cubecal.analyze: analysis.json as a typed object
    (to_dict() is its content). write(dir) writes the files of `cubecal
    analyze --out DIR`; cubecal.simulate(analysis) simulates the sensors it
    measured."""

    __slots__ = ("_handle", "_command")
    _spec = """
    format_version: int -- the version of analysis.json's layout
    command: str -- the call that made it
    input: AnalysisInput -- the record
    ci: float -- the confidence of the intervals (0 to 1)
    channels: list[AnalysisChannel] -- each channel's analysis
    covariance: Covariance -- the covariance of the channels
    excluded_taus: list[ExcludedTau] -- listed taus left out of the curves
    merged_taus: list[MergedTau] -- listed taus merged with an earlier one
    model_excluded_taus: list[ExcludedTau] -- taus left out of the models' curve
    stream?: Any -- a streamed run: its window bound
    composite?: CompositeSettings -- how the composite models were fitted
    composite_skipped?: str -- why no composite model was fitted
    drift_skipped?: str -- why no drift was computed
    twin_check?: TwinCheck -- the twin check
    estimator_files?: Any -- the estimators' noise files written ("for", noise_factor)
    """

    def __init__(self, handle, command):
        super().__init__(handle.document(command))
        object.__setattr__(self, "_handle", handle)
        object.__setattr__(self, "_command", command)

    def write(self, directory: "str | os.PathLike[str]", force: bool = False) -> "list[str]":
        """Writes the files of `cubecal analyze --out DIR`.

        Parameters
        ----------
        directory : str or os.PathLike
            The directory (created if missing).
        force : bool
            Replace files that exist (else an existing file is refused).

        Returns
        -------
        list of str
            The paths written: analysis.json, adev.csv, drift.csv, imu.yaml.
        """
        return self._handle.write(_args.path(directory, "directory"), _args.flag(force, "force"), self._command)

    def _summary(self):
        i = self.input
        lines = [f"{i.file!r}, {i.samples} samples at {_fmt(i.rate_hz)} Hz ({_fmt(i.duration_s)} s)"]
        lines += ["  " + c._summary() for c in self.channels]
        return "\n".join(lines)


def _composite_named(call, *arguments):
    """The call; the library's errors on the composite model (its field is
    cubecal model's `model`) name analyze's keyword, composite."""
    try:
        return call(*arguments)
    except _cubecal.UsageError as e:
        if e.option != "model":
            raise
        raise usage("composite", f"composite: {e}") from None


def _call_text(first, kwargs):
    given = ", ".join(f"{k}={v!r}" for k, v in kwargs.items() if v is not None)
    return f"cubecal.analyze({first}{', ' + given if given else ''})"


@_args.public
def analyze(data, rate=None, unit=None, temperature=None, taus="log:10", ci=0.683, temp_order=1, drift_window=0.0,
            cov_samples=0, max_samples=0, model_lsb=None, names=None, threads=0, psd=False, composite=None,
            composite_bootstrap=0, **read_options):
    """Static characterization of every channel, as `cubecal analyze`.

    Fixed bias, OADEV with intervals, the noise terms (N, B, K, Q, R) by
    slope read-offs and the five-term fit, the paper's random-walk model and
    a Gauss-Markov model, bias drift, covariance and, with a temperature, the
    temperature coefficients and the compensated analysis.

    Parameters
    ----------
    data : str, os.PathLike, array_like, dict, cubecal.Record or DataFrame
        A path, read as the CLI reads it (read_options are cubecal.read's:
        columns, time, skip_rows, lsb, gaps, topics, dataset, binary, ...),
        or arrays (1-D, 2-D with one channel per column, a list, a dict /
        Record / DataFrame of columns) sampled at `rate`.
    rate : float, optional
        Sampling rate of arrays, Hz (default: a Record's; a file's from its
        time column unless given).
    unit : str or list of str, optional
        One unit for all channels or one per channel ("deg/s", "rad/s",
        "mGauss", "uT", "g", "m/s^2", "counts", ...); default: from the
        column names (gx_dps, mag_x_uT, ...).
    temperature : str or array_like, optional
        A column name (of the file or of a dict of columns) or one value per
        sample, degC.
    taus : str or sequence of float
        The OADEV grid: "log:K" (K per decade), "octave", "decade", "all" or
        taus in s.
    ci : float
        Confidence of the intervals (0 to 1; 0.683: 1 sigma).
    temp_order : int
        Order of the bias(T) polynomial.
    drift_window : float
        Moving-average window of the drift, s (0: the default).
    cov_samples, max_samples : int
        Samples of the covariance and of the analysis (0: all).
    model_lsb : float or list of float, optional
        Quantization step of the sensor model per channel, counts per unit.
    names : list of str, optional
        Names of array channels.
    threads : int
        Worker threads (0: every core).
    psd : bool
        Also the spectral view, as `cubecal analyze --psd` (each channel's
        `spectral`).
    composite : None, bool or str
        The composite noise model beside the two sensor models, as
        `--composite`: None each channel's twin (docs/twins.md; left out with
        the reason in `composite_skipped` for a record that cannot carry
        one), False or "none" none, "twin" the twin required, True or "auto"
        selected by the WIC among the default candidates, a model
        ("WN+GM+RW") or candidates joined by commas.
    composite_bootstrap : int
        Parametric-bootstrap replicates of its uncertainties (0: none).
    **read_options
        cubecal.read's options for a path.

    Returns
    -------
    Analysis
        analysis.json as a typed object (to_dict() is its content);
        cubecal.simulate(analysis) simulates the sensors it measured.

    Raises
    ------
    cubecal.UsageError
        A bad argument (.option names it).
    cubecal.InputError
        Bad data in the file or the arrays.
    """
    args = _cubecal._AnalyzeArgs()
    args.units = string_list(unit, "unit")
    args.taus = _args.taus(taus)
    args.ci = _args.number(ci, "ci")
    args.temp_order = _args.count(temp_order, "temp_order")
    args.drift_window = _args.number(drift_window, "drift_window")
    args.cov_samples = _args.count(cov_samples, "cov_samples")
    args.max_samples = _args.count(max_samples, "max_samples")
    args.model_lsb = number_list(model_lsb, "model_lsb")
    args.threads = _args.threads(threads)
    args.psd = _args.flag(psd, "psd")
    if composite is True:
        composite = "auto"
    if composite is False:
        composite = "none"
    if composite is not None:
        if not isinstance(composite, str):
            raise usage("composite", "composite: None (the twin), False or \"none\", True or \"auto\", \"twin\", a "
                                     "model such as \"WN+GM+RW\" or candidates")
        args.composite = composite
    args.composite_bootstrap = _args.count(composite_bootstrap, "composite_bootstrap")
    # The call as the result's "command": every argument that changes the
    # analysis, so that it reproduces it (arrays are shown as <arrays>).
    shown = {"rate": rate, "unit": unit, "temperature": temperature if isinstance(temperature, str) else None,
             "taus": taus if taus != "log:10" else None, "ci": ci if ci != 0.683 else None,
             "temp_order": temp_order if temp_order != 1 else None,
             "drift_window": drift_window or None, "cov_samples": cov_samples or None,
             "max_samples": max_samples or None, "model_lsb": model_lsb, "names": names,
             "psd": True if psd else None, "composite": args.composite or None,
             "composite_bootstrap": composite_bootstrap or None}
    if isinstance(data, (str, os.PathLike)):
        if names is not None:
            raise usage("names", "names: give columns= to choose the columns of a file")
        path = _args.path(data, "data")
        if temperature is not None and not isinstance(temperature, str):
            raise usage("temperature", "temperature: a column name of the file")
        ro = dict(read_options)
        if rate is not None:
            ro["rate"] = rate
        handle = _composite_named(_cubecal._analyze_file, path, read_args(**ro), args, temperature or "")
        return Analysis(handle, _call_text(repr(path), {**shown, **ro}))
    if read_options:
        raise usage(next(iter(read_options)), f"{', '.join(read_options)}: options of a file; data are arrays here")
    temp_name, temp_values, exclude = "temp", None, ()
    if isinstance(temperature, str):
        if not (isinstance(data, dict) or hasattr(data, "columns")):
            raise usage("temperature", "temperature: a column name needs data with named columns (a dict or DataFrame)")
        if temperature not in data:
            raise usage("temperature", f"temperature: no column {temperature!r} in the data")
        temp_name, temp_values, exclude = temperature, _args.samples(data[temperature], "temperature"), (temperature,)
    elif temperature is not None:
        temp_values = _args.samples(temperature, "temperature")
    names, arrays = channels_of(data, names, exclude)
    if rate is None:
        rate = getattr(data, "rate_hz", None)
        if not rate:
            raise usage("rate", "rate: give the sampling rate of the arrays in Hz")
    label = getattr(data, "file", None) or "<arrays>"
    handle = _composite_named(_cubecal._analyze_arrays, arrays, names, _args.rate(rate), args, temp_values, temp_name,
                              label)
    if temperature is not None and not isinstance(temperature, str):
        shown["temperature"] = "<array>"
    return Analysis(handle, _call_text("<arrays>", shown))
