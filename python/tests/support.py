"""What the Python tests share: the paths ctest passes, the Stable32 tables,
and the CLI run beside the module."""
import json
import os
import subprocess
import sys
import unittest

import numpy as np

SHARED = os.environ.get("CUBECAL_SHARED_DATA", os.path.join(os.path.dirname(__file__), "..", "..", "..", "shared", "data"))
STABLE32 = os.path.join(SHARED, "stable32")
BINARY = os.environ.get("CUBECAL_BINARY", "")


def stable32_table(path):
    """Rows of a Stable32 result file: dicts with af, tau, n, alpha, lo, sigma, hi."""
    rows = []
    with open(path) as f:
        for line in f:
            if line.startswith("#") or not line.strip():
                continue
            v = line.split()
            rows.append({"af": int(v[0]), "tau": float(v[1]), "n": int(v[2]), "alpha": int(v[3]),
                         "lo": float(v[4]), "sigma": float(v[5]), "hi": float(v[6])})
    return rows


def phase_dat():
    return np.loadtxt(os.path.join(STABLE32, "phasedat", "PHASE.DAT"))


def cli(*args, expect=0):
    """Runs the built cubecal binary; returns its standard output."""
    if not BINARY:
        raise unittest.SkipTest("CUBECAL_BINARY is not set (run the tests through ctest)")
    p = subprocess.run([BINARY, *map(str, args)], capture_output=True, text=True)
    if p.returncode != expect:
        raise AssertionError(f"cubecal {' '.join(map(str, args))}: exit {p.returncode}: {p.stderr.strip()}")
    return p.stdout


def cli_json(*args):
    return json.loads(cli(*args))


def relative(a, b):
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    scale = np.maximum(np.abs(a), np.abs(b))
    return np.max(np.where(scale > 0, np.abs(a - b) / np.where(scale > 0, scale, 1), 0.0)) if a.size else 0.0


def allantools():
    """AllanTools itself, imported from its public source (ALLANTOOLS_SRC, or
    CUBECAL_ALLANTOOLS_SRC that ctest sets from the configure-time
    environment: a checkout of github.com/aewallin/allantools); the test is
    skipped, saying why, when there is none."""
    for src in (os.environ.get("ALLANTOOLS_SRC"), os.environ.get("CUBECAL_ALLANTOOLS_SRC")):
        if src and os.path.isfile(os.path.join(src, "allantools", "allantools.py")):
            if src not in sys.path:
                sys.path.insert(0, src)
            import allantools as peer
            return peer
    raise unittest.SkipTest("AllanTools' source is not here: set ALLANTOOLS_SRC to a checkout of "
                            "github.com/aewallin/allantools to compare with it")
