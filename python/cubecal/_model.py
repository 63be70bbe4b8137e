"""cubecal.model: `cubecal model` on a file or on arrays; the result's
to_dict() is the command's JSON."""

from . import _args, _cubecal
from ._data import string_list
from ._result import ModelChannel, Result, _fmt  # noqa: F401  (ModelChannel: the channels' class)
from ._spectral import _source


class NoiseModel(Result):
    """The result of cubecal.model: `cubecal model --format json` as a typed
    object (to_dict() is that document)."""

    __slots__ = ()
    _spec = """
    command: str -- "model"
    file: str -- the record (a path, or "<arrays>")
    rate_hz: float -- its sampling rate, Hz
    samples: int -- its samples per channel
    model: str -- the model asked for (terms joined by +, candidates joined by commas, or "auto")
    ci: float -- the confidence of the intervals (0 to 1)
    bootstrap: int -- parametric-bootstrap replicates behind the uncertainties (0: none)
    seed: int -- the bootstrap's seed
    selection_replicates: int -- bootstrap replicates of the WIC's optimism (0: its asymptotic form)
    robust: bool -- whether the robust (biweight) wavelet variance was fitted
    robust_efficiency: float | None -- its Gaussian efficiency (None unless robust)
    channels: list[ModelChannel] -- each channel's fitted model
    """

    def _summary(self):
        return f"{self.samples} samples at {_fmt(self.rate_hz)} Hz; " + "; ".join(
            c._summary() for c in self.channels)


@_args.public
def model(data, model, rate=None, unit=None, bootstrap=0, seed=1, ci=0.95, starts=32, names=None, threads=0,
          wic_replicates=50, robust=False, efficiency=0.6, **read_options):
    """A composite noise model fitted by the GMWM, as `cubecal model`.

    Each channel's Haar wavelet variance is fitted by the generalized method
    of wavelet moments.

    Parameters
    ----------
    data : str, os.PathLike, array_like, dict, cubecal.Record or DataFrame
        A path (read_options as cubecal.read) or arrays sampled at `rate`.
    model : str
        Terms joined by + (WN, QN, RW, DR, GM or AR1, k*GM), e.g.
        "WN+RW+2*GM"; several joined by commas, or "auto" (the default
        candidates), are ranked per channel by the Wavelet Information
        Criterion.
    rate : float, optional
        Sampling rate of arrays, Hz.
    unit : str or list of str, optional
        One unit for all channels or one per channel (default: from the
        names, else none: the terms in u).
    bootstrap : int
        Parametric-bootstrap replicates of the uncertainties (0: none).
    seed : int
        The bootstrap's seed.
    ci : float
        Confidence of the wavelet variance's and the bootstrap's intervals
        (0 to 1).
    starts : int
        Starting points of the optimiser.
    names : list of str, optional
        Names of array channels.
    threads : int
        Worker threads (0: every core).
    wic_replicates : int
        Bootstrap replicates of the WIC's optimism (0: its asymptotic form).
    robust : bool
        Fit the robust (biweight) wavelet variance, for records with spikes.
    efficiency : float
        Its Gaussian efficiency (0 to 1).
    **read_options
        cubecal.read's options for a path.

    Returns
    -------
    NoiseModel
        `cubecal model --format json` as a typed object.
    """
    a = _cubecal._ModelArgs()
    a.model = _args.text(model, "model")
    a.units = string_list(unit, "unit")
    a.bootstrap, a.seed = _args.count(bootstrap, "bootstrap"), _args.seed(seed)
    a.ci, a.starts, a.threads = _args.number(ci, "ci"), _args.count(starts, "starts"), _args.threads(threads)
    a.wic_replicates = _args.count(wic_replicates, "wic_replicates")
    a.robust, a.efficiency = _args.flag(robust, "robust"), _args.number(efficiency, "efficiency")
    path, ra, arrays, names, rate = _source(data, rate, names, read_options)
    return NoiseModel(_cubecal._model(path, ra, arrays, names, rate, a))
