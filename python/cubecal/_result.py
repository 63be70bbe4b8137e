"""Result objects: attribute access over the JSON form of a library result.

Every result of the library has a JSON form (what the CLI writes: analysis.json,
`dev --format json`, the calibration files); a Result holds that dict and shows
it as attributes, nested dicts as Results and lists of numbers as NumPy arrays,
so that `r.channels[0].noise.adev.dev` is an array and `r.to_dict()` is the
file's content.
"""
import copy
import json
import numbers

import numpy as np


def _is_number(v):
    return v is None or (isinstance(v, numbers.Number) and not isinstance(v, bool))


def _plain(v):
    """v with the NumPy arrays a result may hold (spectra handed over as
    arrays, not as JSON text) as the JSON's lists: NaN as null."""
    if isinstance(v, dict):
        return {k: _plain(x) for k, x in v.items()}
    if isinstance(v, list):
        return [_plain(x) for x in v]
    if isinstance(v, np.ndarray):
        if v.dtype.kind == "f" and np.isnan(v).any():
            return [None if np.isnan(x) else x for x in v.tolist()]
        return v.tolist()
    return copy.deepcopy(v)


def _wrap(v):
    if isinstance(v, np.ndarray):
        out = v.view()
        out.flags.writeable = False  # results are read-only
        return out
    if isinstance(v, dict):
        return Result(v)
    if isinstance(v, list):
        if v and all(_is_number(x) for x in v) and any(x is not None for x in v):
            if all(isinstance(x, numbers.Integral) for x in v):
                return np.array(v, dtype=np.int64)
            return np.array([np.nan if x is None else x for x in v], dtype=np.float64)
        if v and all(isinstance(x, bool) for x in v):
            return np.array(v, dtype=bool)
        return [_wrap(x) for x in v]
    return v


class Result:
    """A library result: its JSON keys as attributes (and as items)."""

    def __init__(self, data):
        object.__setattr__(self, "_data", data)

    def __getattr__(self, key):
        data = object.__getattribute__(self, "_data")
        if key in data:
            return _wrap(data[key])
        raise AttributeError(f"{type(self).__name__} has no '{key}' (it has: {', '.join(data)})")

    def __getitem__(self, key):
        return _wrap(self._data[key])

    def __contains__(self, key):
        return key in self._data

    def __setattr__(self, key, value):
        raise AttributeError("results are read-only: use to_dict() for a copy to change")

    def __dir__(self):
        return sorted(set(self._data) | set(super().__dir__()))

    def keys(self):
        return self._data.keys()

    def to_dict(self):
        """A deep copy of the result as plain Python data (the JSON's content)."""
        return _plain(self._data)

    def to_json(self, indent=1):
        return json.dumps(_plain(self._data), indent=indent)

    def __repr__(self):
        keys = ", ".join(list(self._data)[:8])
        more = ", ..." if len(self._data) > 8 else ""
        return f"{type(self).__name__}({keys}{more})"
