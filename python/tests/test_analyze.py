"""cubecal.analyze equals `cubecal analyze` (analysis.json) on the same
record, from the file and from arrays; its result feeds cubecal.simulate
and writes the CLI's files."""
import json
import os
import tempfile
import unittest

import numpy as np

import cubecal
from support import cli

UNITS = "deg/s,deg/s,deg/s,mGauss,mGauss,mGauss"


def without(d, *keys):
    return {k: v for k, v in d.items() if k not in keys}


class Analyze(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.TemporaryDirectory()
        cls.csv = os.path.join(cls.dir.name, "imu.csv")
        cli("simulate", "--preset", "sport-gyro,sport-mag", "--rate", 10, "--duration", "3h", "--seed", 3,
            "--temp", "sine:25,5,3600", "--out", cls.csv)
        out = os.path.join(cls.dir.name, "cli")
        cli("analyze", cls.csv, "--unit", UNITS, "--temp-col", "temp", "--out", out)
        with open(os.path.join(out, "analysis.json")) as f:
            cls.want = json.load(f)

    @classmethod
    def tearDownClass(cls):
        cls.dir.cleanup()

    def test_file_equals_cli(self):
        a = cubecal.analyze(self.csv, unit=UNITS, temperature="temp")
        self.assertEqual(without(a.to_dict(), "command"), without(self.want, "command"))
        self.assertTrue(a.command.startswith("cubecal.analyze("), a.command)

    def test_arrays_equal_file(self):
        rec = cubecal.read(self.csv, extra="temp")
        self.assertEqual(rec.extra, ["temp"])
        a = cubecal.analyze(rec, unit=UNITS, temperature="temp")
        got = a.to_dict()
        for key in ("command", "file"):
            got.pop(key, None)
        self.assertEqual(got, without(self.want, "command", "file"))

    def test_attributes(self):
        a = cubecal.analyze(self.csv, unit=UNITS, temperature="temp")
        self.assertEqual([c.name for c in a.channels], ["gx", "gy", "gz", "mx", "my", "mz"])
        adev = a.channels[0].adev
        self.assertIsInstance(adev.dev, np.ndarray)
        self.assertEqual(adev.dev.tolist(), self.want["channels"][0]["adev"]["dev"])
        self.assertEqual(a.channels[3].unit, "mGauss")
        self.assertEqual(a.input.samples, 108000)

    def test_simulate_from_the_analysis(self):
        a = cubecal.analyze(self.csv, unit=UNITS, temperature="temp")
        r1 = cubecal.simulate(a, duration=600, seed=5)
        r2 = cubecal.simulate(a, duration=600, seed=5)
        self.assertEqual(list(r1), ["t", "gx", "gy", "gz", "mx", "my", "mz", "temp"])
        self.assertEqual(r1.rate_hz, 10.0)
        self.assertEqual(len(r1["gx"]), 6000)
        for k in r1:
            np.testing.assert_array_equal(r1[k], r2[k])
        # The simulated gyro's white noise is the analysed one's: its OADEV at
        # 1 s within 10 % of the measured.
        measured = a.channels[0].adev
        twin = cubecal.dev(r1["gx"], rate=10.0, taus=[1.0])
        self.assertAlmostEqual(twin.dev[0] / measured.dev[measured.tau.tolist().index(1.0)], 1.0, delta=0.1)

    def test_write(self):
        a = cubecal.analyze(self.csv, unit=UNITS, temperature="temp")
        with tempfile.TemporaryDirectory() as d:
            written = a.write(d)
            self.assertEqual(sorted(os.path.basename(p) for p in written),
                             ["adev.csv", "analysis.json", "drift.csv", "imu.yaml"])
            with open(os.path.join(d, "analysis.json")) as f:
                self.assertEqual(without(json.load(f), "command"), without(self.want, "command"))
            with self.assertRaises(cubecal.UsageError):
                a.write(d)
            a.write(d, force=True)


if __name__ == "__main__":
    unittest.main()
