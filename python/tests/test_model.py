"""cubecal.model equals `cubecal model --format json` on the same record,
from the file and from arrays, with and without the bootstrap, with a
selection among candidates, with the robust wavelet variance; a bad model
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
        # The sandwich sd beside the bootstrap's, in both units.
        self.assertGreater(q["asymptotic_sd"], 0.0)
        self.assertAlmostEqual(q["display"]["asymptotic_sd"] / q["asymptotic_sd"],
                               q["display"]["value"] / q["value"], places=12)

    def test_selection_equals_the_cli(self):
        args = ["--model", "WN,WN+GM,WN+RW", "--wic-replicates", "8", "--seed", "2", "--format", "json"]
        want = cli_json("model", self.csv, *args)
        got = cubecal.model(self.csv, "WN,WN+GM,WN+RW", wic_replicates=8, seed=2).to_dict()
        self.assertEqual(got, want)
        c = got["channels"][0]
        self.assertEqual([m["model"] for m in c["candidates"]][0], c["model"])
        self.assertEqual(len(c["candidates"]) + len(c["failed"]), 3)

    def test_robust_equals_the_cli(self):
        # The record with 0.1 % of its samples replaced by 60-sigma spikes:
        # the robust white noise stays near the clean fit's, the classical
        # one is several times larger.
        y = self.gx.copy()
        rng = np.random.default_rng(9)
        at = rng.choice(len(y), len(y) // 1000, replace=False)
        y[at] = 60 * 0.05 * rng.choice([-1.0, 1.0], size=len(at))
        path = os.path.join(self.dir.name, "spiky.csv")
        np.savetxt(path, np.column_stack([np.arange(len(y)) / 10.0, y]), delimiter=",", header="t,gx_dps",
                   comments="", fmt="%.17g")
        want = cli_json("model", path, "--model", "WN+GM", "--robust", "--efficiency", "0.7", "--format", "json")
        got = cubecal.model(path, "WN+GM", robust=True, efficiency=0.7).to_dict()
        self.assertEqual(got, want)
        self.assertIs(got["robust"], True)
        self.assertEqual(got["robust_efficiency"], 0.7)
        classical = cubecal.model(path, "WN+GM").to_dict()
        self.assertIs(classical["robust"], False)
        self.assertIsNone(classical["robust_efficiency"])
        clean = cubecal.model(self.csv, "WN+GM", robust=True, efficiency=0.7).to_dict()
        wn = lambda r: r["channels"][0]["terms"][0]["parameters"]["value"]
        self.assertLess(abs(wn(got) / wn(clean) - 1.0), 0.05)
        self.assertGreater(wn(classical) / wn(clean), 2.0)
        with self.assertRaises(cubecal.UsageError) as e:
            cubecal.model(path, "WN+GM", robust=True, efficiency=1.5)
        self.assertEqual(e.exception.option, "efficiency")

    def test_bad_model(self):
        with self.assertRaises(cubecal.UsageError) as e:
            cubecal.model(self.csv, "WN+XX")
        self.assertEqual(e.exception.option, "model")
        self.assertIn("unknown term 'XX'", str(e.exception))
        with self.assertRaises(cubecal.UsageError) as e:
            cubecal.model(self.csv, "WN", bootstrap=1)
        self.assertEqual(e.exception.option, "bootstrap")
        with self.assertRaises(cubecal.UsageError) as e:
            cubecal.model(self.csv, "WN,WN+RW", wic_replicates=1)
        self.assertEqual(e.exception.option, "wic_replicates")


if __name__ == "__main__":
    unittest.main()
