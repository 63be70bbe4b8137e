"""Type stubs of cubecal.dataset (AllanTools' Dataset)."""
import os
from typing import Any, Dict, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

from ._cubecal import UsageError

__all__ = ["Dataset", "UnknownFunctionError", "NotADeviationError"]

_Taus = Union[None, str, float, Sequence[float], npt.ArrayLike]

class UnknownFunctionError(UsageError, AttributeError): ...
class NotADeviationError(UsageError, RuntimeError): ...

class Dataset:
    inp: Dict[str, Any]
    out: Dict[str, Any]
    def __init__(self, data: Optional[npt.ArrayLike] = ..., rate: float = ..., data_type: str = ...,
                 taus: _Taus = ...) -> None: ...
    def set_input(self, data: Optional[npt.ArrayLike], rate: float = ..., data_type: str = ...,
                  taus: _Taus = ...) -> None: ...
    def compute(self, function: str) -> Dict[str, np.ndarray]: ...
    def write_results(self, filename: Union[str, os.PathLike], digits: int = ...,
                      header_params: Dict[Any, Any] = ...) -> None: ...
