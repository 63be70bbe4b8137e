# Type stub of cubecal._analyze (cubecal.analyze). The classes between BEGIN
# and END are written by scripts/result-stubs.py from their _spec.
import os
from typing import Any, Sequence

import numpy as np
from numpy.typing import NDArray

from ._result import AllanCurve, ExcludedTau, MergedTau, ModelChannel, Quantity, Result
from ._spectral import SpectralView

Data = str | os.PathLike[str] | Any


def analyze(data: Data, rate: float | None = None, unit: str | Sequence[str] | None = None,
            temperature: str | Any | None = None, taus: str | Sequence[float] = "log:10", ci: float = 0.683,
            temp_order: int = 1, drift_window: float = 0.0, cov_samples: int = 0, max_samples: int = 0,
            model_lsb: float | Sequence[float] | None = None, names: Sequence[str] | None = None, threads: int = 0,
            psd: bool = False, composite: bool | str | None = None, composite_bootstrap: int = 0,
            **read_options: Any) -> Analysis: ...


# BEGIN result classes (scripts/result-stubs.py)


class AnalysisInput(Result):
    file: str
    samples: int
    rate_hz: float
    duration_s: float
    segments: int
    gaps: str


class NoiseTerm(Quantity):
    tau_range_s: NDArray[np.float64] | None
    read_at_tau_s: float | None
    white_at_read_tau: bool | None
    no_minimum_within_record: bool | None
    significant: bool | None


class ReportedEstimate(Quantity):
    source: str | None


class ReportedTerm(NoiseTerm):
    source: str
    upper_bound: bool
    significance_sigmas: float | None
    estimate: ReportedEstimate | None


class ReportedTerms(Result):
    white_noise: ReportedTerm
    rate_random_walk: ReportedTerm
    bias_instability: ReportedTerm


class CurveMinimum(Result):
    tau_s: float
    tau_range_s: NDArray[np.float64]


class ValueWithUnit(Result):
    value: float | None
    unit: str


class NoiseFit(Result):
    method: str
    note: str
    quantization: NoiseTerm
    arw: NoiseTerm
    bias_instability: NoiseTerm
    rate_random_walk: NoiseTerm
    rate_ramp: NoiseTerm
    coefficients: NDArray[np.float64]
    coefficients_sigma: NDArray[np.float64]
    chi2: float
    dof: int
    rms_rel_residual: float


class Densities(Result):
    white: Quantity
    random_walk: Quantity
    white_si: Quantity
    random_walk_si: Quantity
    white_source: str
    random_walk_source: str


class AccelerometerTerms(Result):
    velocity_random_walk: list[Quantity]
    bias_instability: list[Quantity]
    acceleration_random_walk: list[Quantity]


class AccelerometerView(Result):
    read_off: AccelerometerTerms
    fit: AccelerometerTerms


class BiasChoice(Result):
    trust: str
    fit_over_read_off: float | None
    beyond_combined_sigma: bool
    other_terms_share_at_minimum: float
    reason: str


class NoiseAnalysis(Result):
    method: str
    arw: NoiseTerm
    bias_instability: NoiseTerm
    time_constant_s: float | None
    time_constant_range_s: NDArray[np.float64] | None
    time_constant_rel_sigma: float | None
    curve_minimum: CurveMinimum
    sigma_min: ValueWithUnit
    rate_random_walk: NoiseTerm
    quantization: NoiseTerm
    rate_ramp: NoiseTerm
    fit: NoiseFit
    reported: ReportedTerms
    densities: Densities
    accelerometer: AccelerometerView | None
    bias_instability_choice: BiasChoice
    adev: AllanCurve | None


class GaussMarkovModel(Result):
    sigma: float
    tau_s: float
    sigma_n: float
    residual_rms_log: float
    residual_chi2: float


class SensorModel(Result):
    unit: str
    samples: int
    sigma_n: float | None
    sigma_mu: float | None
    sigma_mu_unit: str | None
    lsb: float
    residual_rms_log: float | None
    residual_chi2: float | None
    error: str | None
    gauss_markov: GaussMarkovModel | None
    gauss_markov_error: str | None
    better_fit: str | None
    adev: AllanCurve | None
    composite: ModelChannel | None


class Drift(Result):
    window_s: float
    fixed_bias: float
    points: int
    file: str


class TemperatureFit(Result):
    t_ref: float
    offset: float
    offset_sigma: float
    coeff: NDArray[np.float64]
    coeff_sigma: NDArray[np.float64]
    coeff_cov: NDArray[np.float64]
    r2: float
    residual_rms: float
    method_text: str | None


class TemperatureNoiseModel(Result):
    sigma_n: float
    sigma_mu: float
    sigma_mu_unit: str
    lsb: float
    iterations: int
    converged: bool


class TemperatureAnalysis(TemperatureFit):
    sensor: str
    order: int
    unit: str
    coeff_units: list[str]
    method: str
    method_text: str
    noise_model: TemperatureNoiseModel | None
    joint_error: str | None
    ols: TemperatureFit
    compensated: NoiseAnalysis
    compensated_model: SensorModel


class AnalysisChannel(Result):
    name: str
    unit: str
    kind: str
    mean: float
    stddev: float
    adev: AllanCurve
    adev_stride: NDArray[np.int64] | None
    noise: NoiseAnalysis
    model: SensorModel
    drift: Drift
    temperature: TemperatureAnalysis | None
    spectral: SpectralView | None


class Covariance(Result):
    channels: list[str]
    matrix: NDArray[np.float64]
    samples: int
    unit: str


class CompositeSettings(Result):
    method: str
    model: str
    selection_replicates: int
    bootstrap: int
    seed: int
    robust: bool
    robust_efficiency: float | None


class TwinCheckChannel(Result):
    name: str
    tau: NDArray[np.float64]
    measured: NDArray[np.float64]
    twins: NDArray[np.float64]
    twins_lo: NDArray[np.float64]
    twins_hi: NDArray[np.float64]
    max_error_10s: float | None
    max_error_100s: float | None
    max_error: float
    max_error_tau_s: float


class TwinCheck(Result):
    twins: int
    seed: int
    samples: int
    note: str
    channels: list[TwinCheckChannel]


class Analysis(Result):
    format_version: int
    command: str
    input: AnalysisInput
    ci: float
    channels: list[AnalysisChannel]
    covariance: Covariance
    excluded_taus: list[ExcludedTau]
    merged_taus: list[MergedTau]
    model_excluded_taus: list[ExcludedTau]
    stream: Any | None
    composite: CompositeSettings | None
    composite_skipped: str | None
    drift_skipped: str | None
    twin_check: TwinCheck | None
    estimator_files: Any | None
    def write(self, directory: str | os.PathLike[str], force: bool = False) -> list[str]: ...


# END result classes
