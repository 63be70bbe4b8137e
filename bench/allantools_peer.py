#!/usr/bin/python3
"""The peer of `make bench`: AllanTools (its public source, run with Debian's
numpy and scipy) on the record cubecal times, in the same run.

    allantools_peer.py ALLANTOOLS_SRC RECORD.csv DEV_JSON RUNS

Loads the record with numpy (as an AllanTools user would: np.loadtxt), then
computes allantools.oadev of every column cubecal analysed, at the taus
cubecal reported in DEV_JSON (`cubecal dev --format json` of the same
record), RUNS times. Prints one line per run, "run LOAD_S OADEV_S", and last
the largest relative difference between AllanTools' deviations and
cubecal's, so that the two timings are of the same numbers.
"""
import json
import sys
import time

src, record, dev_json, runs = sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4])
sys.path.insert(0, src)
import numpy as np  # noqa: E402
import allantools  # noqa: E402

dev = json.load(open(dev_json))
rate = dev["rate_hz"]
with open(record) as f:
    header = f.readline().strip().split(",")
columns = [(header.index(c["name"]), np.array(c["tau"]), np.array(c["dev"])) for c in dev["columns"]]
worst = 0.0
for _ in range(runs):
    t0 = time.perf_counter()
    data = np.loadtxt(record, delimiter=",", skiprows=1)
    t1 = time.perf_counter()
    for index, taus, ref in columns:
        t, d, _, _ = allantools.oadev(data[:, index], rate=rate, data_type="freq", taus=taus)
        if len(t) != len(taus) or np.max(np.abs(t / taus - 1.0)) > 1e-12:
            sys.exit(f"allantools returned other taus than cubecal's for column {header[index]}")
        worst = max(worst, float(np.max(np.abs(d / ref - 1.0))))
    t2 = time.perf_counter()
    print(f"run {t1 - t0:.4f} {t2 - t1:.4f}", flush=True)
print(f"max_rel_diff {worst:.3e}")
