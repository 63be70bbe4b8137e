# Type stub of cubecal/_args.py: the exceptions it defines (the argument
# checks are private to the package).
from typing import Any

from ._cubecal import UsageError

class RateError(UsageError, RuntimeError): ...
class TauError(UsageError, UserWarning): ...

def __getattr__(name: str) -> Any: ...
