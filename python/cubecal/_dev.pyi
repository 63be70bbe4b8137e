# Type stub of cubecal._dev (cubecal.dev). The classes between BEGIN and END
# are written by scripts/result-stubs.py from their _spec.
from typing import Any, Sequence

import numpy as np
from numpy.typing import NDArray

from ._result import ExcludedTau, MergedTau, Result


class Curve:
    name: str
    af: NDArray[np.int64]
    tau: NDArray[np.float64]
    dev: NDArray[np.float64]
    n: NDArray[np.int64]
    lo: NDArray[np.float64] | None
    hi: NDArray[np.float64] | None
    edf: NDArray[np.float64] | None
    alpha: NDArray[np.int64] | None
    type_carried: NDArray[np.bool_] | None
    def __init__(self, columns: dict[str, Any]) -> None: ...
    @property
    def m(self) -> NDArray[np.int64]: ...
    def to_dict(self) -> dict[str, Any]: ...
    def __len__(self) -> int: ...


def dev(data: Any, rate: float | None = None, stat: str = "oadev", data_type: str = "freq",
        taus: str | Sequence[float] = "octave", ci: float = 0.683, alpha: int | None = None, edf: str = "greenhall",
        conservative: bool = False, intervals: bool = True, names: Sequence[str] | None = None, threads: int = 0,
        gaps: str | None = None) -> DevResult: ...


# BEGIN result classes (scripts/result-stubs.py)


class DevResult(Result):
    stat: str
    type: str
    rate_hz: float
    file: str
    samples: int
    segments: int
    ci: float | None
    edf_method: str
    stream: Any | None
    excluded_taus: list[ExcludedTau]
    merged_taus: list[MergedTau]
    channels: list[Curve]
    def to_dict(self) -> dict[str, Any]: ...


# END result classes
