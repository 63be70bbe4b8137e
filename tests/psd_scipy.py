#!/usr/bin/python3
"""scipy.signal.welch of a record, for tests/test_psd_scipy.cpp.

    psd_scipy.py X.bin RATE OUT_PREFIX SPEC...

X.bin holds the samples as little-endian float64. Each SPEC is
WINDOW:DETREND:NPERSEG:NOVERLAP (window: hann, hamming, blackman, boxcar;
detrend: none, constant, linear); the one-sided density of spec i is written
to OUT_PREFIX<i>.txt as lines "frequency density" (17 significant digits).
Exit 3 when scipy cannot be imported (the test then says why it skips).
"""
import sys

try:
    import numpy as np
    from scipy import signal
except ImportError as e:  # pragma: no cover - the test reports it
    print(f"scipy not importable: {e}", file=sys.stderr)
    sys.exit(3)


def main() -> int:
    path, rate, prefix = sys.argv[1], float(sys.argv[2]), sys.argv[3]
    x = np.fromfile(path, dtype="<f8")
    for i, spec in enumerate(sys.argv[4:]):
        window, detrend, nperseg, noverlap = spec.split(":")
        f, p = signal.welch(x, fs=rate, window=window, nperseg=int(nperseg), noverlap=int(noverlap),
                            detrend=False if detrend == "none" else detrend, return_onesided=True,
                            scaling="density", average="mean")
        np.savetxt(f"{prefix}{i}.txt", np.column_stack([f, p]), fmt="%.17e")
    return 0


if __name__ == "__main__":
    sys.exit(main())
