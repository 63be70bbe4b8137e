"""cubecal.model: `cubecal model` on a file or on arrays; the result's
to_dict() is the command's JSON."""

from . import _args, _cubecal
from ._data import string_list
from ._result import Result
from ._spectral import _source


class NoiseModel(Result):
    """The result of cubecal.model, as `cubecal model --format json`: model,
    ci, bootstrap, seed, selection_replicates, robust, robust_efficiency
    (None unless robust) and channels [{name, unit,
    model (the selected one), candidates [{model, parameters, wic, loss,
    optimism, replicates, objective}] (ranked, with several), failed,
    objective, converged,
    replicates, terms [{term, parameters {value, phi}, quantities [{name,
    value, unit, sd, lo, hi, asymptotic_sd, display {value, sigma, lo, hi,
    asymptotic_sd, unit}}]}] (sd, lo, hi: the bootstrap's, None without;
    asymptotic_sd: the GMWM's sandwich standard deviation by the delta
    method, None where the fit does not determine it),
    wavelet_variance {tau_samples, tau_s, nu2, lo, hi, edf, n, model}}]."""


@_args.public
def model(data, model, rate=None, unit=None, bootstrap=0, seed=1, ci=0.95, starts=32, names=None, threads=0,
          wic_replicates=50, robust=False, efficiency=0.6, **read_options):
    """A composite noise model fitted to each channel's Haar wavelet variance
    by the GMWM, as `cubecal model`.

    data: a path (read_options as cubecal.read) or arrays sampled at `rate`
    Hz. model: terms joined by + (WN, QN, RW, DR, GM or AR1, k*GM), e.g.
    "WN+RW+2*GM"; several joined by commas, or "auto" (the default
    candidates), are ranked per channel by the Wavelet Information
    Criterion, its optimism from `wic_replicates` bootstrap replicates (0:
    its asymptotic form). unit: one for all channels or one per channel (default:
    from the names, else none). bootstrap: parametric-bootstrap replicates
    for the uncertainties (0: none), with `seed`; ci: the confidence of the
    wavelet variance's and the bootstrap's intervals; starts: starting points
    of the optimiser; robust: the robust (biweight) wavelet variance at
    Gaussian `efficiency`, for records with spikes. Returns a NoiseModel.
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
