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


class PlanTargetSpec(Result):
    term: str
    precision: float


class PlanChannel(Result):
    name: str
    unit: str


class PlanRow(Result):
    channel: str
    term: str
    kind: str
    precision: float | None
    duration_s: float | None
    achieved: float | None
    value: float | None
    unit: str
    tau_lo: float | None
    tau_hi: float | None
    reason: str | None
    why: str | None


class PlanCurve(Result):
    channel: str
    term: str
    duration_s: NDArray[np.float64]
    precision: NDArray[np.float64]


class Plan(Result):
    command: str
    source: str
    source_name: str
    source_note: str
    rate_hz: float
    ci: float
    defaults: bool
    duration_s: float | None
    targets: list[PlanTargetSpec]
    channels: list[PlanChannel]
    rows: list[PlanRow]
    curves: list[PlanCurve]


# END result classes
