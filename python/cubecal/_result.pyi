# Type stub of cubecal._result: the typed results' base class and the kinds
# several documents share. The classes between BEGIN and END are written by
# scripts/result-stubs.py from their _spec; the rest by hand.
from typing import Any, Iterator, KeysView

import numpy as np
from numpy.typing import NDArray

__all__ = ["Result"]


class Result:
    def __init__(self, data: dict[str, Any]) -> None: ...
    def __getattr__(self, key: str) -> Any: ...
    def __getitem__(self, key: str) -> Any: ...
    def __contains__(self, key: object) -> bool: ...
    def __iter__(self) -> Iterator[str]: ...
    def keys(self) -> KeysView[str]: ...
    def items(self) -> list[tuple[str, Any]]: ...
    def values(self) -> list[Any]: ...
    def get(self, key: str, default: Any = None) -> Any: ...
    def to_dict(self) -> dict[str, Any]: ...
    def to_json(self, indent: int | None = 1) -> str: ...


# BEGIN result classes (scripts/result-stubs.py)


class Node(Result):
    ...


class Quantity(Result):
    value: float | None
    sigma: float | None
    unit: str


class Misalignment(Result):
    xy: float
    xz: float
    yx: float
    yz: float
    zx: float
    zy: float


class AllanCurve(Result):
    af: NDArray[np.int64] | None
    m: NDArray[np.int64] | None
    tau: NDArray[np.float64]
    dev: NDArray[np.float64]
    n: NDArray[np.int64]
    lo: NDArray[np.float64] | None
    hi: NDArray[np.float64] | None
    edf: NDArray[np.float64] | None
    alpha: NDArray[np.int64] | None


class ExcludedTau(Result):
    tau_s: float
    af: int | float
    needs_samples: int | float
    samples: int
    reason: str


class MergedTau(Result):
    tau_s: float
    merged_with_tau_s: float
    af: int


class ModelQuantityDisplay(Result):
    value: float
    sigma: float | None
    lo: float | None
    hi: float | None
    asymptotic_sd: float | None
    unit: str


class ModelQuantity(Result):
    name: str
    value: float
    unit: str
    sd: float | None
    lo: float | None
    hi: float | None
    asymptotic_sd: float | None
    display: ModelQuantityDisplay


class ModelParameters(Result):
    value: float
    phi: float | None
    theta: float | None
    omega: float | None


class ModelTerm(Result):
    term: str
    parameters: ModelParameters
    quantities: list[ModelQuantity]


class ModelCandidate(Result):
    model: str
    parameters: int
    wic: float
    loss: float
    optimism: float
    replicates: int
    objective: float


class WaveletVariance(Result):
    tau_samples: NDArray[np.float64]
    tau_s: NDArray[np.float64]
    nu2: NDArray[np.float64]
    lo: NDArray[np.float64]
    hi: NDArray[np.float64]
    edf: NDArray[np.float64]
    n: NDArray[np.int64]
    model: NDArray[np.float64]


class SpectralLine(Result):
    frequency_hz: float
    power: float
    amplitude: float
    peak_ratio: float
    width_hz: float


class TwinFidelity(Result):
    scales: int
    inside_95: int
    share_inside: float
    max_error: float
    max_error_tau_s: float
    faithful: bool


class TwinError(Result):
    taus: int
    inside: int
    share_inside: float
    max_error: float
    max_error_tau_s: float
    max_error_10s: float | None
    max_error_100s: float | None
    note: str


class ModelChannel(Result):
    name: str
    unit: str | None
    model: str
    candidates: list[ModelCandidate]
    failed: list[str]
    objective: float
    converged: bool
    replicates: int
    terms: list[ModelTerm]
    wavelet_variance: WaveletVariance
    lines: list[SpectralLine] | None
    lines_error: str | None
    fidelity: TwinFidelity | None
    residual_rms_log: float | None
    residual_chi2: float | None
    twin_error: TwinError | None


# END result classes
