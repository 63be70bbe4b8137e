"""Kasdin & Walter's power-law noise in AllanTools' shape
(``allantools.noise_kasdin.Noise``, also ``cubecal.Noise``).

    noise = cubecal.Noise(nr=2 ** 16, qd=1e-20, b=-2)   # white FM phase data
    noise.generateNoise()
    x = noise.time_series                              # phase, s
    noise.adev(tau0=1.0, tau=10.0)                     # the ADEV to expect

The generator is cubecal's (sim/power_law_generator.hpp): N. J. Kasdin and
T. Walter, "Discrete simulation of power law noise", Proc. 1992 IEEE
Frequency Control Symposium, pp. 274-283. Innovations of variance qd
through the causal filter 1 / (1 - z^-1)^(-b/2), the filter as long as the
record (exact, no spectral truncation). The expected deviations are the
closed forms AllanTools uses: the library's AVAR of each power law
(spectral/allan_conversion.hpp, NIST SP 1065 Table 2), and here those it
has not (flicker PM's AVAR; MVAR and PVAR: Vernotte 2015, Benkler 2015).
"""
import math

import numpy as np

from . import _args, _cubecal
from ._args import usage
from .noise import _seed

__all__ = ["Noise"]

# Euler-Mascheroni constant (flicker PM's AVAR).
_EULER_GAMMA = 0.57721566490153286060651209

# b: the exponent of the phase PSD, S_x(f) = g_b f^b (a = b + 2 for S_y).
_NOISE_TYPES = {0: "white PM", -1: "flicker PM", -2: "white FM", -3: "flicker FM", -4: "random-walk FM"}

# tau exponent c of AVAR and MVAR (AVAR = prefactor^2 tau^c).
_C_AVAR = {-4: 1.0, -3: 0.0, -2: -1.0, -1: -2.0, 0: -2.0}
_C_MVAR = {-4: 1.0, -3: 0.0, -2: -1.0, -1: -2.0, 0: -3.0}


