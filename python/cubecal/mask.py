"""ITU limits on TDEV and MTIE of reference clocks (AllanTools' mask
module): the mask value at an observation interval tau.

    import cubecal
    cubecal.mask.prc_tdev(500.0)          # 1.5e-08 s
    cubecal.mask.prtcA_mtie(taus)         # an array of taus gives an array

Each function takes tau in seconds (a number, or an array for an array of
values) and returns the limit in seconds:

  prc_tdev, prc_mtie        Primary Reference Clock, ITU-T G.811 (1997) Amd. 1 (04/2016)
  prtcA_tdev, prtcB_tdev    Primary Reference Time Clock classes A and B, G.8272 (11/2018), Tables 3, 4
  prtcA_mtie, prtcB_mtie    the same, Tables 1, 2
  eprtc_tdev, eprtc_mtie    Enhanced PRTC, G.8272.1 (2016) Amd. 1 (08/2017), Tables 2, 1

The breakpoints and slopes are those of the Recommendations as AllanTools
writes them; a tau at a breakpoint takes the segment AllanTools gives it.
"""
import numbers

import numpy as np

from . import _args

__all__ = ["prc_tdev", "prc_mtie", "eprtc_tdev", "eprtc_mtie", "prtcA_tdev", "prtcB_tdev", "prtcA_mtie",
           "prtcB_mtie"]


def _piecewise(tau, pieces, last):
    """pieces: (test(t), value(t)) in order, the first whose test holds;
    `last`: the value beyond them. A number gives a float, an array an array."""
    scalar = isinstance(tau, numbers.Real) and not isinstance(tau, (bool, np.bool_))
    t = np.asarray(_args.number(tau, "tau") if scalar else _args.samples(tau, "tau", dimensions=(0, 1, 2)),
                   dtype=np.float64)
    out = last(t) * np.ones_like(t)
    done = np.zeros(t.shape, dtype=bool)
    for test, value in pieces:
        here = test(t) & ~done
        out = np.where(here, value(t), out)
        done |= here
    return float(out) if scalar else out


def prc_tdev(tau):
    """TDEV limit of a Primary Reference Clock (ITU-T G.811), s.

    Parameters
    ----------
    tau : float or array_like
        Observation interval, s.

    Returns
    -------
    float or ndarray
        3 ns below 100 s, 0.03 ns * tau below 1000 s, 30 ns beyond.
    """
    return _piecewise(tau, [(lambda t: t < 100, lambda t: 3e-9 + 0 * t),
                            (lambda t: t < 1000, lambda t: 0.03 * 1.0e-9 * t)], lambda t: 30e-9 + 0 * t)


def prc_mtie(tau):
    """MTIE limit of a Primary Reference Clock (ITU-T G.811), s.

    Parameters
    ----------
    tau : float or array_like
        Observation interval, s.

    Returns
    -------
    float or ndarray
        (0.275e-3 tau + 0.025) us below 1000 s, (1e-5 tau + 0.29) us beyond.
    """
    return _piecewise(tau, [(lambda t: t < 1000, lambda t: 1e-6 * (t * 0.275e-3 + 0.025))],
                      lambda t: 1e-6 * (t * 1.0e-5 + 0.29))


def eprtc_tdev(tau):
    """TDEV limit of an Enhanced Primary Reference Time Clock (ITU-T G.8272.1, Table 2), s.

    Parameters
    ----------
    tau : float or array_like
        Observation interval, s.

    Returns
    -------
    float or ndarray
        1 ns below 30000 s, 3.33333e-5 ns * tau below 300000 s, 10 ns beyond.
    """
    return _piecewise(tau, [(lambda t: t < 30e3, lambda t: 1e-9 + 0 * t),
                            (lambda t: t < 300e3, lambda t: 3.33333e-5 * 1e-9 * t)], lambda t: 10e-9 + 0 * t)


def eprtc_mtie(tau):
    """MTIE limit of an Enhanced Primary Reference Time Clock (ITU-T G.8272.1, Table 1), s.

    Parameters
    ----------
    tau : float or array_like
        Observation interval, s.

    Returns
    -------
    float or ndarray
        4 ns up to 1 s, (0.11114 tau + 3.89) ns up to 100 s,
        (0.0375e-3 tau + 15) ns up to 400000 s, 30 ns beyond.
    """
    return _piecewise(tau, [(lambda t: t <= 1, lambda t: 4e-9 + 0 * t),
                            (lambda t: t <= 100, lambda t: 1e-9 * (0.11114 * t + 3.89)),
                            (lambda t: t <= 400000, lambda t: 1e-9 * (0.0375e-3 * t + 15))],
                      lambda t: 1e-9 * 30 + 0 * t)


def prtcA_tdev(tau):  # noqa: N802 (AllanTools' name)
    """TDEV limit of a Primary Reference Time Clock, class A (ITU-T G.8272, Table 3), s.

    Parameters
    ----------
    tau : float or array_like
        Observation interval, s.

    Returns
    -------
    float or ndarray
        3 ns below 100 s, 0.03 ns * tau below 1000 s, 30 ns beyond.
    """
    return _piecewise(tau, [(lambda t: t < 100, lambda t: 3e-9 + 0 * t),
                            (lambda t: t < 1000, lambda t: 0.03e-9 * t)], lambda t: 30e-9 + 0 * t)


def prtcB_tdev(tau):  # noqa: N802 (AllanTools' name)
    """TDEV limit of a Primary Reference Time Clock, class B (ITU-T G.8272, Table 4), s.

    Parameters
    ----------
    tau : float or array_like
        Observation interval, s.

    Returns
    -------
    float or ndarray
        1 ns below 100 s, 0.01 ns * tau below 500 s, 5 ns beyond.
    """
    return _piecewise(tau, [(lambda t: t < 100, lambda t: 1e-9 + 0 * t),
                            (lambda t: t < 500, lambda t: 0.01e-9 * t)], lambda t: 5e-9 + 0 * t)


def prtcA_mtie(tau):  # noqa: N802 (AllanTools' name)
    """MTIE limit of a Primary Reference Time Clock, class A (ITU-T G.8272, Table 1), s.

    Parameters
    ----------
    tau : float or array_like
        Observation interval, s.

    Returns
    -------
    float or ndarray
        (0.275e-3 tau + 0.025) us below 273 s, 100 ns beyond.
    """
    return _piecewise(tau, [(lambda t: t < 273, lambda t: 1e-6 * (0.275e-3 * t + 0.025))],
                      lambda t: 1e-6 * 0.1 + 0 * t)


def prtcB_mtie(tau):  # noqa: N802 (AllanTools' name)
    """MTIE limit of a Primary Reference Time Clock, class B (ITU-T G.8272, Table 2), s.

    Parameters
    ----------
    tau : float or array_like
        Observation interval, s.

    Returns
    -------
    float or ndarray
        (0.275e-3 tau + 0.025) us below 54.5 s, 40 ns beyond.
    """
    return _piecewise(tau, [(lambda t: t < 54.5, lambda t: 1e-6 * (0.275e-3 * t + 0.025))],
                      lambda t: 1e-6 * 0.04 + 0 * t)
