"""cubecal.analyze: `cubecal analyze` on a file or on arrays."""
import os

import numpy as np

from . import _args, _cubecal
from ._args import usage
from ._data import channels_of, number_list, string_list
from ._read import read_args
from ._result import Result


class Analysis(Result):
    """The result of cubecal.analyze: the content of analysis.json as
    attributes (input.file, input.samples, input.rate_hz, channels[i].adev.dev,
    channels[i].noise.reported, channels[i].model, covariance, ...).
    to_dict() is analysis.json's content; write(dir) writes the files of
    `cubecal analyze --out DIR`; cubecal.simulate(analysis) simulates the
    sensors it measured."""

    def __init__(self, handle, command):
        super().__init__(handle.document(command))
        object.__setattr__(self, "_handle", handle)
        object.__setattr__(self, "_command", command)

    def write(self, directory, force=False):
        """Writes analysis.json, adev.csv, drift.csv and imu.yaml into
        `directory` (created if missing); an existing file is refused unless
        force. Returns the paths written."""
        return self._handle.write(_args.path(directory, "directory"), _args.flag(force, "force"), self._command)


def _composite_named(call, *arguments):
    """The call; the library's errors on the composite model (its field is
    cubecal model's `model`) name analyze's keyword, composite."""
    try:
        return call(*arguments)
    except _cubecal.UsageError as e:
        if e.option != "model":
            raise
        raise usage("composite", f"composite: {e}") from None


def _call_text(first, kwargs):
    given = ", ".join(f"{k}={v!r}" for k, v in kwargs.items() if v is not None)
    return f"cubecal.analyze({first}{', ' + given if given else ''})"


@_args.public
def analyze(data, rate=None, unit=None, temperature=None, taus="log:10", ci=0.683, temp_order=1, drift_window=0.0,
            cov_samples=0, max_samples=0, model_lsb=None, names=None, threads=0, psd=False, composite=None,
            composite_bootstrap=0, **read_options):
    """Static characterization of every channel, as `cubecal analyze`: fixed
    bias, OADEV with intervals, the noise terms (N, B, K, Q, R) by slope
    read-offs and the five-term fit, the paper's random-walk model and a
    Gauss-Markov model, bias drift, covariance and, with a temperature, the
    temperature coefficients and the compensated analysis.

    data: a path (read as the CLI reads it; read_options are cubecal.read's:
    columns, time, skip_rows, lsb, gaps, topics, dataset, binary, ...), or
    arrays (a 1-D array, a 2-D array with one channel per column, a list, a
    dict / cubecal.Record / DataFrame of columns) sampled at `rate` Hz.
    unit: one for all channels or one per channel ("deg/s", "rad/s",
    "mGauss", "uT", "g", "m/s^2", "counts", ...); default: from the column
    names (gx_dps, mag_x_uT, ...). temperature: a column name (of the file or
    of a dict of columns) or an array, one value per sample, in degC.
    psd: also the spectral view, as `cubecal analyze --psd`: each channel's
    power spectral density (cubecal.psd's defaults), its power-law fit and
    the N, B, K it stands for beside the Allan curve's (to_dict()'s
    channels[i]["spectral"]).
    composite: the composite noise model beside the two sensor models, as
    `cubecal analyze --composite`: None (the default) each channel's twin
    (docs/twins.md; left out, with the reason in to_dict()["composite_skipped"],
    for a record that cannot carry one), False or "none" none, "twin" the
    twin required, True or "auto" (selected by the WIC among the default
    candidates), a model ("WN+GM+RW") or candidates joined by commas
    (to_dict()'s channels[i]["model"]["composite"]); composite_bootstrap:
    replicates of its parametric-bootstrap uncertainties (0: none).
    cubecal.simulate(analysis) simulates it.
    Returns an Analysis.
    """
    args = _cubecal._AnalyzeArgs()
    args.units = string_list(unit, "unit")
    args.taus = _args.taus(taus)
    args.ci = _args.number(ci, "ci")
    args.temp_order = _args.count(temp_order, "temp_order")
    args.drift_window = _args.number(drift_window, "drift_window")
    args.cov_samples = _args.count(cov_samples, "cov_samples")
    args.max_samples = _args.count(max_samples, "max_samples")
    args.model_lsb = number_list(model_lsb, "model_lsb")
    args.threads = _args.threads(threads)
    args.psd = _args.flag(psd, "psd")
    if composite is True:
        composite = "auto"
    if composite is False:
        composite = "none"
    if composite is not None:
        if not isinstance(composite, str):
            raise usage("composite", "composite: None (the twin), False or \"none\", True or \"auto\", \"twin\", a "
                                     "model such as \"WN+GM+RW\" or candidates")
        args.composite = composite
    args.composite_bootstrap = _args.count(composite_bootstrap, "composite_bootstrap")
    # The call as the result's "command": every argument that changes the
    # analysis, so that it reproduces it (arrays are shown as <arrays>).
    shown = {"rate": rate, "unit": unit, "temperature": temperature if isinstance(temperature, str) else None,
             "taus": taus if taus != "log:10" else None, "ci": ci if ci != 0.683 else None,
             "temp_order": temp_order if temp_order != 1 else None,
             "drift_window": drift_window or None, "cov_samples": cov_samples or None,
             "max_samples": max_samples or None, "model_lsb": model_lsb, "names": names,
             "psd": True if psd else None, "composite": args.composite or None,
             "composite_bootstrap": composite_bootstrap or None}
    if isinstance(data, (str, os.PathLike)):
        if names is not None:
            raise usage("names", "names: give columns= to choose the columns of a file")
        path = _args.path(data, "data")
        if temperature is not None and not isinstance(temperature, str):
            raise usage("temperature", "temperature: a column name of the file")
        ro = dict(read_options)
        if rate is not None:
            ro["rate"] = rate
        handle = _composite_named(_cubecal._analyze_file, path, read_args(**ro), args, temperature or "")
        return Analysis(handle, _call_text(repr(path), {**shown, **ro}))
    if read_options:
        raise usage(next(iter(read_options)), f"{', '.join(read_options)}: options of a file; data are arrays here")
    temp_name, temp_values, exclude = "temp", None, ()
    if isinstance(temperature, str):
        if not (isinstance(data, dict) or hasattr(data, "columns")):
            raise usage("temperature", "temperature: a column name needs data with named columns (a dict or DataFrame)")
        if temperature not in data:
            raise usage("temperature", f"temperature: no column {temperature!r} in the data")
        temp_name, temp_values, exclude = temperature, _args.samples(data[temperature], "temperature"), (temperature,)
    elif temperature is not None:
        temp_values = _args.samples(temperature, "temperature")
    names, arrays = channels_of(data, names, exclude)
    if rate is None:
        rate = getattr(data, "rate_hz", None)
        if not rate:
            raise usage("rate", "rate: give the sampling rate of the arrays in Hz")
    label = getattr(data, "file", None) or "<arrays>"
    handle = _composite_named(_cubecal._analyze_arrays, arrays, names, _args.rate(rate), args, temp_values, temp_name,
                              label)
    if temperature is not None and not isinstance(temperature, str):
        shown["temperature"] = "<array>"
    return Analysis(handle, _call_text("<arrays>", shown))
