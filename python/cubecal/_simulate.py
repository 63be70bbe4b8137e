"""cubecal.simulate: sensor records from presets or from an analysis."""
import os

import numpy as np

from . import _args, _cubecal
from ._analyze import Analysis
from ._data import number_list, string_list
from ._read import Record


@_args.public
def presets():
    """The names of the built-in sensor models.

    Returns
    -------
    list of str
        The presets `simulate` takes by name (the paper's SPORT gyro and
        magnetometer, the ADIS16405 axes, ...), as `cubecal simulate --list`
        prints them.
    """
    return list(_cubecal._preset_names())


@_args.public
def simulate(model, rate=None, duration=3600.0, seed=1, temperature="sine:25,5", bias=None,
             true_input=None, flicker=None):
    """A simulated record, as `cubecal simulate` writes it.

    Parameters
    ----------
    model : str, Analysis, os.PathLike or list of them
        A preset name or a list of them (`cubecal.presets()`), an Analysis
        from `cubecal.analyze`, the path of an analysis.json, or the path
        of the JSON of `cubecal model --format json` (its composite models).
    rate : float, optional
        Sampling rate, Hz. Default: the analysis's rate, else 10 Hz; a
        model is rescaled to it, keeping its N and K (a composite model
        keeps N, Q, K, R, sigma_b and T_c).
    duration : float or str
        Length of the record, s, or a duration text ("72h", "30m", "2d").
    seed : int
        Seed of the generator: the same seed gives the same record.
    temperature : str or array_like
        "const:T" (degC), "sine:MEAN,AMPLITUDE[,PERIOD_S]" (degC, degC, s;
        the default "sine:25,5" is 25 +- 5 degC over a day, as the CLI), or
        one value per sample, degC.
    bias : str, optional
        The bias model taken from an analysis: None (its twins where every
        channel has one, else "random-walk"), "twin", "composite" (each term
        in its discrete-time form at `rate`), "random-walk" (the paper's) or
        "gauss-markov". A model result's is composite.
    true_input : tuple of 4 array_like, optional
        (t, wx, wy, wz): times, s, and the true rate of the gyro triad, in
        the gyro's unit.
    flicker : float or list of float, optional
        Bias instability B added as flicker noise to every axis (a flicker
        floor of 0.664 B in the Allan deviation), in each triad's unit: one
        B for all triads or one per triad.

    Returns
    -------
    Record
        Column name -> NumPy array: "t" (s), the channels in their units,
        and "temp" (degC).

    Raises
    ------
    cubecal.UsageError
        A bad argument (.option names it).
    """
    a = _cubecal._SimulateArgs()
    models = model if isinstance(model, (list, tuple)) else [model]
    for m in models:
        if isinstance(m, Analysis):
            if a.analysis is not None:
                raise _args.usage("model", "model: one analysis at a time")
            a.analysis = m._handle
        elif isinstance(m, os.PathLike) or (isinstance(m, str) and m.endswith(".json")):
            a.model_file = os.fspath(m)
        elif isinstance(m, str):
            a.presets = a.presets + string_list(m, "model")
        else:
            raise _args.usage("model",
                              f"model: a preset name, an Analysis or an analysis.json path, not {type(m).__name__}")
    if rate is not None:
        a.rate = _args.rate(rate)
    if isinstance(duration, str):
        try:
            a.duration = _cubecal._parse_duration(duration)
        except _cubecal.UsageError as e:
            raise _args.usage("duration", str(e)) from None
    else:
        a.duration = _args.number(duration, "duration", positive=True)
    a.seed = _args.seed(seed)
    if bias is not None:
        a.bias = _args.text(bias, "bias")
    if isinstance(temperature, str):
        a.temperature = temperature
    else:
        a.temperature_values = _args.samples(temperature, "temperature")
    if true_input is not None:
        if isinstance(true_input, (str, bytes)) or not hasattr(true_input, "__len__") or len(true_input) != 4:
            raise _args.usage("true_input", "true_input: (t, wx, wy, wz), four arrays")
        t, *w = true_input
        a.true_t = _args.samples(t, "true_input")
        a.true_w = [_args.samples(x, "true_input") for x in w]
    if flicker is not None:
        a.flicker = number_list(flicker, "flicker")
        if any(not 0.0 <= b <= 1e100 for b in a.flicker):
            raise _args.usage("flicker", f"flicker: a bias instability from 0 to 1e100 is expected, not {flicker!r}")
    names, arrays, rate_hz = _cubecal._simulate(a)
    n = len(arrays[0]) if arrays else 0
    columns = {"t": np.arange(n, dtype=np.float64) / rate_hz}
    columns.update(zip(names, arrays))
    channels = [x for x in names if x != "temp"]
    meta = {"file": "<simulated>", "rate_hz": rate_hz, "rate_from_time": False, "time": "t", "channels": channels,
            "extra": [x for x in names if x == "temp"], "units": [], "left_out": [], "topics": [],
            "segments": [(0, n)], "bytes": 0}
    return Record(columns, meta)
