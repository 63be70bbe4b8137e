"""Noise generators and spectra in AllanTools' shape (``allantools.noise``).

    from cubecal import noise
    x = noise.white(1024, b0=1e-2, fs=10.0)      # S(f) = b0 up to fs/2
    f, s = noise.numpy_psd(x, f_sample=10.0)     # one-sided periodogram

The same functions, arguments, defaults and return values as AllanTools'
``noise`` module. The power-law generators (white, brown, violet, pink,
iterpink) run on cubecal's Kasdin & Walter generator
(sim/power_law_generator.hpp): the innovations are drawn by the library's
seeded engine, so each takes a ``seed`` keyword beyond AllanTools' arguments;
without it the seed is drawn from NumPy's global generator, so that
``np.random.seed(k)`` before a call makes it repeatable as with AllanTools
(the samples themselves differ from AllanTools', the spectra do not).
timmer_koenig_from_psd draws NumPy's global generator as AllanTools does, so
a seeded call gives AllanTools' samples. The spectra are cubecal's Welch
estimator (pipeline/welch_psd.hpp). docs/allantools-differences/noise.md
lists where the calls differ from AllanTools'.
"""
import math

import numpy as np

from . import _args, _cubecal
from ._args import public, usage

__all__ = ["numpy_psd", "scipy_psd", "white", "brown", "violet", "pink", "iterpink", "timmer_koenig_from_psd"]

# The samples drawn from the endless stream at a time (iterpink).
_STREAM_BLOCK = 4096
# The longest filter the streaming generator takes (PowerLawGenerator::kMaxFilter).
_MAX_FILTER_DEPTH = 18


def _seed(seed):
    """The library's 64-bit seed: `seed` itself, or drawn from NumPy's global
    generator (np.random.seed makes the call repeatable)."""
    if seed is None:
        return int(np.random.randint(0, 2 ** 63 - 1, dtype=np.int64))
    return _args.seed(seed)


def _rate(value, option):
    return _args.number(value, option, positive=True)


def _power_law(alpha, h, fs, n, seed, skip=0):
    return _cubecal._power_law(alpha, h, 1.0 / fs, n, _seed(seed), skip)


def _series(x, option="x"):
    a = _args.samples(x, option)
    if not np.all(np.isfinite(a)):
        raise usage(option, f"{option}: the samples must be finite numbers (a NaN or an infinity was found)")
    return a


@public
def numpy_psd(x, f_sample=1.0):
    """One-sided periodogram of `x` (AllanTools' ``noise.numpy_psd``).

    The squared magnitude of the discrete Fourier transform, scaled by
    2 / (N f_sample) at every bin (DC and Nyquist included), on the
    frequency axis ``linspace(0, f_sample / 2, N // 2 + 1)``: AllanTools'
    scaling and axis. The transform is cubecal's Welch estimator with one
    rectangular segment the length of the record and no detrending.

    Parameters
    ----------
    x : array_like
        The signal, 1-D, at least 4 samples, in a unit X.
    f_sample : float, optional
        Sampling frequency in Hz (1 / f_sample is the interval between
        samples).

    Returns
    -------
    f_axis : numpy.ndarray
        Frequencies in Hz, N // 2 + 1 of them from 0 to f_sample / 2.
    psd_of_x : numpy.ndarray
        One-sided power spectral density in X^2/Hz.

    Raises
    ------
    cubecal.UsageError
        For fewer than 4 samples, a non-finite sample or a non-positive
        f_sample (a ValueError).
    """
    a = _series(x)
    fs = _rate(f_sample, "f_sample")
    if a.size < 4:
        raise usage("x", f"x: at least 4 samples are needed for a spectrum, got {a.size}")
    _, density = _cubecal._welch(a, fs, a.size, 0.0, "rectangular", "none")
    # The estimator holds half the density in the DC and Nyquist bins, as
    # scipy does; AllanTools' periodogram doubles every bin.
    density[0] *= 2.0
    if a.size % 2 == 0:
        density[-1] *= 2.0
    return np.linspace(0.0, fs / 2.0, density.size), density


