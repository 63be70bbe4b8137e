#!/usr/bin/python3
"""cubecal.oadev beside allantools.oadev in the same run (`make bench`).

    PYTHONPATH=BUILD/python python_speed.py BUILD [RUNS]

One 72 h x 10 Hz gyro channel (2,592,000 samples, simulated with
cubecal.simulate, seed 1), frequency data, at AllanTools' octave taus and at
cubecal's log:20 grid (the same taus passed to both). Each call is single
threaded on both sides. Prints min/median/max of RUNS calls of each, the
ratio of the medians, the largest relative difference of the deviations, and
the Python call's overhead over the same work called from C++
(bench_deviation_call on the same samples and factors).

AllanTools' source: ALLANTOOLS_SRC (a checkout of github.com/aewallin/allantools),
else BENCH_OUT/allantools; without it only cubecal's side is printed.
"""
import os
import subprocess
import sys
import tempfile

import numpy as np

import cubecal
from bench_timing import span, timed

build = sys.argv[1]
runs = int(sys.argv[2]) if len(sys.argv) > 2 else 5
src = os.environ.get("ALLANTOOLS_SRC") or os.path.join(os.environ.get("BENCH_OUT", "bench-out"), "allantools")
allantools = None
if os.path.isfile(os.path.join(src, "allantools", "allantools.py")):
    sys.path.insert(0, src)
    import allantools


y = cubecal.simulate("sport-gyro", rate=10, duration="72h", seed=1, temperature="const:25")["gx"]
rate = 10.0
log20 = cubecal.dev(y, rate=rate, taus="log:20", intervals=False).tau
print(f"== Python: cubecal.oadev vs allantools.oadev, {y.size} samples, freq data, one thread each, "
      f"min / median / max of {runs}")
for label, taus in (("octave", "octave"), ("log:20", log20)):
    cc, (t1, d1, _, _) = timed(lambda: cubecal.oadev(y, rate=rate, data_type="freq", taus=taus), runs)
    line = f"  {label:7s} {len(t1):4d} taus  cubecal {span(cc)}"
    if allantools is not None:
        at, (t0, d0, _, _) = timed(lambda: allantools.oadev(y, rate=rate, data_type="freq", taus=taus), runs)
        if not np.array_equal(t0, t1):
            sys.exit(f"allantools and cubecal gave other taus at {label}")
        diff = float(np.max(np.abs(d1 / d0 - 1.0)))
        line += f"  allantools {span(at)}  ratio {at[len(at) // 2] / cc[len(cc) // 2]:.1f}x  max rel diff {diff:.1e}"
    print(line)
    # The same work from C++: the Python call's overhead is the difference.
    with tempfile.TemporaryDirectory() as d:
        samples, factors = os.path.join(d, "y.f64"), os.path.join(d, "m.txt")
        np.ascontiguousarray(y, dtype=np.float64).tofile(samples)
        np.savetxt(factors, np.round(t1 * rate).astype(np.int64), fmt="%d")
        out = subprocess.run([os.path.join(build, "bin", "bench_deviation_call"), samples, factors, str(rate),
                              str(runs)], capture_output=True, text=True, check=True).stdout.split()
        cpp = sorted(float(x) for x in out)
        py_median = cc[len(cc) // 2]
        print(f"          C++ call {cpp[0]:.4f} / {cpp[1]:.4f} / {cpp[2]:.4f} s; the Python call adds "
              f"{(py_median - cpp[1]) * 1e3:.2f} ms ({100 * (py_median / cpp[1] - 1):.1f} %) at the median")
if allantools is None:
    print(f"  (no AllanTools source at {src}: set ALLANTOOLS_SRC to a checkout of github.com/aewallin/allantools)")
