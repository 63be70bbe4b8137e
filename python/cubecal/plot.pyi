"""Type stubs of cubecal.plot (AllanTools' Plot, on matplotlib)."""
import os
from types import ModuleType
from typing import IO, Any, Union

from ._cubecal import Error
from .dataset import Dataset

__all__ = ["Plot", "PlotError"]

class PlotError(Error, RuntimeError): ...

class Plot:
    plt: ModuleType
    fig: Any  # matplotlib.figure.Figure
    ax: Any  # matplotlib.axes.Axes
    def __init__(self, no_display: bool = ...) -> None: ...
    def plot(self, atDataset: Dataset, errorbars: bool = ..., grid: bool = ..., **kwargs: Any) -> None: ...
    def show(self) -> None: ...
    def save(self, f: Union[str, os.PathLike, IO[bytes]]) -> None: ...
