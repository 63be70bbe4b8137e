"""The calibrations and the runs commands: `cubecal calibrate rate-table`,
`calibrate mag`, `calibrate temperature`, `calibrate multiposition`,
`turnon` and `compare`, on a file (read as the CLI reads it) or on arrays.

Each returns a Result whose to_dict() is the JSON document the CLI writes
for the same data (`--format json`); where the CLI adds its command line as
"invocation", the Python call's text is there instead.
"""
import os

import numpy as np

from . import _args, _cubecal
from ._data import channels_of, number_list, string_list
from ._read import read_args
from ._result import AllanCurve, Misalignment, Quantity, Result, _fmt  # noqa: F401

__all__ = [
    "RateTableCalibration", "MagCalibration", "TemperatureCalibration", "MultipositionCalibration", "TurnOn",
    "Comparison", "calibrate_rate_table", "calibrate_mag", "calibrate_temperature", "calibrate_multiposition",
    "turnon", "compare",
]


class Residuals(Result):
    """The residuals of a calibration, before or after it."""

    __slots__ = ()
    _spec = """
    max: float -- the largest absolute residual, in `unit`
    rms: float -- their rms, in `unit`
    mean?: float -- their mean, in `unit`
    unit: str -- the unit
    """


class RateTableForward(Result):
    """The forward model w_g = S w + b_g of a rate-table calibration."""

    __slots__ = ()
    _spec = """
    S: matrix -- the 3 x 3 scale and misalignment matrix (1)
    S_sigma: matrix -- its 1-sigma uncertainties
    bias: array -- b_g, in the calibration's unit
    bias_sigma: array -- its 1-sigma uncertainties
    cov: matrix -- the covariance of S and b_g (12 x 12)
    scale_factor_error: array -- S_ii - 1 per axis (1)
    scale_factor_error_sigma: array -- their 1-sigma uncertainties
    scale_factor_ppm: array -- the same in ppm
    scale_factor_ppm_sigma: array -- their 1-sigma uncertainties, ppm
    scale_factor_percent: array -- the same in percent
    misalignment: matrix -- misalignment angles, rad (key ij: atan(S_ij / S_ii))
    misalignment_sigma: matrix -- their 1-sigma uncertainties, rad
    misalignment_mrad: Misalignment -- the angles by key, mrad
    misalignment_mrad_sigma: Misalignment -- their 1-sigma uncertainties by key, mrad
    misalignment_deg: Misalignment -- the angles by key, deg
    misalignment_convention: str -- what the keys mean
    """


class RateTableFit(Result):
    """The least-squares fit of a rate-table calibration."""

    __slots__ = ()
    _spec = """
    plateaus: int -- the plateaus fitted
    dof: int -- degrees of freedom
    noise_from_residuals: bool -- whether the noise covariance comes from the residuals
    noise_cov: matrix -- the noise covariance of a plateau mean, in the unit squared
    earth_rate: array -- the Earth rate added to every reference rate, in the unit
    """


class PlateauDetection(Result):
    """What the plateau detection saw."""

    __slots__ = ()
    _spec = """
    skipped_rows: int -- rows left out
    noise: array -- the noise per axis the detection assumed, in the unit
    """


class Plateau(Result):
    """A plateau of a rate-table run: a stretch at a constant rate."""

    __slots__ = ()
    _spec = """
    begin: int -- its first sample
    end: int -- one past its last sample
    t_begin: float -- its start, s
    t_end: float -- its end, s
    n: int -- its samples
    gyro: array -- the gyro mean per axis, in the unit
    gyro_std: array -- the gyro standard deviation per axis
    gyro_cov: matrix -- the covariance of the gyro mean
    ref: array -- the reference rate per axis, in the unit
    has_ref: bool -- whether the reference rate is known
    residual_after?: array -- the residual per axis after the calibration
    """


class RateTableCalibration(Result):
    """The result of cubecal.calibrate_rate_table: `calibrate rate-table
    --format json` as a typed object. The calibration w = A w_g + beta (the
    paper's eq. 6), in `unit`, with the forward model w_g = S w + b_g."""

    __slots__ = ()
    _spec = """
    file: str -- the record
    unit: str -- deg/s or rad/s
    model: str -- the model's equations
    A: matrix -- the 3 x 3 calibration matrix (1)
    A_sigma: matrix -- its 1-sigma uncertainties
    beta: array -- the offset, in `unit`
    beta_sigma: array -- its 1-sigma uncertainties
    inverse_cov: matrix -- the covariance of A and beta (12 x 12)
    residual_before: Residuals -- plateau residuals before, in `unit`
    residual_after: Residuals -- plateau residuals after, in `unit`
    error_covariance: matrix -- the covariance of the calibrated rate's error (eq. 12), error_covariance_unit
    error_covariance_unit: str -- its unit, (unit)^2
    forward: RateTableForward -- the forward model
    fit: RateTableFit -- the fit
    plateau_source: str -- reference, schedule or signal_schedule
    plateaus_dropped_short: int -- plateaus shorter than min_plateau
    plateaus_unmatched: int -- plateaus without a rate of the schedule
    detection: PlateauDetection -- the detection
    plateaus: list[Plateau] -- the plateaus used
    invocation?: str -- the call that made it
    """

    def _summary(self):
        f = self.forward
        ppm = ", ".join(_fmt(x) for x in f.scale_factor_ppm)
        return f"{len(self.plateaus)} plateaus; scale factor error [{ppm}] ppm; bias " \
               f"[{', '.join(_fmt(x) for x in f.bias)}] {self.unit}; residual rms " \
               f"{_fmt(self.residual_before.rms)} -> {_fmt(self.residual_after.rms, self.unit)}"


class NamedCovariance(Result):
    """A covariance matrix with the names of its parameters."""

    __slots__ = ()
    _spec = """
    names: list[str] -- the parameters, in the matrix's order
    matrix: matrix -- the covariance, in the parameters' units
    """


class MagCoverage(Result):
    """How much of the sphere the magnetometer points cover."""

    __slots__ = ()
    _spec = """
    centre: array -- the centre the directions are taken from, in the unit
    centre_from_sphere_fit: bool -- whether it comes from a sphere fit
    resultant: float -- the mean resultant length of the directions (0 to 1; 1: one direction)
    lambda_min: float -- the smallest eigenvalue of the directions' scatter
    spread: array -- the directions' spread per axis
    octants: int -- the octants holding points
    """


