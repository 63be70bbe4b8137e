"""cubecal.psd and cubecal.davar equal `cubecal psd` and `cubecal davar`
(--format json) on the same record, from the file and from arrays."""
import os
import tempfile
import unittest

import numpy as np

import cubecal
from support import cli, cli_json


class Spectral(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.TemporaryDirectory()
        cls.csv = os.path.join(cls.dir.name, "g.csv")
        rng = np.random.default_rng(11)
        n = 36000
        gx = 0.05 * rng.normal(size=n) + np.cumsum(1e-3 * rng.normal(size=n))
        gy = 0.05 * rng.normal(size=n)
        np.savetxt(cls.csv, np.column_stack([np.arange(n) / 10.0, gx, gy]), delimiter=",", header="t,gx_dps,gy_dps",
                   comments="", fmt="%.17g")
        cls.arrays = {"gx_dps": gx, "gy_dps": gy}

    @classmethod
    def tearDownClass(cls):
        cls.dir.cleanup()

    def test_psd(self):
        want = cli_json("psd", self.csv, "--format", "json", "--window", "hamming", "--detrend", "linear")
        got = cubecal.psd(self.csv, window="hamming", detrend="linear").to_dict()
        self.assertEqual(got, want)
        from_arrays = cubecal.psd(self.arrays, rate=10.0, window="hamming", detrend="linear").to_dict()
        want.pop("file", None)
        from_arrays.pop("file", None)
        self.assertEqual(from_arrays, want)
        s = cubecal.psd(self.arrays, rate=10.0, bins_per_decade=10)
        self.assertEqual(s.channels[0].unit, "deg/s")
        self.assertLess(len(s.channels[0].frequency_hz), 60)

    def test_davar(self):
        want = cli_json("davar", self.csv, "--window", "10min", "--step", "60s", "--taus", "octave", "--format", "json")
        want.pop("invocation", None)
        got = cubecal.davar(self.csv, window="10min", step="60s", taus="octave").to_dict()
        self.assertEqual(got, want)
        d = cubecal.davar(self.arrays, rate=10.0, window=6000, step=600, taus="octave", alpha=0)
        self.assertEqual(len(d.channels), 2)

    def test_errors(self):
        with self.assertRaises(cubecal.UsageError) as cm:
            cubecal.psd(self.arrays, rate=10.0, window="triangle")
        self.assertEqual(cm.exception.option, "window")
        with self.assertRaises(cubecal.UsageError):
            cubecal.davar(self.arrays)  # no rate for arrays


if __name__ == "__main__":
    unittest.main()
