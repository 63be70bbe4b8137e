# Type stub of the extension cubecal._cubecal: the exceptions and the version
# the package exports. The bindings the package's modules call (names with a
# leading underscore) are private and left to the partial stub's __getattr__.
from typing import Any

__version__: str


class Error(ValueError):
    """Base of cubecal's errors (a ValueError)."""


class InputError(Error):
    file: str
    line: int
    column: int


class UsageError(Error):
    option: str


class CalibrationError(Error):
    reason: str


def __getattr__(name: str) -> Any: ...
