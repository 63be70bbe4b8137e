"""cubecal.psd and cubecal.davar equal `cubecal psd` and `cubecal davar`
(--format json) on the same record, from the file and from arrays; with
gaps="skip", cubecal.read, cubecal.davar and cubecal.dev equal the CLI's
--gaps skip."""
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


class GapsSkip(unittest.TestCase):
    """gaps="skip" as the CLI's --gaps skip: cubecal.read keeps empty fields,
    NaN and rows never logged as NaN; cubecal.davar of the file and
    cubecal.dev of the Record equal `cubecal davar --gaps skip` and `cubecal
    dev --gaps skip`; the calls that need every sample refuse it."""

    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.TemporaryDirectory()
        cls.csv = os.path.join(cls.dir.name, "holes.csv")
        rng = np.random.default_rng(23)
        n = 6000
        gx = 0.05 * rng.normal(size=n) + np.cumsum(1e-3 * rng.normal(size=n))
        gy = 0.05 * rng.normal(size=n)
        gx[[130, 131, 2000]] = np.nan         # empty fields
        gx[4321] = np.nan                     # NaN spelled out
        gx[3000:3005] = np.nan                # rows never logged (a gap of whole periods)
        gy[3000:3005] = np.nan
        gx[4500:5100:5] = np.nan              # every fifth: no 6 whole samples in a row
        lines = ["t,gx_dps,gy_dps"]
        for k in range(n):
            if 3000 <= k < 3005:
                continue
            x = "NaN" if k == 4321 else ("" if np.isnan(gx[k]) else repr(float(gx[k])))
            lines.append(f"{k / 10:.1f},{x},{gy[k]!r}")
        with open(cls.csv, "w") as f:
            f.write("\n".join(lines) + "\n")
        cls.gx, cls.gy, cls.n = gx, gy, n

    @classmethod
    def tearDownClass(cls):
        cls.dir.cleanup()

    def test_read(self):
        rec = cubecal.read(self.csv, gaps="skip")
        self.assertEqual(rec.gaps, "skip")
        self.assertEqual(len(rec["gx_dps"]), self.n)
        np.testing.assert_array_equal(np.isnan(rec["gx_dps"]), np.isnan(self.gx))
        np.testing.assert_array_equal(np.isnan(rec["gy_dps"]), np.isnan(self.gy))
        self.assertEqual(rec.missing_samples, [int(np.isnan(self.gx).sum()), int(np.isnan(self.gy).sum())])
        whole = ~np.isnan(self.gx)
        np.testing.assert_array_equal(rec["gx_dps"][whole], self.gx[whole])
        clean = os.path.join(self.dir.name, "clean.csv")
        np.savetxt(clean, np.column_stack([np.arange(100) / 10.0, self.gy[:100]]), delimiter=",", header="t,gy",
                   comments="", fmt="%.17g")
        plain = cubecal.read(clean, gaps="split")
        self.assertEqual((plain.gaps, plain.missing_samples), ("split", [0]))
        # Without skip, the first empty field is an error at its place that names the way to keep it.
        with self.assertRaises(cubecal.InputError) as cm:
            cubecal.read(self.csv)
        self.assertEqual((cm.exception.line, cm.exception.column), (132, 6))  # '13.0,' then the field
        self.assertIn("gaps= skip leaves it out of the OADEV terms", str(cm.exception))

    def test_davar_equals_cli(self):
        args = dict(window="60s", step="20s", taus="octave")
        want = cli_json("davar", self.csv, "--gaps", "skip", "--window", "60s", "--step", "20s", "--taus", "octave",
                        "--format", "json")
        want.pop("invocation", None)
        self.assertEqual(want["missing_samples"], int(np.isnan(self.gx).sum() + np.isnan(self.gy).sum()))
        self.assertIn("terms", want["channels"][0])
        self.assertTrue(any(v is None for row in want["channels"][0]["dev"] for v in row))
        got = cubecal.davar(self.csv, gaps="skip", **args).to_dict()
        self.assertEqual(got, want)
        with self.assertRaises(cubecal.InputError):
            cubecal.davar(self.csv, **args)  # without skip the empty field is refused

    def test_dev_of_the_record_equals_cli(self):
        want = cli_json("dev", self.csv, "--gaps", "skip", "--taus", "all", "--format", "json")
        rec = cubecal.read(self.csv, gaps="skip")
        got = cubecal.dev(rec, taus="all").to_dict()
        got["file"] = want["file"]
        self.assertEqual(got, want)
        self.assertLess(len(got["columns"][0]["af"]), len(got["columns"][1]["af"]))  # gx's long taus have no term
        # As arrays the NaN is refused (at its place) unless asked for.
        arrays = {"gx_dps": np.asarray(rec["gx_dps"]), "gy_dps": np.asarray(rec["gy_dps"])}
        with self.assertRaises(cubecal.InputError):
            cubecal.dev(arrays, rate=10.0, taus="all")
        self.assertEqual(cubecal.dev(arrays, rate=10.0, taus="all", gaps="skip").to_dict()["columns"],
                         want["columns"])
        with self.assertRaises(cubecal.UsageError) as cm:
            cubecal.dev(rec, stat="mdev")  # OADEV only, as dev --gaps skip
        self.assertEqual(cm.exception.option, "stat")

    def test_refused_where_every_sample_is_needed(self):
        for call in (lambda: cubecal.psd(self.csv, gaps="skip"), lambda: cubecal.analyze(self.csv, gaps="skip")):
            with self.assertRaises(cubecal.UsageError) as cm:
                call()
            self.assertEqual(cm.exception.option, "gaps")
            self.assertIn("skipped by dev and davar", str(cm.exception))
        with self.assertRaises(cubecal.UsageError) as cm:
            cubecal.read(self.csv, gaps="fill")
        self.assertEqual(cm.exception.option, "gaps")


if __name__ == "__main__":
    unittest.main()