class MagCalibration(Result):
    """The result of cubecal.calibrate_mag: `calibrate mag --format json` as
    a typed object. h_cal = soft_iron (h - bias) with |h_cal| = field_norm."""

    __slots__ = ()
    _spec = """
    file: str -- the points (a path, or "<arrays>")
    method: str -- twostep, twostep-full or ellipsoid
    model: str -- the model's equation
    unit: str -- the unit of the points after lsb
    bias: array -- the hard-iron bias, in `unit`
    bias_sigma: array -- its 1-sigma uncertainties
    soft_iron: matrix -- the 3 x 3 soft-iron matrix (1)
    soft_iron_sigma: matrix -- its 1-sigma uncertainties
    soft_iron_unit: str -- "1"
    field_norm: float -- the field magnitude F, in `unit`
    field_norm_source: str -- where F comes from
    field_norm_default: bool -- whether F is the default (the mean raw norm)
    field_norm_per_point: bool -- whether a norm per point was given
    norm_error_before: Residuals -- |h| - F before, in `unit`
    norm_error_after: Residuals -- |h_cal| - F after, in `unit`
    chi2: float -- the fit's chi-squared
    dof: int -- its degrees of freedom
    p_value: float | None -- the chi-squared test's p-value (None: no noise given)
    noise: float -- the per-axis noise, in `unit`
    noise_estimated: bool -- whether it was estimated from the residuals
    points: int -- points used
    points_total: int -- points given
    rejected: int -- points rejected
    reject_sigma: float -- the rejection threshold, standard deviations (0: none)
    rejected_lines: int_array -- the lines (of a file) or 1-based numbers (of arrays) rejected
    rejected_gross_lines: int_array -- those rejected as gross outliers
    first_data_line: int -- the line of the first point
    iterations: int -- iterations of the fit
    converged: bool -- whether it converged
    eta: float -- the fit's conditioning measure
    semi_axes: array -- the ellipsoid's semi-axes, in `unit`
    axis_ratio: float -- the largest over the smallest semi-axis
    coverage: MagCoverage -- the coverage of the sphere
    covariance: NamedCovariance -- the covariance of the parameters
    notes: list[str] -- warnings
    invocation?: str -- the call that made it
    """

    def _summary(self):
        return f"{self.method}, {self.points} points; bias [{', '.join(_fmt(x) for x in self.bias)}] {self.unit}; " \
               f"|h| error rms {_fmt(self.norm_error_before.rms)} -> {_fmt(self.norm_error_after.rms, self.unit)}"


class TemperatureChannel(Result):
    """A channel's polynomial bias(T) = sum_p coeff[p] (T - t_ref)^p."""

    __slots__ = ()
    _spec = """
    name: str -- the channel
    t_ref: float -- the reference temperature, degC
    coeff: array -- coeff[p], in coeff_units[p]
    coeff_sigma: array -- their 1-sigma uncertainties
    coeff_units: list[str] -- unit, unit/degC, unit/degC^2, ...
    covariance: matrix -- the covariance of coeff
    r2: float -- the fit's R^2
    residual_rms: float -- rms residual, in the unit
    order: int -- the polynomial's order
    """


class TemperatureCalibration(Result):
    """The result of cubecal.calibrate_temperature: `calibrate temperature
    --format json` as a typed object; a flight computer applies corrected =
    raw - sum_{p>=1} coeff[p] (T - t_ref)^p."""

    __slots__ = ()
    _spec = """
    file: str -- the record
    temperature_column: str -- the temperature's column
    order: int -- the polynomial's order
    unit: str -- the channels' unit
    samples: int -- samples per channel
    model: str -- the model's equations
    channels: list[TemperatureChannel] -- each channel's polynomial
    """

    def _summary(self):
        def slope(c):
            return _fmt(c.coeff[1], c.coeff_units[1]) if len(c.coeff) > 1 and len(c.coeff_units) > 1 else "-"

        return f"order {self.order}; " + "; ".join(f"{c.name!r} {slope(c)}" for c in self.channels)


class TriadModel(Result):
    """A triad's model X' = T K (X - B)."""

    __slots__ = ()
    _spec = """
    B: array -- the bias, raw units
    K: array -- the scale per axis (unit of X' per raw unit)
    T: matrix -- the misalignment matrix (1)
    TK: matrix -- T K
    misalignment: Misalignment -- the misalignment angles by key, rad
    """


class Parameter(Result):
    """A fitted parameter with its 1-sigma uncertainty."""

    __slots__ = ()
    _spec = """
    name: str -- the parameter
    value: float -- its value, in `unit`
    sigma: float -- its 1-sigma uncertainty, in `unit`
    unit: str -- its unit
    """


class FitResiduals(Result):
    """A multi-position fit's residuals, before or after it."""

    __slots__ = ()
    _spec = """
    count: int -- the residuals
    rms: float -- their rms
    max: float -- their largest magnitude
    cost: float -- the fit's cost
    """


class TriadCalibration(Result):
    """The calibration of one triad (accelerometer or gyroscope)."""

    __slots__ = ()
    _spec = """
    parameters: list[Parameter] -- the fitted parameters
    covariance: NamedCovariance -- their covariance
    model: TriadModel -- the fitted model
    initial: TriadModel -- the initial guess
    init_samples: int -- samples of the initial static period
    residual: str -- the residual's definition
    before: FitResiduals -- residuals before the fit
    after: FitResiduals -- residuals after it
    sigma0: float -- the residuals' standard deviation after the fit
    iterations: int -- iterations of the fit
    converged: bool -- whether it converged
    sigma_fit?: array -- gyroscope: the per-axis noise of the fit
    init_bias?: array -- gyroscope: the bias of the initial static period, raw
    init_bias_sigma?: array -- its 1-sigma uncertainties
    bias_sigma?: array -- gyroscope: the bias's 1-sigma uncertainties
    pairs?: int -- gyroscope: pairs of static intervals integrated between
    angle_rms_before_deg?: float -- gyroscope: rms rotation error before, deg
    angle_rms_after_deg?: float -- rms rotation error after, deg
    angle_max_after_deg?: float -- largest rotation error after, deg
    """


class StaticInterval(Result):
    """A static interval of a multi-position run."""

    __slots__ = ()
    _spec = """
    begin: int -- its first sample
    end: int -- one past its last sample
    t_begin: float -- its start, s
    t_end: float -- its end, s
    """


