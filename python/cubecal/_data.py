"""The shapes of data the Python calls accept, as (names, 1-D arrays).

Accepted: a 1-D array (one channel); a 2-D array, one channel per column; a
list or tuple of 1-D arrays; a dict of name -> array (of a cubecal.Record,
from cubecal.read or cubecal.simulate, its channels: not its time and extra
columns); a pandas DataFrame (or anything
with .columns and [name]). Arrays are passed on as they are: a contiguous
float64 array reaches the library without a copy.
"""
import numpy as np


def _is_frame(data):
    return hasattr(data, "columns") and hasattr(data, "__getitem__") and not isinstance(data, dict)


def channels_of(data, names=None, exclude=()):
    """(names, arrays) of `data`; `exclude` names columns to leave out."""
    if isinstance(data, dict):
        skip = set(exclude)
        # A Record knows its channels: its time and extra columns are not.
        listed = getattr(data, "channels", None)
        keys = [k for k in (listed if listed is not None else data) if k not in skip]
        arrays = [np.asarray(data[k]) for k in keys]
        out_names = [str(k) for k in keys]
    elif _is_frame(data):
        keys = [k for k in data.columns if k not in set(exclude)]
        arrays = [np.asarray(data[k]) for k in keys]
        out_names = [str(k) for k in keys]
    elif isinstance(data, (list, tuple)) and data and np.ndim(data[0]) == 1:
        arrays = [np.asarray(a) for a in data]
        out_names = [f"ch{i + 1}" for i in range(len(arrays))]
    else:
        a = np.asarray(data)
        if a.ndim == 1:
            arrays = [a]
        elif a.ndim == 2:
            arrays = [a[:, j] for j in range(a.shape[1])]
        else:
            raise ValueError(f"data: 1-D or 2-D (samples x channels) expected, got {a.ndim} dimensions")
        out_names = [f"ch{i + 1}" for i in range(len(arrays))]
    if names is not None:
        names = [names] if isinstance(names, str) else list(names)
        if len(names) != len(arrays):
            raise ValueError(f"names: {len(names)} names for {len(arrays)} channels")
        out_names = names
    if not arrays:
        raise ValueError("data: no channel")
    return out_names, arrays


def string_list(value):
    """None -> [], "a,b" -> ["a", "b"], ["a", "b"] -> ["a", "b"]."""
    if value is None:
        return []
    if isinstance(value, str):
        return [v.strip() for v in value.split(",") if v.strip()]
    return [str(v) for v in value]


def number_list(value):
    if value is None:
        return []
    if np.ndim(value) == 0:
        return [float(value)]
    return [float(v) for v in value]
