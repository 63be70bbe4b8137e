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
from ._result import Result

__all__ = [
    "RateTableCalibration", "MagCalibration", "TemperatureCalibration", "MultipositionCalibration", "TurnOn",
    "Comparison", "calibrate_rate_table", "calibrate_mag", "calibrate_temperature", "calibrate_multiposition",
    "turnon", "compare",
]


class RateTableCalibration(Result):
    """A rate-table calibration, as `calibrate rate-table --format json`:
    A, A_sigma, beta, beta_sigma (w = A w_g + beta, the paper's eq. 6, in
    `unit`), forward {S, bias, scale_factor_ppm, misalignment_mrad, ... with
    their sigmas} (w_g = S w + b_g), residual_before / residual_after {max,
    rms}, error_covariance (eq. 12), fit {plateaus, dof, ...},
    plateau_source, plateaus [{t_begin, t_end, n, ref, mean, ...,
    residual_after}] and the detection's counts."""


class MagCalibration(Result):
    """A magnetometer calibration, as `calibrate mag --format json`:
    h_cal = soft_iron (h - bias) with |h_cal| = field_norm; bias and
    bias_sigma (in `unit`), soft_iron and soft_iron_sigma, field_norm and
    its source, norm_error_before / norm_error_after {mean, rms, max}, chi2,
    dof, p_value, noise, points used and rejected (rejected_lines: the lines
    of a file, or the 1-based numbers of points given as arrays), semi_axes,
    axis_ratio, coverage, covariance and notes."""


class TemperatureCalibration(Result):
    """A temperature calibration, as `calibrate temperature --format json`:
    per channel (channels[i]) the polynomial bias(T) = sum_p coeff[p]
    (T - t_ref)^p with coeff_sigma, coeff_units, covariance, r2 and
    residual_rms; a flight computer applies corrected = raw - sum_{p>=1}
    coeff[p] (T - t_ref)^p."""


class MultipositionCalibration(Result):
    """A multi-position calibration (Tedaldi, Pretto & Menegatti 2014), as
    `calibrate multiposition --format json`: X' = T K (X - B) for the
    accelerometer (accelerometer.parameters, .model, .before / .after
    residuals) and, when a gyroscope was given, the gyroscope (gyroscope, or
    None); the static intervals found, the thresholds tried (trials), the
    options used."""


class TurnOn(Result):
    """The turn-on bias over power-cycled runs, as `turnon --format json`:
    runs (each run's file, samples, rate_hz and per channel its bias (mean),
    stddev, arw, bias_instability, OADEV curve) and channels [{name, unit,
    mean_bias, turn_on_bias (the standard deviation of the run biases),
    turn_on_bias_lo / _hi (its chi-squared interval at ci)}]."""