class ThresholdTrial(Result):
    """A threshold the static detection tried."""

    __slots__ = ()
    _spec = """
    th_mult: int -- the multiple of the initial variance
    threshold: float -- the threshold
    intervals: int -- static intervals found
    fitted: bool -- whether the accelerometer was fitted with them
    cost: float | None -- the fit's cost (None: not fitted)
    """


class MultipositionOptions(Result):
    """The options of a multi-position calibration."""

    __slots__ = ()
    _spec = """
    g: float -- local gravity (the unit of a')
    init_static_s: float -- the initial static period, s
    window: int -- samples of the variance window
    interval_samples: int -- samples per static interval
    min_intervals: int -- the fewest static intervals accepted
    acc_bias_guess: array -- the initial bias guess, raw
    acc_scale_guess: float -- the initial scale guess (0: from the initial period)
    gyro_scale_guess: float -- the gyroscope's initial scale guess, rad/s per raw count
    acc_use_means: bool -- one accelerometer residual per interval
    refine_gyro_bias: bool -- whether 3 gyroscope bias corrections are fitted
    max_iterations: int -- the most iterations of a fit
    th_mult_min: int -- the smallest threshold multiple tried
    th_mult_max: int -- the largest
    """


class MultipositionCalibration(Result):
    """The result of cubecal.calibrate_multiposition: `calibrate
    multiposition --format json` as a typed object (Tedaldi, Pretto &
    Menegatti 2014): X' = T K (X - B) for each triad."""

    __slots__ = ()
    _spec = """
    method: str -- the method
    acc_file: str -- the accelerometer record
    gyro_file: str | None -- the gyroscope record (None: none)
    model: str -- the model's equations
    samples: int -- samples
    rate_hz: float -- the sampling rate, Hz
    g: float -- local gravity, the magnitude of a' (its unit)
    init_static_s: float -- the initial static period, s
    window: int -- samples of the variance window
    interval_samples: int -- samples per static interval
    min_intervals: int -- the fewest static intervals accepted
    options: MultipositionOptions -- the options used
    th_mult: int -- the threshold multiple chosen
    threshold: float -- the threshold chosen
    init_variance_norm: float -- the initial period's variance norm
    static_intervals: int -- the static intervals used
    intervals: list[StaticInterval] -- the intervals
    trials: list[ThresholdTrial] -- the thresholds tried
    accelerometer: TriadCalibration -- the accelerometer's calibration
    gyroscope: TriadCalibration | None -- the gyroscope's (None: no gyroscope)
    invocation?: str -- the call that made it
    """

    def _summary(self):
        a = self.accelerometer
        text = f"{self.static_intervals} static intervals; accelerometer residual rms {_fmt(a.before.rms)} -> " \
               f"{_fmt(a.after.rms)}"
        if self.gyroscope is not None:
            text += f"; gyroscope angle rms {_fmt(self.gyroscope.angle_rms_before_deg)} -> " \
                    f"{_fmt(self.gyroscope.angle_rms_after_deg, 'deg')}"
        return text


class UnitSI(Result):
    """A unit's SI counterpart."""

    __slots__ = ()
    _spec = """
    kind: str -- the kind of sensor (rate, acceleration, ...)
    si_name: str -- the SI unit
    to_si: float -- the factor to it
    """


class ReadOff(Result):
    """A slope read-off of an Allan curve, in the data unit and seconds."""

    __slots__ = ()
    _spec = """
    value: float -- the term, in the data unit and seconds
    sigma: float -- its 1-sigma uncertainty
    valid: bool -- whether the curve determines it
    tau_lo: float -- the first tau it was read over, s
    tau_hi: float -- the last, s
    """


class ReadOffs(Result):
    """A run's slope read-offs."""

    __slots__ = ()
    _spec = """
    N: ReadOff -- white noise
    B: ReadOff -- bias instability
    K: ReadOff -- rate random walk
    Q: ReadOff -- quantization
    R: ReadOff -- rate ramp
    sigma_min: float -- the curve's minimum, in the channel's unit
    tau_min: float -- its tau, s
    tau_min_lo: float -- the taus around it, s
    tau_min_hi: float -- s
    """


class RunChannel(Result):
    """A channel of one run (turnon, compare)."""

    __slots__ = ()
    _spec = """
    name: str -- the channel
    unit: str -- its unit
    unit_si: UnitSI -- its SI counterpart
    mean: float -- the run's bias (its mean), in `unit`
    stddev: float -- its standard deviation, in `unit`
    arw: Quantity -- N, e.g. deg/sqrt(h)
    bias_instability: Quantity -- B, e.g. deg/h
    time_constant_s: float | None -- T, s
    readoffs: ReadOffs -- the slope read-offs
    adev: AllanCurve -- the OADEV curve, in `unit`
    """

    def _summary(self):
        return f"{self.name!r} bias {_fmt(self.mean, self.unit)}, N {self.arw._summary()}, B " \
               f"{self.bias_instability._summary()}"


class Run(Result):
    """One run of turnon or compare."""

    __slots__ = ()
    _spec = """
    file: str -- the record (a path, or "<run k>")
    samples: int -- samples per channel
    rate_hz: float -- the sampling rate, Hz
    channels: list[RunChannel] -- each channel
    """


class TurnOnChannel(Result):
    """A channel's turn-on bias over the runs."""

    __slots__ = ()
    _spec = """
    name: str -- the channel
    unit: str -- its unit
    unit_si: UnitSI -- its SI counterpart
    mean_bias: float -- the mean of the run biases, in `unit`
    turn_on_bias: float -- the sample standard deviation of the run biases, in `unit`
    turn_on_bias_lo: float -- its chi-squared interval's lower end at ci, in `unit`
    turn_on_bias_hi: float -- its upper end, in `unit`
    """


class TurnOn(Result):
    """The result of cubecal.turnon: `turnon --format json` as a typed object."""

    __slots__ = ()
    _spec = """
    ci: float -- the confidence of the intervals (0 to 1)
    runs: list[Run] -- each run
    channels: list[TurnOnChannel] -- each channel's turn-on bias
    """

    def _summary(self):
        return f"{len(self.runs)} runs; " + "; ".join(
            f"{c.name!r} turn-on bias {_fmt(c.turn_on_bias, c.unit)}" for c in self.channels)


