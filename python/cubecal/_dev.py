"""`cubecal dev` on arrays: one statistic over Stable32's tau grids and
limits, with noise identification, EDF and confidence intervals per tau."""

from typing import Any  # noqa: F401  (the annotations' names)

import numpy as np

from . import _args, _cubecal
from ._data import channels_of
from ._read import Record
from ._result import ExcludedTau, MergedTau, Result  # noqa: F401

_CURVE = ("af", "tau", "dev", "n", "lo", "hi", "edf", "alpha", "type_carried")


class Curve:
    """One channel's points of cubecal.dev, as NumPy arrays.

    Attributes
    ----------
    name : str
        The channel.
    af : numpy.ndarray of int64
        Averaging factors m (tau = m / rate); also as `m`.
    tau : numpy.ndarray of float64
        Averaging times, s.
    dev : numpy.ndarray of float64
        The deviation at each tau, in the data's unit (fractional frequency, or s of phase for TIE
        statistics).
    n : numpy.ndarray of int64
        The number of terms behind each point.
    lo, hi : numpy.ndarray of float64 or None
        The confidence interval's ends at ci, in the data's unit (None without intervals).
    edf : numpy.ndarray of float64 or None
        Equivalent degrees of freedom of each point.
    alpha : numpy.ndarray of int64 or None
        The power-law noise type identified at each tau (+2 .. -2; -3, -4 for the Hadamard family).
    type_carried : numpy.ndarray of bool or None
        Whether the type was carried from the previous factor (Stable32's run rule).
    """

    def __init__(self, columns):
        self.name = columns["name"]
        for key in _CURVE:
            setattr(self, key, columns.get(key))

    @property
    def m(self):
        """The averaging factors (af)."""
        return self.af

    def to_dict(self):
        """The channel's entry of `columns` in `cubecal dev --format json`."""
        d = {"name": self.name}
        for key in _CURVE:
            v = getattr(self, key)
            if v is not None and key != "type_carried":
                d[key] = v.tolist()
        return d

    def __len__(self):
        return len(self.tau)

    def __repr__(self):
        if len(self) == 0:
            return f"Curve({self.name!r}, no taus)"
        return f"Curve({self.name!r}, {len(self)} taus, {self.tau[0]:.4g} .. {self.tau[-1]:.4g} s, dev " \
               f"{np.nanmin(self.dev):.4g} .. {np.nanmax(self.dev):.4g})"


class DevResult(Result):
    """The result of cubecal.dev: `cubecal dev --format json` as a typed
    object, `channels` one Curve per channel (the document's `columns`).
    With one channel its arrays are also the result's own (r.tau, r.dev,
    r.lo, r.hi, ...)."""

    __slots__ = ("channels",)
    channels: "list[Curve]"  # one per channel (the document's columns)
    _spec = """
    stat: str -- the statistic (oadev, mdev, hdev, ...)
    type: str -- the data type (freq or phase)
    rate_hz: float -- the sampling rate, Hz
    file: str -- the record ("<arrays>")
    samples: int -- samples per channel
    segments: int -- contiguous pieces
    ci: float | None -- the confidence of the intervals (None: no intervals)
    edf_method: str -- greenhall or simple
    stream?: Any -- a streamed run: its window bound
    excluded_taus: list[ExcludedTau] -- listed taus left out
    merged_taus: list[MergedTau] -- listed taus merged with an earlier one
    """

    def __init__(self, meta, columns):
        super().__init__(meta)
        object.__setattr__(self, "channels", [Curve(c) for c in columns])

    def __getattr__(self, key):
        channels = object.__getattribute__(self, "channels")
        if (key in _CURVE or key == "m") and len(channels) == 1:
            return getattr(channels[0], key)
        return super().__getattr__(key)

    def to_dict(self) -> "dict[str, Any]":
        """The content of `cubecal dev --format json` for the same data."""
        d = super().to_dict()
        d["columns"] = [c.to_dict() for c in self.channels]
        return d

    def _summary(self):
        names = ", ".join(c.name for c in self.channels)
        return f"{self.stat} of {names}; {self.samples} samples at {self.rate_hz:.4g} Hz"


@_args.public
def dev(data, rate=None, stat="oadev", data_type="freq", taus="octave", ci=0.683, alpha=None, edf="greenhall",
        conservative=False, intervals=True, names=None, threads=0, gaps=None):
    """One statistic of each channel over a tau grid, as `cubecal dev`.

    With Stable32's grids and limits, noise identification, EDF and
    confidence intervals per tau.

    Parameters
    ----------
    data : array_like, dict, cubecal.Record or DataFrame
        A 1-D array, a 2-D array (one channel per column), a list of arrays
        or a dict / DataFrame of columns: fractional frequency (data_type
        "freq") or phase in s ("phase").
    rate : float, optional
        Sampling rate, Hz (default: a Record's rate, else 1).
    stat : str
        The statistic: oadev, adev, mdev, tdev, hdev, ohdev, totdev, mtotdev,
        ttotdev, htotdev, theo1, mtie, tierms, ...
    data_type : str
        freq or phase.
    taus : str or sequence of float
        "octave", "decade", "all", "log:K" or taus in s.
    ci : float
        Confidence factor of the intervals (0.683: 1 sigma).
    alpha : int, optional
        A fixed noise type instead of identification (-2 to +2; -3 and -4
        for hdev, ohdev and htotdev only).
    edf : str
        greenhall or simple.
    conservative : bool
        Below 30 averages, the widest interval of the identified type and its
        neighbours.
    intervals : bool
        Confidence intervals, EDF and noise types.
    names : list of str, optional
        Names of the channels.
    threads : int
        Worker threads (0: every core).
    gaps : str, optional
        "skip" takes NaN as a missing sample, left out of the OADEV terms as
        `cubecal dev --gaps skip` (OADEV only); "error" refuses it. Default:
        a Record's (cubecal.read(path, gaps="skip")), else "error".

    Returns
    -------
    DevResult
        `cubecal dev --format json` as a typed object; `channels` one Curve
        per channel (tau in s, dev in the data's unit).
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
