# Type stub of cubecal._calibrate (the calibrations, turnon and compare). The
# classes between BEGIN and END are written by scripts/result-stubs.py from
# their _spec.
import os
from typing import Any, Sequence

import numpy as np
from numpy.typing import NDArray

from ._result import AllanCurve, Misalignment, Quantity, Result

Data = str | os.PathLike[str] | Any
Columns = str | Sequence[str] | None

__all__ = [
    "RateTableCalibration", "MagCalibration", "TemperatureCalibration", "MultipositionCalibration", "TurnOn",
    "Comparison", "calibrate_rate_table", "calibrate_mag", "calibrate_temperature", "calibrate_multiposition",
    "turnon", "compare",
]


def calibrate_rate_table(data: Data, rate: float | None = None, reference: Any = None, schedule: Any = None,
                         from_signal: bool = False, margin: float = 10.0, min_plateau: float = 30.0,
                         ref_tolerance: float = 1e-6, window: float = 10.0,
                         earth_axis: Sequence[float] | None = None, unit: str = "deg/s", columns: Columns = None,
                         time: Any = None, names: Sequence[str] | None = None,
                         **read_options: Any) -> RateTableCalibration: ...


def calibrate_mag(points: Data, method: str = "ellipsoid", field_norm: float | None = None,
                  field_column: Any = None, noise: float | None = None, reject: float = 0.0,
                  allow_partial: bool = False, unit: str | None = None, lsb: float = 1.0, columns: Columns = None,
                  skip_rows: int = 0, threads: int = 0) -> MagCalibration: ...


def calibrate_temperature(data: Data, temperature: Any, rate: float | None = None, order: int = 1,
                          unit: str = "counts", columns: Columns = None, names: Sequence[str] | None = None,
                          **read_options: Any) -> TemperatureCalibration: ...


def calibrate_multiposition(acc: Data, gyro: Data | None = None, rate: float | None = None, time: Any = None,
                            gyro_time: Any = None, acc_columns: Columns = None, gyro_columns: Columns = None,
                            g: float = 9.80665, init_static: float = 50.0, window: int = 101,
                            interval_samples: int = 100, min_intervals: int = 12,
                            acc_bias: float | Sequence[float] = 0.0, acc_scale: float = 0.0,
                            gyro_scale: float = 1.0, refine_gyro_bias: bool = False, use_means: bool = False,
                            skip_rows: int = 0, threads: int = 0) -> MultipositionCalibration: ...


def turnon(runs: Sequence[Any], rate: float | None = None, unit: str | Sequence[str] | None = None,
           taus: str | Sequence[float] = "log:10", ci: float = 0.683, columns: Columns = None,
           names: Sequence[str] | None = None, threads: int = 0, **read_options: Any) -> TurnOn: ...


def compare(runs: Sequence[Any], rate: float | None = None, unit: str | Sequence[str] | None = None,
            taus: str | Sequence[float] = "log:10", ci: float = 0.683, columns: Columns = None,
            names: Sequence[str] | None = None, threads: int = 0, **read_options: Any) -> Comparison: ...


# BEGIN result classes (scripts/result-stubs.py)


class Residuals(Result):
    max: float
    rms: float
    mean: float | None
    unit: str


class RateTableForward(Result):
    S: NDArray[np.float64]
    S_sigma: NDArray[np.float64]
    bias: NDArray[np.float64]
    bias_sigma: NDArray[np.float64]
    cov: NDArray[np.float64]
    scale_factor_error: NDArray[np.float64]
    scale_factor_error_sigma: NDArray[np.float64]
    scale_factor_ppm: NDArray[np.float64]
    scale_factor_ppm_sigma: NDArray[np.float64]
    scale_factor_percent: NDArray[np.float64]
    misalignment: NDArray[np.float64]
    misalignment_sigma: NDArray[np.float64]
    misalignment_mrad: Misalignment
    misalignment_mrad_sigma: Misalignment
    misalignment_deg: Misalignment
    misalignment_convention: str


class RateTableFit(Result):
    plateaus: int
    dof: int
    noise_from_residuals: bool
    noise_cov: NDArray[np.float64]
    earth_rate: NDArray[np.float64]


class PlateauDetection(Result):
    skipped_rows: int
    noise: NDArray[np.float64]


class Plateau(Result):
    begin: int
    end: int
    t_begin: float
    t_end: float
    n: int
    gyro: NDArray[np.float64]
    gyro_std: NDArray[np.float64]
    gyro_cov: NDArray[np.float64]
    ref: NDArray[np.float64]
    has_ref: bool
    residual_after: NDArray[np.float64] | None


class RateTableCalibration(Result):
    file: str
    unit: str
    model: str
    A: NDArray[np.float64]
    A_sigma: NDArray[np.float64]
    beta: NDArray[np.float64]
    beta_sigma: NDArray[np.float64]
    inverse_cov: NDArray[np.float64]
    residual_before: Residuals
    residual_after: Residuals
    error_covariance: NDArray[np.float64]
    error_covariance_unit: str
    forward: RateTableForward
    fit: RateTableFit
    plateau_source: str
    plateaus_dropped_short: int
    plateaus_unmatched: int
    detection: PlateauDetection
    plateaus: list[Plateau]
    invocation: str | None