class Noise:
    """Discrete power-law (colored) noise by Kasdin & Walter's method.

    Parameters
    ----------
    nr : int, optional
        Length of the generated series (AllanTools asks for a power of two;
        any length of at least 1 works here).
    qd : float, optional
        Discrete variance of the white innovations, in X^2 (X the unit of
        the series: s for phase data).
    b : float, optional
        Exponent of the phase PSD S_x(f) = g_b f^b: 0 white PM, -1 flicker
        PM, -2 white FM, -3 flicker FM, -4 random-walk FM. Any real b can be
        generated; the expected deviations (adev, mdev, ...) are known for
        these five.
    seed : int, optional
        Seed of cubecal's generator (0 to 2^64 - 1): successive
        generateNoise() calls give successive, different, repeatable series.
        None (AllanTools' behavior) draws each series' seed from NumPy's
        global generator, so np.random.seed(k) before makes it repeatable.

    Attributes
    ----------
    nr : int
        Series length.
    qd : float
        Innovation variance, X^2.
    b : float
        Phase-PSD exponent.
    time_series : numpy.ndarray
        The last generated series (empty before generateNoise()), in X.

    Examples
    --------
    >>> import cubecal
    >>> noise = cubecal.Noise(nr=2 ** 8, qd=1.0e-20, b=-1, seed=1)
    >>> noise.generateNoise()
    >>> noise.time_series.shape
    (256,)
    """

    def __init__(self, nr=2, qd=1, b=0, seed=None):
        self.nr = nr
        self.qd = qd
        self.b = b
        self.time_series = np.array([])
        self._seed = None if seed is None else _args.seed(seed)
        self._draws = 0

    def __repr__(self):
        return f"Noise(nr={self.nr!r}, qd={self.qd!r}, b={self.b!r})"

    def set_input(self, nr=2, qd=1, b=0):
        """Set the inputs after initialization (those not given return to
        their defaults, as in AllanTools).

        Parameters
        ----------
        nr : int, optional
            Length of the generated series.
        qd : float, optional
            Discrete variance of the innovations, X^2.
        b : float, optional
            Exponent of the phase PSD (0, -1, -2, -3, -4 for WPM, FPM, WFM,
            FFM, RWFM).
        """
        self.nr = nr
        self.qd = qd
        self.b = b

    def _next_seed(self):
        if self._seed is None:
            return _seed(None)
        # A distinct, repeatable stream per draw from the one seed.
        self._draws += 1
        return (self._seed * 0x9E3779B97F4A7C15 + self._draws) % 2 ** 64

    def generateNoise(self):
        """Generate a new series into ``time_series``.

        The series has one-sided phase PSD S_x(f) = g_b f^b, g_b =
        phase_psd_from_qd(tau0), for f well below the Nyquist frequency,
        whatever the sampling interval tau0 it is read with.

        Returns
        -------
        None
            As AllanTools; the series is in ``self.time_series`` (nr samples,
            in X).

        Raises
        ------
        cubecal.UsageError
            (a ValueError) for nr below 1, qd negative or not finite, or b
            not a finite number.
        """
        n = _args.count(self.nr, "nr", minimum=1)
        qd = _args.number(self.qd, "qd", minimum=0.0)
        b = _args.number(self.b, "b")
        # Sampled at dt = 1 the generator's innovations have variance
        # h / (2 (2 pi)^alpha): h = 2 qd (2 pi)^b gives them variance qd.
        h = 2.0 * qd * (2.0 * math.pi) ** b
        self.time_series = _cubecal._power_law(b, h, 1.0, n, self._next_seed())

    def _noise_type(self, tau0):
        """b as an int for the closed forms, once b, qd and tau0 are checked."""
        b = _args.number(self.b, "b")
        if b not in _NOISE_TYPES:
            raise usage("b", f"b: the expected deviations are known for b = 0, -1, -2, -3, -4, not {self.b!r}")
        _args.number(self.qd, "qd", minimum=0.0)
        _args.number(tau0, "tau0", positive=True)
        return int(b)

    def phase_psd_from_qd(self, tau0=1.0):
        """Level g_b of the phase PSD, S_x(f) = g_b f^b ([Kasdin1992] eq. 39).

        Parameters
        ----------
        tau0 : float, optional
            Interval between samples, s.

        Returns
        -------
        float
            g_b = 2 qd (2 pi)^b tau0^(b + 1), in X^2/Hz times Hz^-b.
        """
        return self.qd * 2.0 * pow(2.0 * np.pi, self.b) * pow(tau0, self.b + 1.0)

    def frequency_psd_from_qd(self, tau0=1.0):
        """Level h_a of the fractional-frequency PSD, S_y(f) = h_a f^a with
        a = b + 2 ([Kasdin1992] eq. 39).

        Parameters
        ----------
        tau0 : float, optional
            Interval between samples, s.

        Returns
        -------
        float
            h_a = 2 qd (2 pi)^a tau0^(a - 1), in Hz^-1-a when the series is
            phase in s.
        """
        a = self.b + 2.0
        return self.qd * 2.0 * pow(2.0 * np.pi, a) * pow(tau0, a - 1.0)

    def c_avar(self):
        """The tau exponent c of the Allan variance, AVAR ~ tau^c.

        Returns
        -------
        float
            1, 0, -1, -2, -2 for b = -4, -3, -2, -1, 0; None for another b
            (as AllanTools).
        """
        return _C_AVAR.get(self.b)

    def c_mvar(self):
        """The tau exponent c of the modified Allan variance, MVAR ~ tau^c.

        Returns
        -------
        float
            1, 0, -1, -2, -3 for b = -4, -3, -2, -1, 0; None for another b
            (as AllanTools).
        """
        return _C_MVAR.get(self.b)

    def adev_from_qd(self, tau0=1.0, tau=1.0):
        """Prefactor of the Allan deviation: AVAR = prefactor^2 tau^c.

        prefactor^2 = coeff h_a with coeff 3 f_h / (4 pi^2) (WPM),
        (3 gamma - ln 2 + 3 ln(2 pi f_h tau)) / (4 pi^2) (FPM), 1/2 (WFM),
        2 ln 2 (FFM), 2 pi^2 / 3 (RWFM), f_h = 1 / (2 tau0): the library's
        power-law AVAR (NIST SP 1065 Table 2) but for FPM (Vernotte 2015
        Table I).

        Parameters
        ----------
        tau0 : float, optional
            Interval between samples, s.
        tau : float, optional
            Averaging time, s (used by flicker PM only).

        Returns
        -------
        float
            The prefactor, sqrt(coeff h_a).

        Raises
        ------
        cubecal.UsageError
            (a ValueError) for b other than 0, -1, -2, -3, -4, qd negative
            or tau0 not positive.
        """
        b = self._noise_type(tau0)
        h = self.frequency_psd_from_qd(tau0)
        f_h = 0.5 / tau0
        if b == -1:
            # Flicker PM, not in the library's table (its level depends on tau).
            coeff = (3.0 * _EULER_GAMMA - math.log(2.0) + 3.0 * np.log(2.0 * math.pi * f_h * np.asarray(tau, dtype=float)))
            return np.sqrt(coeff / (4.0 * math.pi ** 2) * h)
        # The library's AVAR of h f^a at tau = 1 s: coeff h (f_h for white PM).
        return np.sqrt(_cubecal._power_law_avar(b + 2, h, 1.0, f_h))

    def mdev_from_qd(self, tau0=1.0, tau=1.0):
        """Prefactor of the modified Allan deviation: MVAR = prefactor^2 tau^c.

        prefactor^2 = coeff h_a with coeff 3 / (8 pi^2) (WPM),
        (24 ln 2 - 9 ln 3) / (8 pi^2) (FPM), 1/4 (WFM), 27 ln 2 / 20 (FFM,
        Benkler 2015), 11 pi^2 / 20 (RWFM).

        Parameters
        ----------
        tau0 : float, optional
            Interval between samples, s.
        tau : float, optional
            Averaging time, s (unused, kept for AllanTools' signature).

        Returns
        -------
        float
            The prefactor, sqrt(coeff h_a).

        Raises
        ------
        cubecal.UsageError
            (a ValueError) for b other than 0, -1, -2, -3, -4, qd negative
            or tau0 not positive.
        """
        b = self._noise_type(tau0)
        coeff = {
            0: 3.0 / (8.0 * math.pi ** 2),
            -1: (24.0 * math.log(2.0) - 9.0 * math.log(3.0)) / (8.0 * math.pi ** 2),
            -2: 0.25,
            -3: 27.0 / 20.0 * math.log(2.0),
            -4: 11.0 / 20.0 * math.pi ** 2,
        }[b]
        return np.sqrt(coeff * self.frequency_psd_from_qd(tau0))

    def pdev_from_qd(self, tau0=1.0, tau=1.0):
        """Prefactor of the parabolic deviation: PVAR = prefactor^2 tau^c.

        prefactor^2 = coeff g_b (2 pi)^2 with coeff 3 / (2 pi^2) (WPM),
        (3 ln 16 - 1) / (2 pi^2) (FPM), 3/5 (WFM), 2 (7 - ln 16) / 5 (FFM),
        26 pi^2 / 35 (RWFM) (Vernotte 2015 Table I).

        Parameters
        ----------
        tau0 : float, optional
            Interval between samples, s.
        tau : float, optional
            Averaging time, s (unused, kept for AllanTools' signature).

        Returns
        -------
        float
            The prefactor.

        Raises
        ------
        cubecal.UsageError
            (a ValueError) for b other than 0, -1, -2, -3, -4, qd negative
            or tau0 not positive.
        """
        b = self._noise_type(tau0)
        coeff = {
            0: 3.0 / (2.0 * math.pi ** 2),
            -1: (3.0 * math.log(16.0) - 1.0) / (2.0 * math.pi ** 2),
            -2: 3.0 / 5.0,
            -3: 2.0 * (7.0 - math.log(16.0)) / 5.0,
            -4: 26.0 / 35.0 * math.pi ** 2,
        }[b]
        return np.sqrt(coeff * self.phase_psd_from_qd(tau0) * (2.0 * math.pi) ** 2)

    def adev(self, tau0, tau):
        """The Allan deviation expected of the series at tau.

        Parameters
        ----------
        tau0 : float
            Interval between samples, s.
        tau : float or array_like
            Averaging time, s.

        Returns
        -------
        float or numpy.ndarray
            ADEV (dimensionless when the series is phase in s).
        """
        return np.sqrt(self.adev_from_qd(tau0=tau0, tau=tau) ** 2 * np.power(tau, self.c_avar()))

    def mdev(self, tau0, tau):
        """The modified Allan deviation expected of the series at tau.

        Parameters
        ----------
        tau0 : float
            Interval between samples, s.
        tau : float or array_like
            Averaging time, s.

        Returns
        -------
        float or numpy.ndarray
            MDEV (dimensionless when the series is phase in s).
        """
        return np.sqrt(self.mdev_from_qd(tau0=tau0, tau=tau) ** 2 * np.power(tau, self.c_mvar()))
