"""cubecal.model equals `cubecal model --format json` on the same record,
from the file and from arrays, with and without the bootstrap; a bad model
is a UsageError naming the option."""
import os
import tempfile
import unittest

import numpy as np
import scipy.signal

import cubecal
from support import cli_json


class Model(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.TemporaryDirectory()
        cls.csv = os.path.join(cls.dir.name, "g.csv")
        rng = np.random.default_rng(5)
        n = 60000
        phi = np.exp(-1.0 / 300.0)  # a Gauss-Markov bias with T_c = 30 s at 10 Hz
        gm = scipy.signal.lfilter([1.0], [1.0, -phi], 0.002 * rng.normal(size=n))
        gx = 0.05 * rng.normal(size=n) + gm
        np.savetxt(cls.csv, np.column_stack([np.arange(n) / 10.0, gx]), delimiter=",", header="t,gx_dps",
                   comments="", fmt="%.17g")
        cls.gx = gx

    @classmethod
    def tearDownClass(cls):
        cls.dir.cleanup()

    def test_file_and_arrays_equal_the_cli(self):
        want = cli_json("model", self.csv, "--model", "WN+GM", "--format", "json")
        got = cubecal.model(self.csv, "WN+GM")
        self.assertEqual(got.to_dict(), want)
        self.assertEqual(got.channels[0].terms[0].quantities[0].display.unit, "deg/sqrt(h)")
        arrays = cubecal.model({"gx_dps": self.gx}, "WN+GM", rate=10.0).to_dict()
        self.assertEqual(arrays["file"], "<arrays>")
        self.assertEqual(arrays["channels"], want["channels"])
        # The wavelet variance's arrays arrive as NumPy arrays.
        self.assertEqual(got.channels[0].wavelet_variance.nu2.dtype, np.float64)

    def test_bootstrap_equals_the_cli(self):
        args = ["--model", "WN+GM", "--bootstrap", "8", "--seed", "3", "--format", "json"]
        want = cli_json("model", self.csv, *args)
        got = cubecal.model(self.csv, "WN+GM", bootstrap=8, seed=3).to_dict()
        self.assertEqual(got, want)
        q = got["channels"][0]["terms"][1]["quantities"][0]
        self.assertEqual(q["name"], "sigma_b")
        self.assertGreater(q["sd"], 0.0)
        self.assertLess(q["lo"], q["hi"])

    def test_bad_model(self):
        with self.assertRaises(cubecal.UsageError) as e:
            cubecal.model(self.csv, "WN+XX")
        self.assertEqual(e.exception.option, "model")
        self.assertIn("unknown term 'XX'", str(e.exception))
        with self.assertRaises(cubecal.UsageError) as e:
            cubecal.model(self.csv, "WN", bootstrap=1)
        self.assertEqual(e.exception.option, "bootstrap")


if __name__ == "__main__":
    unittest.main()