class Comparison(Result):
    """Runs side by side, as `compare --format json`: runs, each with its
    file, samples, rate_hz and per channel the OADEV curve and N, B, T."""


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
    """Gyro scale factors, misalignment and bias from a rate-table run (the
    paper's eq. 6-13), as `cubecal calibrate rate-table`: the plateaus where
    the table held a constant rate are found, the gyro mean of each is fitted
    by least squares to w_g = S w + b_g, and the calibration w = A w_g + beta
    is given with 1-sigma uncertainties.

    data: the gyro record (3 channels, in `unit`, "deg/s" or "rad/s"): a path,
    read as the CLI reads it (columns= the 3 gyro columns; time=, rate=,
    skip_rows, lsb, gaps, ... as cubecal.read), or arrays (an (n, 3) array,
    3 arrays, or a dict / cubecal.Record / DataFrame with columns= naming the
    gyro columns) sampled at `rate` Hz, or stamped with time= (an array in
    seconds, or a column name; a Record's time column by default).

    The true rates come from one of:
      reference: the 3 reference (table) rate columns, in `unit`, not scaled
        by lsb: column names of the file or of the data, or an (n, 3) array /
        3 arrays; plateaus are the runs where they stay constant within
        ref_tolerance;
      schedule: a CSV file of rows t_begin,t_end,wx,wy,wz, or an array of such
        rows, in seconds of the record's time base (its time stamps, else
        sample / rate from 0); from_signal=True finds the plateaus in the
        gyro signal (moving standard deviation over `window` s) and takes only
        their rates from the schedule.
    margin: seconds dropped at both ends of a plateau; min_plateau: shortest
    plateau kept (s, after the margins). earth_axis: (X, Y, Z), the Earth's
    axis in the sensor frame: the Earth rate along it is added to every
    reference rate (default: ignored, as by a table that compensates it).

    Returns a RateTableCalibration. Raises CalibrationError (.reason
    "no_plateaus", "too_few_points", "degenerate", ...) when the run cannot
    determine the calibration, UsageError for bad arguments, InputError for
    bad data in a file or array.
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
    """Magnetometer hard- and soft-iron calibration from points measured over
    many orientations (no time stamps needed), as `cubecal calibrate mag`:
    h_cal = soft_iron (h - bias) with |h_cal| = F.

    points: a path (delimited text, optionally gzip, with 3 magnetometer
    columns, or columns= naming them; skip_rows lines of preamble), or an
    (n, 3) array, 3 arrays, or a dict / cubecal.Record / DataFrame (columns=
    naming the 3 columns; default: every column, which must then be 3).
    lsb: counts per unit, one value for the three axes. unit: the name of the
    unit after lsb (uT, mG, ...), for the result.
    method: "twostep" (bias only, tolerates partial coverage), "twostep-full"
    (bias + symmetric D) or "ellipsoid" (Li-Griffiths, as Magneto).
    field_norm: the local field magnitude F (e.g. from IGRF) in the units
    after lsb; default: the mean raw |h| (Magneto's default).
    field_column: a field norm per point (TWOSTEP only): a column name, or an
    array with one value per point (not divided by lsb).
    noise: per-axis 1-sigma noise for the weights and the chi-squared test
    (default: estimated from the residuals). reject: drop points whose |h|
    is more than this many standard deviations from the mean (0: none).
    allow_partial: fit even when the points cover too little of the sphere.

    Returns a MagCalibration. Raises CalibrationError (.reason
    "poor_coverage", "degenerate", "field_norm", ...) when the points cannot
    determine the calibration, UsageError for bad arguments, InputError for
    bad data.
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
    """Polynomial bias(T) of every channel with the covariance of its
    coefficients, as `cubecal calibrate temperature`, in the form a flight
    computer applies: corrected = raw - sum_{p>=1} c_p (T - t_ref)^p.

    data: a path (read as the CLI reads it: columns=, rate= when there is no
    time column, skip_rows, lsb, ... as cubecal.read), or arrays (a 1-D
    array, a 2-D array with one channel per column, a list, a dict /
    cubecal.Record / DataFrame, columns= choosing among named columns).
    temperature: degC, one value per sample: the temperature column's name
    (of the file, or of the dict), or an array. rate: Hz; arrays need none
    (the fit does not use time). order: of the polynomial, 1 to 5. unit: the
    unit of the channels, one for all (names the coefficients' units:
    "unit", "unit/degC", ...).

    Returns a TemperatureCalibration. Raises CalibrationError (.reason
    "degenerate" when the temperature does not vary enough, "too_few_points")
    when a channel's bias(T) cannot be determined, UsageError for bad
    arguments, InputError for bad data.
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
    """Accelerometer (and gyroscope) calibration from a sequence of static
    poses without a turntable (Tedaldi, Pretto & Menegatti 2014), as `cubecal
    calibrate multiposition`: X' = T K (X - B) for each triad; the
    accelerometer from |a'| = g over at least min_intervals static poses,
    the gyroscope by integrating it between them.

    acc: the raw accelerometer record: a path (delimited text, optionally
    gzip; acc_columns= its 3 columns, default every column but the time
    column, which must then be 3; skip_rows), or an (n, 3) array, 3 arrays,
    or a dict / cubecal.Record / DataFrame (acc_columns= naming the 3).
    gyro: the raw gyroscope record, on the same clock, in the same form (a
    path read with gyro_columns, default acc_columns); or None with
    gyro_columns= naming its columns in `acc` (one file or table holding
    both); or None for the accelerometer alone.
    Sampling: rate (Hz), or time stamps (s, increasing, without gaps): time=
    the time column of the files (name or 1-based index), or an array (or a
    column of `acc`); gyro_time= the gyroscope's own stamps when they differ.
    g: local gravity, the magnitude of a' (sets its unit). init_static:
    seconds of the initial static period (threshold and gyroscope bias).
    window: samples of the centred variance window (odd, >= 11).
    interval_samples: samples used per static interval (and its minimum
    length). acc_bias: initial bias guess (raw), one value or x, y, z;
    acc_scale: initial scale guess (g units per raw, 0: from the initial
    period); gyro_scale: initial gyroscope scale guess (rad/s per raw count).
    refine_gyro_bias: fit 3 gyroscope bias corrections besides the 9
    parameters. use_means: one accelerometer residual per interval.

    Returns a MultipositionCalibration. Raises CalibrationError (.reason
    "too_few_intervals", "initial_static", "scale_guess", ...) when the
    record cannot determine the calibration, UsageError for bad arguments,
    InputError for bad data.
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
    """Turn-on bias over power-cycled runs of the same sensor, as `cubecal
    turnon`: every run is analysed as `analyze` does; the result holds each
    run's bias (its mean), bias instability and OADEV, and per channel the
    mean bias over the runs, the turn-on bias (the sample standard deviation
    of the run biases, runs - 1 dof) and its chi-squared interval at `ci`.

    runs: a list of at least 2 records with the same channels, each a path
    (read as the CLI reads it, with the call's columns=, rate= and
    read_options: skip_rows, lsb, gaps, ... as cubecal.read) or arrays (a
    2-D array, a list, a dict / cubecal.Record / DataFrame) sampled at `rate`
    Hz (a Record's own rate by default). A run may be a pair (run, options)
    whose options (columns, time, rate, skip_rows, lsb, gaps, names, ...)
    replace the call's for that run, as the CLI's FILE:key=value.
    unit: one for all channels or one per channel ("deg/s", "rad/s", ...),
    the same for every run; default: from the channel names (gx_dps, ...).
    taus: the OADEV grid ("log:10", "octave", "decade", "all" or taus in s).

    Returns a TurnOn. Raises UsageError for fewer than 2 runs, runs with
    different channels, or bad arguments; InputError for bad data.
    """
    inputs = _run_inputs(runs, rate, columns, names, threads, read_options, False, "turnon")
    if len(inputs) < 2:
        raise _usage("runs", f"runs: the turn-on bias needs at least 2 runs (power cycles), got {len(inputs)}")
    return TurnOn(_cubecal._turnon(inputs, _runs_args(unit, taus, ci, threads)))


@_args.public
def compare(runs, rate=None, unit=None, taus="log:10", ci=0.683, columns=None, names=None, threads=0,
            **read_options):
    """Several runs side by side, as `cubecal compare`: each analysed on its
    own (OADEV with its interval, N, B and T), e.g. one sensor at several
    sampling rates. runs, rate, unit, taus, ci and the read options as in
    cubecal.turnon, except that the runs may differ in channels, and a run's
    own options may give its unit (("run.csv", {"unit": "rad/s"})).

    Returns a Comparison (runs [{file, samples, rate_hz, channels [...]}]).
    """
    inputs = _run_inputs(runs, rate, columns, names, threads, read_options, True, "compare")
    return Comparison(_cubecal._compare(inputs, _runs_args(unit, taus, ci, threads)))
