#!/usr/bin/env python3
"""The cost of cubecal's typed results: making an Analysis from the library's
result (the binding's conversion of the document and the Python object),
making it and reading every channel's Allan curve and reported N, and
to_dict(), on an ADIS16405 run (6 channels, 1,000,000 samples at 100 Hz);
and a Spectrum (cubecal.psd of 3 channels: 98,307 bins) with its to_dict().
Best of 20 (5 for the spectrum's to_dict). Run it against two builds to set
the typed results beside an earlier package:

    PYTHONPATH=build/python /usr/bin/python3 bench/python_results.py ../shared/data/imu/adis16405/run1.csv.gz
"""
import json
import sys
import time

import cubecal


def best(f, n=20):
    times = []
    for _ in range(n):
        t = time.perf_counter()
        f()
        times.append(time.perf_counter() - t)
    return min(times) * 1e3


def main(path):
    a = cubecal.analyze(path, columns="2,3,4,5,6,7", unit=["deg/s"] * 3 + ["g"] * 3, composite=False)

    def make_and_read():
        b = cubecal.Analysis(a._handle, a._command)
        for c in b.channels:
            c.adev.tau, c.adev.dev, c.adev.lo, c.adev.hi, c.noise.reported.white_noise.value

    rec = cubecal.read(path, columns="2,3,4")
    t = time.perf_counter()
    p = cubecal.psd(rec, unit="deg/s")
    psd_s = time.perf_counter() - t
    print(json.dumps({"analysis_make_ms": round(best(lambda: cubecal.Analysis(a._handle, a._command)), 3),
                      "analysis_make_and_read_ms": round(best(make_and_read), 3),
                      "analysis_to_dict_ms": round(best(a.to_dict), 3),
                      "psd_s": round(psd_s, 3), "psd_to_dict_ms": round(best(p.to_dict, 5), 1),
                      "psd_bins": int(sum(len(c.density) for c in p.channels))}))


if __name__ == "__main__":
    main(sys.argv[1])
