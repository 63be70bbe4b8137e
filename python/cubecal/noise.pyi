# Type stub of cubecal.noise (AllanTools' allantools.noise).
from typing import Iterator, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

_Array = npt.NDArray[np.float64]
_Real = Union[float, int, np.floating, np.integer]

__all__: list[str]

def numpy_psd(x: npt.ArrayLike, f_sample: _Real = ...) -> Tuple[_Array, _Array]: ...
def scipy_psd(x: npt.ArrayLike, f_sample: _Real = ..., nr_segments: _Real = ...) -> Tuple[_Array, _Array]: ...
def white(num_points: int = ..., b0: _Real = ..., fs: _Real = ..., seed: Optional[int] = ...) -> _Array: ...
def brown(num_points: int = ..., b_minus2: _Real = ..., fs: _Real = ..., seed: Optional[int] = ...) -> _Array: ...
def violet(num_points: int = ..., b2: _Real = ..., fs: _Real = ..., seed: Optional[int] = ...) -> _Array: ...
def pink(num_points: int = ..., depth: int = ..., seed: Optional[int] = ...) -> _Array: ...
def iterpink(depth: int = ..., seed: Optional[int] = ...) -> Iterator[np.float64]: ...
def timmer_koenig_from_psd(
    f_nodes: npt.ArrayLike,
    h: npt.ArrayLike,
    alpha: npt.ArrayLike,
    duration: _Real,
    timestep: _Real,
    output: str = ...,
    seed: Optional[int] = ...,
) -> _Array: ...