@public
def scipy_psd(x, f_sample=1.0, nr_segments=4):
    """One-sided Welch spectrum of `x` (AllanTools' ``noise.scipy_psd``).

    As ``scipy.signal.welch(x, f_sample, nperseg=len(x) / nr_segments)``:
    Hann window, segments of int(len(x) / nr_segments) samples overlapping
    by half, each segment's mean removed, densities averaged. Computed by
    cubecal's Welch estimator.

    Parameters
    ----------
    x : array_like
        The signal, 1-D, in a unit X.
    f_sample : float, optional
        Sampling frequency in Hz.
    nr_segments : int, optional
        The record's length over the segment length (segments of at least 4
        samples).

    Returns
    -------
    f_axis : numpy.ndarray
        Frequencies k f_sample / L in Hz, k = 0 .. L // 2 (L the segment
        length).
    psd_of_x : numpy.ndarray
        One-sided power spectral density in X^2/Hz.

    Raises
    ------
    cubecal.UsageError
        For segments shorter than 4 samples, a non-finite sample or a
        non-positive f_sample or nr_segments (a ValueError).
    """
    a = _series(x)
    fs = _rate(f_sample, "f_sample")
    segments = _args.number(nr_segments, "nr_segments", positive=True)
    length = min(int(a.size / segments), a.size)
    if length < 4:
        raise usage("nr_segments",
                    f"nr_segments: segments of {length} samples are too short (at least 4); use fewer segments")
    return _cubecal._welch(a, fs, length, 0.5, "hann", "constant")


@public
def white(num_points=1024, b0=1.0, fs=1.0, seed=None):
    """White noise of one-sided PSD b0 up to the Nyquist frequency fs / 2.

    Gaussian samples of variance b0 fs / 2.

    Parameters
    ----------
    num_points : int, optional
        Number of samples.
    b0 : float, optional
        The power spectral density in X^2/Hz (X the unit of the samples).
    fs : float, optional
        Sampling frequency in Hz.
    seed : int, optional
        Seed of cubecal's generator (0 to 2^64 - 1); None draws one from
        NumPy's global generator.

    Returns
    -------
    numpy.ndarray
        num_points samples, in X.
    """
    n = _args.count(num_points, "num_points")
    level = _args.number(b0, "b0", minimum=0.0)
    return _power_law(0.0, level, _rate(fs, "fs"), n, seed)


@public
def brown(num_points=1024, b_minus2=1.0, fs=1.0, seed=None):
    """Brownian (random-walk) noise of one-sided PSD b_minus2 f^-2.

    The running sum of white noise (Kasdin & Walter's filter for f^-2).

    Parameters
    ----------
    num_points : int, optional
        Number of samples.
    b_minus2 : float, optional
        The level: the PSD is b_minus2 f^-2, in X^2/Hz when f is in Hz
        (X^2 Hz).
    fs : float, optional
        Sampling frequency in Hz.
    seed : int, optional
        Seed of cubecal's generator; None draws one from NumPy's global
        generator.

    Returns
    -------
    numpy.ndarray
        num_points samples, in X.
    """
    n = _args.count(num_points, "num_points")
    level = _args.number(b_minus2, "b_minus2", minimum=0.0)
    return _power_law(-2.0, level, _rate(fs, "fs"), n, seed)


@public
def violet(num_points=1024, b2=1, fs=1, seed=None):
    """Violet noise of one-sided PSD b2 f^2 (for f well below fs / 2).

    The first difference of white noise, stationary from the first sample.

    Parameters
    ----------
    num_points : int, optional
        Number of samples.
    b2 : float, optional
        The level: the PSD is b2 f^2, in X^2/Hz when f is in Hz (X^2/Hz^3).
    fs : float, optional
        Sampling frequency in Hz.
    seed : int, optional
        Seed of cubecal's generator; None draws one from NumPy's global
        generator.

    Returns
    -------
    numpy.ndarray
        num_points samples, in X.
    """
    n = _args.count(num_points, "num_points")
    level = _args.number(b2, "b2", minimum=0.0)
    # One more innovation than samples, dropped, so that every sample is a
    # difference of two innovations (Kasdin & Walter's first is one alone).
    return _power_law(2.0, level, _rate(fs, "fs"), n, seed, skip=1)


