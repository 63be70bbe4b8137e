"""AllanTools' conversions between a fractional-frequency spectrum S_y(f)
and Allan deviations: psd2allan (the integral over a sampled density),
adev2psd_piecewise_approx and psd_piecewise_to_adev (a piecewise power-law
density from an ADEV or HDEV curve, and back; De Marchi et al. 2024). With
AllanTools' signatures and return values; the quadratures are SciPy's
(imported when called: `import cubecal` does not need SciPy)."""
import math
import numbers
import warnings

import numpy as np

from . import _args
from ._args import public, usage


def _positive_grid(value, option):
    a = _args.series(value, option)
    if not np.all(np.isfinite(a)):
        raise usage(option, f"{option}: every value must be a finite number")
    return a


@public
def psd2allan(S_y, f=1.0, kind="adev", base=2):
    """Allan or modified Allan deviation of a one-sided density S_y(f).

    sigma^2(tau) = 2 int_0^f_max S_y(f) |sin(pi f tau)^(k+1) / (pi f tau)^k|^2 df,
    k = 1 (ADEV) or 2 (MDEV), by Simpson's rule on the density interpolated
    (cubic) to four times as many frequencies, as AllanTools computes it.

    Parameters
    ----------
    S_y : ndarray
        One-sided density of fractional frequency, 1/Hz, at f = 0, df, 2 df ...
        (the first value is S_y(0)); at least 4 values.
    f : ndarray or float
        The frequencies, Hz (their first step is df), or df itself (default 1 Hz).
    kind : {"adev", "mdev"}
        Only the first letter counts ("a" or "m", any case).
    base : float
        Taus spaced by powers of `base` (2: octave, 10: decade); 1 or less: every factor.

    Returns
    -------
    taus : ndarray
        Averaging times, s: m * tau0 with tau0 = 1 / f_max.
    devs : ndarray
        ADEV or MDEV at each tau (dimensionless).
    """
    from scipy.integrate import simpson
    from scipy.interpolate import make_interp_spline

    if not isinstance(S_y, np.ndarray):
        raise usage("S_y", "S_y: a NumPy array of the density is expected")
    s = _positive_grid(S_y, "S_y")
    if s.size < 4:
        raise usage("S_y", "S_y: at least 4 values are needed")
    if isinstance(f, np.ndarray):
        grid = _positive_grid(f, "f")
        if grid.size < 2:
            raise usage("f", "f: at least two frequencies are needed")
        df = float(grid[1] - grid[0])
    elif isinstance(f, numbers.Real) and not isinstance(f, bool):
        df = float(f)
    else:
        raise usage("f", f"f: an array of frequencies or the frequency step is expected, not {f!r}")
    if not (math.isfinite(df) and df > 0.0):
        raise usage("f", "f: the frequency step must be positive")
    if not isinstance(kind, str) or kind[:1].lower() not in ("a", "m"):
        raise usage("kind", f"kind must be \"adev\" or \"mdev\", not {kind!r}")
    exponent = 1.0 if kind[0].lower() == "a" else 2.0
    base = _args.number(base, "base")
    over = 4
    # The density on its grid of step df, interpolated to steps of df / over from df / over on.
    fine = np.arange(1, over * (s.size - 1) + 1) * (df / over)
    density = make_interp_spline(np.arange(s.size) * df, s, k=3)(fine)
    tau0 = 1.0 / fine[-1]
    n = 1.0 / df / tau0 / 2.0
    if base > 1:
        m = np.unique(np.round(np.append(base ** np.arange(np.floor(np.log(n) / np.log(base))), n)))
    else:
        m = np.arange(1, n)
    taus = m * tau0
    x = np.pi * np.outer(taus, fine)
    integrand = density * np.abs(np.sin(x) ** (exponent + 1.0) / x ** exponent) ** 2
    integrand = np.insert(integrand, 0, 0.0, axis=1)
    devs = np.sqrt(2.0 * simpson(integrand, x=np.insert(fine, 0, 0.0)))
    return taus, devs


def _sin4_integral(lower, upper, power):
    """int_lower^upper sin(z)^4 / z^power dz (SciPy's quad)."""
    from scipy.integrate import IntegrationWarning, quad

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", category=IntegrationWarning)
        value, _ = quad(lambda z: np.sin(z) ** 4 / z ** power, lower, upper)
    return value


