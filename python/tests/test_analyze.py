"""cubecal.analyze equals `cubecal analyze` (analysis.json) on the same
record, from the file and from arrays; its result feeds cubecal.simulate
and writes the CLI's files; with psd=True it carries the spectral view as
`cubecal analyze --psd` does."""
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


class AnalyzePsd(unittest.TestCase):
    """psd=True: the spectral view, as `analyze --psd` writes it in analysis.json."""

    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.TemporaryDirectory()
        cls.csv = os.path.join(cls.dir.name, "gyro.csv")
        cli("simulate", "--preset", "sport-gyro", "--rate", 10, "--duration", "6h", "--seed", 5, "--out", cls.csv)
        out = os.path.join(cls.dir.name, "cli")
        cli("analyze", cls.csv, "--columns", "gx,gy,gz", "--unit", "deg/s", "--psd", "--out", out)
        with open(os.path.join(out, "analysis.json")) as f:
            cls.want = json.load(f)

    @classmethod
    def tearDownClass(cls):
        cls.dir.cleanup()

    def test_file_equals_cli(self):
        a = cubecal.analyze(self.csv, unit="deg/s", columns="gx,gy,gz", psd=True)
        got = a.to_dict()
        self.assertEqual(without(got, "command"), without(self.want, "command"))
        self.assertIn("psd=True", a.command)
        for c in got["channels"]:
            s = c["spectral"]
            self.assertEqual(s["spectrum"]["bins_per_decade"], 20)
            self.assertEqual([t["term"] for t in s["terms"]], ["N", "B", "K", "Q"])
            n = s["terms"][0]
            # The difference beside the Allan curve's N, as its definition says.
            self.assertAlmostEqual(n["difference_sigmas"],
                                   (n["value"] - n["allan_fit"]["value"]) / np.hypot(n["sigma"], n["allan_fit"]["sigma"]),
                                   delta=1e-9)

    def test_spectrum_is_cubecal_psd_at_twenty_bands_per_decade(self):
        a = cubecal.analyze(self.csv, unit="deg/s", columns="gx,gy,gz", psd=True)
        p = cubecal.psd(self.csv, unit="deg/s", columns="gx,gy,gz", bins_per_decade=20)
        for mine, theirs in zip(a.to_dict()["channels"], p.channels):
            s = mine["spectral"]
            np.testing.assert_array_equal(np.asarray(s["spectrum"]["density"]), theirs.density)
            np.testing.assert_array_equal(np.asarray(s["spectrum"]["frequency_hz"]), theirs.frequency_hz)
            self.assertEqual([t["h"] for t in s["fit"]["terms"]], [t.h for t in theirs.fit.terms])

    def test_off_by_default(self):
        a = cubecal.analyze(self.csv, unit="deg/s", columns="gx,gy,gz")
        self.assertTrue(all("spectral" not in c for c in a.to_dict()["channels"]))
        self.assertNotIn("psd=", a.command)


class AnalyzeComposite(unittest.TestCase):
    """composite=: the composite noise model as `analyze --composite` writes it, and
    cubecal.simulate(analysis, bias="composite") at another rate."""

    def test_equals_cli_and_simulates_at_another_rate(self):
        with tempfile.TemporaryDirectory() as d:
            csv = os.path.join(d, "gyro.csv")
            cli("simulate", "--preset", "sport-gyro", "--rate", 10, "--duration", "2h", "--seed", 4, "--out", csv)
            out = os.path.join(d, "cli")
            cli("analyze", csv, "--columns", "gx", "--unit", "deg/s", "--composite", "WN+RW",
                "--composite-bootstrap", 16, "--out", out)
            with open(os.path.join(out, "analysis.json")) as f:
                want = json.load(f)
            a = cubecal.analyze(csv, unit="deg/s", columns="gx", composite="WN+RW", composite_bootstrap=16)
        got = a.to_dict()
        self.assertEqual(without(got, "command"), without(want, "command"))
        self.assertIn("composite='WN+RW'", a.command)
        self.assertEqual(got["composite"]["bootstrap"], 16)
        comp = got["channels"][0]["model"]["composite"]
        self.assertEqual(comp["model"], "WN+RW")
        # The white noise is the preset's (13.9e-3 deg/s per sample with its
        # quantizer's 1/(12 lsb^2)), within 3 bootstrap sigmas.
        n = comp["terms"][0]["quantities"][0]
        self.assertEqual(n["name"], "N")
        truth = np.sqrt((13.9e-3 ** 2 + 1.0 / (12 * 145.6 ** 2)) * 0.1)  # deg/sqrt(s)
        self.assertLess(abs(n["value"] - truth), 3 * n["sd"], (n["value"], truth, n["sd"]))
        # Simulated at 20 Hz: the model's Allan deviation at 1 s, the measured one within 10 %.
        rec = cubecal.simulate(a, bias="composite", rate=20, duration=1200, seed=2)
        self.assertEqual(list(rec), ["t", "gx", "temp"])
        self.assertEqual(rec.rate_hz, 20.0)
        twin = cubecal.dev(rec["gx"], rate=20.0, taus=[1.0])
        measured = a.channels[0].adev
        self.assertAlmostEqual(twin.dev[0] / measured.dev[measured.tau.tolist().index(1.0)], 1.0, delta=0.1)


if __name__ == "__main__":
    unittest.main()
