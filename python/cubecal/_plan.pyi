# Type stub of cubecal._plan (cubecal.plan). The classes between BEGIN and
# END are written by scripts/result-stubs.py from their _spec.
import os
from typing import Mapping, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._analyze import Analysis
from ._model import NoiseModel
from ._result import Result


def plan(model: str | Sequence[str] | Analysis | NoiseModel | os.PathLike[str] | None = None,
         target: str | Mapping[str, float] | None = None, duration: float | str | None = None,
         datasheet: str | None = None, rate: float | None = None, ci: float = 0.683,
         taus: str | ArrayLike = "log:10") -> Plan: ...


# BEGIN result classes (scripts/result-stubs.py)
# END result classes
