"""`cubecal dev` on arrays: one statistic over Stable32's tau grids and
limits, with noise identification, EDF and confidence intervals per tau."""

import numpy as np

from . import _args, _cubecal
from ._data import channels_of
from ._read import Record
from ._result import Result

_CURVE = ("af", "tau", "dev", "n", "lo", "hi", "edf", "alpha", "type_carried")


class Curve:
    """One channel's points as NumPy arrays: af (the averaging factor m), tau,
    dev, n, and with intervals lo, hi, edf, alpha (the identified noise type)
    and type_carried (the type carried from the previous factor, Stable32's
    run rule)."""

    def __init__(self, columns):
        self.name = columns["name"]
        for key in _CURVE:
            setattr(self, key, columns.get(key))

    @property
    def m(self):
        return self.af

    def to_dict(self):
        d = {"name": self.name}
        for key in _CURVE:
            v = getattr(self, key)
            if v is not None and key != "type_carried":
                d[key] = v.tolist()
        return d

    def __len__(self):
        return len(self.tau)

    def __repr__(self):
        return f"Curve({self.name!r}, {len(self)} taus)"


class DevResult(Result):
    """The result of cubecal.dev: the keys of `cubecal dev --format json`
    (stat, type, rate_hz, samples, ci, edf_method, ...) and `channels`, one
    Curve per channel. With one channel its arrays are also the result's own
    (r.tau, r.dev, r.lo, r.hi ...)."""

    def __init__(self, meta, columns):
        super().__init__(meta)
        object.__setattr__(self, "channels", [Curve(c) for c in columns])

    def __getattr__(self, key):
        channels = object.__getattribute__(self, "channels")
        if (key in _CURVE or key == "m") and len(channels) == 1:
            return getattr(channels[0], key)
        return super().__getattr__(key)

    def to_dict(self):
        """The content of `cubecal dev --format json` for the same data."""
        d = super().to_dict()
        d["columns"] = [c.to_dict() for c in self.channels]
        return d


@_args.public
def dev(data, rate=None, stat="oadev", data_type="freq", taus="octave", ci=0.683, alpha=None, edf="greenhall",
        conservative=False, intervals=True, names=None, threads=0, gaps=None):
    """One statistic of each channel over a tau grid, as `cubecal dev`.

    data: a 1-D array, a 2-D array (one channel per column), a list of arrays
    or a dict / DataFrame of columns. taus: "octave", "decade", "all", "log:K"
    or taus in seconds. rate: Hz (default: a Record's rate, else 1). ci: the confidence factor of the intervals; alpha: a
    fixed noise type instead of identification (-2 to +2; -3 and -4 for
    hdev, ohdev and htotdev only); conservative: below 30
    averages, the widest interval of the identified type and its neighbours.
    gaps: "skip" takes NaN as a missing sample, left out of the OADEV terms
    as `cubecal dev --gaps skip` (OADEV only); "error" refuses it. Default: a
    Record's (cubecal.read(path, gaps="skip")), else "error".
    """
    if gaps is None:
        gaps = "skip" if isinstance(data, Record) and data.gaps == "skip" else "error"
    names, arrays = channels_of(data, names)
    if rate is None:
        rate = getattr(data, "rate_hz", None) or 1.0
    meta, columns = _cubecal._dev(arrays, names, _args.rate(rate), _args.text(stat, "stat"),
                                  _args.text(data_type, "data_type"), _args.taus(taus), _args.number(ci, "ci"),
                                  _args.optional_count(alpha, "alpha", minimum=-_args.INT_MAX, maximum=_args.INT_MAX),
                                  _args.text(edf, "edf"), _args.flag(conservative, "conservative"),
                                  _args.flag(intervals, "intervals"), _args.threads(threads), _args.text(gaps, "gaps"))
    return DevResult(meta, columns)
