"""Deviations updated sample by sample, as AllanTools' ``allantools.realtime``.

    rt = cubecal.realtime.oadev_realtime(afs=[1, 10, 100], tau0=1.0)
    for x in phase_stream:          # phase samples (s), one at a time
        rt.add_phase(x)
    rt.taus(), rt.devs()            # OADEV at tau = af * tau0, after any sample

``oadev_realtime``, ``ohdev_realtime`` and ``tdev_realtime`` (which also
gives MDEV) take AllanTools' arguments, defaults and attributes (``afs``,
``tau0``, ``auto_afs``, ``pts_per_decade``, ``af_taus``, ``af_idx``,
``af_decade``, ``dev``). The work is the C++ library's RealtimeDeviation
(include/cubecal/stats/realtime_deviation.hpp): each sample costs one term
per averaging factor, and the deviations after N samples equal the batch
``cubecal.oadev``, ``ohdev`` and ``tdev`` of those N samples at the same
factors, to rounding. Phase is kept back to what the largest factor needs
(3 af + 1 samples), not the whole record; with ``auto_afs=True`` the record
is kept whole, as each new factor takes every term of the record so far.
``add_phase`` and ``add_frequency`` also take a 1-D array of samples, added
in one call. Where this differs from AllanTools (factors added in auto-AF
mode take their first terms; ``add_frequency`` integrates ``f * tau0``; no
``x`` list), docs/allantools-differences/dataset.md says why.
"""
import numbers

import numpy as np

from . import _args, _cubecal
from ._args import usage

__all__ = ["dev_realtime", "oadev_realtime", "ohdev_realtime", "tdev_realtime"]


def _afs(afs):
    """The averaging factors: whole numbers of at least 1, as a list."""
    if isinstance(afs, (str, bytes)) or not np.iterable(afs):
        raise usage("afs", f"afs: a list of whole averaging factors is expected, not {afs!r}")
    out = []
    for af in np.asarray(afs, dtype=object).ravel():
        out.append(_args.count(af, "afs", minimum=1, maximum=_args.INT_MAX))
    if not out:
        raise usage("afs", "afs: give at least one averaging factor, or auto_afs=True")
    return out


def _samples(value, option):
    """A float for one sample, or a 1-D float64 array of them."""
    if isinstance(value, numbers.Real) and not isinstance(value, (bool, np.bool_)):
        return float(value)
    a = _args.samples(value, option, dimensions=(0, 1))
    return float(a) if a.ndim == 0 else a


