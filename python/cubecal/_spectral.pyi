# Type stub of cubecal._spectral (cubecal.psd, cubecal.davar). The classes
# between BEGIN and END are written by scripts/result-stubs.py from their _spec.
import os
from typing import Any, Sequence

import numpy as np
from numpy.typing import NDArray

from ._result import Quantity, Result

Data = str | os.PathLike[str] | Any


def psd(data: Data, rate: float | None = None, unit: str | Sequence[str] | None = None, window: str = "hann",
        segment: int = 0, fmin: float = 0.0, overlap: float = 0.5, detrend: str = "constant",
        bins_per_decade: int = 0, fit: bool = True, fit_min: float = 0.0, fit_max: float = 0.0,
        names: Sequence[str] | None = None, threads: int = 0, **read_options: Any) -> Spectrum: ...


def davar(data: Data, rate: float | None = None, window: str | int | None = None, step: str | int | None = None,
          taus: str | Sequence[float] = "log:10", data_type: str = "freq", intervals: bool = True, ci: float = 0.683,
          alpha: int | None = None, names: Sequence[str] | None = None, threads: int = 0,
          **read_options: Any) -> DynamicAllan: ...


# BEGIN result classes (scripts/result-stubs.py)


class Welch(Result):
    window: str
    segment_length: int
    overlap: float
    overlap_samples: int
    detrend: str
    segments: int
    samples_used: int
    resolution_hz: float
    enbw_hz: float
    bins_per_decade: int | None
    pieces: int | None
    pieces_used: int | None


class PowerLawTerm(Result):
    alpha: int
    h: float
    sigma: float
    valid: bool
    unit: str
    f_lo_hz: float
    f_hi_hz: float


class PowerLawFit(Result):
    f_lo_hz: float
    f_hi_hz: float
    bands: int
    chi2: float
    dof: int
    scale: float
    terms: list[PowerLawTerm]
    covariance: NDArray[np.float64]


class AllanTermDisplay(Result):
    value: float
    sigma: float
    unit: str


class AllanTerm(Result):
    term: str
    alpha: int
    valid: bool
    value: float
    sigma: float
    unit: str
    display: AllanTermDisplay


class DensityRate(Result):
    unit: str
    values: NDArray[np.float64]


class SpectrumChannel(Result):
    name: str
    unit: str | None
    density_unit: str
    frequency_hz: NDArray[np.float64]
    density: NDArray[np.float64]
    edf: NDArray[np.float64]
    bins: NDArray[np.int64]
    density_rate: DensityRate | None
    fit: PowerLawFit | None
    fit_error: str | None
    allan_terms: list[AllanTerm] | None


class Spectrum(Result):
    command: str
    file: str
    rate_hz: float
    samples: int
    pieces: int
    pieces_used: int
    one_sided: bool
    welch: Welch | None
    channels: list[SpectrumChannel]


class BandedSpectrum(Result):
    bins_per_decade: int
    density_unit: str
    frequency_hz: NDArray[np.float64]
    density: NDArray[np.float64]
    edf: NDArray[np.float64]
    bins: NDArray[np.int64]
    first_bin: NDArray[np.int64]


class TermComparison(Quantity):
    term: str
    alpha: int
    allan_fit: Quantity
    difference_sigmas: float | None


class SpectralView(Result):
    method: str
    welch: Welch
    spectrum: BandedSpectrum
    fit: PowerLawFit | None
    fit_error: str | None
    terms: list[TermComparison]


class DavarWindow(Result):
    samples: int
    seconds: float
    asked: str


class DavarIntervals(Result):
    enabled: bool
    ci: float | None
    edf: str | None
    alpha: int | str | None


class DavarExcludedTau(Result):
    tau: float
    reason: str


class DavarChannel(Result):
    name: str
    t_start: NDArray[np.float64]
    t: NDArray[np.float64]
    m: NDArray[np.int64]
    tau: NDArray[np.float64]
    n: NDArray[np.int64]
    missing_samples: NDArray[Any]
    dev: NDArray[np.float64]
    terms: NDArray[Any] | None
    lo: NDArray[np.float64] | None
    hi: NDArray[np.float64] | None
    edf: NDArray[np.float64] | None
    alpha: NDArray[Any] | None


class DynamicAllan(Result):
    command: str
    statistic: str
    file: str
    rate_hz: float
    type: str
    samples: int
    missing_samples: int
    window: DavarWindow
    step: DavarWindow
    windows: int
    window_points: int
    intervals: DavarIntervals
    excluded_taus: list[DavarExcludedTau]
    channels: list[DavarChannel]


# END result classes