# The 1/f level of Voss & McCartney's sum of unit-variance rows, each held
# twice as long as the one before: sum_k 2 T_k sinc^2(pi f T_k) ~ 1/(f ln 2).
_PINK_LEVEL = 1.0 / math.log(2.0)


@public
def pink(num_points=1024, depth=80, seed=None):
    """Pink (flicker) noise of one-sided PSD f^-1 / ln 2, sampled at 1 Hz.

    Kasdin & Walter's filter for f^-1: with 2^depth at least num_points the
    exact generator (1/f down to the record's length); otherwise a filter of
    2^min(depth, 18) taps, the law holding down to f ~ 2^-min(depth, 18) Hz
    and the spectrum flat below. The level, 1 / ln 2, is that of the ideal
    Voss & McCartney generator AllanTools approximates.

    Parameters
    ----------
    num_points : int, optional
        Number of samples.
    depth : int, optional
        Octaves below the Nyquist frequency down to which the spectrum is
        1/f (at least 0).
    seed : int, optional
        Seed of cubecal's generator; None draws one from NumPy's global
        generator.

    Returns
    -------
    numpy.ndarray
        num_points samples (arbitrary unit X; the PSD is in X^2/Hz).
    """
    n = _args.count(num_points, "num_points")
    d = _args.count(depth, "depth")
    if n == 0 or d >= 64 or (1 << d) >= n:
        return _power_law(-1.0, _PINK_LEVEL, 1.0, n, seed)
    stream = _cubecal._PowerLawStream(-1.0, _PINK_LEVEL, 1.0, 1 << min(d, _MAX_FILTER_DEPTH), _seed(seed))
    return stream.next(n)


def iterpink(depth=20, seed=None):
    """An endless sequence of pink (flicker) noise samples, PSD f^-1 / ln 2.

    A generator (as AllanTools' ``noise.iterpink``): each ``next()`` gives
    one sample; any run of consecutive samples has the 1/f spectrum down to
    f ~ 2^-min(depth, 18) Hz (Kasdin & Walter's filter of that many taps,
    applied block by block).

    Parameters
    ----------
    depth : int, optional
        Octaves below the Nyquist frequency down to which the spectrum is
        1/f (0 to 18 are used; more counts as 18).
    seed : int, optional
        Seed of cubecal's generator; None draws one from NumPy's global
        generator.

    Yields
    ------
    numpy.float64
        The next sample (arbitrary unit X; the PSD is in X^2/Hz at 1 Hz
        sampling).
    """
    d = _args.count(depth, "depth")
    stream = _cubecal._PowerLawStream(-1.0, _PINK_LEVEL, 1.0, 1 << min(d, _MAX_FILTER_DEPTH), _seed(seed))
    return _iterate(stream)


def _iterate(stream):
    while True:
        yield from stream.next(_STREAM_BLOCK)


def _segment_levels(frequencies, f_nodes, h, alpha):
    """S_y at each frequency: h_i f^alpha_i on the interval i between the
    nodes (below the first node the first law, at or above the last the
    last)."""
    i = np.searchsorted(f_nodes, frequencies, side="right")
    return h[i] * frequencies ** alpha[i]


