"""The AllanTools switch: AllanTools' own statistics (its public source, run
here with Debian's numpy and scipy) and cubecal's AllanTools-shaped calls on
the Stable32 datasets give the same taus and ns, and deviations and errors
equal to 1e-10 relative.

AllanTools' source is github.com/aewallin/allantools: ALLANTOOLS_SRC (at
configure time or in the environment) names a checkout. Without one these
tests are skipped with that reason (the machine may have no network)."""
import gzip
import os
import sys
import time
import unittest

import numpy as np

import cubecal
from support import STABLE32, allantools, phase_dat, relative




def datasets():
    """(name, data, rate, data_type, tau grids) of the Stable32 inputs."""
    ocxo = np.loadtxt(os.path.join(STABLE32, "ocxo", "ocxo_frequency.txt"))
    return [
        ("PHASE.DAT", phase_dat(), 1.0, "phase", ("all", "octave", "decade")),
        ("nbs14", np.loadtxt(os.path.join(STABLE32, "nbs14", "generated_nbs14_1000point_frequency.txt")), 1.0, "freq",
         ("all", "octave", "decade")),
        ("pink_frequency", np.loadtxt(os.path.join(STABLE32, "pink_frequency", "pink_frequency.txt")), 1 / 42.0,
         "freq", ("octave", "decade")),
        ("ocxo", (ocxo - 1e7) / 1e7, 1.0, "freq", ("octave", "decade")),
    ]


STATS = ("adev", "oadev", "mdev", "tdev", "hdev", "ohdev", "totdev")


class Parity(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.at = allantools()

    def test_statistics(self):
        worst = {}
        for name, data, rate, dtype, grids in datasets():
            for stat in STATS:
                for taus in grids:
                    with self.subTest(data=name, stat=stat, taus=taus):
                        t0, d0, e0, n0 = getattr(self.at, stat)(data, rate=rate, data_type=dtype, taus=taus)
                        t1, d1, e1, n1 = getattr(cubecal, stat)(data, rate=rate, data_type=dtype, taus=taus)
                        np.testing.assert_array_equal(t1, t0)
                        np.testing.assert_array_equal(n1, n0)
                        rd, re = relative(d1, d0), relative(e1, e0)
                        worst[stat] = max(worst.get(stat, 0.0), rd, re)
                        self.assertLess(rd, 1e-10)
                        self.assertLess(re, 1e-10)
        print("\nlargest relative difference to AllanTools, per statistic:",
              ", ".join(f"{k} {v:.1e}" for k, v in worst.items()), file=sys.stderr)

    def test_time_error_and_total_statistics(self):
        # AllanTools' total statistics are slow (pure Python loops): PHASE.DAT
        # and nbs14 at octave and decade taus.
        for name, data, rate, dtype, _ in datasets()[:2]:
            for stat in ("mtotdev", "ttotdev", "htotdev", "tierms", "mtie"):
                for taus in ("octave", "decade"):
                    with self.subTest(data=name, stat=stat, taus=taus):
                        t0, d0, e0, n0 = getattr(self.at, stat)(data, rate=rate, data_type=dtype, taus=taus)
                        t1, d1, e1, n1 = getattr(cubecal, stat)(data, rate=rate, data_type=dtype, taus=taus)
                        np.testing.assert_array_equal(t1, t0)
                        np.testing.assert_array_equal(n1, n0)
                        self.assertLess(relative(d1, d0), 1e-10)
                        if stat != "tierms":  # AllanTools gives 0 there
                            self.assertLess(relative(e1, e0), 1e-10)

    def test_gradev(self):
        # AllanTools' own gradev data: 1000 phase points, 200 of them NaN.
        folder = os.path.join(os.path.dirname(STABLE32), "allantools", "gradev")
        for name in ("y.dat", "y_gap.dat"):
            y = np.loadtxt(os.path.join(folder, name))
            for taus in ("octave", "all"):
                with self.subTest(data=name, taus=taus):
                    t0, d0, e0, n0 = self.at.gradev(y, rate=1.0, data_type="phase", taus=taus)
                    t1, d1, e1, n1 = cubecal.gradev(y, rate=1.0, data_type="phase", taus=taus)
                    np.testing.assert_array_equal(t1, t0)
                    np.testing.assert_array_equal(n1, n0)
                    self.assertLess(relative(d1, d0), 1e-10)

    def test_cs5071a_octave(self):
        # 556,990 phase points: the long record, octave taus.
        with gzip.open(os.path.join(STABLE32, "cs5071a", "5071A_phase.txt.gz"), "rt") as f:
            x = np.loadtxt(f)
        start = time.perf_counter()
        t0, d0, e0, n0 = self.at.oadev(x, rate=1.0, data_type="phase", taus="octave")
        at_s = time.perf_counter() - start
        start = time.perf_counter()
        t1, d1, e1, n1 = cubecal.oadev(x, rate=1.0, data_type="phase", taus="octave")
        cc_s = time.perf_counter() - start
        np.testing.assert_array_equal(t1, t0)
        np.testing.assert_array_equal(n1, n0)
        self.assertLess(relative(d1, d0), 1e-10)
        print(f"\ncs5071a oadev octave: AllanTools {at_s:.3f} s, cubecal {cc_s:.4f} s", file=sys.stderr)


if __name__ == "__main__":
    unittest.main()