@public
def adev2psd_piecewise_approx(adev, taus, vartype="adev", mu_tol=1e-5):
    """A piecewise power-law density S_y(f) = h_i f^alpha_i from an ADEV or
    HDEV curve (De Marchi et al. 2024).

    Between consecutive taus the variance is a power law tau^mu (slopes
    within `mu_tol` of the previous one merged), alpha = -mu - 1, and h from
    the exact integral J(mu) = int_0^inf q(z) sin^4 z / z^(3 + mu) dz
    (q = 1 for ADEV, 4/3 sin^2 z for HDEV).

    Parameters
    ----------
    adev : array_like
        Deviations, positive, one per tau.
    taus : array_like
        Averaging times, s, positive and increasing.
    vartype : {"adev", "hdev"}
        The deviation given.
    mu_tol : float
        Slopes closer than this to the previous one are merged.

    Returns
    -------
    f_nodes : ndarray
        Break frequencies, Hz, increasing.
    Sy_nodes : ndarray
        S_y at f_nodes, 1/Hz.
    h : ndarray
        Coefficient of each segment, in frequency order.
    alpha : ndarray
        Exponent of each segment, in frequency order.

    Raises
    ------
    cubecal.UsageError
        A slope outside -2 .. 2 (ADEV) or -2 .. 4 (HDEV): the integral diverges.
    """
    from scipy.integrate import IntegrationWarning, quad

    a = _positive_grid(adev, "adev")
    t = _positive_grid(taus, "taus")
    if a.size != t.size:
        raise usage("taus", "adev and taus must have the same length")
    if a.size < 2:
        raise usage("adev", "adev: at least two points are needed")
    if np.any(a <= 0) or np.any(t <= 0):
        raise usage("adev", "adev and taus must be positive")
    if not np.all(np.diff(t) > 0):
        raise usage("taus", "taus must increase strictly")
    vt = vartype.lower() if isinstance(vartype, str) else None
    if vt not in ("adev", "hdev"):
        raise usage("vartype", f"vartype must be \"adev\" or \"hdev\", not {vartype!r}")
    mu_tol = _args.number(mu_tol, "mu_tol")
    mus, node_dev, node_tau = [], [a[0]], [t[0]]
    for i in range(1, a.size):
        mu = 2.0 * (math.log(a[i]) - math.log(a[i - 1])) / (math.log(t[i]) - math.log(t[i - 1]))
        if not mus or abs(mu - mus[-1]) > mu_tol:
            mus.append(mu)
            node_dev.append(a[i])
            node_tau.append(t[i])
    top = 2.0 if vt == "adev" else 4.0
    for i, mu in enumerate(mus):
        if not -2.0 <= mu <= top:
            raise usage("adev", f"adev: the curve between {node_tau[i]:g} s and {node_tau[i + 1]:g} s has slope "
                                f"mu = {mu:g} (variance ~ tau^mu), outside -2 to {top:g}: no density gives it")
    mus = np.array(mus)
    node_dev, node_tau = np.array(node_dev), np.array(node_tau)
    q = (lambda z: 1.0) if vt == "adev" else (lambda z: (4.0 / 3.0) * np.sin(z) ** 2)
    b = node_dev[1:] ** 2 * node_tau[1:] ** (-mus)
    integrals = []
    for mu in mus:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", category=IntegrationWarning)
            value, _ = quad(lambda z, mu=mu: q(z) * np.sin(z) ** 4 / z ** (3.0 + mu), 0.0, np.inf)
        integrals.append(value)
    integrals = np.array(integrals)
    h = (b / (2.0 * integrals * np.pi ** mus))[::-1].copy()
    alpha = -mus[::-1] - 1.0
    if node_dev.size == 2:
        f_nodes = (1.0 / node_tau)[::-1]
        sy = h[0] * f_nodes ** alpha[0]
    else:
        f_nodes = np.array([1.0 / (10.0 * np.pi * node_tau[i]) * (integrals[i] / integrals[i + 1])
                            ** (1.0 / (mus[i + 1] - mus[i])) for i in range(mus.size - 1)])[::-1]
        sy = h[:f_nodes.size] * f_nodes ** alpha[:f_nodes.size]
    return f_nodes, sy, h, alpha


@public
def psd_piecewise_to_adev(h, alpha, f_nodes, taus):
    """ADEV of a piecewise power-law density S_y(f) = h_i f^alpha_i.

    sigma^2(tau) = 2 sum_i h_i / (pi tau)^(alpha_i + 1) int_{pi tau f_(i-1)}^{pi tau f_i} sin^4 z / z^(2 - alpha_i) dz,
    with f_0 = 0 and the last segment to infinity (NIST SP 1065 eq. 65).

    Parameters
    ----------
    h : array_like
        Coefficient of each segment, in frequency order.
    alpha : array_like
        Exponent of each segment.
    f_nodes : array_like
        Break frequencies, Hz, one fewer than the segments.
    taus : array_like
        Averaging times, s.

    Returns
    -------
    ndarray
        ADEV at each tau (dimensionless).
    """
    h = np.atleast_1d(np.asarray(h, dtype=np.float64))
    alpha = np.atleast_1d(np.asarray(alpha, dtype=np.float64))
    nodes = np.atleast_1d(np.asarray(f_nodes, dtype=np.float64))
    t = np.asarray(taus, dtype=np.float64)
    if alpha.shape != h.shape:
        raise usage("alpha", "alpha: one exponent per coefficient h is expected")
    if nodes.size < h.size - 1:
        raise usage("f_nodes", "f_nodes: one break frequency between each two segments is expected")
    edges = np.concatenate(([0.0], nodes, [np.inf]))
    out = np.empty_like(t, dtype=np.float64)
    for k, tau in enumerate(t.flat):
        total = 0.0
        for i in range(h.size):
            total += h[i] / (np.pi * tau) ** (alpha[i] + 1.0) * _sin4_integral(
                np.pi * tau * edges[i], np.pi * tau * edges[i + 1], 2.0 - alpha[i])
        out.flat[k] = math.sqrt(2.0 * total)
    return out