class Comparison(Result):
    """The result of cubecal.compare: `compare --format json` as a typed object."""

    __slots__ = ()
    _spec = """
    runs: list[Run] -- each run
    """

    def _summary(self):
        return "; ".join(f"{r.file!r} at {_fmt(r.rate_hz)} Hz" for r in self.runs)


# ---------------------------------------------------------------------------
# Shared helpers


_usage = _args.usage


def _is_path(x):
    return isinstance(x, (str, os.PathLike))


def _is_table(data):
    return isinstance(data, dict) or (hasattr(data, "columns") and hasattr(data, "__getitem__")
                                      and not isinstance(data, np.ndarray))


def _column_names(data):
    return [str(k) for k in (data.keys() if isinstance(data, dict) else data.columns)]


def _column(data, name, option):
    """The column `name` of a dict / cubecal.Record / DataFrame, as float64."""
    if not _is_table(data):
        raise _usage(option, f"{option}: '{name}' names a column: the data must have named columns "
                             "(a dict, cubecal.Record or DataFrame)")
    if name not in _column_names(data):
        raise _usage(option, f"{option}: no column '{name}' (columns: {', '.join(_column_names(data))})")
    return _args.samples(data[name], option)


def _vector(value, option):
    """A 1-D float64 array of the values given for `option`."""
    a = _args.samples(value, option, dimensions=(0, 1, 2))
    if a.ndim != 1:
        raise _usage(option, f"{option}: one value per sample (a 1-D array) is expected, got shape {a.shape}")
    return a


def _record_time(data):
    """The time column's name of a cubecal.Record that has one, else None."""
    name = getattr(data, "time", None) if isinstance(data, dict) else None
    return name if isinstance(name, str) and name and name in data else None


def _check_one_segment(data, remedy="give one contiguous piece"):
    """A cubecal.Record read with gaps="split" holds pieces whose joins the
    arrays do not show: refused."""
    segments = getattr(data, "segments", None) if isinstance(data, dict) else None
    if segments is not None and len(segments) > 1:
        raise _usage("data", f"data: the record was split at {len(segments) - 1} gaps: {remedy}")


def _channels(data, columns, names, exclude=(), option="data"):
    """(names, arrays) of the channels: the named columns of a table, else
    every column but `exclude` (and a Record's time), or the arrays given."""
    if columns is not None:
        cols = string_list(columns, "columns")
        arrays = [_column(data, c, "columns") for c in cols]
        if names is not None:
            names = string_list(names, "names")
            if len(names) != len(arrays):
                raise _usage("names", f"names: {len(names)} names for {len(arrays)} columns")
            cols = names
        return cols, arrays
    return channels_of(data, names, exclude, option)


def _triad(value, option, label_names=("x", "y", "z")):
    """Three 1-D arrays out of an (n, 3) array or a sequence of 3 arrays."""
    if isinstance(value, (list, tuple)) and len(value) == 3 and all(np.ndim(v) == 1 for v in value):
        return list(label_names), [_args.samples(v, option) for v in value]
    a = _args.samples(value, option, dimensions=(0, 1, 2))
    if a.ndim == 2 and a.shape[1] == 3:
        return list(label_names), [a[:, j] for j in range(3)]
    raise _usage(option, f"{option}: three axes x, y, z are expected: an array of shape (n, 3) or 3 arrays, "
                         f"got shape {a.shape}")


def _rate_of(rate, data):
    if rate is not None:
        return _args.rate(rate)
    r = getattr(data, "rate_hz", None)
    return _args.rate(r) if r else None


def _call_text(function, first, kwargs):
    given = ", ".join(f"{k}={v!r}" for k, v in kwargs.items() if v is not None)
    return f"cubecal.{function}({first}{', ' + given if given else ''})"


def _label(data, default="<arrays>"):
    return getattr(data, "file", None) or default


def _no_read_options(read_options):
    if read_options:
        raise _usage(next(iter(read_options)),
                     f"{', '.join(read_options)}: options of a file; the data are arrays here")


# ---------------------------------------------------------------------------
# calibrate rate-table


