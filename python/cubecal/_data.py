"""The shapes of data the Python calls accept, as (names, 1-D arrays).

Accepted: a 1-D array (one channel); a 2-D array, one channel per column; a
list or tuple of 1-D arrays; a dict of name -> array (of a cubecal.Record,
from cubecal.read or cubecal.simulate, its channels: not its time and extra
columns); a pandas DataFrame (or anything
with .columns and [name]). Arrays are passed on as they are: a contiguous
float64 array reaches the library without a copy.
"""
import numbers

import numpy as np

from ._args import number, samples, usage


def _channel(value, option):
    """One channel as a 1-D float64 array (a float64 array as it is)."""
    return samples(value, option)


def _is_frame(data):
    return hasattr(data, "columns") and hasattr(data, "__getitem__") and not isinstance(data, dict)


def channels_of(data, names=None, exclude=(), option="data"):
    """(names, arrays) of `data`, the argument `option`; `exclude` names
    columns to leave out."""
    if isinstance(data, dict):
        skip = set(exclude)
        # A Record knows its channels: its time and extra columns are not.
        listed = getattr(data, "channels", None)
        keys = [k for k in (listed if listed is not None else data) if k not in skip]
        arrays = [_channel(data[k], option) for k in keys]
        out_names = [str(k) for k in keys]
    elif _is_frame(data):
        keys = [k for k in data.columns if k not in set(exclude)]
        arrays = [_channel(data[k], option) for k in keys]
        out_names = [str(k) for k in keys]
    elif isinstance(data, (list, tuple)) and data and np.ndim(data[0]) == 1 and not isinstance(data[0], str):
        arrays = [_channel(a, option) for a in data]
        out_names = [f"ch{i + 1}" for i in range(len(arrays))]
    else:
        a = samples(data, option, dimensions=(1, 2))
        if a.ndim == 1:
            arrays = [a]
        else:
            arrays = [a[:, j] for j in range(a.shape[1])]
        out_names = [f"ch{i + 1}" for i in range(len(arrays))]
    if names is not None:
        names = string_list([names] if isinstance(names, str) else names, "names")
        if len(names) != len(arrays):
            raise usage("names", f"names: {len(names)} names for {len(arrays)} channels")
        out_names = names
    if not arrays:
        raise usage(option, f"{option}: no channel")
    return out_names, arrays


def string_list(value, option):
    """None -> [], "a,b" -> ["a", "b"], ["a", "b"] -> ["a", "b"]; a whole
    number (a 1-based column index) -> ["3"]. Anything else is a
    cubecal.UsageError naming `option`."""
    if value is None:
        return []
    if isinstance(value, str):
        return [v.strip() for v in value.split(",") if v.strip()]
    if isinstance(value, numbers.Integral) and not isinstance(value, (bool, np.bool_)):
        return [str(value)]
    if isinstance(value, np.ndarray) and value.ndim == 1:
        value = value.tolist()
    if not isinstance(value, (list, tuple)) or not all(
            isinstance(v, str) or (isinstance(v, numbers.Integral) and not isinstance(v, (bool, np.bool_)))
            for v in value):
        raise usage(option, f"{option}: a name or a list of names is expected, not {value!r}")
    return [str(v) for v in value]


def number_list(value, option):
    """None -> [], x -> [x], a sequence of numbers -> a list of floats, each
    finite (a cubecal.UsageError naming `option` otherwise)."""
    if value is None:
        return []
    if isinstance(value, str) or np.ndim(value) > 1:
        raise usage(option, f"{option}: a number or a list of numbers is expected, not {value!r}")
    if np.ndim(value) == 0:
        return [number(value, option)]
    return [number(v, option) for v in value]
