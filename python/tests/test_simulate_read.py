"""cubecal.simulate and cubecal.read against the CLI's files."""
import os
import tempfile
import unittest

import numpy as np

import cubecal
from support import cli


class SimulateRead(unittest.TestCase):
    def test_simulate_equals_cli(self):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "g.csv")
            cli("simulate", "--preset", "sport-gyro", "--rate", 50, "--duration", "120s", "--seed", 9, "--out", path)
            file = np.genfromtxt(path, delimiter=",", names=True)
            rec = cubecal.simulate("sport-gyro", rate=50, duration="120s", seed=9)
            self.assertEqual(list(rec), ["t", "gx", "gy", "gz", "temp"])
            self.assertEqual(len(rec["gx"]), 6000)
            for name in rec:
                # The file keeps nine significant digits.
                np.testing.assert_allclose(rec[name], file[name], rtol=1e-8, atol=1e-12, err_msg=name)

    def test_flicker_equals_cli(self):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "f.csv")
            cli("simulate", "--preset", "sport-gyro", "--rate", 10, "--duration", "600s", "--seed", 2,
                "--flicker", 0.01, "--out", path)
            file = np.genfromtxt(path, delimiter=",", names=True)
            rec = cubecal.simulate("sport-gyro", rate=10, duration=600, seed=2, flicker=0.01)
            plain = cubecal.simulate("sport-gyro", rate=10, duration=600, seed=2)
            for name in ("gx", "gy", "gz"):
                np.testing.assert_allclose(rec[name], file[name], rtol=1e-8, atol=1e-12, err_msg=name)
                self.assertFalse(np.array_equal(rec[name], plain[name]))
            with self.assertRaises(cubecal.UsageError) as cm:
                cubecal.simulate("sport-gyro", flicker=[0.01, 0.02])
            self.assertEqual(cm.exception.option, "flicker")

    def test_presets_and_seed(self):
        self.assertIn("sport-gyro", cubecal.presets())
        a = cubecal.simulate(["sport-gyro", "sport-mag"], duration=100, seed=1)
        b = cubecal.simulate(["sport-gyro", "sport-mag"], duration=100, seed=2)
        self.assertEqual(a.rate_hz, 10.0)
        self.assertFalse(np.array_equal(a["gx"], b["gx"]))

    def test_read_names_that_are_not_utf8(self):
        # A Latin-1 header (issue 33, item 1): the name comes back with the
        # bad byte as \xNN, as every CLI writer shows it, instead of a
        # UnicodeDecodeError; columns= takes either form.
        with tempfile.TemporaryDirectory() as d:
            csv = os.path.join(d, "l.csv")
            with open(csv, "wb") as f:
                f.write(b"t,g\xe9x,gy\n" + b"".join(b"%g,%g,%g\n" % (k / 100, k % 7, k % 5) for k in range(400)))
            rec = cubecal.read(csv)
            self.assertEqual(list(rec), ["t", "g\\xe9x", "gy"])
            self.assertEqual(rec.channels, ["g\\xe9x", "gy"])
            np.testing.assert_array_equal(cubecal.read(csv, columns=["g\\xe9x"])["g\\xe9x"], np.arange(400) % 7)

    def test_read_text_and_npy(self):
        rng = np.random.default_rng(4)
        data = rng.normal(size=(500, 3))
        with tempfile.TemporaryDirectory() as d:
            csv = os.path.join(d, "r.csv")
            np.savetxt(csv, np.column_stack([np.arange(500) / 20.0, data]), delimiter=",", header="t,a_dps,b_dps,c_dps",
                       comments="", fmt="%.17g")
            rec = cubecal.read(csv)
            self.assertEqual(list(rec), ["t", "a_dps", "b_dps", "c_dps"])
            self.assertEqual(rec.rate_hz, 20.0)
            self.assertEqual(rec.time, "t")
            np.testing.assert_array_equal(rec["b_dps"], data[:, 1])
            sub = cubecal.read(csv, columns=["c_dps"], lsb=2.0)
            np.testing.assert_array_equal(sub["c_dps"], data[:, 2] / 2.0)
            npy = os.path.join(d, "r.npy")
            np.save(npy, data)
            r2 = cubecal.read(npy, rate=20.0)
            self.assertEqual(list(r2), ["col1", "col2", "col3"])
            np.testing.assert_array_equal(r2["col3"], data[:, 2])

    def test_frame(self):
        with tempfile.TemporaryDirectory() as d:
            csv = os.path.join(d, "r.csv")
            np.savetxt(csv, np.arange(30.0).reshape(10, 3), delimiter=",", header="t,x,y", comments="")
            try:
                import pandas  # noqa: F401
            except ImportError:
                with self.assertRaises(ImportError) as cm:
                    cubecal.read(csv, frame=True)
                self.assertIn("python3-pandas", str(cm.exception))
                return
            self.assertEqual(list(cubecal.read(csv, frame=True).columns), ["t", "x", "y"])


if __name__ == "__main__":
    unittest.main()