@_args.public
def calibrate_rate_table(data, rate=None, reference=None, schedule=None, from_signal=False, margin=10.0,
                         min_plateau=30.0, ref_tolerance=1e-6, window=10.0, earth_axis=None, unit="deg/s",
                         columns=None, time=None, names=None, **read_options):
    """Gyro scale factors, misalignment and bias from a rate-table run, as `cubecal calibrate rate-table`.

    The plateaus where the table held a constant rate are found, the gyro
    mean of each is fitted by least squares to w_g = S w + b_g, and the
    calibration w = A w_g + beta (the paper's eq. 6-13) is given with
    1-sigma uncertainties.

    Parameters
    ----------
    data : str, os.PathLike, array_like, dict, cubecal.Record or DataFrame
        The gyro record (3 channels, in `unit`): a path, read as the CLI
        reads it (columns= the 3 gyro columns; time=, rate=, skip_rows, lsb,
        gaps, ... as cubecal.read), or arrays (an (n, 3) array, 3 arrays, or
        a dict / Record / DataFrame with columns= naming the gyro columns)
        sampled at `rate`, or stamped with time=.
    rate : float, optional
        Sampling rate, Hz.
    reference : str, list or array_like, optional
        The 3 reference (table) rate columns, in `unit`, not scaled by lsb:
        column names, or an (n, 3) array / 3 arrays; plateaus are the runs
        where they stay constant within ref_tolerance.
    schedule : str, os.PathLike or array_like, optional
        A CSV file of rows t_begin,t_end,wx,wy,wz (s, s, `unit`), or an array
        of such rows, in the record's time base.
    from_signal : bool
        Find the plateaus in the gyro signal (moving standard deviation over
        `window`) and take only their rates from the schedule.
    margin : float
        Seconds dropped at both ends of a plateau, s.
    min_plateau : float
        Shortest plateau kept (after the margins), s.
    ref_tolerance : float
        Largest change of the reference within a plateau, in `unit`.
    window : float
        The moving window of from_signal, s.
    earth_axis : sequence of 3 float, optional
        The Earth's axis (X, Y, Z) in the sensor frame: the Earth rate along
        it is added to every reference rate (default: ignored).
    unit : str
        "deg/s" or "rad/s".
    columns : str or list, optional
        The gyro columns.
    time : str or array_like, optional
        Time stamps, s: a column name or an array.
    names : list of str, optional
        Names of array channels.
    **read_options
        cubecal.read's options for a path.

    Returns
    -------
    RateTableCalibration
        `calibrate rate-table --format json` as a typed object.

    Raises
    ------
    cubecal.CalibrationError
        The run cannot determine the calibration (.reason "no_plateaus",
        "too_few_points", "degenerate", ...).
    cubecal.UsageError
        A bad argument.
    cubecal.InputError
        Bad data in a file or array.
    """
    args = _cubecal._RateTableArgs()
    args.from_signal = _args.flag(from_signal, "from_signal")
    args.margin = _args.number(margin, "margin")
    args.min_plateau = _args.number(min_plateau, "min_plateau")
    args.ref_tolerance = _args.number(ref_tolerance, "ref_tolerance")
    args.window = _args.number(window, "window")
    args.earth_axis = number_list(earth_axis, "earth_axis")
    args.unit = _args.text(unit, "unit")
    if schedule is not None:
        if _is_path(schedule):
            args.schedule_file = _args.path(schedule, "schedule")
        else:
            rows = _args.samples(schedule, "schedule", dimensions=(1, 2))
            if rows.ndim == 1 and rows.size == 5:
                rows = rows.reshape(1, 5)
            args.schedule = np.ascontiguousarray(rows)
    shown = {"rate": rate, "reference": reference if isinstance(reference, str) or _names_only(reference) else None,
             "schedule": os.fspath(schedule) if _is_path(schedule) else None, "from_signal": from_signal or None,
             "margin": margin if margin != 10.0 else None, "min_plateau": min_plateau if min_plateau != 30.0 else None,
             "unit": unit if unit != "deg/s" else None, "columns": columns}
    if _is_path(data):
        path = os.fspath(data)
        if names is not None:
            raise _usage("names", "names: give columns= to choose the columns of a file")
        if reference is not None and not (isinstance(reference, str) or _names_only(reference)):
            raise _usage("reference", "reference: the reference of a file: the names (or 1-based indices) of its "
                                      "3 columns")
        args.reference = string_list(reference, "reference")
        ro = dict(read_options, columns=columns, time=time, rate=rate)
        doc = _cubecal._rate_table_file(path, read_args(**ro), args,
                                        _call_text("calibrate_rate_table", repr(path), {**shown, **read_options}))
        return RateTableCalibration(doc)
    _no_read_options(read_options)
    _check_one_segment(data, "calibrate its file, read with gaps=\"split\", or give one contiguous piece")
    exclude = []
    ref_names, ref_arrays = [], []
    if reference is not None:
        if isinstance(reference, str) or _names_only(reference):
            ref_names = string_list(reference, "reference")
            if len(ref_names) != 3:
                raise _usage("reference", "reference: the 3 reference rate columns x, y, z")
            ref_arrays = [_column(data, n, "reference") for n in ref_names]
            exclude += ref_names
        else:
            _, ref_arrays = _triad(reference, "reference")
            ref_names = ["rx", "ry", "rz"]
    time_values = None
    if isinstance(time, str):
        time_values = _column(data, time, "time")
        exclude.append(time)
    elif time is not None:
        time_values = _vector(time, "time")
    elif _record_time(data):
        time_values = np.asarray(data[_record_time(data)], dtype=np.float64)
    chan_names, arrays = _channels(data, columns, names, tuple(exclude))
    r = _rate_of(rate, data)
    if r is None and time_values is None:
        raise _usage("rate", "rate: give the sampling rate of the arrays in Hz (or their time stamps, time=)")
    doc = _cubecal._rate_table_arrays(arrays, chan_names, r or 0.0, time_values, ref_arrays, ref_names, args,
                                      _label(data), _call_text("calibrate_rate_table", "<arrays>", shown))
    return RateTableCalibration(doc)


def _names_only(value):
    return isinstance(value, (list, tuple)) and len(value) > 0 and all(isinstance(v, str) for v in value)


# ---------------------------------------------------------------------------
# calibrate mag


@_args.public
def calibrate_mag(points, method="ellipsoid", field_norm=None, field_column=None, noise=None, reject=0.0,
                  allow_partial=False, unit=None, lsb=1.0, columns=None, skip_rows=0, threads=0):
    """Magnetometer hard- and soft-iron calibration, as `cubecal calibrate mag`.

    From points measured over many orientations (no time stamps needed):
    h_cal = soft_iron (h - bias) with |h_cal| = F.

    Parameters
    ----------
    points : str, os.PathLike, array_like, dict, cubecal.Record or DataFrame
        A path (delimited text, optionally gzip, with 3 magnetometer columns,
        or columns= naming them), or an (n, 3) array, 3 arrays, or a dict /
        Record / DataFrame (columns= naming the 3; default: every column,
        which must then be 3).
    method : str
        "twostep" (bias only, tolerates partial coverage), "twostep-full"
        (bias + symmetric D) or "ellipsoid" (Li-Griffiths, as Magneto).
    field_norm : float, optional
        The local field magnitude F (e.g. from IGRF), in the unit after lsb;
        default: the mean raw |h| (Magneto's default).
    field_column : str or array_like, optional
        A field norm per point (TWOSTEP only): a column name, or one value
        per point (not divided by lsb).
    noise : float, optional
        Per-axis 1-sigma noise for the weights and the chi-squared test, in
        the unit after lsb (default: estimated from the residuals).
    reject : float
        Drop points whose |h| is more than this many standard deviations
        from the mean (0: none).
    allow_partial : bool
        Fit even when the points cover too little of the sphere.
    unit : str, optional
        The name of the unit after lsb (uT, mG, ...), for the result.
    lsb : float
        Counts per unit, one value for the three axes.
    columns : str or list, optional
        The 3 magnetometer columns.
    skip_rows : int
        Lines of preamble of a file.
    threads : int
        Worker threads of the reader (0: every core).

    Returns
    -------
    MagCalibration
        `calibrate mag --format json` as a typed object.

    Raises
    ------
    cubecal.CalibrationError
        The points cannot determine the calibration (.reason
        "poor_coverage", "degenerate", "field_norm", ...).
    cubecal.UsageError
        A bad argument.
    cubecal.InputError
        Bad data.
    """
    args = _cubecal._MagArgs()
    args.method = _args.text(method, "method")
    args.lsb = _args.number(lsb, "lsb")
    args.field_norm = _args.optional_number(field_norm, "field_norm")
    args.noise = _args.optional_number(noise, "noise")
    args.reject = _args.number(reject, "reject")
    args.allow_partial = _args.flag(allow_partial, "allow_partial")
    args.unit = _args.optional_text(unit, "unit") or ""
    skip_rows, threads = _args.count(skip_rows, "skip_rows"), _args.threads(threads)
    shown = {"method": method if method != "ellipsoid" else None, "field_norm": field_norm,
             "field_column": field_column if isinstance(field_column, str) else None, "noise": noise,
             "reject": reject or None, "allow_partial": allow_partial or None, "unit": unit,
             "lsb": lsb if lsb != 1.0 else None, "columns": columns}
    if _is_path(points):
        path = os.fspath(points)
        if field_column is not None and not isinstance(field_column, str):
            raise _usage("field_column", "field_column: the field column of a file: its name or 1-based index")
        doc = _cubecal._mag_file(path, string_list(columns, "columns"), skip_rows, threads, field_column or "", args,
                                 _call_text("calibrate_mag", repr(path), shown))
        return MagCalibration(doc)
    if skip_rows:
        raise _usage("skip_rows", "skip_rows: an option of a file; the points are arrays here")
    field_values = None
    exclude = []
    if isinstance(field_column, str):
        field_values = _column(points, field_column, "field_column")
        exclude.append(field_column)
    elif field_column is not None:
        field_values = _vector(field_column, "field_column")
    if _is_table(points):
        names, arrays = _channels(points, columns, None, tuple(exclude), "points")
        if len(arrays) != 3:
            raise _usage("columns", f"columns: {len(arrays)} columns ({', '.join(names)}): name the 3 "
                                    "magnetometer columns with columns=")
    else:
        if columns is not None:
            raise _usage("columns", "columns: names of the columns of a dict or DataFrame; the points are arrays here")
        names, arrays = _triad(points, "points")
    doc = _cubecal._mag_arrays(arrays, names, field_values, args, _label(points),
                               _call_text("calibrate_mag", "<arrays>", shown))
    return MagCalibration(doc)