class dev_realtime:
    """Base class of the real-time deviations: the averaging factors, the
    sample period and the automatic choice of factors.

    Parameters
    ----------
    afs : list of int, default [1]
        Averaging factors; the deviations are at tau = af * tau0. Ignored
        when ``auto_afs`` is True (the factors start at [1]).
    tau0 : float, default 1.0
        Sample period (s), > 0.
    auto_afs : bool, default False
        Add factors as the record grows: ``pts_per_decade`` per decade
        (1, 2, 3, 6, 10, 18, ... for 4), each once the record has
        2 af + 1 phase samples.
    pts_per_decade : int, default 4
        Factors per decade in auto mode, >= 1.

    Attributes
    ----------
    afs : numpy.ndarray of int
        The averaging factors, in the order given (then added).
    tau0 : float
        Sample period (s).
    auto_afs : bool
        Whether factors are added as the record grows.
    af_taus : numpy.ndarray
        ``logspace(0, 1, pts_per_decade + 1)[:-1]``: the factors of a decade
        in auto mode, before rounding.
    af_idx, af_decade : int
        Where in ``af_taus`` and in which decade the last automatic factor
        was.
    dev : numpy.ndarray
        The deviation at each factor after the samples so far (0 where the
        record is still too short for it): fractional frequency for OADEV and
        OHDEV, the phase's unit (s) for TDEV.
    """

    _stat = None

    def __init__(self, afs=[1], tau0=1.0, auto_afs=False, pts_per_decade=4):  # noqa: B006 (AllanTools' default)
        if self._stat is None:
            raise usage("", "dev_realtime is the base class: use oadev_realtime, ohdev_realtime or tdev_realtime")
        self.tau0 = _args.number(tau0, "tau0", positive=True)
        self.auto_afs = _args.flag(auto_afs, "auto_afs")
        ppd = _args.count(pts_per_decade, "pts_per_decade", minimum=1, maximum=1000)
        self.af_taus = np.logspace(0, 1, ppd + 1)[:-1]
        self.af_idx = 0
        self.af_decade = 0
        factors = [1] if self.auto_afs else _afs(afs)
        self._rt = _cubecal._Realtime(self._stat, factors, self.auto_afs)

    @property
    def afs(self):
        """The averaging factors (numpy.ndarray of int)."""
        return self._rt.factors

    @property
    def dev(self):
        """The deviations at ``afs`` after the samples so far (numpy.ndarray;
        0 where the record is too short): fractional frequency for OADEV and
        OHDEV, phase unit (s) for TDEV."""
        return self._rt.deviations(self.tau0)

    @property
    def n(self):
        """Terms averaged at each factor so far (numpy.ndarray of int; a
        cubecal addition)."""
        return self._rt.terms

    @property
    def samples(self):
        """Phase samples added so far (int; a cubecal addition)."""
        return self._rt.samples

    def _next_af(self):
        idx, decade = self.af_idx + 1, self.af_decade
        if idx == len(self.af_taus):
            idx, decade = 0, decade + 1
        return idx, decade, int(np.round(10.0 ** decade * self.af_taus[idx]))

    def update_af(self):
        """Auto mode: add the next averaging factor if the record has
        2 af + 1 phase samples for it (one factor per call, as AllanTools).

        Returns
        -------
        bool
            Whether a factor was added.
        """
        idx, decade, af = self._next_af()
        if self._rt.samples < 2 * af + 1:
            return False
        self._rt.add_factor(af)
        self.af_idx, self.af_decade = idx, decade
        return True

    def _added(self):
        if self.auto_afs:
            while self.update_af():
                pass

    def add_phase(self, xnew):
        """Add phase samples.

        Parameters
        ----------
        xnew : float or array_like
            One phase sample (s), or a 1-D array of them in order. NaN or
            infinite values raise cubecal.UsageError (nothing is added from
            the bad sample on).
        """
        x = _samples(xnew, "xnew")
        if isinstance(x, float):
            self._rt.add_phase(x)
            if self.auto_afs:
                self.update_af()
        else:
            self._rt.add_phases(x)
            self._added()

    def add_frequency(self, f):
        """Add fractional frequency samples, integrated to phase: the first
        one also puts the phase origin (0), then each adds ``f * tau0`` (s).

        Parameters
        ----------
        f : float or array_like
            One fractional frequency sample (dimensionless), or a 1-D array
            of them in order.
        """
        y = _samples(f, "f")
        if isinstance(y, float):
            first = self._rt.samples == 0
            self._rt.add_frequency(y, self.tau0)
            if self.auto_afs:
                if first:  # two phase samples, as AllanTools: two chances
                    self.update_af()
                self.update_af()
        else:
            self._rt.add_frequencies(y, self.tau0)
            self._added()

    def taus(self):
        """The taus of the factors (numpy.ndarray, s): ``afs * tau0``."""
        return self.tau0 * np.array(self.afs)

    def devs(self):
        """The deviations at ``taus()`` (numpy.ndarray), as ``dev``."""
        return self.dev


class oadev_realtime(dev_realtime):
    """Overlapping Allan deviation updated with each phase or frequency
    sample (Dobrogowski et al., 2007): after N phase samples, ``dev`` equals
    ``cubecal.oadev`` of those samples at ``afs`` (0 while N < 2 af + 1).

    Parameters
    ----------
    afs : list of int, default [1]
        Averaging factors (tau = af * tau0).
    tau0 : float, default 1.0
        Sample period (s).
    auto_afs : bool, default False
        Add factors as the record grows (see dev_realtime).
    pts_per_decade : int, default 4
        Factors per decade in auto mode.
    """

    _stat = "oadev"


class ohdev_realtime(dev_realtime):
    """Overlapping Hadamard deviation updated with each phase or frequency
    sample: after N phase samples, ``dev`` equals ``cubecal.ohdev`` of those
    samples at ``afs`` (0 while N < 3 af + 1).

    Parameters
    ----------
    afs : list of int, default [1]
        Averaging factors (tau = af * tau0).
    tau0 : float, default 1.0
        Sample period (s).
    auto_afs : bool, default False
        Add factors as the record grows (see dev_realtime).
    pts_per_decade : int, default 4
        Factors per decade in auto mode.
    """

    _stat = "ohdev"


class tdev_realtime(dev_realtime):
    """Time deviation (and, by ``mdev()``, the modified Allan deviation)
    updated with each phase or frequency sample: after N phase samples,
    ``dev`` equals ``cubecal.tdev`` of those samples at ``afs`` (s; 0 while
    N < 3 af).

    Parameters
    ----------
    afs : list of int, default [1]
        Averaging factors (tau = af * tau0).
    tau0 : float, default 1.0
        Sample period (s).
    auto_afs : bool, default False
        Add factors as the record grows (see dev_realtime).
    pts_per_decade : int, default 4
        Factors per decade in auto mode.
    """

    _stat = "tdev"

    def mdev(self):
        """The modified Allan deviation at ``taus()`` (numpy.ndarray,
        fractional frequency): ``dev * sqrt(3) / tau``."""
        return self.dev * np.sqrt(3.0) / (np.asarray(self.afs) * self.tau0)