@public
def timmer_koenig_from_psd(f_nodes, h, alpha, duration, timestep, output="phase", seed=None):
    """Clock noise of a piecewise power-law PSD S_y(f) by Timmer & Koenig's
    Fourier synthesis (AllanTools' ``noise.timmer_koenig_from_psd``).

    On the grid f_k = linspace(1 / ((n - 1) dt), 1 / (2 dt), n // 2 + 1)
    (n = int(duration / dt)), S_x = S_y / (2 pi f)^2 (the first point set to
    0), X_k = sqrt(S_x(f_k)) / 2 (a_k + i b_k) with a_k, b_k standard
    normals, the spectrum made Hermitian and inverse-transformed, times
    sqrt((n - 1) / dt). The normals come from NumPy's global generator in
    AllanTools' order, so that a seed gives AllanTools' samples.

    Parameters
    ----------
    f_nodes : array_like
        Break frequencies in Hz between the power-law intervals, ascending:
        len(h) - 1 of them (or none for a single law).
    h : array_like
        Level h_i of each interval, S_y(f) = h_i f^alpha_i, in Hz^-1-alpha_i.
    alpha : array_like
        Exponent alpha_i of each interval, as many as h.
    duration : float
        Length of the series in s.
    timestep : float
        Sampling interval dt in s.
    output : {'phase', 'freq'}, optional
        'phase': the time error x(t) in s; 'freq': the fractional frequency
        y(t) = dx/dt (dimensionless), its first sample 0.
    seed : int, optional
        Seeds NumPy's global generator (np.random.seed) before the draw, as
        AllanTools does; None uses the generator's current state.

    Returns
    -------
    numpy.ndarray
        n = int(duration / timestep) samples: x in s or y.

    Raises
    ------
    cubecal.UsageError
        (a ValueError, as AllanTools raises) for a non-positive duration or
        timestep, fewer than 4 samples, h and alpha of different lengths,
        a wrong number of nodes or an unknown output.
    """
    nodes = np.atleast_1d(np.asarray(f_nodes, dtype=float)) if np.size(f_nodes) else np.zeros(0)
    levels = np.atleast_1d(np.asarray(h, dtype=float))
    slopes = np.atleast_1d(np.asarray(alpha, dtype=float))
    length = _args.number(duration, "duration")
    dt = _args.number(timestep, "timestep")
    if output not in ("phase", "freq"):
        raise usage("output", f"output: 'phase' or 'freq' is expected, not {output!r}")
    if length <= 0.0 or dt <= 0.0:
        raise usage("duration", "duration and timestep must be positive (s)")
    if levels.size != slopes.size or levels.size == 0:
        raise usage("alpha", f"alpha: one exponent per level h is expected ({levels.size} levels, "
                             f"{slopes.size} exponents)")
    if nodes.size not in (0, levels.size - 1):
        raise usage("f_nodes", f"f_nodes: len(h) - 1 = {levels.size - 1} break frequencies (or none) are expected, "
                               f"not {nodes.size}")
    if seed is not None:
        np.random.seed(_args.count(seed, "seed", maximum=2 ** 32 - 1))
    n = int(length / dt)
    if n < 4:
        raise usage("duration", f"duration / timestep gives {n} samples; at least 4 are needed")
    half = n // 2
    frequencies = np.linspace(1.0 / ((n - 1) * dt), 1.0 / (2.0 * dt), half + 1)
    sx = _segment_levels(frequencies, nodes, levels, slopes) / (2.0 * np.pi * frequencies) ** 2
    sx[0] = 0.0
    normals = np.random.normal(0.0, 1.0, size=(half, 2))
    spectrum = np.zeros(n, dtype=complex)
    spectrum[1:half + 1] = np.sqrt(sx[1:]) / 2.0 * (normals[:, 0] + 1j * normals[:, 1])
    mirrored = np.arange(1, n - half)  # X[n - j] = conj(X[j]), the Nyquist bin (even n) left as drawn
    spectrum[n - mirrored] = np.conj(spectrum[mirrored])
    x = np.fft.ifft(spectrum).real * np.sqrt((n - 1) / dt)
    if output == "phase":
        return x
    return np.concatenate(([0.0], np.diff(x) / dt))