# ---------------------------------------------------------------------------
# calibrate temperature


@_args.public
def calibrate_temperature(data, temperature, rate=None, order=1, unit="counts", columns=None, names=None,
                          **read_options):
    """Polynomial bias(T) of every channel, as `cubecal calibrate temperature`.

    With the covariance of its coefficients, in the form a flight computer
    applies: corrected = raw - sum_{p>=1} c_p (T - t_ref)^p.

    Parameters
    ----------
    data : str, os.PathLike, array_like, dict, cubecal.Record or DataFrame
        A path (read as the CLI reads it: columns=, rate= when there is no
        time column, skip_rows, lsb, ... as cubecal.read), or arrays (1-D,
        2-D with one channel per column, a list, a dict / Record /
        DataFrame, columns= choosing among named columns).
    temperature : str or array_like
        One value per sample, degC: the temperature column's name (of the
        file, or of the dict), or an array.
    rate : float, optional
        Sampling rate, Hz (arrays need none: the fit does not use time).
    order : int
        Order of the polynomial, 1 to 5.
    unit : str
        The channels' unit, one for all (names the coefficients' units:
        "unit", "unit/degC", ...).
    columns : str or list, optional
        The channels' columns.
    names : list of str, optional
        Names of array channels.
    **read_options
        cubecal.read's options for a path.

    Returns
    -------
    TemperatureCalibration
        `calibrate temperature --format json` as a typed object.

    Raises
    ------
    cubecal.CalibrationError
        A channel's bias(T) cannot be determined (.reason "degenerate" when
        the temperature does not vary enough, "too_few_points").
    cubecal.UsageError
        A bad argument.
    cubecal.InputError
        Bad data.
    """
    args = _cubecal._TemperatureArgs()
    order = _args.count(order, "order")
    if order < 1 or order > 5:
        raise _usage("order", "order: the polynomial order is 1 to 5")
    args.order = order
    args.unit = _args.text(unit, "unit")
    if _is_path(data):
        path = os.fspath(data)
        if names is not None:
            raise _usage("names", "names: give columns= to choose the columns of a file")
        if not isinstance(temperature, str):
            raise _usage("temperature", "temperature: the temperature of a file: the name (or 1-based index) of "
                                        "its column")
        ro = dict(read_options, columns=columns, rate=rate)
        return TemperatureCalibration(_cubecal._temperature_file(path, read_args(**ro), temperature, args))
    _no_read_options(read_options)
    if temperature is None:
        raise _usage("temperature", "temperature: give the temperature: a column name or one value per sample (degC)")
    if isinstance(temperature, str):
        temp_name, temp_values = temperature, _column(data, temperature, "temperature")
        exclude = (temperature,)
    else:
        temp_name, temp_values, exclude = "temperature", _vector(temperature, "temperature"), ()
    chan_names, arrays = _channels(data, columns, names, exclude)
    r = _rate_of(rate, data) or 1.0
    doc = _cubecal._temperature_arrays(arrays, chan_names, r, temp_values, temp_name, args, _label(data))
    return TemperatureCalibration(doc)


# ---------------------------------------------------------------------------
# calibrate multiposition


def _triad_of_data(data, columns, exclude, option):
    """(names, 3 arrays) of a triad given as arrays or named columns."""
    if _is_table(data):
        names, arrays = _channels(data, columns, None, exclude, option.split("_")[0])
        if len(arrays) != 3:
            raise _usage(option, f"{option}: {len(arrays)} columns ({', '.join(names)}): name the 3 columns "
                                 f"with {option}=")
        return names, arrays
    if columns is not None:
        raise _usage(option, f"{option}: column names need data with named columns (a dict, cubecal.Record or "
                             "DataFrame)")
    return _triad(data, option.split("_")[0])