class NamedCovariance(Result):
    names: list[str]
    matrix: NDArray[np.float64]


class MagCoverage(Result):
    centre: NDArray[np.float64]
    centre_from_sphere_fit: bool
    resultant: float
    lambda_min: float
    spread: NDArray[np.float64]
    octants: int


class MagCalibration(Result):
    file: str
    method: str
    model: str
    unit: str
    bias: NDArray[np.float64]
    bias_sigma: NDArray[np.float64]
    soft_iron: NDArray[np.float64]
    soft_iron_sigma: NDArray[np.float64]
    soft_iron_unit: str
    field_norm: float
    field_norm_source: str
    field_norm_default: bool
    field_norm_per_point: bool
    norm_error_before: Residuals
    norm_error_after: Residuals
    chi2: float
    dof: int
    p_value: float | None
    noise: float
    noise_estimated: bool
    points: int
    points_total: int
    rejected: int
    reject_sigma: float
    rejected_lines: NDArray[np.int64]
    rejected_gross_lines: NDArray[np.int64]
    first_data_line: int
    iterations: int
    converged: bool
    eta: float
    semi_axes: NDArray[np.float64]
    axis_ratio: float
    coverage: MagCoverage
    covariance: NamedCovariance
    notes: list[str]
    invocation: str | None


class TemperatureChannel(Result):
    name: str
    t_ref: float
    coeff: NDArray[np.float64]
    coeff_sigma: NDArray[np.float64]
    coeff_units: list[str]
    covariance: NDArray[np.float64]
    r2: float
    residual_rms: float
    order: int


class TemperatureCalibration(Result):
    file: str
    temperature_column: str
    order: int
    unit: str
    samples: int
    model: str
    channels: list[TemperatureChannel]


class TriadModel(Result):
    B: NDArray[np.float64]
    K: NDArray[np.float64]
    T: NDArray[np.float64]
    TK: NDArray[np.float64]
    misalignment: Misalignment


class Parameter(Result):
    name: str
    value: float
    sigma: float
    unit: str


class FitResiduals(Result):
    count: int
    rms: float
    max: float
    cost: float


class TriadCalibration(Result):
    parameters: list[Parameter]
    covariance: NamedCovariance
    model: TriadModel
    initial: TriadModel
    init_samples: int
    residual: str
    before: FitResiduals
    after: FitResiduals
    sigma0: float
    iterations: int
    converged: bool
    sigma_fit: NDArray[np.float64] | None
    init_bias: NDArray[np.float64] | None
    init_bias_sigma: NDArray[np.float64] | None
    bias_sigma: NDArray[np.float64] | None
    pairs: int | None
    angle_rms_before_deg: float | None
    angle_rms_after_deg: float | None
    angle_max_after_deg: float | None


class StaticInterval(Result):
    begin: int
    end: int
    t_begin: float
    t_end: float


class ThresholdTrial(Result):
    th_mult: int
    threshold: float
    intervals: int
    fitted: bool
    cost: float | None


class MultipositionOptions(Result):
    g: float
    init_static_s: float
    window: int
    interval_samples: int
    min_intervals: int
    acc_bias_guess: NDArray[np.float64]
    acc_scale_guess: float
    gyro_scale_guess: float
    acc_use_means: bool
    refine_gyro_bias: bool
    max_iterations: int
    th_mult_min: int
    th_mult_max: int


class MultipositionCalibration(Result):
    method: str
    acc_file: str
    gyro_file: str | None
    model: str
    samples: int
    rate_hz: float
    g: float
    init_static_s: float
    window: int
    interval_samples: int
    min_intervals: int
    options: MultipositionOptions
    th_mult: int
    threshold: float
    init_variance_norm: float
    static_intervals: int
    intervals: list[StaticInterval]
    trials: list[ThresholdTrial]
    accelerometer: TriadCalibration
    gyroscope: TriadCalibration | None
    invocation: str | None


class UnitSI(Result):
    kind: str
    si_name: str
    to_si: float


class ReadOff(Result):
    value: float
    sigma: float
    valid: bool
    tau_lo: float
    tau_hi: float


class ReadOffs(Result):
    N: ReadOff
    B: ReadOff
    K: ReadOff
    Q: ReadOff
    R: ReadOff
    sigma_min: float
    tau_min: float
    tau_min_lo: float
    tau_min_hi: float


class RunChannel(Result):
    name: str
    unit: str
    unit_si: UnitSI
    mean: float
    stddev: float
    arw: Quantity
    bias_instability: Quantity
    time_constant_s: float | None
    readoffs: ReadOffs
    adev: AllanCurve


class Run(Result):
    file: str
    samples: int
    rate_hz: float
    channels: list[RunChannel]


class TurnOnChannel(Result):
    name: str
    unit: str
    unit_si: UnitSI
    mean_bias: float
    turn_on_bias: float
    turn_on_bias_lo: float
    turn_on_bias_hi: float


class TurnOn(Result):
    ci: float
    runs: list[Run]
    channels: list[TurnOnChannel]


class Comparison(Result):
    runs: list[Run]


# END result classes
