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

Errors in the data or the arguments raise cubecal.Error subclasses (ValueErrors): InputError
(.file, .line, .column; arrays are checked as the readers check a file),
UsageError (.option, the keyword at fault), CalibrationError (.reason).
Long computations release the GIL.
"""
from ._cubecal import CalibrationError, Error, InputError, UsageError, __version__
from ._allantools import adev, gradev, hdev, htotdev, mdev, mtie, mtotdev, oadev, ohdev, tdev, tierms, totdev, ttotdev
from ._dev import Curve, DevResult, dev
from ._read import Record, read
from ._analyze import Analysis, analyze
from ._simulate import presets, simulate
from ._spectral import DynamicAllan, Spectrum, davar, psd
from ._model import NoiseModel, model
from ._result import Result
from ._calibrate import *  # noqa: F401,F403  (calibrate_* and turnon: see cubecal/_calibrate.py)

from . import ci
from .ci import (autocorr_noise_id, confidence_interval, confidence_interval_noiseID, edf_greenhall, edf_mtotdev,
                 edf_simple, edf_totdev)
