#!/usr/bin/python3
"""cubecal.psd beside scipy.signal.welch in the same run (`make bench`).

    PYTHONPATH=BUILD/python psd_speed.py [RUNS]

One 72 h x 10 Hz gyro channel (2,592,000 samples, simulated with
cubecal.simulate, seed 1), Hann window, constant detrend, half overlap, at
two segment lengths: cubecal's default (about n/8 rounded to a power of
two) and 2^14. scipy's welch is single threaded; cubecal runs on one
thread and on every core. cubecal's call includes what a Python user gets:
the spectrum with every bin (no fit, no banding) through its JSON result.
Prints min/median/max of RUNS calls each, the ratio of the medians to
scipy's, and the largest relative difference of the two spectra.
"""
import sys

import numpy as np
import scipy.signal

import cubecal
from bench_timing import median, span, timed

runs = int(sys.argv[1]) if len(sys.argv) > 1 else 5


y = cubecal.simulate("sport-gyro", rate=10, duration="72h", seed=1, temperature="const:25")["gx"]
y = np.ascontiguousarray(y, dtype=np.float64)
print(f"== PSD (Welch, hann, half overlap, constant detrend): {len(y)} samples, min / median / max of {runs}")
for segment in (0, 1 << 14):
    length = int(cubecal.psd(y[:1 << 16] if segment else y, rate=10.0, segment=segment, fit=False,
                             threads=1).to_dict()["welch"]["segment_length"])
    s_scipy, (f_ref, p_ref) = timed(lambda: scipy.signal.welch(y, fs=10.0, window="hann", nperseg=length,
                                                                 noverlap=length // 2, detrend="constant"), runs)
    s_one, one = timed(lambda: cubecal.psd(y, rate=10.0, segment=length, fit=False, threads=1), runs)
    s_all, _ = timed(lambda: cubecal.psd(y, rate=10.0, segment=length, fit=False, threads=0), runs)
    ch = one.to_dict()["channels"][0]
    p = np.asarray(ch["density"])
    assert np.array_equal(np.asarray(ch["frequency_hz"]), f_ref)
    k = p_ref > 0.0
    diff = float(np.max(np.abs(p[k] - p_ref[k]) / p_ref[k]))
    print(f"  segment {length}: scipy.signal.welch {span(s_scipy)}; cubecal.psd 1 thread {span(s_one)} "
          f"({median(s_scipy) / median(s_one):.1f}x); all cores {span(s_all)} ({median(s_scipy) / median(s_all):.1f}x); "
          f"largest relative difference {diff:.1e}")