@_args.public
def calibrate_multiposition(acc, gyro=None, rate=None, time=None, gyro_time=None, acc_columns=None,
                            gyro_columns=None, g=9.80665, init_static=50.0, window=101, interval_samples=100,
                            min_intervals=12, acc_bias=0.0, acc_scale=0.0, gyro_scale=1.0, refine_gyro_bias=False,
                            use_means=False, skip_rows=0, threads=0):
    """Accelerometer (and gyroscope) calibration from static poses, as `cubecal calibrate multiposition`.

    Without a turntable (Tedaldi, Pretto & Menegatti 2014): X' = T K (X - B)
    for each triad; the accelerometer from |a'| = g over at least
    min_intervals static poses, the gyroscope by integrating it between them.

    Parameters
    ----------
    acc : str, os.PathLike, array_like, dict, cubecal.Record or DataFrame
        The raw accelerometer record: a path (delimited text, optionally
        gzip; acc_columns= its 3 columns), or an (n, 3) array, 3 arrays, or
        a dict / Record / DataFrame (acc_columns= naming the 3).
    gyro : same as acc, optional
        The raw gyroscope record on the same clock; or None with
        gyro_columns= naming its columns in `acc`; or None for the
        accelerometer alone.
    rate : float, optional
        Sampling rate, Hz (or time stamps).
    time : str, int or array_like, optional
        Time stamps, s (increasing, without gaps): the time column of the
        files (name or 1-based index), an array, or a column of `acc`.
    gyro_time : str or array_like, optional
        The gyroscope's own stamps, s, when they differ.
    acc_columns, gyro_columns : str or list, optional
        The triads' columns.
    g : float
        Local gravity, the magnitude of a' (sets its unit, e.g. m/s^2).
    init_static : float
        The initial static period (threshold and gyroscope bias), s.
    window : int
        Samples of the centred variance window (odd, >= 11).
    interval_samples : int
        Samples used per static interval (and its minimum length).
    min_intervals : int
        The fewest static intervals accepted.
    acc_bias : float or sequence of 3 float
        Initial bias guess, raw units.
    acc_scale : float
        Initial scale guess, g units per raw unit (0: from the initial
        period).
    gyro_scale : float
        Initial gyroscope scale guess, rad/s per raw count.
    refine_gyro_bias : bool
        Fit 3 gyroscope bias corrections besides the 9 parameters.
    use_means : bool
        One accelerometer residual per interval.
    skip_rows : int
        Lines of preamble of a file.
    threads : int
        Worker threads of the reader (0: every core).

    Returns
    -------
    MultipositionCalibration
        `calibrate multiposition --format json` as a typed object.

    Raises
    ------
    cubecal.CalibrationError
        The record cannot determine the calibration (.reason
        "too_few_intervals", "initial_static", "scale_guess", ...).
    cubecal.UsageError
        A bad argument.
    cubecal.InputError
        Bad data.
    """
    args = _cubecal._MultipositionArgs()
    args.g = _args.number(g, "g")
    args.init_static = _args.number(init_static, "init_static")
    args.window = _args.count(window, "window")
    args.interval_samples = _args.count(interval_samples, "interval_samples")
    args.min_intervals = _args.count(min_intervals, "min_intervals")
    args.acc_bias = number_list(acc_bias, "acc_bias")
    args.acc_scale = _args.number(acc_scale, "acc_scale")
    args.gyro_scale = _args.number(gyro_scale, "gyro_scale")
    args.refine_gyro_bias = _args.flag(refine_gyro_bias, "refine_gyro_bias")
    args.use_means = _args.flag(use_means, "use_means")
    skip_rows, threads = _args.count(skip_rows, "skip_rows"), _args.threads(threads)
    shown = {"rate": rate, "time": time if isinstance(time, str) else None, "acc_columns": acc_columns,
             "gyro_columns": gyro_columns, "g": g if g != 9.80665 else None,
             "init_static": init_static if init_static != 50.0 else None,
             "gyro_scale": gyro_scale if gyro_scale != 1.0 else None,
             "refine_gyro_bias": refine_gyro_bias or None, "use_means": use_means or None}
    if _is_path(acc):
        if gyro is not None and not _is_path(gyro):
            raise _usage("gyro", "gyro: with an accelerometer file, the gyroscope is a file too (or gyro_columns=)")
        if time is not None and not isinstance(time, str):
            raise _usage("time", "time: the time of a file: the name (or 1-based index) of its column")
        if gyro_time is not None:
            raise _usage("gyro_time", "gyro_time: files are read with the same time column (time=)")
        acc_path = os.fspath(acc)
        gyro_path = os.fspath(gyro) if gyro is not None else ""
        first = repr(acc_path) + (", " + repr(gyro_path) if gyro_path else "")
        doc = _cubecal._multiposition_file(acc_path, gyro_path, string_list(acc_columns, "acc_columns"),
                                           string_list(gyro_columns, "gyro_columns"),
                                           str(time or ""), _args.rate(rate) if rate is not None else 0.0, skip_rows,
                                           threads, args,
                                           _call_text("calibrate_multiposition", first, shown))
        return MultipositionCalibration(doc)
    if _is_path(gyro):
        raise _usage("gyro", "gyro: with accelerometer arrays, the gyroscope is arrays too")
    if skip_rows:
        raise _usage("skip_rows", "skip_rows: an option of a file; the data are arrays here")
    _check_one_segment(acc)
    exclude = []
    time_values = None
    if isinstance(time, str):
        time_values = _column(acc, time, "time")
        exclude.append(time)
    elif time is not None:
        time_values = _vector(time, "time")
    elif rate is None and _record_time(acc):
        time_values = np.asarray(acc[_record_time(acc)], dtype=np.float64)
    gyro_time_values = None
    if isinstance(gyro_time, str):
        gyro_time_values = _column(gyro if gyro is not None else acc, gyro_time, "gyro_time")
    elif gyro_time is not None:
        gyro_time_values = _vector(gyro_time, "gyro_time")
    gyro_arrays = None
    gyro_label = "<gyro arrays>"
    if gyro is not None:
        # A gyroscope table stamped like the accelerometer's: its own stamps.
        own = time if isinstance(time, str) else _record_time(gyro) if time is None and rate is None else None
        if gyro_time is None and own and _is_table(gyro) and own in _column_names(gyro):
            gyro_time_values = _column(gyro, own, "time")
        _, gyro_arrays = _triad_of_data(gyro, gyro_columns if gyro_columns is not None else acc_columns,
                                        tuple([time] if isinstance(time, str) else []), "gyro_columns")
        gyro_label = _label(gyro, gyro_label)
    elif gyro_columns is not None:
        if acc_columns is None:
            raise _usage("acc_columns", "acc_columns: give acc_columns with gyro_columns for a table holding both")
        _, gyro_arrays = _triad_of_data(acc, gyro_columns, (), "gyro_columns")
        gyro_label = _label(acc)
    _, acc_arrays = _triad_of_data(acc, acc_columns, tuple(exclude), "acc_columns")
    r = _rate_of(rate, acc) if time_values is None else (_args.rate(rate) if rate is not None else 0.0)
    doc = _cubecal._multiposition_arrays(acc_arrays, gyro_arrays, time_values, gyro_time_values, r or 0.0, args,
                                         _label(acc), gyro_label,
                                         _call_text("calibrate_multiposition", "<arrays>", shown))
    return MultipositionCalibration(doc)


