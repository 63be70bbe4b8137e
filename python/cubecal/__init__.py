"""cubecal: characterize, model, simulate and calibrate inertial sensors and clocks.

The C++ library's calls on NumPy arrays:

    import cubecal                      # instead of: import allantools
    taus, devs, errs, ns = cubecal.oadev(y, rate=100.0, data_type="freq", taus="octave")

    r = cubecal.dev(y, rate=100.0, taus="log:10")        # Stable32's grid, intervals, EDF, noise type
    a = cubecal.analyze("log.csv", unit="deg/s", temperature="temp")   # analysis.json as an object
    rec = cubecal.simulate("sport-gyro", rate=10, duration="1h", seed=1)
    rec = cubecal.read("log.csv", columns="gx,gy,gz")
    s = cubecal.psd(rec, unit="deg/s"); d = cubecal.davar(rec, window="1h", step="60s")
    m = cubecal.model(rec, "WN+RW+2*GM", unit="deg/s", bootstrap=200)   # GMWM
    p = cubecal.plan("sport-gyro", target="B:10%,K:20%")   # how long to record

Errors in the data or the arguments raise cubecal.Error subclasses (ValueErrors): InputError
(.file, .line, .column; arrays are checked as the readers check a file),
UsageError (.option, the keyword at fault), CalibrationError (.reason).
AllanTools' calls keep AllanTools' exceptions too: a refused rate is a
RateError (a UsageError and a RuntimeError), no tau left a TauError (a
UsageError and a UserWarning).
Long computations release the GIL.
"""
from ._cubecal import CalibrationError, Error, InputError, UsageError, __version__
from ._allantools import adev, gradev, hdev, htotdev, mdev, mtie, mtotdev, oadev, ohdev, tdev, tierms, totdev, ttotdev
from ._args import RateError, TauError
from ._allantools import (calc_hdev_phase, calc_htotdev_freq, calc_mtotdev_phase, gcodev, mtie_phase_fast, pdev, theo1,
                          three_cornered_hat_phase)
from ._conversions import (frequency2fractional, frequency2phase, phase2frequency, phase2radians, remove_small_ns,
                           tau_generator, tau_reduction, trim_data)
from ._psd import adev2psd_piecewise_approx, psd2allan, psd_piecewise_to_adev
from . import allantools, mask
from ._dev import Curve, DevResult, dev
from ._read import Record, read
from ._analyze import Analysis, analyze
from ._simulate import presets, simulate
from ._spectral import DynamicAllan, Spectrum, davar, psd
from ._model import NoiseModel, model
from ._plan import Plan, plan
from ._result import Result
from . import noise, noise_kasdin  # AllanTools' allantools.noise and allantools.noise_kasdin
from .noise_kasdin import Noise
from ._calibrate import *  # noqa: F401,F403  (calibrate_* and turnon: see cubecal/_calibrate.py)
from .dataset import Dataset  # AllanTools' Dataset and Plot (matplotlib, imported by Plot())
from .plot import Plot
from . import realtime  # AllanTools' realtime: deviations updated sample by sample
from .realtime import oadev_realtime, ohdev_realtime, tdev_realtime

from . import ci
from .ci import (autocorr_noise_id, confidence_interval, confidence_interval_noiseID, edf_greenhall, edf_mtotdev,
                 edf_simple, edf_totdev)

# `from cubecal import *`: cubecal's own names and every name of AllanTools'
# __all__ (`import cubecal as allantools`; docs/allantools-differences/).
# Keep this at the end of the file: it lists what the imports above bind.
_ALLANTOOLS_ALL = [
    "__version__", "adev", "oadev", "mdev", "pdev", "hdev", "ohdev", "calc_hdev_phase", "tdev", "totdev", "mtotdev",
    "calc_mtotdev_phase", "ttotdev", "htotdev", "calc_htotdev_freq", "theo1", "mtie", "mtie_phase_fast", "tierms",
    "frequency2phase", "phase2frequency", "phase2radians", "frequency2fractional", "three_cornered_hat_phase",
    "noise", "gradev", "gcodev", "trim_data", "edf_simple", "edf_greenhall", "edf_totdev", "edf_mtotdev",
    "confidence_interval", "confidence_interval_noiseID", "autocorr_noise_id", "Dataset", "Noise", "Plot",
    "psd2allan", "tau_generator", "tau_reduction",
]
__all__ = sorted(set(_ALLANTOOLS_ALL) | {n for n in dir() if not n.startswith("_")})
