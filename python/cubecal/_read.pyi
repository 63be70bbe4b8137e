# Type stub of cubecal._read (cubecal.read).
import os
from typing import Any, Sequence

import numpy as np
from numpy.typing import NDArray


class Record(dict[str, NDArray[np.float64]]):
    file: str
    rate_hz: float
    rate_from_time: bool
    time: str
    channels: list[str]
    extra: list[str]
    units: list[str]
    left_out: list[str]
    topics: list[str]
    segments: list[tuple[int, int]]
    gaps: str
    missing_samples: list[int]
    bytes: int
    def __init__(self, columns: dict[str, NDArray[np.float64]], meta: dict[str, Any]) -> None: ...


def read_args(columns: str | Sequence[str | int] | None = None, time: str | int | None = None,
              rate: float | None = None, skip_rows: int = 0, lsb: float | Sequence[float] | None = None,
              gaps: str = "error", topics: str | Sequence[str] | None = None, dataset: str | None = None,
              binary: str | None = None, header_bytes: int = 0, extra: str | Sequence[str] | None = None,
              threads: int = 0) -> Any: ...


def read(path: str | os.PathLike[str], columns: str | Sequence[str | int] | None = None,
         time: str | int | None = None, rate: float | None = None, skip_rows: int = 0,
         lsb: float | Sequence[float] | None = None, gaps: str = "error", topics: str | Sequence[str] | None = None,
         dataset: str | None = None, binary: str | None = None, header_bytes: int = 0,
         extra: str | Sequence[str] | None = None, frame: bool = False, threads: int = 0) -> Any: ...
