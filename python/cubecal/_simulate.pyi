# Type stub of cubecal._simulate (cubecal.simulate, cubecal.presets).
import os
from typing import Sequence

from numpy.typing import ArrayLike

from ._analyze import Analysis
from ._read import Record

_Model = str | Analysis | os.PathLike[str]


def presets() -> list[str]: ...


def simulate(model: _Model | Sequence[_Model], rate: float | None = None, duration: float | str = 3600.0,
             seed: int = 1, temperature: str | ArrayLike = "sine:25,5", bias: str | None = None,
             true_input: tuple[ArrayLike, ArrayLike, ArrayLike, ArrayLike] | None = None,
             flicker: float | Sequence[float] | None = None) -> Record: ...
