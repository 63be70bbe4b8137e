"""The arguments of the public calls, checked before they reach the C++
module: a value of the wrong type or out of range is a cubecal.UsageError
whose .option is the keyword at fault and whose message names it ("bootstrap:
a whole number from 0 to ..."), never pybind11's signature of a private
function, an OverflowError or a NaN in the result.

Every public function is wrapped by `public`, which also turns what would
still escape as such (a value the checks here do not know) into a
UsageError, so that every failure of a call is a cubecal.Error.
"""
import functools
import math
import numbers
import operator
import os

import numpy as np

from . import _cubecal

# The C++ types the counts go to.
SIZE_MAX = 2 ** 64 - 1
UNSIGNED_MAX = 2 ** 32 - 1
INT_MAX = 2 ** 31 - 1


class RateError(_cubecal.UsageError, RuntimeError):
    """A sampling rate that cannot be taken (zero, negative, not finite, or
    outside the readers' range of 1e-9 to 1e9 Hz): a cubecal.UsageError
    whose .option is "rate", and a RuntimeError, the exception AllanTools
    raises for rate=0, so that code written for either catches it."""

    __module__ = "cubecal"


class TauError(_cubecal.UsageError, UserWarning):
    """No tau of the request leaves a deviation of at least two terms on the
    record: a cubecal.UsageError whose .option is "taus", and a UserWarning,
    the exception AllanTools raises then ("nothing remains")."""

    __module__ = "cubecal"


def usage(option, message, kind=None):
    """A cubecal.UsageError (or its subclass `kind`) naming `option`, in one
    line that names it first ("option: ..." unless it is named before the
    message's first colon)."""
    message = " ".join(message.split())
    e = (kind or _cubecal.UsageError)(message if option in message.split(":", 1)[0] else f"{option}: {message}")
    e.option = option
    return e


def _shown(value):
    text = " ".join(repr(value).split())
    return text if len(text) <= 40 else text[:37] + "..."


def number(value, option, minimum=None, maximum=None, positive=False):
    """A finite float (a Python or NumPy real, not a bool or a string)."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise usage(option, f"{option}: a number is expected, not {_shown(value)}")
    try:
        x = float(value)
    except (OverflowError, ValueError, TypeError):
        raise usage(option, f"{option}: {_shown(value)} is not a number a double can hold") from None
    if not math.isfinite(x):
        raise usage(option, f"{option}: a finite number is expected, not {_shown(value)}")
    if positive and not x > 0.0:
        raise usage(option, f"{option}: a positive number is expected, not {_shown(value)}")
    if (minimum is not None and x < minimum) or (maximum is not None and x > maximum):
        low = "" if minimum is None else f"{minimum:g}"
        high = "" if maximum is None else f"{maximum:g}"
        raise usage(option, f"{option}: {_shown(value)} is outside the range {low} to {high}")
    return x


def optional_number(value, option, **limits):
    return None if value is None else number(value, option, **limits)


def count(value, option, minimum=0, maximum=SIZE_MAX):
    """A whole number (an int, a NumPy integer or a float without a fraction)
    from `minimum` to `maximum`, the range of the C++ type it goes to."""
    if isinstance(value, (bool, np.bool_)):
        raise usage(option, f"{option}: a whole number is expected, not {_shown(value)}")
    if isinstance(value, numbers.Integral):
        k = operator.index(value)
    elif isinstance(value, numbers.Real) and math.isfinite(float(value)) and float(value).is_integer():
        k = int(value)
    else:
        raise usage(option, f"{option}: a whole number is expected, not {_shown(value)}")
    if not minimum <= k <= maximum:
        raise usage(option, f"{option}: a whole number from {minimum} to {maximum} is expected, not {k}")
    return k


def optional_count(value, option, **limits):
    return None if value is None else count(value, option, **limits)


def threads(value):
    return count(value, "threads", maximum=UNSIGNED_MAX)


def seed(value):
    return count(value, "seed", maximum=SIZE_MAX)


def text(value, option):
    """A string (a str; a NumPy string too)."""
    if not isinstance(value, str):
        raise usage(option, f"{option}: a string is expected, not {_shown(value)}")
    return str(value)


def optional_text(value, option):
    return None if value is None else text(value, option)


def path(value, option="path"):
    """A file's path: a str or an os.PathLike."""
    if not isinstance(value, (str, os.PathLike)):
        raise usage(option, f"{option}: a file's path is expected, not {_shown(value)}")
    p = os.fspath(value)
    if not isinstance(p, str):
        raise usage(option, f"{option}: a file's path is expected as text, not {_shown(value)}")
    return p


def flag(value, option):
    """True or False (a bool, a NumPy bool, or 0 and 1)."""
    if isinstance(value, (bool, np.bool_)) or (isinstance(value, numbers.Integral) and value in (0, 1)):
        return bool(value)
    raise usage(option, f"{option}: True or False is expected, not {_shown(value)}")


def rate(value, option="rate"):
    """A sampling rate in Hz, in the range the readers take (the C++ check);
    a RateError (a UsageError and a RuntimeError) otherwise."""
    try:
        x = number(value, option)
        _cubecal._check_rate(x)
    except _cubecal.UsageError as e:
        raise usage(option, str(e), RateError) from None
    return x


def samples(value, option="data", dimensions=(1,)):
    """`value` as a float64 array of the given number of dimensions, with at
    least one sample (an array of float64 is not copied)."""
    if value is None or isinstance(value, (str, bytes)):
        raise usage(option, f"{option}: an array of numbers is expected, not {_shown(value)}")
    try:
        a = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError, OverflowError):
        raise usage(option, f"{option}: an array of numbers is expected, not {_shown(value)}") from None
    if a.ndim not in dimensions:
        shapes = " or ".join(f"{d}-D" for d in dimensions)
        raise usage(option, f"{option}: a {shapes} array is expected, got shape {a.shape}")
    if a.size == 0:
        raise usage(option, f"{option}: the array is empty")
    return a


def series(value, option="data"):
    """One record of samples as AllanTools takes it: a 1-D sequence or a
    column of shape (N, 1), as a 1-D float64 array converted once (a list
    once, an array of float64 not at all)."""
    a = samples(value, option, dimensions=range(0, 65))
    if a.ndim == 2 and a.shape[1] == 1:
        return a[:, 0]  # a view, still contiguous
    if a.ndim != 1:
        raise usage(option, f"{option}: a 1-D array or one column, shape (N, 1), is expected, got shape {a.shape}")
    return a


def taus(value, option="taus"):
    """A tau grid: a string ("octave", "log:10", ...), None, or taus in
    seconds (a number or a 1-D sequence of them)."""
    if value is None or isinstance(value, str):
        return value
    if isinstance(value, numbers.Real) and not isinstance(value, (bool, np.bool_)):
        value = [value]
    return samples(value, option)


def _pybind_signature(e):
    return isinstance(e, TypeError) and "incompatible function arguments" in str(e)


def public(function):
    """Wraps a public call: a pybind11 signature error or an overflow that
    the checks above have not caught becomes a cubecal.UsageError."""

    @functools.wraps(function)
    def call(*args, **kwargs):
        try:
            return function(*args, **kwargs)
        except (TypeError, OverflowError) as e:
            if not (_pybind_signature(e) or isinstance(e, OverflowError)):
                raise
            raise usage("", f"cubecal.{function.__name__}: an argument has a type or value it cannot take") from None

    return call
