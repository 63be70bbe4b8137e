# Type stub of cubecal._model (cubecal.model). The classes between BEGIN and
# END are written by scripts/result-stubs.py from their _spec.
import os
from typing import Any, Sequence

from ._result import ModelChannel, Result

Data = str | os.PathLike[str] | Any


def model(data: Data, model: str, rate: float | None = None, unit: str | Sequence[str] | None = None,
          bootstrap: int = 0, seed: int = 1, ci: float = 0.95, starts: int = 32,
          names: Sequence[str] | None = None, threads: int = 0, wic_replicates: int = 50, robust: bool = False,
          efficiency: float = 0.6, **read_options: Any) -> NoiseModel: ...


# BEGIN result classes (scripts/result-stubs.py)


class NoiseModel(Result):
    command: str
    file: str
    rate_hz: float
    samples: int
    model: str
    ci: float
    bootstrap: int
    seed: int
    selection_replicates: int
    robust: bool
    robust_efficiency: float | None
    channels: list[ModelChannel]


# END result classes