# ---------------------------------------------------------------------------
# turnon, compare

_RUN_KEYS = ("columns", "time", "rate", "skip_rows", "lsb", "gaps", "topics", "dataset", "binary", "header_bytes",
             "names", "unit")


def _run_inputs(runs, rate, columns, names, threads, read_options, per_run_unit, command):
    if _is_path(runs) or not isinstance(runs, (list, tuple)):
        raise _usage("runs", "runs: a list of runs: paths, arrays or dicts of columns (one record each)")
    inputs = []
    for k, item in enumerate(runs):
        own = {}
        if isinstance(item, tuple) and len(item) == 2 and isinstance(item[1], dict):
            item, own = item
            unknown = [key for key in own if key not in _RUN_KEYS]
            if unknown:
                raise _usage("runs", f"runs: run {k + 1}: unknown option {', '.join(unknown)} "
                                     f"(known: {', '.join(_RUN_KEYS)})")
        if "unit" in own and not per_run_unit:
            raise _usage("unit", f"unit: run {k + 1}: {command} averages the runs' biases, so every run is in the same "
                                 "unit: give unit= to turnon (or scale a run with lsb=), not a unit per run")
        run = _cubecal._RunInput()
        run.units = string_list(own.get("unit"), "unit")
        if _is_path(item):
            if "names" in own or names is not None:
                raise _usage("names", "names: give columns= to choose the columns of a file")
            ro = dict(read_options, columns=columns, rate=rate, threads=threads)
            ro.update({key: v for key, v in own.items() if key != "unit"})
            run.path = os.fspath(item)
            run.read = read_args(**ro)
        else:
            _no_read_options(read_options)
            file_keys = [key for key in own if key not in ("rate", "names", "unit", "columns")]
            if file_keys:
                raise _usage(file_keys[0], f"run {k + 1}: {', '.join(file_keys)}: options of a file; the run is arrays")
            _check_one_segment(item, "give its file, read with gaps=\"split\", or one contiguous piece")
            run_names, arrays = _channels(item, own.get("columns", columns), own.get("names", names), (), "runs")
            r = _rate_of(own.get("rate", rate), item)
            if r is None:
                raise _usage("rate", f"rate: run {k + 1}: give the sampling rate of the arrays in Hz")
            run.channels = arrays
            run.names = run_names
            run.rate = r
            run.label = _label(item, f"<run {k + 1}>")
        inputs.append(run)
    return inputs


def _runs_args(unit, taus, ci, threads):
    a = _cubecal._RunsArgs()
    a.units = string_list(unit, "unit")
    a.taus = _args.taus(taus)
    a.ci = _args.number(ci, "ci")
    a.threads = _args.threads(threads)
    return a


@_args.public
def turnon(runs, rate=None, unit=None, taus="log:10", ci=0.683, columns=None, names=None, threads=0,
           **read_options):
    """Turn-on bias over power-cycled runs of the same sensor, as `cubecal turnon`.

    Every run is analysed as `analyze` does; the result holds each run's
    bias (its mean), bias instability and OADEV, and per channel the mean
    bias over the runs, the turn-on bias (the sample standard deviation of
    the run biases, runs - 1 dof) and its chi-squared interval at `ci`.

    Parameters
    ----------
    runs : list
        At least 2 records with the same channels, each a path (read with the
        call's columns=, rate= and read_options) or arrays (a 2-D array, a
        list, a dict / Record / DataFrame) sampled at `rate`; a run may be a
        pair (run, options) whose options (columns, time, rate, skip_rows,
        lsb, gaps, names, ...) replace the call's for it, as the CLI's
        FILE:key=value.
    rate : float, optional
        Sampling rate of array runs, Hz (a Record's own by default).
    unit : str or list of str, optional
        One unit for all channels or one per channel ("deg/s", ...), the
        same for every run; default: from the channel names.
    taus : str or sequence of float
        The OADEV grid ("log:10", "octave", "decade", "all" or taus in s).
    ci : float
        Confidence of the intervals (0 to 1).
    columns : str or list, optional
        The channels' columns.
    names : list of str, optional
        Names of array channels.
    threads : int
        Worker threads (0: every core).
    **read_options
        cubecal.read's options for the paths.

    Returns
    -------
    TurnOn
        `turnon --format json` as a typed object (biases in each channel's
        unit).

    Raises
    ------
    cubecal.UsageError
        Fewer than 2 runs, runs with different channels, or a bad argument.
    cubecal.InputError
        Bad data.
    """
    inputs = _run_inputs(runs, rate, columns, names, threads, read_options, False, "turnon")
    if len(inputs) < 2:
        raise _usage("runs", f"runs: the turn-on bias needs at least 2 runs (power cycles), got {len(inputs)}")
    return TurnOn(_cubecal._turnon(inputs, _runs_args(unit, taus, ci, threads)))


@_args.public
def compare(runs, rate=None, unit=None, taus="log:10", ci=0.683, columns=None, names=None, threads=0,
            **read_options):
    """Several runs side by side, as `cubecal compare`.

    Each run analysed on its own (OADEV with its interval, N, B and T), e.g.
    one sensor at several sampling rates.

    Parameters
    ----------
    runs : list
        Records as in cubecal.turnon, except that they may differ in
        channels, and a run's own options may give its unit
        (("run.csv", {"unit": "rad/s"})).
    rate : float, optional
        Sampling rate of array runs, Hz.
    unit : str or list of str, optional
        One unit for all channels or one per channel.
    taus : str or sequence of float
        The OADEV grid.
    ci : float
        Confidence of the intervals (0 to 1).
    columns : str or list, optional
        The channels' columns.
    names : list of str, optional
        Names of array channels.
    threads : int
        Worker threads (0: every core).
    **read_options
        cubecal.read's options for the paths.

    Returns
    -------
    Comparison
        `compare --format json` as a typed object (runs [{file, samples,
        rate_hz, channels [...]}]).
    """
    inputs = _run_inputs(runs, rate, columns, names, threads, read_options, True, "compare")
    return Comparison(_cubecal._compare(inputs, _runs_args(unit, taus, ci, threads)))
